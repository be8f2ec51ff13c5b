//! The reproduction of the paper's academic studies (Sec. 4 and
//! Appendix C): every case file of a folder, with each contact law, solved
//! on the symmetry basis, on the paper's basis and on the full wheel in
//! physical coordinates; the reduced runs checked against the full one
//! ([`exactness`]), their stability checked ([`stability`]: Hill's method
//! per symmetry class on the symmetry basis) and the whole written up as a
//! report ([`report`]).
//!
//! The claim under test is the paper's: the reductions are exact. So
//! nothing here is tuned until it passes: a reduced run that does not
//! reproduce the full one is reported as such, with its figures.

pub mod exactness;
pub mod report;
mod runner;
pub mod stability;

pub use runner::{case_files, multiple_of_sectors, provide_fan_mesh, quick_case, reproduce};

use cyclorub::case::{BasisChoice, CaseError, LawKind};
use cyclorub::continuation::{Progress, StopReason};
use cyclorub::plot::PlotError;
use cyclorub::results::ResultsError;
use cyclorub::run::{RunError, RunOutcome, Timings};
use exactness::{EnergyOutside, PointByPoint};
use serde::Serialize;
use stability::StabilitySummary;
use std::path::{Path, PathBuf};

/// The cases of the quick reproduction (CI): one traveling, one standing
/// and the mixed case of Sec. 4.3.3, all on N = 24.
pub const QUICK_CASES: &[&str] = &[
    "n24-traveling-h1",
    "n24-standing-h4",
    "n24-mixed-h6-casing-h8",
];

/// Largest relative difference between a reduced run and the full wheel
/// for the reduction to count as exact (the harmonic balance core's).
pub const TOLERANCE: f64 = 1e-8;

/// Largest fraction of the full solution's energy outside a reduced basis
/// for the basis to count as complete.
pub const ENERGY_TOLERANCE: f64 = 1e-10;

/// Largest distance (scaled, see [`exactness::curve_distance`]) between
/// the full branch and a reduced one for the two to count as the same
/// curve: the independent continuations place their points differently,
/// so this judges the path, not round-off.
pub const CURVE_TOLERANCE: f64 = 1e-2;

/// Errors that stop a reproduction before it starts (a run that fails is
/// reported in the report, not here).
#[derive(Debug, thiserror::Error)]
pub enum ReproduceError {
    /// The folder of case files cannot be read or holds none.
    #[error("{folder}: {message}")]
    Folder {
        /// The folder.
        folder: PathBuf,
        /// What is wrong.
        message: String,
    },
    /// A case asked for is not in the folder.
    #[error("--cases: no case named {name:?} in {folder}; the cases there are: {available}")]
    UnknownCase {
        /// The name asked for.
        name: String,
        /// The folder.
        folder: PathBuf,
        /// The names there, comma-separated.
        available: String,
    },
    /// A case file is not valid.
    #[error(transparent)]
    Case(#[from] CaseError),
    /// A case's model or problem cannot be built.
    #[error("case {case}: {message}")]
    Prepare {
        /// The case name.
        case: String,
        /// Why.
        message: String,
    },
    /// Writing the report.
    #[error(transparent)]
    Results(#[from] ResultsError),
    /// Drawing a figure.
    #[error(transparent)]
    Plot(#[from] PlotError),
}

impl ReproduceError {
    /// Whether the error is in what the user gave (the folder, the case
    /// names, the case files), as opposed to a failure while writing the
    /// report or its figures.
    pub fn is_input_error(&self) -> bool {
        !matches!(self, Self::Results(_) | Self::Plot(_))
    }
}

/// What to reproduce.
#[derive(Clone, Debug)]
pub struct ReproduceOptions {
    /// The folder of case files (`examples/`).
    pub folder: PathBuf,
    /// Where the report and every run's results folder go.
    pub output: PathBuf,
    /// Short runs of [`QUICK_CASES`] (see [`quick_case`]).
    pub quick: bool,
    /// Case names (file stems) to run; empty: every case (quick: [`QUICK_CASES`]).
    pub cases: Vec<String>,
    /// Contact laws; empty: both.
    pub laws: Vec<LawKind>,
    /// Check the stability of the symmetry-basis runs (and of the full
    /// wheel's, when its eigenproblem is small: see [`stability`]).
    pub stability: bool,
}

/// What a reproduction reports as it goes.
#[derive(Clone, Copy, Debug)]
pub enum Step<'a> {
    /// A run starts.
    Run {
        /// Case name.
        case: &'a str,
        /// Contact law.
        law: LawKind,
        /// Basis.
        basis: BasisChoice,
    },
    /// A case's finite-element files were missing: the open fan is being
    /// written for it (see [`provide_fan_mesh`]).
    Mesh {
        /// Case name.
        case: &'a str,
        /// The folder written, where the case's model files now point.
        folder: &'a Path,
        /// `cyclorub mesh fan --refine`.
        refine: usize,
    },
    /// A point of the running branch.
    Point(&'a Progress),
    /// The reduced runs are being checked against the full one.
    Checking {
        /// Case name.
        case: &'a str,
        /// Contact law.
        law: LawKind,
    },
}

/// One run of a study.
#[derive(Clone, Debug, Serialize)]
pub struct RunSummary {
    /// The basis (`symmetry`, `paper` or `physical` in report.json).
    pub basis: BasisChoice,
    /// Real unknowns solved for.
    pub unknowns: usize,
    /// Real unknowns of the full wheel.
    pub full_unknowns: usize,
    /// Reduction of the unknown count, %.
    pub reduction_percent: f64,
    /// Sectors sampled by the AFT.
    pub sampled_sectors: usize,
    /// Signed nodal diameters per harmonic (cyclic bases).
    pub harmonics: Vec<cyclorub::run::HarmonicRecord>,
    /// Points of the branch (0 when not run).
    pub points: usize,
    /// Newton iterations.
    pub iterations: usize,
    /// Why the branch stopped (absent when not run).
    pub stop: Option<StopReason>,
    /// How the branch was followed from both ends, when the sweep from the
    /// start stopped short.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub sweeps: Option<cyclorub::continuation::Sweeps>,
    /// Wall-clock times (absent when not run).
    pub timings: Option<Timings>,
    /// The run's results folder, relative to the report.
    pub folder: Option<PathBuf>,
    /// Set when this basis is the same as another's and was not run again.
    pub same_as: Option<BasisChoice>,
    /// Why the run failed, if it did.
    pub error: Option<String>,
    /// The stability of the branch's points (absent when the run failed).
    pub stability: Option<StabilitySummary>,
}

impl RunSummary {
    fn from_outcome(
        outcome: &RunOutcome,
        basis: BasisChoice,
        folder: PathBuf,
        stability: StabilitySummary,
    ) -> Self {
        let r = &outcome.record;
        Self {
            basis,
            unknowns: r.basis.unknowns,
            full_unknowns: r.basis.full_unknowns,
            reduction_percent: r.basis.reduction_percent,
            sampled_sectors: r.basis.sampled_sectors,
            harmonics: r.basis.harmonics.clone(),
            points: r.points,
            iterations: r.total_iterations,
            stop: Some(r.stop.clone()),
            sweeps: r.sweeps.clone(),
            timings: Some(r.timings.clone()),
            folder: Some(folder),
            same_as: None,
            error: None,
            stability: Some(stability),
        }
    }

    fn failed(basis: BasisChoice, error: &RunError) -> Self {
        Self {
            basis,
            unknowns: 0,
            full_unknowns: 0,
            reduction_percent: 0.0,
            sampled_sectors: 0,
            harmonics: Vec::new(),
            points: 0,
            iterations: 0,
            stop: None,
            sweeps: None,
            timings: None,
            folder: None,
            same_as: None,
            error: Some(error.to_string()),
            stability: None,
        }
    }

    /// Whether the branch reached its end frequency.
    pub fn complete(&self) -> bool {
        matches!(self.stop, Some(StopReason::EndReached))
    }
}

/// A reduced run against the full wheel.
#[derive(Clone, Debug, Serialize)]
pub struct Comparison {
    /// The reduced basis.
    pub basis: BasisChoice,
    /// Point by point (absent if either run failed).
    pub point_by_point: Option<PointByPoint>,
    /// Curve by curve.
    pub curve_distance: Option<f64>,
    /// The full branch's energy outside this basis (every dof of the
    /// sector), at its resonance and along the branch.
    pub energy_outside: Option<EnergyOutside>,
    /// Full solve time over reduced solve time.
    pub time_ratio: Option<f64>,
}

impl Comparison {
    /// The reduction is exact: every point of the reduced branch is a
    /// solution of the full problem, to [`TOLERANCE`] relative.
    pub fn exact(&self) -> bool {
        self.point_by_point.as_ref().is_some_and(|p| {
            p.points > 0
                && p.not_converged == 0
                && p.largest_unknowns_difference <= TOLERANCE
                && p.largest_displacement_difference <= TOLERANCE
        })
    }

    /// The basis holds the full solution at its resonance, to
    /// [`ENERGY_TOLERANCE`] of its energy.
    pub fn complete(&self) -> bool {
        self.energy_outside
            .as_ref()
            .is_some_and(|e| e.at_resonance <= ENERGY_TOLERANCE)
    }

    /// The independent full branch lies on the reduced one.
    pub fn same_curve(&self) -> bool {
        self.curve_distance.is_some_and(|d| d <= CURVE_TOLERANCE)
    }
}

/// One case with one contact law.
#[derive(Clone, Debug, Serialize)]
pub struct Study {
    /// The case name (file stem).
    pub case: String,
    /// What the case is (the first comment line of its file).
    pub description: String,
    /// Contact law.
    pub law: LawKind,
    /// `N`.
    pub sectors: usize,
    /// `N_h`.
    pub harmonics: usize,
    /// `N_t` used.
    pub time_samples: usize,
    /// `N_t` of the case file.
    pub time_samples_in_file: usize,
    /// Frequency range, Hz.
    pub start_hz: f64,
    /// Frequency range, Hz.
    pub end_hz: f64,
    /// The runs: symmetry, paper, physical.
    pub runs: Vec<RunSummary>,
    /// The reduced runs against the full one.
    pub comparisons: Vec<Comparison>,
    /// Frequency of the full branch's resonance (largest amplitude), Hz.
    pub resonance_hz: Option<f64>,
    /// Figures, relative to the report.
    pub figures: Vec<PathBuf>,
}

impl Study {
    /// Every reduced run is exact (see [`Comparison::exact`]) and no run failed.
    pub fn exact(&self) -> bool {
        !self.comparisons.is_empty()
            && self.comparisons.iter().all(Comparison::exact)
            && self.runs.iter().all(|r| r.error.is_none())
    }

    /// Every reduced basis holds the full solution at its resonance (see
    /// [`Comparison::complete`]).
    pub fn complete(&self) -> bool {
        !self.comparisons.is_empty() && self.comparisons.iter().all(Comparison::complete)
    }
}

/// How much is reproduced (`report.json`'s `mode`).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum ReproduceMode {
    /// A few short cases ([`ReproduceOptions::quick`]).
    Quick,
    /// Every case with the paper's settings.
    Full,
}

impl ReproduceMode {
    /// The mode of `options`.
    pub fn of(options: &ReproduceOptions) -> Self {
        if options.quick {
            Self::Quick
        } else {
            Self::Full
        }
    }
}

/// The word report.json holds (`quick`, `full`).
impl std::fmt::Display for ReproduceMode {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(match self {
            Self::Quick => "quick",
            Self::Full => "full",
        })
    }
}

/// The whole reproduction.
#[derive(Clone, Debug, Serialize)]
pub struct Report {
    /// Quick or full.
    pub mode: ReproduceMode,
    /// The folder of case files.
    pub folder: PathBuf,
    /// The studies.
    pub studies: Vec<Study>,
    /// Wall time of the whole reproduction, s.
    pub wall_s: f64,
}

impl Report {
    /// Every study is exact.
    pub fn exact(&self) -> bool {
        !self.studies.is_empty() && self.studies.iter().all(Study::exact)
    }

    /// Every study's full solutions lie in the reduced bases at their resonance.
    pub fn complete(&self) -> bool {
        !self.studies.is_empty() && self.studies.iter().all(Study::complete)
    }
}
