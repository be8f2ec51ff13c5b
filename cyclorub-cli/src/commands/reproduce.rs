//! `cyclorub reproduce [FOLDER] [--output DIR] [--quick] [--cases A,B] [--laws regularized,dlft]
//! [--stability | --no-stability]`

use super::{outln, CliError};
use cyclorub::case::LawKind;
use cyclorub_app::reproduce::{reproduce, ReproduceOptions, Step};
use std::path::PathBuf;
use std::time::{Duration, Instant};

/// Arguments of `cyclorub reproduce`.
#[derive(clap::Args)]
pub struct ReproduceArgs {
    /// Folder of case files (the paper's studies are in `examples/`).
    #[arg(default_value = "examples")]
    folder: PathBuf,
    /// Folder of the report (`report.md`, `report.json`, `figures/`) and of
    /// every run's results (`runs/CASE/LAW/BASIS/`).
    #[arg(long, default_value = "reproduction")]
    output: PathBuf,
    /// A few short cases (N = 24: traveling h = 1, standing h = 4, mixed
    /// h = 6 with casing h_c = 8) with N_h = 5 and a narrow frequency window.
    #[arg(long)]
    quick: bool,
    /// Only these cases (file names without `.toml`, comma-separated).
    #[arg(long, value_delimiter = ',')]
    cases: Vec<String>,
    /// Only these contact laws: regularized, dlft (comma-separated; default both).
    #[arg(long, value_delimiter = ',')]
    laws: Vec<String>,
    /// Check the stability of the symmetry-basis runs (Hill's method per
    /// symmetry class; the full wheel's too where its eigenproblem is
    /// small): the default in full mode, asked for with --quick (it
    /// multiplies the quick mode's time by about 4).
    #[arg(long, conflicts_with = "no_stability")]
    stability: bool,
    /// Skip the stability check.
    #[arg(long)]
    no_stability: bool,
}

fn law(name: &str) -> Result<LawKind, CliError> {
    LawKind::parse(name).map_err(|e| CliError::usage(format!("--laws: {e}")))
}

/// Runs `cyclorub reproduce`.
pub fn execute(args: ReproduceArgs) -> Result<(), CliError> {
    let options = ReproduceOptions {
        folder: args.folder,
        output: args.output,
        quick: args.quick,
        cases: args.cases,
        laws: args.laws.iter().map(|l| law(l)).collect::<Result<_, _>>()?,
        stability: if args.quick {
            args.stability
        } else {
            !args.no_stability
        },
    };
    eprintln!(
        "cyclorub reproduce: {} ({} mode), report in {}",
        options.folder.display(),
        if options.quick { "quick" } else { "full" },
        options.output.display()
    );
    let mut last_log = Instant::now();
    let mut run_clock = Instant::now();
    let report = reproduce(&options, |step| match step {
        Step::Run { case, law, basis } => {
            tracing::info!("{case}, {law:?}: {} basis", basis.name());
            run_clock = Instant::now();
        }
        Step::Mesh {
            case,
            folder,
            refine,
        } => {
            tracing::info!(
                "{case}: its model files are missing: wrote the open fan (cyclorub mesh fan \
                 --refine {refine}) in {} and read the case's model from there",
                folder.display()
            );
        }
        Step::Point(p) => {
            if last_log.elapsed() > Duration::from_secs(5) {
                tracing::info!(
                    "  point {} at {:.4} Hz, step {:.2e} ({:.0} s)",
                    p.points,
                    p.frequency_hz,
                    p.step,
                    run_clock.elapsed().as_secs_f64()
                );
                last_log = Instant::now();
            }
        }
        Step::Checking { case, law } => {
            tracing::info!("{case}, {law:?}: checking the reduced runs against the full wheel");
        }
    })?;
    let exact = report.studies.iter().filter(|s| s.exact()).count();
    outln!(
        "{exact} of {} studies exact, in {:.1} s; report: {}",
        report.studies.len(),
        report.wall_s,
        options.output.join("report.md").display()
    );
    for study in report.studies.iter().filter(|s| !s.exact()) {
        outln!("  not exact: {} with {:?}", study.case, study.law);
    }
    if report.exact() {
        Ok(())
    } else {
        Err(CliError::failure(format!(
            "some reductions did not reproduce the full wheel (or a run failed): see {}",
            options.output.join("report.md").display()
        )))
    }
}
