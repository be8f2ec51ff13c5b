//! Newton corrector and pseudo-arc-length continuation, for any residual
//! `R(x, ω)` that gives its Jacobians (it knows nothing of harmonic balance).
//!
//! The front door is [`continue_branch`] (one sweep), [`continue_from_both_ends`]
//! and [`solve_at_frequencies`]; below them, drivers that advance one point
//! at a time ([`Continuation`], [`BothEnds`], [`AtFrequencies`]) with
//! [`Observer`]s attached and [`Settings`] for every number. The parts:
//!
//! | module | what |
//! |---|---|
//! | `driver` | the step loop: predict, correct, judge, place, stop |
//! | `predictor` | the tangent and the branch's orientation |
//! | `corrector` | Newton on the plane through the prediction |
//! | `linear` | the bordered system, behind [`LinearSolver`] |
//! | `structured` | Jacobians too large to form: preconditioned GMRES |
//! | `step_control` | shrinking and growing the step |
//! | `policy` | smooth, piecewise and nonsmooth residuals |
//! | `steps` | a step accepted, refused, and how it was made |
//! | `kinks` | turning kinks, leaping small structures |
//! | `guards` | the trail, closed loops, old sheets |
//! | `geometry` | scaling, distances to segments |
//! | `events` | folds, branch points, kinks, stops |
//! | `observer` | what watches points go by |
//! | `both_ends` | a sweep back from the end, joined to the first |
//! | `natural`, `newton` | fixed-frequency runs and plain Newton |
//!
//! Why the rules are what they are, and how they fared on the paper's
//! cases: `docs/continuation-notes.md`.

mod both_ends;
mod bridge;
mod corrector;
mod driver;
mod events;
mod geometry;
mod guards;
mod interrupt;
mod kinks;
mod linear;
mod natural;
mod newton;
mod observer;
mod policy;
mod predictor;
mod settings;
mod step_control;
mod steps;
mod structured;
mod swept_path;
mod workspace;

pub use both_ends::{continue_from_both_ends, BothEnds, Sweeps};
pub use driver::{continue_branch, Continuation, ContinuationError, Step};
pub use events::{Event, EventKind};
pub use interrupt::Interrupt;
pub(crate) use linear::permutation_is_odd;
pub use linear::{Bordered, DenseLu, LinearSolver, Solution};
pub use natural::{solve_at_frequencies, AtFrequencies, AtFrequenciesSettings};
pub use newton::{correct, correct_until, NewtonSettings};
pub use observer::{Observer, ProgressFn, State};
pub use policy::PolicyKind;
pub use settings::{
    ArcLengthSettings, ClosedLoopSettings, CorrectorSettings, GuardSettings, JoinSettings,
    KinkSettings, OldSheetSettings, PiecewisePredictor, RetraceSettings, ScalingSettings, Settings,
    SettingsError, StepSettings, TurnLimits,
};
pub use structured::{solve_structured, Approximation, KrylovSolver, StructuredJacobian};

use faer::Mat;
use serde::{Deserialize, Serialize};
use std::fmt;

/// A residual and its Jacobians at one point.
#[derive(Clone, Debug)]
pub struct Evaluation {
    /// `R(x, ω)`.
    pub residual: Vec<f64>,
    /// `∂R/∂x` (filled when asked).
    pub jacobian: Mat<f64>,
    /// `∂R/∂ω` (filled with the Jacobian).
    pub derivative_omega: Vec<f64>,
    /// `∂R/∂x` in the problem's own structure, for a problem too large for
    /// the dense `jacobian` (then left empty): the solves run GMRES with its
    /// approximation (see [`StructuredJacobian`]).
    pub structured: Option<std::sync::Arc<dyn StructuredJacobian>>,
}

impl Default for Evaluation {
    fn default() -> Self {
        Self {
            residual: Vec::new(),
            jacobian: Mat::zeros(0, 0),
            derivative_omega: Vec::new(),
            structured: None,
        }
    }
}

/// What continuation needs from a problem.
pub trait Problem {
    /// Error of an evaluation.
    type Error: std::error::Error + Send + Sync + 'static;
    /// Number of real unknowns `x`.
    fn unknowns(&self) -> usize;
    /// A force by which residuals are divided for the convergence test.
    fn force_scale(&self) -> f64;
    /// Evaluates `R(x, ω)`, and `∂R/∂x`, `∂R/∂ω` if `jacobian`. Without
    /// `jacobian`, `out.jacobian` and `out.derivative_omega` must be left
    /// as they are: the corrector evaluates the residual alone at its
    /// trials and keeps the last Jacobians it factored.
    fn evaluate(
        &mut self,
        x: &[f64],
        omega: f64,
        jacobian: bool,
        out: &mut Evaluation,
    ) -> Result<(), Self::Error>;
    /// Squared weights of the unknowns in the arc-length norm, so that
    /// equivalent layouts (reduced, full) measure the same step.
    fn norm_weights(&self) -> Vec<f64> {
        vec![1.0; self.unknowns()]
    }
    /// For a piecewise-smooth residual: which smooth piece holds `(x, ω)`,
    /// as an identifier that differs between pieces (for DLFT-HBM, a hash of
    /// the contact state at every sampled instant). `None` (the default)
    /// for a smooth residual. Continuation uses it to find the kinks of a
    /// branch exactly and to turn onto the next piece.
    fn piece(&mut self, x: &[f64], omega: f64) -> Result<Option<u64>, Self::Error> {
        let _ = (x, omega);
        Ok(None)
    }
    /// The piece of the last evaluation (see [`Self::piece`]), for a
    /// piecewise-smooth residual that keeps it: a factorization made on
    /// the piece of a corrected point serves its tangent. `None` (the
    /// default) when unknown.
    fn piece_of_last_evaluation(&self) -> Option<u64> {
        None
    }
    /// Whether the residual is smooth (continuously differentiable): then
    /// every turn of the branch resolves with a short enough step, and the
    /// corner heuristics for nonsmooth residuals stay off. `false` (the
    /// default) keeps them on.
    fn is_smooth(&self) -> bool {
        false
    }
    /// An approximate solution at `omega` from nothing (a harmonic
    /// balance gives its linear response): where a fixed-frequency run
    /// starts again when its sheet ended and the branch through the fold
    /// does not come back to the frequency asked for ([`AtFrequencies`]).
    /// `steps` are the run's Newton settings, steps and length scale, for
    /// a problem that gets there by a continuation of its own (its `start`
    /// and `end` mean nothing here). `None` (the default): no such guess,
    /// the point fails.
    fn fresh_guess(
        &mut self,
        omega: f64,
        steps: &ArcLengthSettings,
    ) -> Result<Option<Vec<f64>>, Self::Error> {
        let _ = (omega, steps);
        Ok(None)
    }
    /// Lets `interrupt` cut a long evaluation short: once it is raised,
    /// an evaluation may return an error instead of finishing (the driver
    /// then stops as interrupted). Nothing by default.
    fn watch_interrupt(&mut self, interrupt: &Interrupt) {
        let _ = interrupt;
    }
}

/// One converged (or, in fixed-frequency mode, attempted) point.
#[derive(Clone, Debug, Serialize)]
pub struct Point {
    /// Angular frequency, rad/s.
    pub omega: f64,
    /// The unknowns.
    pub unknowns: Vec<f64>,
    /// Newton iterations spent on it.
    pub iterations: usize,
    /// `‖R‖ / force scale` at the point.
    pub residual_norm: f64,
    /// Whether Newton converged (always true along an arc-length branch).
    pub converged: bool,
}

impl Point {
    /// A converged point.
    pub(crate) fn converged(
        omega: f64,
        unknowns: Vec<f64>,
        iterations: usize,
        residual_norm: f64,
    ) -> Self {
        Self {
            omega,
            unknowns,
            iterations,
            residual_norm,
            converged: true,
        }
    }
}

/// Why a branch stopped. Written to `run.json` as its variant (`reason`)
/// and fields, and read back from it.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(tag = "reason", rename_all = "snake_case")]
pub enum StopReason {
    /// The end frequency was reached.
    EndReached,
    /// Every frequency asked for was attempted.
    AllFrequenciesDone,
    /// The step fell below the minimum step without convergence.
    StepUnderflow {
        /// Last converged frequency, Hz.
        frequency_hz: f64,
        /// The step that failed.
        step: f64,
    },
    /// Newton failed on the first point.
    NewtonFailure {
        /// Frequency, Hz.
        frequency_hz: f64,
        /// Relative residual reached.
        residual_norm: f64,
    },
    /// The branch turned back and went past its start frequency, out of
    /// the range asked for (the last point is there, converged).
    LeftRange {
        /// Frequency of the last point, Hz.
        frequency_hz: f64,
    },
    /// The branch came back to a point it had already passed (a closed
    /// curve, or a cycle through the corners of a nonsmooth branch): going
    /// on would repeat it.
    ClosedLoop {
        /// Frequency of the repeated point, Hz.
        frequency_hz: f64,
        /// Index of the earlier point it repeats.
        earlier_point: usize,
    },
    /// A sweep back from the end frequency met the sweep from the start
    /// (see [`continue_from_both_ends`]).
    MetOtherSweep {
        /// Frequency where they met, Hz.
        frequency_hz: f64,
        /// The point of the sweep from the start where they met.
        point: usize,
    },
    /// The cap on points was reached.
    PointCap {
        /// The cap.
        max_points: usize,
    },
    /// Stopped from outside ([`Interrupt::raise`]: Ctrl-C, a notebook);
    /// every point accepted before is kept.
    Interrupted {
        /// Frequency of the last point, Hz (`None` before the first).
        frequency_hz: Option<f64>,
    },
    /// The problem could not be evaluated.
    EvaluationError {
        /// Frequency, Hz.
        frequency_hz: f64,
        /// The error.
        message: String,
    },
}

/// The one wording of a stop, for messages, reports and Python alike
/// (`run.json` keeps the variant and its fields, see [`StopReason`]'s serde
/// form); [`StopReason::advice`] adds what governs it.
impl fmt::Display for StopReason {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let text: String = match self {
            StopReason::EndReached => "end frequency reached".into(),
            StopReason::AllFrequenciesDone => "every frequency attempted".into(),
            StopReason::StepUnderflow { frequency_hz, step } => {
                format!("step underflow at {frequency_hz:.4} Hz, step {step:.2e}")
            }
            StopReason::NewtonFailure {
                frequency_hz,
                residual_norm,
            } => format!(
                "Newton failed at {frequency_hz:.4} Hz, relative residual {residual_norm:.2e}"
            ),
            StopReason::LeftRange { frequency_hz } => {
                format!("turned back past the start frequency, at {frequency_hz:.4} Hz")
            }
            StopReason::ClosedLoop {
                frequency_hz,
                earlier_point,
            } => format!("came back to point {earlier_point} at {frequency_hz:.4} Hz"),
            StopReason::MetOtherSweep {
                frequency_hz,
                point,
            } => format!("met the sweep from the start at its point {point}, {frequency_hz:.4} Hz"),
            StopReason::PointCap { max_points } => format!("cap of {max_points} points"),
            StopReason::Interrupted {
                frequency_hz: Some(frequency_hz),
            } => format!("interrupted after the point at {frequency_hz:.4} Hz"),
            StopReason::Interrupted { frequency_hz: None } => {
                "interrupted before the first point".into()
            }
            StopReason::EvaluationError {
                frequency_hz,
                message,
            } => format!("stopped at {frequency_hz:.4} Hz: {message}"),
        };
        f.write_str(&text)
    }
}

impl StopReason {
    /// What governs the stop and what to try, naming the case keys (`None`
    /// when the stop says it all): shown after the stop by the CLI and
    /// Python.
    pub fn advice(&self) -> Option<&'static str> {
        match self {
            StopReason::StepUnderflow { .. } => Some("the step fell below continuation.min_step"),
            StopReason::ClosedLoop { .. } => Some("going on would loop"),
            StopReason::LeftRange { .. } => {
                Some("the branch left the range at continuation.start_hz")
            }
            StopReason::PointCap { .. } => Some("continuation.max_points"),
            StopReason::NewtonFailure { .. } => Some(
                "continuation.tolerance: the first point did not converge; try a larger \
                 continuation.max_iterations, a continuation.start_hz farther from resonance, \
                 or a casing.gap slightly above 0",
            ),
            _ => None,
        }
    }

    /// The stop and its advice in one line: `stop (advice)`.
    pub fn with_advice(&self) -> String {
        match self.advice() {
            Some(advice) => format!("{self} ({advice})"),
            None => self.to_string(),
        }
    }
}

/// A branch: its points in order, what happened along it and why it stopped.
#[derive(Clone, Debug, Serialize)]
pub struct Branch {
    /// The points.
    pub points: Vec<Point>,
    /// Why it stopped.
    pub stop: StopReason,
    /// Newton iterations in total, failed attempts included.
    pub total_iterations: usize,
    /// When the branch was followed from both ends: how the two sweeps went
    /// (`None`: one sweep from the start).
    pub sweeps: Option<Sweeps>,
    /// Folds, branch points, kinks and stops, in the order of the points
    /// (see [`Event::index`]).
    pub events: Vec<Event>,
}

impl Branch {
    /// The branch of one sweep.
    pub(crate) fn sweep(
        points: Vec<Point>,
        stop: StopReason,
        total_iterations: usize,
        events: Vec<Event>,
    ) -> Self {
        Self {
            points,
            stop,
            total_iterations,
            sweeps: None,
            events,
        }
    }

    /// The branch of a run that could not start at `omega` (rad/s), for
    /// the entry points that never fail.
    pub(crate) fn refused(omega: f64, error: &ContinuationError) -> Self {
        let stop = StopReason::EvaluationError {
            frequency_hz: hertz(omega),
            message: error.to_string(),
        };
        let events = vec![Event::stop(&stop, 0, None)];
        Self::sweep(Vec::new(), stop, 0, events)
    }
}

/// Progress of a running branch, for observers.
#[derive(Clone, Copy, Debug)]
pub struct Progress {
    /// Points so far.
    pub points: usize,
    /// Current frequency, Hz.
    pub frequency_hz: f64,
    /// Current step (scaled arc length; 0 in fixed-frequency mode).
    pub step: f64,
}

/// Euclidean norm.
pub(crate) fn norm(v: &[f64]) -> f64 {
    v.iter().map(|x| x * x).sum::<f64>().sqrt()
}

pub(crate) fn hertz(omega: f64) -> f64 {
    omega / (2.0 * std::f64::consts::PI)
}
