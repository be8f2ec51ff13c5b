//! Writing a solved run's results folder: branch.csv, results.h5,
//! run.json, the figures (docs/design.md §1: results are written once the
//! branch is solved, or streamed point by point by [`super::run_keeping`]).

use super::*;

/// The reported sectors (1-based): `[output] sectors`, or all `sectors`.
pub(super) fn reported_sectors(case: &Case, sectors: usize) -> Result<Vec<usize>, RunError> {
    let list: Vec<usize> = if case.output.sectors.is_empty() {
        (1..=sectors).collect()
    } else {
        case.output.sectors.clone()
    };
    if let Some(&bad) = list.iter().find(|&&s| s == 0 || s > sectors) {
        return Err(ResultsError::Input(format!(
            "output.sectors: sector {bad} does not exist: the wheel has sectors 1..={sectors}"
        ))
        .into());
    }
    Ok(list)
}

/// Writes a solved branch: `branch.csv`, `observed_harmonics.csv`,
/// `results.h5` (feature `hdf5`, see `results::hdf5`), the default figures
/// in `plots/` (feature `plot`) and, last, `run.json` ([`OUTPUT_FILES`]
/// lists them); returns the record and what `results.h5` holds (computed
/// with or without the feature). If `results.h5` or a figure fails,
/// `run.json` is still written and the error returned.
pub fn write(solution: &Solution, output: &Path) -> Result<(RunRecord, ResultsData), RunError> {
    let clock = Instant::now();
    let verdicts = solution.stability.computed().map(|b| {
        b.points
            .iter()
            .map(|p| Some((p.stable(), p.unstable_exponents())))
            .collect()
    });
    write_from(
        solution,
        output,
        solution.point_summaries(),
        verdicts,
        clock,
    )
}

/// [`write()`] from the points' summaries and stability verdicts (in the
/// branch's order; `verdicts` when stability was checked, `None` in it for
/// a point not checked); the output time counts from `clock`.
pub(super) fn write_from(
    solution: &Solution,
    output: &Path,
    summaries: Vec<Result<PointSummary, ResultsError>>,
    verdicts: Option<Vec<Option<(bool, usize)>>>,
    clock: Instant,
) -> Result<(RunRecord, ResultsData), RunError> {
    let (case, model, branch) = (&solution.case, &solution.model, &solution.branch);
    let sectors = reported_sectors(case, model.sectors())?;
    let mut files = BranchFiles::create(
        output,
        &sectors,
        solution.problem.layout().harmonics(),
        verdicts.is_some(),
        case.output.harmonics_csv,
    )?;
    let mut peaks = Vec::with_capacity(branch.points.len());
    // Every point is recovered once, on all sectors: the reported sectors'
    // rows are read from there, and so is `results.h5`.
    let mut kept = Vec::with_capacity(branch.points.len());
    let mut largest = 0.0_f64;
    for (index, (point, summary)) in branch.points.iter().zip(summaries).enumerate() {
        let summary = summary?;
        let observed = &summary.observed;
        largest =
            observed.max_abs.iter().fold(
                largest,
                |m, &x| if x.is_nan() { f64::NAN } else { m.max(x) },
            );
        let row = BranchRow {
            point: index,
            frequency_hz: point.omega / (2.0 * PI),
            amplitudes: sectors.iter().map(|s| observed.peak[s - 1]).collect(),
            iterations: point.iterations,
            residual_norm: point.residual_norm,
            converged: point.converged,
            stability: verdicts
                .as_ref()
                .and_then(|v| v.get(index).copied().flatten()),
        };
        peaks.push(row.amplitudes.iter().copied().fold(0.0, f64::max));
        let coordinates: Vec<&[f64]> = sectors
            .iter()
            .map(|s| observed.coordinates[s - 1].as_slice())
            .collect();
        files.write(&row, &sectors, &coordinates)?;
        kept.push(summary);
    }
    files.flush()?;
    tracing::debug!(
        "output: CSV files rewritten at {:.3} s",
        clock.elapsed().as_secs_f64()
    );
    let summaries = kept;
    let mistuning = mistuning::record(solution, &summaries)?;
    let extras =
        crate::forced_response::results_data_from(solution, summaries).and_then(|mut data| {
            data.mistuning = mistuning.as_ref().map(mistuning::MistuningRecord::data);
            tracing::debug!(
                "output: results data at {:.3} s",
                clock.elapsed().as_secs_f64()
            );
            write_optional_files(output, &data, case, mistuning.as_ref())?;
            tracing::debug!(
                "output: results.h5 and figures at {:.3} s",
                clock.elapsed().as_secs_f64()
            );
            Ok(data)
        });
    let interrupted = solution.interrupted || matches!(branch.stop, StopReason::Interrupted { .. });
    let stability = stability_record(solution, &peaks);
    let mut warnings = plausibility(case, largest);
    warnings.extend(coarse_hill(case, stability.harmonics));
    let mut record = RunRecord {
        status: RunStatus::Finished,
        case: case.clone(),
        basis: solution.basis.clone(),
        mode: solution.mode,
        start: solution.start.clone(),
        failed_points: branch.points.iter().filter(|p| !p.converged).count(),
        points: branch.points.len(),
        stop: branch.stop.clone(),
        sweeps: branch.sweeps.clone(),
        events: branch.events.clone(),
        total_iterations: branch.total_iterations,
        timings: Timings {
            setup_s: solution.setup_s,
            solve_s: solution.solve_s,
            output_s: clock.elapsed().as_secs_f64(),
        },
        stability,
        preload: PreloadRecord::of(case, &solution.model)?,
        output: output.to_path_buf(),
        warnings,
        mistuning,
    };
    record.status = if interrupted {
        RunStatus::Interrupted
    } else if record.finished() {
        RunStatus::Finished
    } else {
        RunStatus::StoppedEarly
    };
    write_json(output, "run.json", &record)?;
    Ok((record, extras?))
}

/// The stability part of `run.json`; `peaks` the largest reported
/// amplitude of every point.
pub(super) fn stability_record(solution: &Solution, peaks: &[f64]) -> StabilityRecord {
    let time_s = solution.stability_s;
    match &solution.stability {
        StabilityOutcome::NotAsked => StabilityRecord {
            status: StabilityStatus::NotAsked,
            reason: None,
            harmonics: None,
            points_by_hill: 0,
            unstable_points: 0,
            markers: Vec::new(),
            time_s,
        },
        StabilityOutcome::NotComputed { reason } => StabilityRecord {
            status: StabilityStatus::NotComputed,
            reason: Some(reason.clone()),
            harmonics: None,
            points_by_hill: 0,
            unstable_points: 0,
            markers: Vec::new(),
            time_s,
        },
        StabilityOutcome::Computed(branch) => StabilityRecord {
            status: StabilityStatus::Computed,
            reason: None,
            harmonics: Some(branch.harmonics),
            points_by_hill: branch.solved_by_hill,
            unstable_points: branch
                .points
                .iter()
                .zip(&solution.branch.points)
                .filter(|(stability, point)| point.converged && !stability.stable())
                .count(),
            markers: branch
                .markers
                .iter()
                .map(|m| {
                    let a = peaks.get(m.index).copied().unwrap_or(0.0);
                    let b = peaks.get(m.index + 1).copied().unwrap_or(a);
                    MarkerRecord {
                        marker: m.clone(),
                        amplitude_m: a + m.fraction * (b - a),
                    }
                })
                .collect(),
            time_s,
        },
    }
}

/// Writes `results.h5` (feature `hdf5`) and the default figures (feature
/// `plot`); nothing without the features.
pub(super) fn write_optional_files(
    output: &Path,
    data: &ResultsData,
    case: &Case,
    mistuning: Option<&mistuning::MistuningRecord>,
) -> Result<(), RunError> {
    #[cfg(feature = "hdf5")]
    hdf5::write_with(&output.join(hdf5::FILE_NAME), data, stored_contents(case))?;
    #[cfg(feature = "hdf5")]
    tracing::debug!("output: results.h5 written");
    #[cfg(feature = "plot")]
    write_figures(
        &output.join(FIGURES_FOLDER),
        data,
        &FigureOptions {
            png: case.output.png_figures(),
            ..FigureOptions::default()
        },
    )?;
    #[cfg(feature = "plot")]
    if let Some(m) = mistuning {
        crate::plot::mistuning::write_mistuning_figures(
            &output.join(FIGURES_FOLDER),
            data,
            &m.sector_peaks_m,
            m.tuned_peak_m,
            case.output.png_figures(),
        )?;
    }
    let _ = (output, data, case, mistuning);
    Ok(())
}

/// What `results.h5` keeps per point, from `[output]`.
#[cfg(feature = "hdf5")]
pub(super) fn stored_contents(case: &Case) -> hdf5::Contents {
    hdf5::Contents {
        contact_harmonics: case.output.contact_harmonics,
    }
}
