//! `cyclorub run [CASE.toml] [--output DIR] [--basis KIND] [--at-hz F1,F2,...]`

use super::{outln, CliError};
use cyclorub::case::{BasisChoice, Case, CaseError};
use cyclorub::continuation::{Interrupt, StopReason};
use cyclorub::forced_response::{ForcedResponse, StartRecord};
use cyclorub::results::output_folder::check_output_folder;
use cyclorub::run::{
    further_crossings, group_markers, run, RunError, RunOptions, RunStatus, StabilityRecord,
    StabilityStatus, OUTPUT_FILES,
};
use cyclorub::stability::StabilitySettings;
use indicatif::{ProgressBar, ProgressStyle};
use std::io::IsTerminal;
use std::path::{Path, PathBuf};
use std::time::{Duration, Instant};

/// Arguments of `cyclorub run`.
#[derive(clap::Args)]
pub struct RunArgs {
    /// Case file (TOML); without it, the paper's default case
    /// (academic model, N = 24, traveling wave h = 1 of 4 N, R-HBM).
    case: Option<PathBuf>,
    /// Results folder (default: `[output] directory` of the case).
    #[arg(long)]
    output: Option<PathBuf>,
    /// Basis: symmetry, paper, nodal_diameter, full or physical (overrides the case).
    #[arg(long)]
    basis: Option<String>,
    /// Solve at exactly these frequencies (Hz, comma-separated) instead of
    /// continuing in arc length.
    #[arg(long, value_delimiter = ',')]
    at_hz: Option<Vec<f64>>,
    /// Skip the stability check of every point (Hill's method per
    /// symmetry class), which runs unless `[stability] enabled = false`.
    #[arg(long)]
    no_stability: bool,
    /// Harmonics of Hill's truncation for the stability check (overrides
    /// `[stability] harmonics`; default: harmonic_balance.harmonics).
    #[arg(long)]
    stability_harmonics: Option<usize>,
    /// Then switch at every branch-point marker (class σ ≠ 0) of the branch: the
    /// bifurcated branches on their enlarged bases, in `RESULTS/branches/`
    /// (as `cyclorub branches RESULTS` does; needs stability on and a
    /// cyclic basis: refused before the run otherwise).
    #[arg(long, conflicts_with = "no_stability")]
    branches: bool,
    /// Replace the results of an earlier run in the results folder (a
    /// folder that holds one is refused otherwise): its files, its
    /// `branches/` and its `recovered_*.csv` are removed first.
    #[arg(long)]
    overwrite: bool,
}

/// Runs `cyclorub run`.
pub fn execute(args: RunArgs) -> Result<(), CliError> {
    let (case, case_dir) = match &args.case {
        Some(path) => (
            Case::from_file_checked(path).map_err(|e| CliError::usage(e.to_string()))?,
            path.parent()
                .map_or_else(|| PathBuf::from("."), Path::to_path_buf),
        ),
        None => (Case::default(), PathBuf::from(".")),
    };
    let basis = match &args.basis {
        Some(name) => {
            BasisChoice::parse(name).map_err(|e| CliError::usage(format!("--basis: {e}")))?
        }
        None => case.basis.kind,
    };
    if args.stability_harmonics == Some(0) {
        return Err(CliError::usage(
            "--stability-harmonics 0: give an integer ≥ 1 (Hill's truncation)",
        ));
    }
    if let Some(list) = &args.at_hz {
        if list.is_empty() {
            return Err(CliError::usage("--at-hz: give at least one frequency (Hz)"));
        }
    }
    refuse_a_mistuned_reduced_basis(&case, args.case.as_deref(), args.basis.is_some(), basis)?;
    let options = RunOptions {
        output: args
            .output
            .clone()
            .unwrap_or_else(|| case.output.directory.clone()),
        basis,
        at_hz: args.at_hz.clone(),
        stability: if args.no_stability {
            None
        } else {
            case.stability.settings().map(|settings| StabilitySettings {
                harmonics: args.stability_harmonics.or(settings.harmonics),
                ..settings
            })
        },
        overwrite: args.overwrite,
        interrupt: stop_on_signals(),
    };
    // --branches switches at Hill's branch-point markers of a symmetric
    // branch: refused before the solve when the run can have none.
    if args.branches {
        if options.stability.is_none() {
            return Err(CliError::usage(
                "--branches: the case has [stability] enabled = false, so the run finds no \
                 branch point (Hill's markers locate them); set enabled = true, or run without \
                 --branches and then `cyclorub branches RESULTS --class σ` (the crossings of \
                 one class, found without stability)",
            ));
        }
        if basis == BasisChoice::Physical {
            return Err(CliError::usage(format!(
                "--branches: the run is on the physical full wheel (basis physical{}), which \
                 has no symmetry to break: no bifurcated branch starts from it; solve a tuned \
                 case on a cyclic basis (symmetry) to switch at its branch points",
                if case.mistuning.is_set() {
                    ", as a mistuned wheel needs"
                } else {
                    ""
                }
            )));
        }
    }
    // Worded as simulate's and plot's (the library checks it again, with
    // the other run's results, before the solve).
    check_output_folder(&options.output, "output.directory or --output")?;
    // A spinner on a terminal; plain log lines otherwise (bars are hidden off a terminal).
    let terminal = std::io::stderr().is_terminal();
    let bar = if terminal {
        let bar = ProgressBar::new_spinner();
        bar.set_style(
            ProgressStyle::with_template("{spinner} {elapsed_precise} {msg}")
                .unwrap_or_else(|_| ProgressStyle::default_spinner()),
        );
        bar.enable_steady_tick(Duration::from_millis(120));
        Some(bar)
    } else {
        None
    };
    eprintln!(
        "cyclorub run: {} basis, results in {}",
        basis.name(),
        options.output.display()
    );
    let mut last_log = Instant::now();
    let started = Instant::now();
    let outcome = run(&case, &case_dir, &options, |p| {
        let pace = pace(p.points, started.elapsed().as_secs_f64());
        let text = format!(
            "point {} at {:.4} Hz, step {:.2e}, {pace}",
            p.points, p.frequency_hz, p.step
        );
        if let Some(bar) = &bar {
            bar.set_message(text);
        } else if last_log.elapsed() > Duration::from_secs(2) || p.points == 1 {
            tracing::info!("{text}");
            last_log = Instant::now();
        }
    });
    if let Some(bar) = &bar {
        bar.finish_and_clear();
    }
    let record = outcome.map_err(|error| {
        name_the_harmonics(
            error,
            &case,
            &case_dir,
            &options,
            args.stability_harmonics.is_some(),
        )
    })?;
    let stop = record.stop.with_advice();
    outln!(
        "{} points ({} not converged), {} Newton iterations; {}",
        record.points,
        record.failed_points,
        record.total_iterations,
        stop
    );
    match &record.start {
        StartRecord::LoadContinuation { points, .. } => {
            outln!("start reached by continuation in the load from no excitation ({points} points)")
        }
        StartRecord::GapContinuation { points, .. } => outln!(
            "start reached by continuation in the gap from a casing out of reach ({points} gaps)"
        ),
        StartRecord::LinearGuess => {}
    }
    if let Some(sweeps) = &record.sweeps {
        outln!("followed from both ends: {}", sweeps.summary());
    }
    outln!(
        "basis {}: {} unknowns of {} ({:.1} % reduction), {} sampled sectors",
        record.basis.kind,
        record.basis.unknowns,
        record.basis.full_unknowns,
        record.basis.reduction_percent,
        record.basis.sampled_sectors
    );
    print_stability(&record.stability)?;
    // Stable or not: a truncation too coarse can call a branch stable.
    if let Some(settings) = &options.stability {
        if record.stability.points_by_hill > 0 {
            super::run_sizes::print_size_estimate(&record.output, &case_dir, settings)?;
        }
    }
    if let Some(m) = &record.mistuning {
        print_mistuning(m)?;
    }
    outln!(
        "time: set-up {:.3} s, solve {:.3} s, stability {:.3} s (alongside the solve, point by point), output {:.3} s",
        record.timings.setup_s,
        record.timings.solve_s,
        record.stability.time_s,
        record.timings.output_s
    );
    // The files this run wrote (observed_harmonics.csv only on demand).
    let files: Vec<String> = OUTPUT_FILES
        .iter()
        .filter(|name| record.output.join(name).exists())
        .map(|name| format!("{}/{name}", record.output.display()))
        .collect();
    outln!("wrote {}", files.join(", "));
    for warning in &record.warnings {
        outln!("warning: {warning}");
        tracing::warn!("{warning}");
    }
    if args.branches && record.status != RunStatus::Interrupted {
        super::branches::execute(super::branches::BranchesArgs::every_marker(
            record.output.clone(),
            case_dir.clone(),
        ))?;
    }
    if record.status == RunStatus::Interrupted {
        Err(CliError::failure(format!(
            "the run was interrupted ({stop}); every computed point is in {}",
            record.output.display()
        )))
    } else if record.finished() {
        Ok(())
    } else {
        Err(CliError::failure(format!(
            "{}; every computed point is in {}",
            incomplete(&record.stop, record.failed_points),
            record.output.display()
        )))
    }
}

/// Why a run that was not interrupted is not complete, in one clause: it
/// stopped before the end of its range, or some points did not converge,
/// or both (the exit code is 1 either way: the curve asked for is not
/// whole).
fn incomplete(stop: &StopReason, failed_points: usize) -> String {
    let ended = matches!(
        stop,
        StopReason::EndReached | StopReason::AllFrequenciesDone
    );
    let failed = match failed_points {
        0 => String::new(),
        1 => "1 point did not converge".to_string(),
        n => format!("{n} points did not converge"),
    };
    let stopped = match stop {
        StopReason::PointCap { max_points } => format!(
            "the run stopped at its cap of {max_points} points before the end of its range \
             (raise continuation.max_points to go further)"
        ),
        _ => format!(
            "the run stopped before the end of its range: {}",
            stop.with_advice()
        ),
    };
    match (ended, failed.is_empty()) {
        (true, _) => failed,
        (false, true) => stopped,
        (false, false) => format!("{stopped}, and {failed}"),
    }
}

/// Refuses a mistuned case on a cyclic basis before any work, as an input
/// error located like the case file's others (`basis` came from `--basis`
/// when `from_option`, else from the case file `path`).
fn refuse_a_mistuned_reduced_basis(
    case: &Case,
    path: Option<&Path>,
    from_option: bool,
    basis: BasisChoice,
) -> Result<(), CliError> {
    if !case.mistuning.is_set() || basis == BasisChoice::Physical {
        return Ok(());
    }
    let allowed = "cannot hold a mistuned wheel ([mistuning]): its sectors are no longer \
                   alike, so the cyclic classes (nodal diameters) do not decouple and no \
                   reduced basis is exact; solve it on the full wheel: basis.kind = \
                   \"physical\" (or cyclorub run --basis physical)";
    if from_option {
        return Err(CliError::usage(format!(
            "--basis {}: {allowed}",
            basis.name()
        )));
    }
    let error = CaseError::Invalid {
        key: "basis.kind".into(),
        value: format!("\"{}\"", basis.name()),
        allowed: allowed.into(),
    };
    let error = match path.and_then(|p| Some((p, std::fs::read_to_string(p).ok()?))) {
        Some((path, text)) => error.located(path, &text),
        None => error,
    };
    Err(CliError::usage(error.to_string()))
}

/// Words the refusal of the stability check for memory (the library names
/// `stability.enabled`) after the harmonics that size it, when they were
/// given (`--stability-harmonics` when `from_option`, else the case's
/// `stability.harmonics`), with the most that fit; any other error as it
/// is.
fn name_the_harmonics(
    error: RunError,
    case: &Case,
    case_dir: &Path,
    options: &RunOptions,
    from_option: bool,
) -> CliError {
    let given = options.stability.as_ref().and_then(|s| s.harmonics);
    let (RunError::Case(CaseError::Invalid { key, allowed, .. }), Some(harmonics)) =
        (&error, given)
    else {
        return error.into();
    };
    if key != "stability.enabled" {
        return error.into();
    }
    let name = match from_option {
        true => format!("--stability-harmonics {harmonics}"),
        false => format!("stability.harmonics = {harmonics}"),
    };
    let most = match most_stability_harmonics(case, case_dir, options, harmonics) {
        Some(0) => "not even 1 harmonic fits here".to_string(),
        Some(h) => format!("at most {h} harmonics fit here"),
        None => "the most that fit could not be found".to_string(),
    };
    CliError::usage(format!(
        "{name}: Hill's truncation is too large for this machine: {allowed}; {most}"
    ))
}

/// The most harmonics of Hill's truncation whose stability check fits in
/// memory beside the run (bisection on the library's own check, which
/// grows with them), 0 when not even one does, below `refused` (which
/// does not fit); `None` when the problem cannot be built.
fn most_stability_harmonics(
    case: &Case,
    case_dir: &Path,
    options: &RunOptions,
    refused: usize,
) -> Option<usize> {
    let settings = options.stability.as_ref()?;
    let mut request = ForcedResponse::from_case(case)
        .ok()?
        .basis(options.basis)
        .case_dir(case_dir);
    if let Some(list) = &options.at_hz {
        request = request.at_frequencies_hz(list.clone());
    }
    let solver = request.build().ok()?;
    let fits = |harmonics: usize| {
        let settings = StabilitySettings {
            harmonics: Some(harmonics),
            ..*settings
        };
        solver.check_stability_memory(&settings, true).is_ok()
    };
    if !fits(1) {
        return Some(0);
    }
    // fits(low) and not fits(high) throughout.
    let (mut low, mut high) = (1, refused);
    while high - low > 1 {
        let middle = low + (high - low) / 2;
        if fits(middle) {
            low = middle;
        } else {
            high = middle;
        }
    }
    Some(low)
}

/// A mistuned run's line: the amplification factor, or why there is none;
/// the most responding sector when a sector moves toward the casing.
fn print_mistuning(m: &cyclorub::run::mistuning::MistuningRecord) -> Result<(), CliError> {
    let sector = m.most_responding_sector;
    let peak = sector
        .checked_sub(1)
        .and_then(|i| m.sector_peaks_m.get(i))
        .copied()
        .filter(|p| p.is_finite() && *p > 0.0);
    let most = match peak {
        Some(peak) => format!("most responding sector {sector}, {peak:.4e} m"),
        None => "no sector moves toward the casing at a converged point".to_string(),
    };
    match (m.amplification_factor, m.tuned_peak_m) {
        (Some(factor), Some(tuned)) => outln!(
            "mistuned wheel: amplification factor {factor:.4} (largest sector peak over the \
             tuned peak {tuned:.4e} m); {most}"
        ),
        _ => outln!(
            "mistuned wheel: {most}; no amplification factor: {}",
            m.no_factor_reason
                .as_deref()
                .unwrap_or(m.tuned_reference.as_str())
        ),
    }
    Ok(())
}

/// An interrupt raised by the first Ctrl-C or SIGTERM: the run stops after
/// its current point and writes everything it has; a second one exits at
/// once (exit code 130).
fn stop_on_signals() -> Interrupt {
    let interrupt = Interrupt::new();
    let raised = interrupt.clone();
    let handler = ctrlc::set_handler(move || {
        if raised.raised() {
            eprintln!("cyclorub run: stopped at once");
            std::process::exit(130);
        }
        eprintln!(
            "cyclorub run: stopping after the current point, the results keep every point (Ctrl-C again to stop at once)"
        );
        raised.raise();
    });
    if let Err(error) = handler {
        tracing::warn!("Ctrl-C will stop the run at once, without writing its results: {error}");
    }
    interrupt
}

/// The stability check's lines: how many points are unstable, and the
/// markers where stability changes.
fn print_stability(stability: &StabilityRecord) -> Result<(), CliError> {
    match stability.status {
        StabilityStatus::Computed => {
            outln!(
                "stability (Hill, H = {}): {} unstable points, {} solved by Hill's method (the others off contact)",
                stability.harmonics.unwrap_or(0),
                stability.unstable_points,
                stability.points_by_hill
            );
            let groups = group_markers(&stability.markers);
            const SHOWN: usize = 12;
            for group in groups.iter().take(SHOWN) {
                let (first, m) = (group.first(), &group.first().marker);
                let diameters = group.nodal_diameters();
                let class = match diameters.len() {
                    0 => String::new(),
                    1 => format!(" nodal diameter {}", diameters[0]),
                    _ => format!(
                        " nodal diameters {}",
                        diameters
                            .iter()
                            .map(i64::to_string)
                            .collect::<Vec<_>>()
                            .join(", ")
                    ),
                };
                let exponent = group
                    .exponent()
                    .map(|e| format!(", exponent {:.3} {:+.3}i", e.re, e.im))
                    .unwrap_or_default();
                outln!(
                    "  {:?}{class} at {:.4} Hz, amplitude {:.4e} m{exponent}, stability {}",
                    m.kind,
                    m.frequency_hz,
                    first.amplitude_m,
                    match (m.loses_stability, m.class_changes) {
                        (true, true) => "lost",
                        (false, true) => "regained",
                        (true, false) => "lost by one more exponent (the class was unstable)",
                        (false, false) => "still lost (one growing exponent fewer)",
                    }
                );
            }
            if groups.len() > SHOWN {
                outln!(
                    "  … {} more markers in run.json (stability.markers)",
                    groups[SHOWN..]
                        .iter()
                        .map(|g| g.records.len())
                        .sum::<usize>()
                );
            }
            let further = further_crossings(&stability.markers);
            if further > 0 {
                outln!(
                    "  and {further} Neimark–Sacker crossings of further exponents in classes already unstable (run.json, class_changes = false)"
                );
            }
        }
        StabilityStatus::NotComputed => outln!(
            "stability not computed: {}",
            stability.reason.as_deref().unwrap_or("")
        ),
        StabilityStatus::NotAsked => {}
    }
    Ok(())
}

/// The run's pace for its progress line: points a second, or seconds a
/// point when slower than one a second (a mistuned fan read "0 points/s").
fn pace(points: usize, elapsed_s: f64) -> String {
    let rate = points as f64 / elapsed_s.max(1e-9);
    if rate >= 1.0 {
        format!("{rate:.0} points/s")
    } else if points == 0 {
        "no point yet".to_string()
    } else {
        format!("{:.1} s a point", 1.0 / rate)
    }
}

#[cfg(test)]
mod pace_tests {
    use super::pace;

    #[test]
    fn a_slow_run_says_seconds_a_point_and_a_fast_one_points_a_second() {
        assert_eq!(pace(300, 2.0), "150 points/s");
        assert_eq!(pace(10, 25.0), "2.5 s a point");
        assert_eq!(pace(0, 3.0), "no point yet");
    }
}

#[cfg(test)]
mod incomplete_tests {
    use super::incomplete;
    use cyclorub::continuation::StopReason;

    #[test]
    fn an_incomplete_run_says_which_way_it_is_incomplete() {
        let cap = StopReason::PointCap { max_points: 10 };
        let said = incomplete(&cap, 0);
        assert!(said.contains("cap of 10 points"), "{said}");
        assert!(said.contains("continuation.max_points"), "{said}");
        assert!(!said.contains("converge"), "{said}");
        let said = incomplete(&StopReason::EndReached, 3);
        assert_eq!(said, "3 points did not converge");
        let underflow = StopReason::StepUnderflow {
            frequency_hz: 127.5,
            step: 1e-7,
        };
        let said = incomplete(&underflow, 1);
        assert!(said.contains("127.5000 Hz"), "{said}");
        assert!(said.contains("continuation.min_step"), "{said}");
        assert!(said.ends_with("and 1 point did not converge"), "{said}");
    }
}
