//! The results folders `cyclorub simulate` reads: the point it starts
//! from (`--from`), and the harmonic balance branch it compares with
//! (`--reference`), each refused when it is not a run of the same case.

use super::CliError;
use cyclorub::case::Case;
use cyclorub::forced_response::{branch_solutions_at, prepare, Prepared};
use cyclorub::results::folder::ResultsFolder;
use cyclorub::results::recovery::BranchRecovery;
use cyclorub::simulate::start::from_harmonic_balance;
use cyclorub::simulate::{State, WheelSetup};
use cyclorub_app::compare::same_case;
use std::f64::consts::PI;
use std::path::Path;

/// The value of `values` nearest `target`.
pub(super) fn nearest(values: &[f64], target: f64) -> f64 {
    values
        .iter()
        .copied()
        .min_by(|a, b| (a - target).abs().total_cmp(&(b - target).abs()))
        .unwrap_or(f64::NAN)
}

/// The branch of the results folder `folder` as `(frequency, amplitude)`,
/// the amplitude the largest over its reported sectors, converged points
/// only; refused when the folder is not a run of `case` (the physics: the
/// basis, the continuation and the output files may differ) or reports
/// another dof.
pub(super) fn reference_branch(case: &Case, folder: &Path) -> Result<Vec<(f64, f64)>, CliError> {
    let flag = format!("--reference {}", folder.display());
    let results =
        ResultsFolder::read(folder).map_err(|e| CliError::usage(format!("{flag}: {e}")))?;
    let ours = serde_json::to_value(case)
        .map_err(|e| CliError::usage(format!("{flag}: the case: {e}")))?;
    let theirs = results.run.get("case").cloned().unwrap_or_default();
    same_case(&ours, &theirs).map_err(|why| CliError::usage(format!("{flag}: {why}")))?;
    let dof = theirs
        .pointer("/output/observed_dof")
        .and_then(|d| d.as_u64());
    if dof != Some(case.output.observed_dof as u64) {
        return Err(CliError::usage(format!(
            "{flag}: its branch reports dof {dof:?}, the simulation observes dof {}",
            case.output.observed_dof
        )));
    }
    let branch: Vec<(f64, f64)> = results
        .branch
        .rows
        .iter()
        .filter(|r| r.converged)
        .map(|r| {
            let largest = r
                .amplitudes
                .iter()
                .copied()
                .fold(f64::NEG_INFINITY, f64::max);
            (r.frequency_hz, largest)
        })
        .collect();
    if branch.len() < 2 {
        return Err(CliError::usage(format!(
            "{flag}: its branch has {} converged points; a curve needs 2",
            branch.len()
        )));
    }
    Ok(branch)
}

/// A harmonic balance point to start from.
pub(super) struct FromPoint {
    /// Its state rebuilt on every dof at phase 0.
    pub(super) state: State,
    /// Its angular frequency, rad/s.
    pub(super) omega: f64,
    /// Its unknowns.
    pub(super) unknowns: Vec<f64>,
    /// The problem it solves.
    pub(super) prepared: Prepared,
}

/// Point `point` of the results folder `folder`, rebuilt on every dof.
pub(super) fn start_from_results(
    case: &Case,
    case_dir: &Path,
    folder: &Path,
    point: usize,
    setup: &WheelSetup,
) -> Result<FromPoint, CliError> {
    let flag = format!("--from {}", folder.display());
    let (data, prepared) = results_problem(case, case_dir, folder, &flag)?;
    let Some(chosen) = data.points.get(point) else {
        return Err(CliError::usage(format!(
            "--point {point}: {} has points 0..={}",
            folder.display(),
            data.points.len().saturating_sub(1)
        )));
    };
    let omega = 2.0 * PI * chosen.frequency_hz;
    let state = from_harmonic_balance(
        &prepared.problem,
        &chosen.unknowns,
        omega,
        &setup.wheel,
        setup.loads.contact_count(),
    )
    .map_err(|e| {
        CliError::usage(format!(
            "--from {}: {e} (was it run with this case?)",
            folder.display()
        ))
    })?;
    Ok(FromPoint {
        state,
        omega,
        unknowns: chosen.unknowns.clone(),
        prepared,
    })
}

/// `results.h5` of the results folder `folder` (named `flag` in messages)
/// and the problem its branch was solved on (its basis, this case),
/// refused when the folder is not a run of `case`.
fn results_problem(
    case: &Case,
    case_dir: &Path,
    folder: &Path,
    flag: &str,
) -> Result<(cyclorub::results::data::ResultsData, Prepared), CliError> {
    let file = folder.join(cyclorub::results::hdf5::FILE_NAME);
    if !file.is_file() {
        return Err(CliError::usage(format!(
            "{flag}: no {} there; give a results folder written by `cyclorub run`",
            cyclorub::results::hdf5::FILE_NAME
        )));
    }
    let data = cyclorub::results::hdf5::read(&file)
        .map_err(|e| CliError::usage(format!("{flag}: {e}")))?;
    let ours = serde_json::to_value(case)
        .map_err(|e| CliError::usage(format!("{flag}: the case: {e}")))?;
    let theirs: serde_json::Value = serde_json::from_str(&data.case_json)
        .map_err(|e| CliError::usage(format!("{flag}: results.h5's case: {e}")))?;
    same_case(&ours, &theirs).map_err(|why| CliError::usage(format!("{flag}: {why}")))?;
    let basis = data
        .basis_choice()
        .map_err(|e| CliError::usage(format!("{flag}: {e}")))?;
    let prepared = prepare(case, case_dir, basis)?;
    Ok((data, prepared))
}

/// The largest amplitude over the sectors of the observed dof on each
/// sheet of the branch of `folder` at `omega` (each solved there by Newton
/// from the branch's points around it), m.
pub(super) fn reference_amplitudes_at(
    case: &Case,
    case_dir: &Path,
    folder: &Path,
    omega: f64,
) -> Result<Vec<f64>, CliError> {
    let flag = format!("--reference {}", folder.display());
    let (data, mut prepared) = results_problem(case, case_dir, folder, &flag)?;
    let points: Vec<(f64, &[f64])> = data
        .points
        .iter()
        .filter(|p| p.converged)
        .map(|p| (2.0 * PI * p.frequency_hz, p.unknowns.as_slice()))
        .collect();
    let solutions = branch_solutions_at(&mut prepared, &points, omega)?;
    let recovery = BranchRecovery::new(
        &prepared.problem,
        case.output.observed_index(),
        case.harmonic_balance.time_samples,
    );
    solutions
        .iter()
        .map(|x| {
            let summary = recovery
                .point(x, omega)
                .map_err(|e| CliError::usage(format!("{flag}: {e}")))?;
            Ok(summary
                .observed
                .peak
                .iter()
                .copied()
                .fold(f64::NEG_INFINITY, f64::max))
        })
        .collect()
}
