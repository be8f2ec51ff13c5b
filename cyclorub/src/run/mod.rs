//! The main job: a case file in, a forced response curve and its result
//! files out (case → model → basis → residual → continuation → results).

use crate::case::{BasisChoice, Case};
use crate::continuation::{
    Branch, Event, Interrupt, Point, Progress, ProgressFn, StopReason, Sweeps,
};
pub use crate::forced_response::{excited_frequency, prepare, Prepared};
use crate::forced_response::{ForcedResponse, Solution, StabilityOutcome, StartRecord};
use crate::hbm::{HarmonicBalance, HbmError};
use crate::model::SectorModel;
#[cfg(feature = "plot")]
use crate::plot::{write_figures, FigureOptions};
#[cfg(feature = "hdf5")]
use crate::results::data::LinearResponse;
use crate::results::data::ResultsData;
#[cfg(feature = "hdf5")]
use crate::results::hdf5;
use crate::results::recovery::PointSummary;
use crate::results::stream::{
    in_branch_order, BranchStream, StreamSettings, Streamed, StreamedCheck,
};
use crate::results::{write_json, BranchFiles, BranchRow, ResultsError};
use crate::stability::{Exponent, Marker, PointStability, StabilitySettings};
use serde::Serialize;
use std::f64::consts::PI;
use std::path::{Path, PathBuf};
use std::time::Instant;

/// Makes the results folder `output` before any work, so that a folder
/// that cannot be written (an empty name, a path under a regular file, no
/// permission) is said before the solve, not after it. A folder that holds
/// another run's results (its `run.json` or `branch.csv`) is refused, so
/// that two runs never mix in one folder, unless `overwrite`: then the
/// files a run writes ([`OUTPUT_FILES`]) and those later commands derive
/// from it (`branches/` of `cyclorub branches`, `recovered_*.csv` of
/// `cyclorub recover`) are removed first, and nothing else.
pub fn prepare_output_folder(output: &Path, overwrite: bool) -> Result<(), RunError> {
    let bad = |message: String| RunError::OutputFolder {
        path: output.to_path_buf(),
        message,
    };
    if output.as_os_str().is_empty() {
        return Err(bad("the name is empty; name a folder".into()));
    }
    if output.exists() && !output.is_dir() {
        return Err(bad("it is a file, not a folder".into()));
    }
    let holds_a_run = ["run.json", "branch.csv"]
        .iter()
        .any(|name| output.join(name).exists());
    if holds_a_run && !overwrite {
        return Err(bad(
            "it holds the results of another run; name another folder (--output), or replace them (--overwrite)"
                .into(),
        ));
    }
    if holds_a_run {
        // The derived outputs describe the earlier run: kept, they would be
        // read (and merged) as this one's.
        let recovered = std::fs::read_dir(output)
            .map_err(|e| bad(e.to_string()))?
            .filter_map(|entry| entry.ok())
            .map(|entry| entry.file_name().to_string_lossy().into_owned())
            .filter(|name| name.starts_with("recovered_") && name.ends_with(".csv"));
        let derived: Vec<String> = recovered.chain(["branches".to_string()]).collect();
        for name in OUTPUT_FILES.iter().map(|n| n.to_string()).chain(derived) {
            let path = output.join(name.trim_end_matches('/'));
            let removed = if path.is_dir() {
                std::fs::remove_dir_all(&path)
            } else if path.exists() {
                std::fs::remove_file(&path)
            } else {
                Ok(())
            };
            removed.map_err(|e| bad(format!("cannot remove {}: {e}", path.display())))?;
        }
    }
    std::fs::create_dir_all(output).map_err(|e| bad(e.to_string()))
}

impl RunError {
    /// Whether the error is in what the user gave (the case, its files, the
    /// command line), as opposed to a failure while computing or writing.
    pub fn is_input_error(&self) -> bool {
        use HbmError::*;
        match self {
            RunError::Model(e) => e.is_input_error(),
            RunError::Case(_)
            | RunError::BadFrequency(_)
            | RunError::NoFrequencies
            | RunError::NoNaturalFrequency { .. }
            | RunError::NothingMoves
            | RunError::OutputFolder { .. } => true,
            RunError::Hbm(e) => matches!(
                e,
                DofOutOfRange { .. }
                    | NoContactDofs
                    | RepeatedContactDof
                    | CasingLength { .. }
                    | InvalidFriction { .. }
                    | InvalidPreload { .. }
                    | TooFewTimeSamples { .. }
                    | TooLarge { .. }
                    | BasisMismatch { .. }
                    | BasisMissesPair { .. }
                    | Load(_)
                    | Basis(_)
            ),
            RunError::Results(_) => false,
            #[cfg(feature = "plot")]
            RunError::Plot(_) => false,
        }
    }
}

/// What to run, beyond the case file.
#[derive(Clone, Debug)]
pub struct RunOptions {
    /// Results folder.
    pub output: PathBuf,
    /// The basis (from the case, or overridden).
    pub basis: BasisChoice,
    /// Solve at exactly these frequencies (Hz) instead of continuing in arc length.
    pub at_hz: Option<Vec<f64>>,
    /// Check every point's stability (`None`: skip it).
    pub stability: Option<StabilitySettings>,
    /// Replace the results of an earlier run in the folder (otherwise
    /// refused, see [`prepare_output_folder`]).
    pub overwrite: bool,
    /// Raised from outside (Ctrl-C) to stop the branch before its next
    /// point; the files then hold every point found.
    pub interrupt: Interrupt,
}

pub mod mistuning;
mod record;
mod write;
#[cfg(feature = "hdf5")]
use crate::forced_response::data::json;
pub use crate::forced_response::{
    BasisRecord, HarmonicRecord, RunError, RunMode, RunStatus, StabilityStatus,
};
pub use record::*;
#[cfg(feature = "hdf5")]
use write::stored_contents;
pub use write::write;
use write::{reported_sectors, write_from};

/// The folder of the figures inside a results folder.
pub const FIGURES_FOLDER: &str = "plots";

/// What [`write()`] may put in a results folder, in the order it writes
/// them (a folder ends with `/`): `observed_harmonics.csv` only when the
/// case asks (`[output] harmonics_csv`), `results.h5` only with the
/// feature `hdf5`, the figures (`plots/`) only with the feature `plot`.
pub const OUTPUT_FILES: &[&str] = &[
    "branch.csv",
    "observed_harmonics.csv",
    #[cfg(feature = "hdf5")]
    "results.h5",
    #[cfg(feature = "plot")]
    "plots/",
    "run.json",
];

/// A finished run with everything it built: the record of `run.json`, the
/// model, the residual and the branch (with its unknowns), and what
/// `results.h5` holds. For callers that go on from a run (the
/// reproduction report compares runs point by point).
pub struct RunOutcome {
    /// What `run.json` holds.
    pub record: RunRecord,
    /// The model.
    pub model: SectorModel,
    /// The residual the branch was solved on.
    pub problem: HarmonicBalance,
    /// The branch.
    pub branch: Branch,
    /// What `results.h5` holds.
    pub data: ResultsData,
}

/// Runs a case: solves it (see [`ForcedResponse`]) and writes the results
/// (see [`write()`]); returns the record of `run.json`. `progress` sees every
/// point as it is computed.
pub fn run(
    case: &Case,
    case_dir: &Path,
    options: &RunOptions,
    progress: impl FnMut(&Progress),
) -> Result<RunRecord, RunError> {
    run_keeping(case, case_dir, options, progress).map(|outcome| outcome.record)
}

/// [`run`], keeping what the run built (see [`RunOutcome`]). Every point
/// is on disk (`branch.csv`, `observed_harmonics.csv`) as soon as it is
/// accepted ([`BranchStream`]), and `run.json` says `"status": "running"`
/// until the run ends; then the files are rewritten in the branch's order
/// with the stability columns, `results.h5` and the figures are written,
/// and `run.json` says how the run stopped.
pub fn run_keeping(
    case: &Case,
    case_dir: &Path,
    options: &RunOptions,
    mut progress: impl FnMut(&Progress),
) -> Result<RunOutcome, RunError> {
    let mut request = ForcedResponse::from_case(case)?
        .case_dir(case_dir)
        .basis(options.basis)
        .interrupt(options.interrupt.clone());
    if let Some(list) = &options.at_hz {
        request = request.at_frequencies_hz(list.clone());
    }
    // Stability is checked on the writer's thread as points come (see
    // `StreamedCheck`), not by the solver after the branch.
    let mut progress = ProgressFn(|_: &Point, p: &Progress| progress(p));
    let solver = request.build()?;
    // A mistuned wheel has one class, the whole wheel: checked unless too
    // large (docs/mistuning.md), and then the run says why.
    let refused = options
        .stability
        .as_ref()
        .and_then(|settings| solver.stability_refusal(settings));
    let stability = match options.stability {
        Some(_) if refused.is_some() => {
            tracing::info!("stability: {}", refused.as_deref().unwrap_or_default());
            None
        }
        other => other,
    };
    if let Some(settings) = &stability {
        solver.check_stability_memory(settings, true)?;
    }
    let output = &options.output;
    prepare_output_folder(output, options.overwrite)?;
    let sectors = reported_sectors(case, case.model.sectors)?;
    // The writer recovers points on its own copy of the problem while the
    // solver goes on: a clone of the one built (issue 41: built once).
    let copy = Prepared {
        case: solver.case().clone(),
        model: solver.model().clone(),
        problem: solver.problem().clone(),
        basis: solver.basis().clone(),
        case_dir: case_dir.to_path_buf(),
    };
    let mut streamed = vec!["branch.csv"];
    if case.output.harmonics_csv {
        streamed.push("observed_harmonics.csv");
    }
    #[cfg(feature = "hdf5")]
    streamed.push(hdf5::FILE_NAME);
    write_json(
        output,
        "run.json",
        &serde_json::json!({
            "status": RunStatus::Running,
            "case": case,
            "output": output,
            "streamed": streamed,
        }),
    )?;
    let settings = StreamSettings {
        sectors,
        observed_dof: case.output.observed_index(),
        time_samples: case.harmonic_balance.time_samples,
        stability: stability.map(|settings| StreamedCheck {
            model: copy.model.clone(),
            contact_dofs: copy.case.contact_dofs(),
            settings,
            interrupt: options.interrupt.clone(),
        }),
        harmonics_csv: case.output.harmonics_csv,
        #[cfg(feature = "hdf5")]
        results_file: Some((
            ResultsData {
                case_json: json(&copy.case),
                basis_json: json(&copy.basis),
                mode: if options.at_hz.is_some() {
                    RunMode::AtFrequencies
                } else {
                    RunMode::Continuation
                },
                stop_json: "null".into(),
                sectors: copy.model.sectors(),
                harmonics: copy.problem.layout().harmonics(),
                time_samples: case.harmonic_balance.time_samples,
                observed_dof: case.output.observed_dof,
                observed_name: crate::forced_response::data::observed_name_of(case, &copy.model),
                contact_dofs: case.contact.dofs.clone(),
                points: Vec::new(),
                linear: LinearResponse::default(),
                natural_frequencies: Vec::new(),
                histories: None,
                gap_after: None,
                stability: None,
                mistuning: None,
                branches: Vec::new(),
            },
            stored_contents(case),
        )),
    };
    let mut stream = BranchStream::start(output, copy.problem, settings)?;
    let mut solution = match solver.run(&mut [&mut progress, &mut stream]) {
        Ok(solution) => solution,
        Err(error) => {
            drop(stream);
            let failed = serde_json::json!({
                "status": "failed",
                "error": error.to_string(),
                "case": case,
                "output": output,
            });
            write_json(output, "run.json", &failed)?;
            return Err(error);
        }
    };
    let clock = Instant::now();
    let streamed = match stream.finish() {
        Ok(streamed) => Some(streamed),
        Err(error) => {
            tracing::warn!("streaming the points failed ({error}): they are recovered again");
            None
        }
    };
    tracing::debug!(
        "output: the writer thread finished {:.3} s after the solve",
        clock.elapsed().as_secs_f64()
    );
    let (summaries, verdicts) =
        streamed_in_branch_order(streamed, &mut solution, stability.as_ref())?;
    if let Some(reason) = refused {
        solution.stability = StabilityOutcome::NotComputed { reason };
    }
    // The output's time starts when the writer's thread (recovering and
    // checking stability alongside the solve) has caught up.
    let clock = Instant::now();
    let summaries = match summaries {
        Some(list) => list.into_iter().map(Ok).collect(),
        None => solution.point_summaries(),
    };
    let (record, data) = write_from(&solution, output, summaries, verdicts, clock)?;
    let Solution {
        model,
        problem,
        branch,
        ..
    } = solution;
    Ok(RunOutcome {
        record,
        model,
        problem,
        branch,
        data,
    })
}

/// What the writer streamed, in the branch's order: the points' summaries
/// (`None`: recover them again) and, when stability was asked, every
/// point's verdict (`None` where it was not checked). The solution's
/// stability is set from the streamed check: computed when every point was
/// checked; else not computed, with why (a run interrupted keeps the
/// verdicts of the points checked before, in `branch.csv`). Without the
/// streamed verdicts (the writer failed) the check runs now, on the
/// solution.
type InBranchOrder = (
    Option<Vec<PointSummary>>,
    Option<Vec<Option<(bool, usize)>>>,
);

fn streamed_in_branch_order(
    streamed: Option<Streamed>,
    solution: &mut Solution,
    settings: Option<&StabilitySettings>,
) -> Result<InBranchOrder, RunError> {
    let Some(settings) = settings else {
        let summaries = streamed.and_then(|s| {
            let accepted = s.points.into_iter().map(|(w, summary, _)| (w, summary));
            in_branch_order(accepted.collect(), &solution.branch)
        });
        return Ok((summaries, None));
    };
    let ordered = streamed.and_then(|s| {
        let accepted = s
            .points
            .into_iter()
            .map(|(w, summary, stability)| (w, (summary, stability)));
        Some((
            in_branch_order(accepted.collect(), &solution.branch)?,
            s.stability,
        ))
    });
    let Some((points, Some(checked))) = ordered else {
        // Nothing streamed that fits the branch: check now.
        let clock = Instant::now();
        solution.stability = match solution
            .stability_check(settings)
            .and_then(|check| check.branch(&solution.branch.points))
            .and_then(|mut branch| {
                without_unconverged_markers(&mut branch, &solution.branch.points);
                solution.locate_markers(settings, &mut branch)?;
                Ok(branch)
            }) {
            Ok(branch) => StabilityOutcome::Computed(branch),
            Err(error) => StabilityOutcome::NotComputed {
                reason: error.to_string(),
            },
        };
        solution.stability_s = clock.elapsed().as_secs_f64();
        let verdicts = solution
            .stability
            .computed()
            .map(|b| verdicts(b.points.iter().map(Some), &solution.branch.points));
        return Ok((None, verdicts));
    };
    let (summaries, stabilities): (Vec<PointSummary>, Vec<Option<PointStability>>) =
        points.into_iter().unzip();
    let verdicts = verdicts(
        stabilities.iter().map(Option::as_ref),
        &solution.branch.points,
    );
    match checked {
        Err(reason) => {
            solution.stability = StabilityOutcome::NotComputed { reason };
            Ok((Some(summaries), None))
        }
        Ok(checked) => {
            solution.stability_s = checked.seconds;
            let complete: Option<Vec<PointStability>> = stabilities.into_iter().collect();
            solution.stability = match (complete, &checked.unchecked) {
                (Some(points), None) => {
                    // The markers located on the branch (they were placed
                    // by interpolation): the solve of a few points each.
                    let clock = Instant::now();
                    let mut branch = checked.branch(points);
                    without_unconverged_markers(&mut branch, &solution.branch.points);
                    if let Err(error) = solution.locate_markers(settings, &mut branch) {
                        tracing::warn!("stability: markers not located ({error})");
                    }
                    solution.stability_s += clock.elapsed().as_secs_f64();
                    StabilityOutcome::Computed(branch)
                }
                (_, reason) => StabilityOutcome::NotComputed {
                    reason: format!(
                        "{}: {} of {} points checked (their verdicts are in branch.csv)",
                        reason.as_deref().unwrap_or("some points were not checked"),
                        verdicts.iter().flatten().count(),
                        verdicts.len()
                    ),
                },
            };
            Ok((Some(summaries), Some(verdicts)))
        }
    }
}

/// Each point's verdict (stable, growing exponents); none where it was not
/// checked, nor where Newton left the point unconverged (no solution).
fn verdicts<'p>(
    stabilities: impl Iterator<Item = Option<&'p PointStability>>,
    points: &[crate::continuation::Point],
) -> Vec<Option<(bool, usize)>> {
    stabilities
        .zip(points)
        .map(|(stability, point)| {
            stability
                .filter(|_| point.converged)
                .map(|p| (p.stable(), p.unstable_exponents()))
        })
        .collect()
}

/// Drops the markers between a point and an unconverged one (a list of
/// frequencies where Newton failed somewhere): no crossing is read there.
fn without_unconverged_markers(
    branch: &mut crate::stability::BranchStability,
    points: &[crate::continuation::Point],
) {
    let converged = |i: usize| points.get(i).is_some_and(|p| p.converged);
    branch
        .markers
        .retain(|m| converged(m.index) && converged(m.index + 1));
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_hill_truncation_below_the_orbits_is_warned_of() {
        let case = Case::default(); // harmonic_balance.harmonics = 10
        assert_eq!(coarse_hill(&case, None), None);
        assert_eq!(coarse_hill(&case, Some(10)), None);
        assert_eq!(coarse_hill(&case, Some(20)), None);
        let warning = coarse_hill(&case, Some(1)).expect("coarser than the orbit");
        for words in [
            "stability.harmonics = 1",
            "harmonic_balance.harmonics = 10",
            "growth can be missed",
        ] {
            assert!(warning.contains(words), "{words}: {warning}");
        }
    }

    #[test]
    fn a_displacement_beyond_a_hundred_gaps_is_not_believed() {
        let case = Case::default(); // casing.gap = 1e-3 m
        assert!(plausibility(&case, 2e-3).is_empty());
        assert!(plausibility(&case, 0.099).is_empty());
        let warnings = plausibility(&case, 0.101);
        assert_eq!(warnings.len(), 1);
        assert!(warnings[0].contains("101 times the gap"), "{}", warnings[0]);
        assert_eq!(plausibility(&case, f64::NAN).len(), 1);
    }

    #[test]
    fn a_first_point_that_fails_says_what_to_try() {
        let message = StopReason::NewtonFailure {
            frequency_hz: 120.0,
            residual_norm: 2.8,
        }
        .with_advice();
        for part in [
            "Newton failed at 120.0000 Hz",
            "continuation.max_iterations",
            "continuation.start_hz",
            "casing.gap",
        ] {
            assert!(message.contains(part), "{message}");
        }
    }
}
