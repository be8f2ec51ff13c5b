//! The front door's errors: what stops a run before it computes anything.

use crate::case::CaseError;
use crate::hbm::HbmError;
use crate::model::ModelError;
#[cfg(feature = "plot")]
use crate::plot::PlotError;
use crate::results::ResultsError;
use std::path::PathBuf;

/// Errors that stop a run before it computes anything (after that, a run
/// always writes what it has and says why it stopped).
#[derive(Debug, thiserror::Error)]
pub enum RunError {
    /// The case file.
    #[error(transparent)]
    Case(#[from] CaseError),
    /// The model.
    #[error(transparent)]
    Model(#[from] ModelError),
    /// The harmonic balance problem.
    #[error(transparent)]
    Hbm(#[from] HbmError),
    /// Writing results.
    #[error(transparent)]
    Results(#[from] ResultsError),
    /// Drawing the figures (feature `plot`).
    #[cfg(feature = "plot")]
    #[error(transparent)]
    Plot(#[from] PlotError),
    /// A frequency given on the command line is not usable.
    #[error("--at-hz {0}: frequencies must be finite and > 0 Hz")]
    BadFrequency(f64),
    /// Fixed-frequency mode with no frequency.
    #[error("--at-hz: give at least one frequency (Hz)")]
    NoFrequencies,
    /// The frequency range is to be taken from the excited nodal diameter's
    /// first mode, and that diameter has no mode.
    #[error("the excited nodal diameter {diameter} has no natural frequency to set the range from: give continuation.start_hz and continuation.end_hz")]
    NoNaturalFrequency {
        /// The unsigned nodal diameter.
        diameter: usize,
    },
    /// Every gap is 0, the casing is circular and nothing excites the
    /// wheel: the response is the static contact state, there is no branch.
    #[error("nothing moves: every casing.gap is 0, the casing has no casing.amplitude and the excitation gives no response; give an excitation amplitude or a casing shape")]
    NothingMoves,
    /// The results folder cannot be made (checked before the solve).
    #[error("the results folder {} (output.directory or --output) cannot be used: {message}", path.display())]
    OutputFolder {
        /// The folder.
        path: PathBuf,
        /// Why.
        message: String,
    },
}
