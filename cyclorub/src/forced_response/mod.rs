//! The library's front door: a case in, a forced response branch in memory
//! out, with everything the result files are made of.
//!
//! ```no_run
//! use cyclorub::case::{BasisChoice, Case};
//! use cyclorub::forced_response::ForcedResponse;
//!
//! # fn main() -> Result<(), cyclorub::run::RunError> {
//! let solution = ForcedResponse::from_case(&Case::default())?
//!     .basis(BasisChoice::Symmetry)
//!     .build()?
//!     .run(&mut [])?;
//! for point in &solution.branch.points {
//!     println!("{:.3} Hz", point.omega / (2.0 * std::f64::consts::PI));
//! }
//! # Ok(())
//! # }
//! ```

use crate::case::{BasisChoice, Case};
use crate::continuation::{
    correct_until, ArcLengthSettings, AtFrequencies, AtFrequenciesSettings, BothEnds, Branch,
    Interrupt, NewtonSettings, Observer, Settings, StepSettings, StopReason,
};
use crate::hbm::HarmonicBalance;
use crate::model::SectorModel;
use crate::results::recovery::{BranchRecovery, PointSummary};
use crate::stability::{Stability, StabilitySettings};
use rayon::prelude::*;
use std::f64::consts::PI;
use std::path::PathBuf;
use std::time::Instant;

mod basis_record;
mod chord;
pub(crate) mod data;
mod error;
mod locate_branch;
mod locate_by_count;
mod locate_error;
mod locate_markers;
mod locate_trial;
pub mod mistuned;
mod mistuned_stability;
mod outcome;
mod prepare;
mod problem;
mod refine;
mod stability_memory;
mod start;
mod states;

pub use basis_record::{BasisRecord, HarmonicRecord};
pub use chord::ChordMetric;
pub(crate) use data::results_data_from;
pub use error::RunError;
pub use locate_branch::locate_branch_markers;
pub use locate_markers::{
    locate_markers, LocateError, Located, BRACKET_FRACTION, BRACKET_HZ, REAL_AT_LOCATION,
};
pub use outcome::{StabilityOutcome, StartRecord};
use prepare::frequency_range;
pub use prepare::{excited_frequency, length_scale, prepare, Prepared};
pub use states::{RunMode, RunStatus, StabilityStatus};

pub use refine::{
    branch_solutions_at, refined_point, refined_stability, Convergence, RefineError, RefinedPoint,
    RefinedStability, Refinement,
};

use mistuned_stability::mistuned_stability_refusal;
pub(crate) use problem::build_problem;
pub use problem::problem_on_basis;
use stability_memory::check_stability_memory;
use start::{start_by_gap_continuation, start_by_load_continuation};

/// What to solve: a case, the folder its relative paths start from, the
/// basis and the mode (arc-length continuation, or fixed frequencies).
#[derive(Clone, Debug)]
pub struct ForcedResponse {
    case: Case,
    case_dir: PathBuf,
    basis: BasisChoice,
    at_hz: Option<Vec<f64>>,
    stability: Option<StabilitySettings>,
    interrupt: Interrupt,
}

impl ForcedResponse {
    /// The forced response of `case` (checked here), on the case's basis,
    /// by continuation over its frequency range; relative paths of the case
    /// start from the working directory (see [`Self::case_dir`]).
    pub fn from_case(case: &Case) -> Result<Self, RunError> {
        case.validate()?;
        Ok(Self {
            case: case.clone(),
            case_dir: PathBuf::from("."),
            basis: case.basis.kind,
            at_hz: None,
            stability: None,
            interrupt: Interrupt::new(),
        })
    }

    /// Stop the branch before its next point once `interrupt` is raised
    /// (from a signal handler or another thread): the solution keeps every
    /// point found, its stop says [`StopReason::Interrupted`], and the
    /// stability check, if asked for, is skipped.
    pub fn interrupt(mut self, interrupt: Interrupt) -> Self {
        self.interrupt = interrupt;
        self
    }

    /// Check the stability of every point once the branch is solved
    /// (Hill's method per symmetry class, see [`crate::stability`]);
    /// `None` (the default here) skips it.
    pub fn stability(mut self, settings: Option<StabilitySettings>) -> Self {
        self.stability = settings;
        self
    }

    /// The folder the case's relative paths (matrix files) start from.
    pub fn case_dir(mut self, dir: impl Into<PathBuf>) -> Self {
        self.case_dir = dir.into();
        self
    }

    /// The basis to solve on (overrides the case's `[basis] kind`).
    pub fn basis(mut self, basis: BasisChoice) -> Self {
        self.basis = basis;
        self
    }

    /// Solve at exactly these frequencies (Hz, each from the last) instead
    /// of continuing in arc length.
    pub fn at_frequencies_hz(mut self, frequencies: Vec<f64>) -> Self {
        self.at_hz = Some(frequencies);
        self
    }

    /// Builds the model, the basis and the residual, and resolves the
    /// frequency range; nothing is solved yet.
    pub fn build(self) -> Result<Solver, RunError> {
        if let Some(list) = &self.at_hz {
            if list.is_empty() {
                return Err(RunError::NoFrequencies);
            }
            if let Some(&bad) = list.iter().find(|f| !(f.is_finite() && **f > 0.0)) {
                return Err(RunError::BadFrequency(bad));
            }
        }
        let clock = Instant::now();
        let prepared = prepare(&self.case, &self.case_dir, self.basis)?;
        // A mistuned wheel too large for the whole wheel's check is solved
        // without it (the solution says why).
        let refused = self.stability.as_ref().and_then(|settings| {
            mistuned_stability_refusal(&prepared, settings, self.at_hz.is_none())
        });
        if let Some(reason) = &refused {
            tracing::info!("stability: {reason}");
        }
        if let (Some(settings), None) = (&self.stability, &refused) {
            check_stability_memory(&prepared, settings, false)?;
        }
        let time_samples = prepared.case.harmonic_balance.time_samples;
        let cost = crate::memory::IterationCost {
            unknowns: prepared.problem.layout().unknowns,
            assembly_products: prepared.problem.jacobian_assembly_products(),
            signal_samples: (prepared.problem.contact_signals() * time_samples) as f64,
            time_samples,
            max_iterations: prepared.case.continuation.max_iterations,
        };
        // The estimate is the dense Jacobian's: a structured one (the
        // large physical full wheel) costs far less an iteration.
        if let Some(notice) = cost.notice().filter(|_| !prepared.problem.is_structured()) {
            tracing::info!("{notice}");
        }
        Ok(Solver {
            prepared,
            at_hz: self.at_hz,
            stability: self.stability,
            stability_refused: refused,
            interrupt: self.interrupt,
            setup_s: clock.elapsed().as_secs_f64(),
        })
    }
}

/// A built problem, ready to solve.
pub struct Solver {
    prepared: Prepared,
    at_hz: Option<Vec<f64>>,
    stability: Option<StabilitySettings>,
    /// Why the stability asked for is not checked (a mistuned wheel too
    /// large for the whole wheel's check).
    stability_refused: Option<String>,
    interrupt: Interrupt,
    setup_s: f64,
}

/// A solved branch with everything it was solved from, in memory.
pub struct Solution {
    /// The case, resolved (basis set, frequency range filled in).
    pub case: Case,
    /// The model.
    pub model: SectorModel,
    /// The residual the branch was solved on.
    pub problem: HarmonicBalance,
    /// The basis.
    pub basis: BasisRecord,
    /// The branch: its points (unknowns and frequency), why it stopped.
    pub branch: Branch,
    /// Arc-length continuation, or solves at given frequencies.
    pub mode: RunMode,
    /// How the first point was reached.
    pub start: StartRecord,
    /// Set-up and solve times, s.
    pub setup_s: f64,
    /// The solve's time, s.
    pub solve_s: f64,
    /// The stability of every point, if asked for.
    pub stability: StabilityOutcome,
    /// The stability check's time, s.
    pub stability_s: f64,
    /// Whether the run was stopped from outside ([`ForcedResponse::interrupt`]):
    /// during the branch (its stop says so) or during the stability check.
    pub interrupted: bool,
    /// Where the case's relative paths start (model files): a mistuned
    /// run's tuned reference is built from there.
    pub case_dir: PathBuf,
}

impl Solution {
    /// The stability check of this solution's points (Hill's method per
    /// symmetry class; see [`crate::stability`]).
    pub fn stability_check(
        &self,
        settings: &StabilitySettings,
    ) -> Result<Stability<'_>, crate::stability::StabilityError> {
        Stability::new(
            &self.model,
            &self.problem,
            &self.case.contact_dofs(),
            settings,
        )
    }
}

impl Solver {
    /// Whether the wheel solved is mistuned (`[mistuning]`).
    pub fn is_mistuned(&self) -> bool {
        self.prepared.model.is_mistuned()
    }

    /// The case, resolved.
    pub fn case(&self) -> &Case {
        &self.prepared.case
    }

    /// The model.
    pub fn model(&self) -> &SectorModel {
        &self.prepared.model
    }

    /// Why a stability check with `settings` is not made on this problem's
    /// points, or `None` when it is: a mistuned wheel has one class, the
    /// whole wheel, refused where its size is beyond the check's largest
    /// eigenproblem (the reason says what it would cost).
    pub fn stability_refusal(&self, settings: &StabilitySettings) -> Option<String> {
        mistuned_stability_refusal(&self.prepared, settings, self.at_hz.is_none())
    }

    /// Refuses a stability check of this problem's points that would not
    /// fit in memory beside the run, on a thread of its own (`own_thread`,
    /// as `cyclorub run` checks on its writer's) or not.
    pub fn check_stability_memory(
        &self,
        settings: &StabilitySettings,
        own_thread: bool,
    ) -> Result<(), RunError> {
        check_stability_memory(&self.prepared, settings, own_thread)
    }

    /// The basis solved on.
    pub fn basis(&self) -> &BasisRecord {
        &self.prepared.basis
    }

    /// The residual.
    pub fn problem(&self) -> &HarmonicBalance {
        &self.prepared.problem
    }

    /// Solves: follows the branch over the case's frequency range (from
    /// both ends when the sweep from the start stops short), or solves at
    /// the frequencies asked for. The observers (a progress display, a
    /// writer, a check; see [`Observer`]) see every point as it is accepted
    /// and every event. Fails only when the problem cannot be evaluated
    /// before the first point; after that the branch says why it stopped.
    pub fn run(self, observers: &mut [&mut dyn Observer]) -> Result<Solution, RunError> {
        let Prepared {
            case,
            model,
            mut problem,
            basis,
            case_dir,
        } = self.prepared;
        let clock = Instant::now();
        let k = &case.continuation;
        let newton = NewtonSettings {
            tolerance: k.tolerance,
            max_iterations: k.max_iterations,
            ..Default::default()
        };
        let mut start_record = StartRecord::LinearGuess;
        let (branch, mode) = match &self.at_hz {
            Some(list) => {
                let omegas: Vec<f64> = list.iter().map(|f| 2.0 * PI * f).collect();
                let start = problem.linear_solution(omegas[0])?;
                // A fold between two frequencies is passed along the
                // branch, with the case's steps.
                let settings = AtFrequenciesSettings {
                    bridge: Some(ArcLengthSettings {
                        start: omegas[0],
                        end: omegas[0],
                        initial_step: k.initial_step,
                        min_step: k.min_step,
                        max_step: k.max_step,
                        length_scale: length_scale(&case.casing()?, &start)?,
                        newton,
                        max_points: k.max_points,
                    }),
                    ..AtFrequenciesSettings::from(newton)
                };
                let branch = match AtFrequencies::new(&mut problem, start, &omegas, settings) {
                    Ok(mut run) => {
                        for observer in observers.iter_mut() {
                            run = run.with_observer(&mut **observer);
                        }
                        run.with_interrupt(self.interrupt.clone()).finish()
                    }
                    Err(error) => Branch::refused(omegas[0], &error),
                };
                (branch, RunMode::AtFrequencies)
            }
            None => {
                let (start_hz, end_hz) = frequency_range(&case)?;
                let start = 2.0 * PI * start_hz;
                let mut guess = problem.linear_solution(start)?;
                let settings = ArcLengthSettings {
                    start,
                    end: 2.0 * PI * end_hz,
                    initial_step: k.initial_step,
                    min_step: k.min_step,
                    max_step: k.max_step,
                    // The clearance the case gives: with a preload measured
                    // after it, the problem's gaps also hold the static
                    // growth, which says nothing of how far the tip swings.
                    length_scale: length_scale(&case.casing()?, &guess)?,
                    newton,
                    max_points: k.max_points,
                };
                // Newton from the linear response at the start, tried apart
                // so that the branch itself starts as it always did.
                let mut probe = guess.clone();
                crate::continuation::Problem::watch_interrupt(&mut problem, &self.interrupt);
                let reached =
                    correct_until(&mut problem, &mut probe, start, &newton, &self.interrupt);
                if !matches!(reached, Ok((true, _, _))) && !self.interrupt.raised() {
                    let first_attempt = match reached {
                        Ok((_, _, residual)) => format!(
                            "Newton from the linear response at {start_hz:.4} Hz: relative residual {residual:.2e}"
                        ),
                        Err(e) => e.to_string(),
                    };
                    tracing::info!(
                        "{first_attempt}: reaching the start by continuation in the load from no excitation"
                    );
                    if let Some((reached, points)) =
                        start_by_load_continuation(&mut problem, &settings)?
                    {
                        tracing::info!(
                            "start reached by continuation in the load ({points} points)"
                        );
                        guess = reached;
                        start_record = StartRecord::LoadContinuation {
                            first_attempt,
                            points,
                        };
                    } else if let Some((reached, points)) =
                        start_by_gap_continuation(&case, &model, &mut problem, &settings)?
                    {
                        tracing::info!(
                            "start reached by continuation in the gap ({points} points)"
                        );
                        guess = reached;
                        start_record = StartRecord::GapContinuation {
                            first_attempt,
                            points,
                        };
                    }
                }
                let guess_at_end = problem.linear_solution(settings.end)?;
                let tuned = Settings {
                    step: StepSettings {
                        piecewise_predictor: k.dlft_predictor,
                        ..StepSettings::default()
                    },
                    ..Settings::from(settings)
                };
                let branch = match BothEnds::new(&mut problem, guess, guess_at_end, tuned) {
                    Ok(mut run) => {
                        for observer in observers.iter_mut() {
                            run = run.with_observer(&mut **observer);
                        }
                        run.with_interrupt(self.interrupt.clone()).finish()
                    }
                    Err(error) => Branch::refused(start, &error),
                };
                (branch, RunMode::Continuation)
            }
        };
        let solve_s = clock.elapsed().as_secs_f64();
        let clock = Instant::now();
        let interrupted = matches!(branch.stop, StopReason::Interrupted { .. });
        let stability = match &self.stability {
            None => StabilityOutcome::NotAsked,
            Some(_) if interrupted || self.interrupt.raised() => StabilityOutcome::NotComputed {
                reason: "the run was interrupted".into(),
            },
            Some(_) if self.stability_refused.is_some() => StabilityOutcome::NotComputed {
                reason: self.stability_refused.clone().unwrap_or_default(),
            },
            Some(settings) => {
                let checked = Stability::new(&model, &problem, &case.contact_dofs(), settings)
                    .and_then(|check| {
                        let mut checked = check.branch_until(&branch.points, &self.interrupt)?;
                        locate_branch_markers(
                            &check,
                            &problem,
                            &branch.points,
                            &mut checked,
                            &case,
                        );
                        Ok(checked)
                    });
                match checked {
                    Ok(result) => StabilityOutcome::Computed(result),
                    Err(error) => {
                        tracing::warn!("stability not computed: {error}");
                        StabilityOutcome::NotComputed {
                            reason: error.to_string(),
                        }
                    }
                }
            }
        };
        Ok(Solution {
            case,
            model,
            problem,
            basis,
            branch,
            mode,
            start: start_record,
            setup_s: self.setup_s,
            solve_s,
            stability,
            stability_s: clock.elapsed().as_secs_f64(),
            interrupted: self.interrupt.raised(),
            case_dir,
        })
    }
}

impl Solution {
    /// The summaries of every point on every sector (observed dof, contact
    /// state; see [`BranchRecovery::point`]), computed on every core: `Err`
    /// for a point whose observed dof cannot be recovered; a contact part
    /// that cannot be recovered is that part's `Err`.
    pub fn point_summaries(&self) -> Vec<Result<PointSummary, crate::results::ResultsError>> {
        let dof = self.case.output.observed_index();
        let recovery =
            BranchRecovery::new(&self.problem, dof, self.case.harmonic_balance.time_samples);
        self.branch
            .points
            .par_iter()
            .map(|point| recovery.point(&point.unknowns, point.omega))
            .collect()
    }
}
