//! The main job: a case file in, a forced response curve and its result
//! files out (case → model → basis → residual → continuation → results).

use crate::basis::SpectralBasis;
use crate::case::{BasisChoice, Case, CaseError};
use crate::continuation::{
    continue_from_both_ends, solve_at_frequencies, ArcLengthSettings, Branch, NewtonSettings,
    Progress, StopReason, Sweeps,
};
use crate::hbm::{Formulation, HarmonicBalance, HbmError, ProblemSpec};
use crate::model::{ModelError, SectorModel};
use crate::plot::{write_figures, FigureOptions, PlotError};
use crate::results::data::{LinearResponse, PointHistories, PointResults, ResultsData};
use crate::results::recovery::{lagrangian_prediction, BranchRecovery, PointSummary, Prediction};
use crate::results::{hdf5, write_json, BranchFiles, BranchRow, ResultsError};
use rayon::prelude::*;
use serde::Serialize;
use std::f64::consts::PI;
use std::path::{Path, PathBuf};
use std::time::Instant;

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
    /// Drawing the figures.
    #[error(transparent)]
    Plot(#[from] PlotError),
    /// A frequency given on the command line is not usable.
    #[error("--at-hz {0}: frequencies must be finite and > 0 Hz")]
    BadFrequency(f64),
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
}

/// One harmonic's signed nodal diameters.
#[derive(Clone, Debug, Serialize)]
pub struct HarmonicRecord {
    /// Harmonic `k`.
    pub k: usize,
    /// Signed nodal diameters kept.
    pub signed_nodal_diameters: Vec<i64>,
}

/// The basis actually solved on.
#[derive(Clone, Debug, Serialize)]
pub struct BasisRecord {
    /// `symmetry`, `paper`, `nodal_diameter`, `full` or `physical`.
    pub kind: String,
    /// Real unknowns solved for.
    pub unknowns: usize,
    /// Sectors sampled by the AFT.
    pub sampled_sectors: usize,
    /// Real unknowns of the full model, `N n_c (2 N_h + 1)`.
    pub full_unknowns: usize,
    /// `100 (1 − unknowns / full_unknowns)`.
    pub reduction_percent: f64,
    /// Per harmonic (cyclic bases only).
    pub harmonics: Vec<HarmonicRecord>,
}

/// Wall-clock times, seconds.
#[derive(Clone, Debug, Serialize)]
pub struct Timings {
    /// Model, basis and residual set-up.
    pub setup_s: f64,
    /// Continuation.
    pub solve_s: f64,
    /// Recovery and files.
    pub output_s: f64,
}

/// What `run.json` holds.
#[derive(Clone, Debug, Serialize)]
pub struct RunRecord {
    /// The case as resolved (defaults filled, frequency range set).
    pub case: Case,
    /// The basis.
    pub basis: BasisRecord,
    /// `continuation` (arc length) or `at_frequencies`.
    pub mode: String,
    /// Why the branch stopped.
    pub stop: StopReason,
    /// When the sweep from the start stopped short of the end: how the
    /// branch was followed back from the end and joined (absent otherwise).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub sweeps: Option<Sweeps>,
    /// Points written.
    pub points: usize,
    /// Points that did not converge (fixed-frequency mode only).
    pub failed_points: usize,
    /// Newton iterations in total.
    pub total_iterations: usize,
    /// Times.
    pub timings: Timings,
    /// The results folder.
    pub output: PathBuf,
}

/// A prepared problem: everything built, nothing solved.
pub struct Prepared {
    /// The case, resolved.
    pub case: Case,
    /// The model.
    pub model: SectorModel,
    /// The residual.
    pub problem: HarmonicBalance,
    /// The basis record.
    pub basis: BasisRecord,
}

/// The first natural frequency (Hz) of the nodal diameter the loads excite.
pub(crate) fn excited_frequency(case: &Case, model: &SectorModel) -> Result<f64, RunError> {
    let n = model.sectors() as i64;
    let order = match case.excitation.kind {
        crate::case::ExcitationKind::None => case.casing.order as i64,
        _ => case.excitation.engine_order as i64,
    };
    let diameter = crate::cyclic::fold_nodal_diameter(order, n as usize).unsigned_abs() as usize;
    let frequencies = model.natural_frequencies()?;
    Ok(frequencies
        .iter()
        .find(|(d, _)| *d == diameter)
        .and_then(|(_, f)| f.first().copied())
        .unwrap_or(1.0))
}

/// Builds the model, basis and residual of `case` (its relative paths taken
/// from `case_dir`), and resolves the frequency range.
pub fn prepare(case: &Case, case_dir: &Path, basis: BasisChoice) -> Result<Prepared, RunError> {
    case.validate()?;
    let mut case = case.clone();
    case.basis.kind = basis;
    let model = case.model.build(case_dir)?;
    case.check_model(&model)?;
    if case.continuation.start_hz.is_none() || case.continuation.end_hz.is_none() {
        let f = excited_frequency(&case, &model)?;
        case.continuation.start_hz.get_or_insert(0.95 * f);
        case.continuation.end_hz.get_or_insert(1.10 * f);
    }
    let forcing = case.forcing();
    let casing = case.casing()?;
    let contact_dofs = case.contact_dofs();
    let spec = ProblemSpec {
        model: &model,
        contact_dofs: &contact_dofs,
        forcing: forcing.as_ref(),
        casing: &casing,
        contact: case.contact_model()?,
        harmonics: case.harmonic_balance.harmonics,
        time_samples: case.harmonic_balance.time_samples,
    };
    let load = spec.load_case();
    let harmonics = case.harmonic_balance.harmonics;
    let spectral = match basis {
        BasisChoice::Symmetry => Some(SpectralBasis::symmetry(&load, harmonics)),
        BasisChoice::Paper => Some(SpectralBasis::paper(&load, harmonics)),
        BasisChoice::NodalDiameter => Some(SpectralBasis::nodal_diameter(&load, harmonics)),
        BasisChoice::Full => Some(SpectralBasis::full(model.sectors(), harmonics)),
        BasisChoice::Physical => None,
    }
    .transpose()
    .map_err(HbmError::Basis)?;
    let formulation = match &spectral {
        Some(b) => Formulation::Cyclic(b.clone()),
        None => Formulation::Physical,
    };
    let problem = spec.build(&formulation)?;
    let full_unknowns = model.sectors() * contact_dofs.len() * (2 * harmonics + 1);
    let unknowns = problem.layout().unknowns;
    let record = BasisRecord {
        kind: basis.name().into(),
        unknowns,
        sampled_sectors: problem.layout().sampled_sectors,
        full_unknowns,
        reduction_percent: 100.0 * (1.0 - unknowns as f64 / full_unknowns as f64),
        harmonics: spectral
            .map(|b| {
                (0..=harmonics)
                    .map(|k| HarmonicRecord {
                        k,
                        signed_nodal_diameters: b.nodal_diameters(k).to_vec(),
                    })
                    .collect()
            })
            .unwrap_or_default(),
    };
    Ok(Prepared {
        case,
        model,
        problem,
        basis: record,
    })
}

/// The folder of the figures inside a results folder.
pub const FIGURES_FOLDER: &str = "plots";

/// The linear problem of a case on its symmetry basis: the cheapest exact
/// way to the linear response, whatever basis the branch was solved on.
fn linear_problem(case: &Case, model: &SectorModel) -> Result<HarmonicBalance, RunError> {
    let forcing = case.forcing();
    let casing = case.casing()?;
    let contact_dofs = case.contact_dofs();
    let spec = ProblemSpec {
        model,
        contact_dofs: &contact_dofs,
        forcing: forcing.as_ref(),
        casing: &casing,
        contact: case.contact_model()?,
        harmonics: case.harmonic_balance.harmonics,
        time_samples: case.harmonic_balance.time_samples,
    };
    let basis = SpectralBasis::symmetry(&spec.load_case(), case.harmonic_balance.harmonics)
        .map_err(HbmError::Basis)?;
    Ok(spec.build(&Formulation::Cyclic(basis))?)
}

/// The frequencies (Hz) of the linear curve: the branch's, 300 evenly
/// spaced over its range, and the natural frequencies inside it.
fn linear_frequencies(branch: &Branch, natural: &[(usize, Vec<f64>)]) -> Vec<f64> {
    let mut list: Vec<f64> = branch.points.iter().map(|p| p.omega / (2.0 * PI)).collect();
    let low = list.iter().cloned().fold(f64::INFINITY, f64::min);
    let high = list.iter().cloned().fold(f64::NEG_INFINITY, f64::max);
    if high > low {
        list.extend((0..=300).map(|i| low + (high - low) * i as f64 / 300.0));
        list.extend(
            natural
                .iter()
                .flat_map(|(_, f)| f.iter().cloned())
                .filter(|f| (low..=high).contains(f)),
        );
    }
    list
}

/// Everything `results.h5` holds for a solved branch of `case`: per point
/// the observed dof and the contact state on all sectors and the cyclic
/// components, the linear response, the natural frequencies and the time
/// histories of the point of largest amplitude.
pub fn results_data(
    case: &Case,
    model: &SectorModel,
    problem: &mut HarmonicBalance,
    branch: &Branch,
    basis: &BasisRecord,
    mode: &str,
) -> Result<ResultsData, RunError> {
    let summaries = point_summaries(case, problem, branch)?
        .into_iter()
        .collect::<Result<Vec<_>, _>>()?;
    results_data_from(case, model, problem, branch, basis, mode, summaries)
}

/// The summaries of every point of `branch` on every sector (see
/// [`BranchRecovery::point`]), computed on every core: `Err` for a point
/// whose observed dof cannot be recovered; a contact part that cannot be
/// recovered (its DLFT prediction included) is that part's `Err`.
fn point_summaries(
    case: &Case,
    problem: &mut HarmonicBalance,
    branch: &Branch,
) -> Result<Vec<Result<PointSummary, ResultsError>>, RunError> {
    let casing = case.casing()?;
    let dof = case.output.observed_dof.saturating_sub(1);
    let time_samples = case.harmonic_balance.time_samples;
    // The DLFT predictions need the problem mutably, one point at a time;
    // the rest reads it, on every core.
    let predictions: Vec<Result<Option<Prediction>, ResultsError>> = branch
        .points
        .iter()
        .map(|p| lagrangian_prediction(problem, &p.unknowns, p.omega))
        .collect();
    let recovery = BranchRecovery::new(problem, &casing, dof, time_samples);
    Ok(branch
        .points
        .par_iter()
        .zip(predictions.into_par_iter())
        .map(|(point, prediction)| {
            let (prediction, failed) = match prediction {
                Ok(p) => (p, None),
                Err(e) => (None, Some(e)),
            };
            let mut summary = recovery.point(&point.unknowns, point.omega, prediction.as_ref())?;
            if let Some(e) = failed {
                summary.contact = Err(e);
            }
            Ok(summary)
        })
        .collect())
}

/// [`results_data`] from the points' summaries (same order as the points).
fn results_data_from(
    case: &Case,
    model: &SectorModel,
    problem: &mut HarmonicBalance,
    branch: &Branch,
    basis: &BasisRecord,
    mode: &str,
    summaries: Vec<PointSummary>,
) -> Result<ResultsData, RunError> {
    let casing = case.casing()?;
    let dof = case.output.observed_dof.saturating_sub(1);
    let time_samples = case.harmonic_balance.time_samples;
    let points = branch
        .points
        .par_iter()
        .zip(summaries.into_par_iter())
        .map(|(point, summary)| {
            PointResults::from_summary(point, summary.observed, summary.contact?)
        })
        .collect::<Result<Vec<_>, _>>()?;
    let natural_frequencies = model.natural_frequencies()?;
    let mut linear_problem = linear_problem(case, model)?;
    let linear = LinearResponse::compute(
        &mut linear_problem,
        dof,
        &linear_frequencies(branch, &natural_frequencies),
        time_samples,
    )?;
    let mut data = ResultsData {
        case_json: json(case),
        basis_json: json(basis),
        mode: mode.to_string(),
        stop_json: json(&branch.stop),
        sectors: model.sectors(),
        harmonics: case.harmonic_balance.harmonics,
        time_samples,
        observed_dof: case.output.observed_dof,
        contact_dofs: case.contact.dofs.clone(),
        points,
        linear,
        natural_frequencies,
        histories: None,
        gap_after: branch
            .sweeps
            .as_ref()
            .and_then(crate::continuation::Sweeps::gap_after),
    };
    if let Some(peak) = data.peak_point() {
        data.histories = Some(PointHistories::compute(
            problem,
            &casing,
            &branch.points[peak],
            peak,
            dof,
            time_samples,
        )?);
    }
    Ok(data)
}

/// JSON text of a record (records always serialize; say so if one did not).
fn json(value: &impl Serialize) -> String {
    serde_json::to_string(value).unwrap_or_else(|e| format!("{{\"error\": \"{e}\"}}"))
}

/// `results.h5` and the default figures of a solved branch, from its
/// points' summaries; returns what `results.h5` holds.
#[allow(clippy::too_many_arguments)] // the run's parts, each needed
fn write_extras(
    case: &Case,
    model: &SectorModel,
    problem: &mut HarmonicBalance,
    branch: &Branch,
    basis: &BasisRecord,
    mode: &str,
    output: &Path,
    summaries: Vec<PointSummary>,
) -> Result<ResultsData, RunError> {
    let data = results_data_from(case, model, problem, branch, basis, mode, summaries)?;
    hdf5::write(&output.join(hdf5::FILE_NAME), &data)?;
    write_figures(
        &output.join(FIGURES_FOLDER),
        &data,
        &FigureOptions::default(),
    )?;
    Ok(data)
}

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

/// Runs a case: prepares it, continues (or solves at given frequencies),
/// writes `branch.csv`, `observed_harmonics.csv`, `results.h5` (see
/// [`crate::results::hdf5`]), the default figures in `plots/` and, last,
/// `run.json`, and returns the record. `progress` sees every point as it
/// is computed. If `results.h5` or a figure fails, `run.json` is still
/// written and the error returned.
pub fn run(
    case: &Case,
    case_dir: &Path,
    options: &RunOptions,
    progress: impl FnMut(&Progress),
) -> Result<RunRecord, RunError> {
    run_keeping(case, case_dir, options, progress).map(|outcome| outcome.record)
}

/// [`run`], keeping what the run built (see [`RunOutcome`]).
pub fn run_keeping(
    case: &Case,
    case_dir: &Path,
    options: &RunOptions,
    mut progress: impl FnMut(&Progress),
) -> Result<RunOutcome, RunError> {
    if let Some(list) = &options.at_hz {
        if let Some(&bad) = list.iter().find(|f| !(f.is_finite() && **f > 0.0)) {
            return Err(RunError::BadFrequency(bad));
        }
    }
    let clock = Instant::now();
    let Prepared {
        case,
        model,
        mut problem,
        basis,
    } = prepare(case, case_dir, options.basis)?;
    let setup_s = clock.elapsed().as_secs_f64();
    let clock = Instant::now();
    let k = &case.continuation;
    let newton = NewtonSettings {
        tolerance: k.tolerance,
        max_iterations: k.max_iterations,
    };
    let (branch, mode): (Branch, &str) = match &options.at_hz {
        Some(list) => {
            let omegas: Vec<f64> = list.iter().map(|f| 2.0 * PI * f).collect();
            let start = problem.linear_solution(omegas[0])?;
            let b = solve_at_frequencies(&mut problem, start, &omegas, &newton, |_, p| progress(p));
            (b, "at_frequencies")
        }
        None => {
            let start = 2.0 * PI * k.start_hz.unwrap_or(1.0);
            let settings = ArcLengthSettings {
                start,
                end: 2.0 * PI * k.end_hz.unwrap_or(1.0),
                initial_step: k.initial_step,
                min_step: k.min_step,
                max_step: k.max_step,
                length_scale: case.length_scale(),
                newton,
                max_points: k.max_points,
            };
            let guess = problem.linear_solution(start)?;
            let guess_at_end = problem.linear_solution(settings.end)?;
            let b =
                continue_from_both_ends(&mut problem, guess, guess_at_end, &settings, |_, p| {
                    progress(p)
                });
            (b, "continuation")
        }
    };
    let solve_s = clock.elapsed().as_secs_f64();
    let clock = Instant::now();
    let sectors: Vec<usize> = if case.output.sectors.is_empty() {
        (1..=model.sectors()).collect()
    } else {
        case.output.sectors.clone()
    };
    if let Some(&bad) = sectors.iter().find(|&&s| s == 0 || s > model.sectors()) {
        return Err(ResultsError::Input(format!(
            "output.sectors: sector {bad} does not exist: the wheel has sectors 1..={}",
            model.sectors()
        ))
        .into());
    }
    let mut files =
        BranchFiles::create(&options.output, &sectors, case.harmonic_balance.harmonics)?;
    // Every point is recovered once, on all sectors: the reported sectors'
    // rows are read from there, and so is `results.h5`.
    let mut summaries = Vec::with_capacity(branch.points.len());
    for (index, (point, summary)) in branch
        .points
        .iter()
        .zip(point_summaries(&case, &mut problem, &branch)?)
        .enumerate()
    {
        let summary = summary?;
        let observed = &summary.observed;
        let row = BranchRow {
            point: index,
            frequency_hz: point.omega / (2.0 * PI),
            amplitudes: sectors.iter().map(|s| observed.peak[s - 1]).collect(),
            iterations: point.iterations,
            residual_norm: point.residual_norm,
            converged: point.converged,
        };
        let coordinates: Vec<&[f64]> = sectors
            .iter()
            .map(|s| observed.coordinates[s - 1].as_slice())
            .collect();
        files.push(&row, &sectors, &coordinates)?;
        summaries.push(summary);
    }
    let extras = write_extras(
        &case,
        &model,
        &mut problem,
        &branch,
        &basis,
        mode,
        &options.output,
        summaries,
    );
    let output_s = clock.elapsed().as_secs_f64();
    let record = RunRecord {
        case,
        basis,
        mode: mode.into(),
        failed_points: branch.points.iter().filter(|p| !p.converged).count(),
        points: branch.points.len(),
        stop: branch.stop.clone(),
        sweeps: branch.sweeps.clone(),
        total_iterations: branch.total_iterations,
        timings: Timings {
            setup_s,
            solve_s,
            output_s,
        },
        output: options.output.clone(),
    };
    write_json(&options.output, "run.json", &record)?;
    let data = extras?;
    Ok(RunOutcome {
        record,
        model,
        problem,
        branch,
        data,
    })
}
