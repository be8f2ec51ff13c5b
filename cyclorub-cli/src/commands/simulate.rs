//! `cyclorub simulate [CASE.toml] --at-hz F [--periods P] [--from RESULTS
//! --point P] [--perturb AMPLITUDE[:SECTOR|:ND=d|:EXPONENT=σ]] [--sweep START..END
//! --rate HZ_PER_S [--reference RESULTS]] [--plot-sectors J,..] [--output
//! DIR [--overwrite]]`: time integration of the full wheel.

use super::simulate_sources::{
    nearest, reference_amplitudes_at, reference_branch, start_from_results, FromPoint,
};
use super::CliError;
use cyclorub::case::Case;
use cyclorub::results::data::observed_name;
use cyclorub::results::output_folder::check_run_folder;
use cyclorub::simulate::output::{default_plotted_sectors, write, SimulationRecord};
use cyclorub::simulate::{
    Attractor, Drive, Perturbation, PerturbationPattern, Simulation, SimulationSettings, State,
    WheelSetup,
};
use cyclorub::stability::{FloquetMode, Stability, StabilityError, StabilitySettings};
use std::f64::consts::PI;
use std::path::{Path, PathBuf};

/// Arguments of `cyclorub simulate`.
#[derive(clap::Args)]
pub struct SimulateArgs {
    /// Case file (TOML); without it, the paper's default case.
    case: Option<PathBuf>,
    /// Excitation frequency, Hz (default with --from: the point's).
    #[arg(long)]
    at_hz: Option<f64>,
    /// Excitation periods to integrate at most, at a fixed frequency
    /// [default: 200]; refused with --sweep, which runs from START to END.
    #[arg(long)]
    periods: Option<usize>,
    /// Time steps per excitation period (at the highest frequency of a sweep).
    #[arg(long, default_value_t = 256)]
    steps_per_period: usize,
    /// Integrate the implicit scheme without its dispersion correction
    /// (at a fixed frequency the scheme's response at the excitation
    /// frequency is made exact by scaling mass and damping; see
    /// docs/time-integration.md).
    #[arg(long)]
    no_dispersion_correction: bool,
    /// Stop when the state repeats a period apart to this relative
    /// distance, 3 periods in a row; 0: never stop early.
    #[arg(long, default_value_t = 1e-6)]
    steady_tolerance: f64,
    /// Start from a point of this results folder (written by `cyclorub run`
    /// of the same case), rebuilt on every dof.
    #[arg(long, requires = "point")]
    from: Option<PathBuf>,
    /// The point of --from (index along the branch, as in branch.csv).
    #[arg(long, requires = "from")]
    point: Option<usize>,
    /// Perturb the initial state: AMPLITUDE (m) on every sector,
    /// AMPLITUDE:SECTOR on one sector, AMPLITUDE:ND=d in nodal diameter d
    /// (static deflections under contact-dof forces), or
    /// AMPLITUDE:EXPONENT=σ along the Floquet mode of the leading exponent
    /// of symmetry class σ at the --from point (Hill's eigenvector with
    /// the case's [stability] harmonics, displacement and velocity): it
    /// grows or decays at that exponent's rate alone. AMPLITUDE (> 0) is
    /// the largest contact displacement added; above 10 casing gaps it is
    /// warned about.
    #[arg(long)]
    perturb: Option<String>,
    /// Sweep the excitation frequency from START to END Hz (`START..END`,
    /// down when END < START) with continuous phase.
    #[arg(long, requires = "rate", conflicts_with_all = ["at_hz", "from"])]
    sweep: Option<String>,
    /// Sweep rate, Hz/s (> 0), at most the one that lasts 10 periods of
    /// END: |END − START| × END / 10.
    #[arg(long, requires = "sweep")]
    rate: Option<f64>,
    /// The branch of this results folder (`cyclorub run` of the same case;
    /// its largest amplitude over the reported sectors): drawn dashed over
    /// a sweep's envelope; at a fixed frequency, its amplitude there (on
    /// each sheet) is compared with what the wheel settled to.
    #[arg(long)]
    reference: Option<PathBuf>,
    /// Periods at the end whose every step goes to simulation.h5 and the
    /// time-history, spectrum and waterfall figures.
    #[arg(long, default_value_t = 5)]
    history_periods: usize,
    /// Sectors (1-based, comma-separated) of the time-history and spectrum
    /// figures; default: sector 1 and those of the largest and smallest
    /// maximum over the last period.
    #[arg(long, value_delimiter = ',')]
    plot_sectors: Vec<usize>,
    /// Output folder; one holding a run's results (`cyclorub run`'s
    /// run.json or branch.csv) is refused unless --overwrite.
    #[arg(long, default_value = "simulation")]
    output: PathBuf,
    /// Write into an output folder that holds a run's results (the
    /// simulation's files are added beside them; files of the same names
    /// are replaced).
    #[arg(long)]
    overwrite: bool,
}

/// The fewest periods of its end frequency a sweep may last: a shorter
/// one is a transient, neither a sweep's response nor a steady state.
const SWEEP_MIN_PERIODS: f64 = 10.0;

/// Gaps above which a --perturb amplitude is warned about.
const PERTURB_GAPS: f64 = 10.0;

/// Runs `cyclorub simulate`.
pub fn execute(args: SimulateArgs) -> Result<(), CliError> {
    let (case, case_dir, case_name) = match &args.case {
        Some(path) => (
            Case::from_file_checked(path).map_err(|e| CliError::usage(e.to_string()))?,
            path.parent()
                .map_or_else(|| PathBuf::from("."), Path::to_path_buf),
            path.display().to_string(),
        ),
        None => (Case::default(), PathBuf::from("."), "default case".into()),
    };
    // Before the integration, worded as run's and plot's; a run's results
    // are not written over unasked (the simulation's figures would mix
    // with the run's in plots/).
    check_run_folder(&args.output, "--output", args.overwrite, "--overwrite")?;
    // --rate without --sweep: clap excuses a missing required argument
    // that conflicts with one given (`is_missing_required_ok`), so
    // `requires = "sweep"` lets --rate through beside --at-hz or --from
    // (which --sweep conflicts with); the rate would be ignored silently.
    if let (Some(rate), None) = (args.rate, &args.sweep) {
        return Err(CliError::usage(format!(
            "--rate {rate}: a sweep rate needs --sweep START..END"
        )));
    }
    if let (Some(periods), Some(range)) = (args.periods, &args.sweep) {
        return Err(CliError::usage(format!(
            "--periods {periods} with --sweep {range}: a sweep lasts |END − START| / --rate, from START to END; leave --periods out"
        )));
    }
    let periods = args.periods.unwrap_or(200);
    if !(args.steady_tolerance.is_finite() && args.steady_tolerance >= 0.0) {
        return Err(CliError::usage(format!(
            "--steady-tolerance {}: give a finite number ≥ 0 (0: never stop early)",
            args.steady_tolerance
        )));
    }
    if periods == 0 {
        return Err(CliError::usage("--periods 0: give at least 1"));
    }
    let reference = match &args.reference {
        Some(folder) => reference_branch(&case, folder)?,
        None => Vec::new(),
    };
    let setup = WheelSetup::from_case(&case, &case_dir)?;
    let contacts = setup.loads.contact_count();
    let sectors = setup.model.sectors();
    if let Some(bad) = args
        .plot_sectors
        .iter()
        .find(|j| !(1..=sectors).contains(*j))
    {
        return Err(CliError::usage(format!(
            "--plot-sectors: sector {bad} does not exist: the wheel has sectors 1..={sectors}"
        )));
    }
    let positive_hz = |flag: &str, f: f64| {
        if f.is_finite() && f > 0.0 {
            Ok(f)
        } else {
            Err(CliError::usage(format!(
                "{flag} {f}: give a finite frequency > 0 Hz"
            )))
        }
    };
    // Checked before any work: the flags alone.
    let perturbation = args
        .perturb
        .as_deref()
        .map(|text| Perturbation::parse(text, sectors))
        .transpose()?;
    // An amplitude far above the casing's gap throws the wheel into the
    // casing: allowed (a deliberate kick), said.
    if let Some(p) = &perturbation {
        let gap = setup
            .loads
            .casing()
            .gaps
            .iter()
            .fold(f64::INFINITY, |m, g| m.min(*g));
        if gap.is_finite() && gap > 0.0 && p.amplitude > PERTURB_GAPS * gap {
            tracing::warn!(
                "--perturb {}: the amplitude {} m is {:.0} times the casing's smallest gap ({gap} m), above {PERTURB_GAPS} gaps: the wheel starts deep in the casing",
                args.perturb.as_deref().unwrap_or_default(),
                p.amplitude,
                p.amplitude / gap
            );
        }
    }
    if let (Some(p), None) = (&perturbation, &args.from) {
        if let PerturbationPattern::Exponent(_) = p.pattern {
            return Err(CliError::usage(format!(
                "--perturb {}: EXPONENT=σ perturbs along a Floquet mode of a harmonic balance point: give --from RESULTS --point P",
                args.perturb.as_deref().unwrap_or_default()
            )));
        }
    }
    // The start and the frequency.
    let mut point_of = None;
    let (mut start, start_text, frequency) = match (&args.from, args.point) {
        (Some(folder), Some(point)) => {
            let from = start_from_results(&case, &case_dir, folder, point, &setup)?;
            let hz = from.omega / (2.0 * PI);
            if let Some(f) = args.at_hz {
                if (f - hz).abs() > 1e-9 * hz {
                    return Err(CliError::usage(format!(
                        "--at-hz {f}: point {point} of {} is at {hz:.9} Hz; leave --at-hz out to use it",
                        folder.display()
                    )));
                }
            }
            let state = from.state.clone();
            point_of = Some(from);
            (
                state,
                format!("{} point {point}", folder.display()),
                Some(hz),
            )
        }
        _ => (
            State::at_rest(setup.wheel.size(), contacts),
            "rest".to_string(),
            args.at_hz.map(|f| positive_hz("--at-hz", f)).transpose()?,
        ),
    };
    if let Some(p) = perturbation {
        match (p.pattern, &point_of) {
            (PerturbationPattern::Exponent(sigma), Some(from)) => {
                let text = args.perturb.as_deref().unwrap_or_default();
                let mode = leading_mode(&case, from, sigma, text)?;
                let multiplier = mode.multiplier();
                tracing::info!(
                    "perturbed along the leading exponent of class {sigma}: λ = {:.6} {:+.6}i 1/s, |multiplier| {:.6} per period (Hill's truncation indicator {:.1e})",
                    mode.exponent.re,
                    mode.exponent.im,
                    multiplier.norm(),
                    mode.truncation
                );
                p.apply_mode(&mut start, &mode, 0.0, &setup.loads)?;
            }
            _ => p.apply(&mut start, &setup.wheel, &setup.loads)?,
        }
    }
    let (drive, stop_time, frequencies, rate) = match (&args.sweep, args.rate, frequency) {
        (Some(range), Some(rate), _) => {
            let (a, b) = range.split_once("..").ok_or_else(|| {
                CliError::usage(format!(
                    "--sweep {range}: give START..END in Hz, e.g. 120..135"
                ))
            })?;
            let parse = |t: &str| {
                t.trim().parse::<f64>().map_err(|_| {
                    CliError::usage(format!("--sweep {range}: {t:?} is not a frequency in Hz"))
                })
            };
            let (a, b) = (
                positive_hz("--sweep", parse(a)?)?,
                positive_hz("--sweep", parse(b)?)?,
            );
            if !(rate.is_finite() && rate > 0.0) || a == b {
                return Err(CliError::usage(format!(
                    "--sweep {range} --rate {rate}: give two different frequencies and a rate > 0 Hz/s"
                )));
            }
            // Shorter than a few periods of END, a sweep is a transient;
            // and the last step, past the stop time, would drive the wheel
            // far beyond END.
            let duration = (b - a).abs() / rate;
            if duration * b < SWEEP_MIN_PERIODS * (1.0 - 1e-9) {
                return Err(CliError::usage(format!(
                    "--rate {rate}: the sweep {range} would last {duration:.3e} s, {:.2} periods of its end frequency {b} Hz; give --rate ≤ {} Hz/s (|END − START| × END / {SWEEP_MIN_PERIODS}: at least {SWEEP_MIN_PERIODS} periods of END)",
                    duration * b,
                    rounded_down((b - a).abs() * b / SWEEP_MIN_PERIODS)
                )));
            }
            let signed = if b > a { rate } else { -rate };
            let drive = Drive::Sweep {
                start_omega: 2.0 * PI * a,
                rate: 2.0 * PI * signed,
            };
            (drive, Some((b - a) / signed), vec![a, b], Some(rate))
        }
        (_, _, Some(f)) => (
            Drive::Fixed {
                omega: 2.0 * PI * f,
            },
            None,
            vec![f],
            None,
        ),
        _ => return Err(CliError::usage(
            "give --at-hz F (Hz), --from RESULTS --point P, or --sweep START..END --rate HZ_PER_S",
        )),
    };
    let settings = SimulationSettings {
        steps_per_period: args.steps_per_period,
        periods,
        steady_tolerance: (args.steady_tolerance > 0.0).then_some(args.steady_tolerance),
        observed_dof: case.output.observed_dof - 1,
        history_periods: args.history_periods,
        dispersion_correction: !args.no_dispersion_correction,
        ..SimulationSettings::default()
    };
    let simulation = Simulation::new(
        setup.wheel.clone(),
        setup.loads.clone(),
        setup.law(),
        drive,
        settings,
        start,
        stop_time,
    )?;
    let dispersion = simulation.dispersion_ratio();
    let scheme = match dispersion {
        Some(ratio) => format!(
            "{}, dispersion-corrected at the excitation frequency (mass × {:.9}, damping × {:.9})",
            simulation.scheme(),
            ratio * ratio,
            ratio
        ),
        None => simulation.scheme().to_string(),
    };
    tracing::info!(
        "integrating the full wheel ({} sectors × {} dofs) from {start_text}: {scheme}, {} steps a period",
        setup.model.sectors(),
        setup.model.dofs_per_sector(),
        simulation.steps_per_period()
    );
    let steps_raised_from = simulation.steps_raised_from();
    let outcome_steps_per_period = simulation.steps_per_period();
    let report_every = (periods / 10).max(1);
    let outcome = simulation.run(|p| {
        if p.period % report_every == 0 {
            let largest = p.maxima.iter().fold(f64::NEG_INFINITY, |m, v| m.max(*v));
            let smallest = p.maxima.iter().fold(f64::INFINITY, |m, v| m.min(*v));
            tracing::info!(
                "period {} ({:.3} Hz): max over sectors {largest:.4e} m, min {smallest:.4e} m, state change {:.1e}",
                p.period,
                p.frequency_hz,
                p.poincare_distance
            );
        }
    })?;
    let attractor = Attractor::of(&outcome.periods, &outcome.ending);
    let fixed_hz = match drive {
        Drive::Fixed { omega } => Some(omega / (2.0 * PI)),
        Drive::Sweep { .. } => None,
    };
    let reference_amplitudes = match (fixed_hz, &args.reference) {
        (Some(f), Some(folder)) => reference_amplitudes_at(&case, &case_dir, folder, 2.0 * PI * f)?,
        _ => Vec::new(),
    };
    // At a fixed frequency the envelope is drawn against time: the
    // branch's nearest sheet as a level.
    let reference = match (fixed_hz, &attractor) {
        (Some(_), Some(found)) if !reference_amplitudes.is_empty() => {
            let nearest = nearest(&reference_amplitudes, found.largest());
            let end = outcome.periods.last().map_or(0.0, |p| p.end_time);
            vec![(0.0, nearest), (end, nearest)]
        }
        (Some(_), _) => Vec::new(),
        (None, _) => reference,
    };
    let (across, over) = outcome.modulation(10);
    let ending = outcome.ending.describe(settings.steady_tolerance);
    let record = SimulationRecord {
        case: case_name,
        mode: if rate.is_some() { "sweep" } else { "fixed" }.into(),
        frequency_hz: frequencies,
        rate_hz_per_s: rate,
        start: start_text,
        perturbation: args.perturb.clone(),
        scheme,
        dispersion_ratio: dispersion,
        step_s: outcome.step,
        steps_per_period: outcome_steps_per_period,
        steps_raised_from,
        attractor: attractor.clone(),
        reference_amplitudes_m: reference_amplitudes.clone(),
        periods: outcome.periods.len(),
        ending: ending.clone(),
        steady_tolerance: settings.steady_tolerance,
        modulation_across_sectors: across,
        modulation_over_periods: over,
        steps: outcome.steps,
        newton_iterations: outcome.newton_iterations,
        halvings: outcome.halvings,
        wall_seconds: outcome.wall_seconds,
        steps_per_second: outcome.steps_per_second(),
        observed_dof: case.output.observed_dof,
        observed_name: observed_name(
            &setup.model,
            case.output.observed_dof.saturating_sub(1),
            case.model.kind == cyclorub::model::ModelKind::Academic,
        ),
        plotted_sectors: if args.plot_sectors.is_empty() {
            default_plotted_sectors(&outcome)
        } else {
            args.plot_sectors.clone()
        },
        figures: case.output.figures.clone(),
    };
    let written = write(&args.output, &outcome, &record, &reference)?;
    println!("{ending}");
    if let Some(found) = &attractor {
        println!("{}", found.describe());
        if !reference_amplitudes.is_empty() {
            let largest = found.largest();
            let near = nearest(&reference_amplitudes, largest);
            println!(
                "harmonic balance at {:.4} Hz: {} mm ({}); the largest sector amplitude {:.5} mm is {:+.3} % of the nearest",
                fixed_hz.unwrap_or(0.0),
                reference_amplitudes
                    .iter()
                    .map(|a| format!("{:.5}", a * 1e3))
                    .collect::<Vec<_>>()
                    .join(", "),
                if reference_amplitudes.len() == 1 {
                    "one sheet".to_string()
                } else {
                    format!("{} sheets", reference_amplitudes.len())
                },
                largest * 1e3,
                100.0 * (largest - near) / near
            );
        }
    }
    // Over one period there is nothing to compare the period with.
    match over {
        Some(over) => println!(
            "modulation over the last {} periods: {across:.2e} across sectors, {over:.2e} over periods",
            outcome.periods.len().min(10)
        ),
        None => println!(
            "modulation over the last period: {across:.2e} across sectors, n/a over periods (one period integrated: give --periods 2 or more)"
        ),
    }
    println!(
        "{} periods, {} steps in {:.2} s ({:.0} steps/s), {} Newton iterations, {} halvings",
        outcome.periods.len(),
        outcome.steps,
        outcome.wall_seconds,
        outcome.steps_per_second(),
        outcome.newton_iterations,
        outcome.halvings
    );
    for path in written {
        println!("wrote {}", path.display());
    }
    Ok(())
}

/// `x > 0` to 6 significant digits, rounded down (a bound the user can
/// give back as it is printed).
fn rounded_down(x: f64) -> String {
    let shift = 5 - x.log10().floor() as i32;
    let up = x * (1.0 + 1e-12);
    let digits = if shift >= 0 {
        let scale = 10f64.powi(shift);
        (up * scale).floor() / scale
    } else {
        let scale = 10f64.powi(-shift);
        (up / scale).floor() * scale
    };
    if digits.is_finite() && digits > 0.0 {
        format!("{digits}")
    } else {
        format!("{x:e}")
    }
}

/// The Floquet mode of the leading exponent of class `sigma` at `from`,
/// with the case's Hill truncation; `text` is the --perturb value.
fn leading_mode(
    case: &Case,
    from: &FromPoint,
    sigma: i64,
    text: &str,
) -> Result<FloquetMode, CliError> {
    let settings = StabilitySettings {
        harmonics: case.stability.harmonics,
        ..StabilitySettings::default()
    };
    let flag = |e: StabilityError| match e {
        StabilityError::NoClass { .. } | StabilityError::TooLarge { .. } => {
            CliError::usage(format!("--perturb {text}: {e}"))
        }
        other => CliError::failure(format!("--perturb {text}: {other}")),
    };
    let check = Stability::new(
        &from.prepared.model,
        &from.prepared.problem,
        &case.contact_dofs(),
        &settings,
    )
    .map_err(flag)?;
    check
        .modes(&from.unknowns, from.omega, sigma, 1)
        .map_err(flag)?
        .pop()
        .ok_or_else(|| {
            CliError::failure(format!(
                "--perturb {text}: class {sigma} has no physical exponent at this truncation: raise [stability] harmonics"
            ))
        })
}
