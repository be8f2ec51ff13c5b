//! The `cyclorub` command: `plan`, `modes`, `init`, `run`, `simulate`, `stability`, `plot`, `compare`, `study`, `reproduce`, `mesh`.

mod commands;

use clap::{Parser, Subcommand};
use std::process::ExitCode;

/// Nonlinear forced responses of bladed disks rubbing on their casing.
#[derive(Parser)]
#[command(name = "cyclorub", version, about)]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(Subcommand)]
enum Command {
    /// Show what each spectral basis keeps, before running anything.
    Plan(commands::plan::PlanArgs),
    /// Natural frequencies per nodal diameter of a case's model; with a
    /// case's [mistuning], the mistuned wheel's modes (localization,
    /// nodal-diameter content) after them.
    Modes(commands::modes::ModesArgs),
    /// Print a commented case file with every key and its default.
    Init(commands::init::InitArgs),
    /// Compute a nonlinear forced response curve.
    Run(commands::run::RunArgs),
    /// Integrate the full wheel in time (every sector, the case's
    /// excitation, casing and contact law), from rest or from a harmonic
    /// balance point: per-period envelope per sector, steady-state detection.
    Simulate(commands::simulate::SimulateArgs),
    /// The Floquet exponents of one point of a results folder, per
    /// symmetry class (Hill's method): which perturbations grow.
    Stability(commands::stability::StabilityArgs),
    /// Where the wheel goes at the branch points of a results folder: the
    /// bifurcated branches (sectors no longer alike), on the enlarged basis.
    ///
    /// A branch point switched at again replaces its earlier record and CSV
    /// (said in the output). Exit codes: 0 when every branch point asked
    /// for was switched at, or found to start no branch (a complex pair, σ
    /// and −σ together, no sign change: said per marker); 1 when a
    /// computation failed (the branches found are still written); 2 when
    /// the request cannot be met: no such marker, a marker that is not a
    /// branch point, a class out of range, a run without stability (and no
    /// --class), a run on the physical full wheel (a mistuned one among
    /// them).
    Branches(commands::branches::BranchesArgs),
    /// Any dof of any sector at any point of a results folder, over one
    /// period, recovered from the stored unknowns (CSV).
    Recover(commands::recover::RecoverArgs),
    /// Redraw the figures of a results folder (forced response, cyclic
    /// components, frequency versus nodal diameter).
    Plot(commands::plot::PlotArgs),
    /// Compare two results folders of the same case point by point
    /// (exit code 1 above the tolerance).
    Compare(commands::compare::CompareArgs),
    /// Solve every case file of a folder (a mistuning study: one pattern
    /// per file): one row each in study.csv, and the distribution of the
    /// amplification factors.
    ///
    /// Exit codes: 0 when every case finished (its whole range, or every
    /// frequency, solved with every point converged); 3 when a case did
    /// not (refused, failed, stopped before the end of its range, or a
    /// point did not converge): study.csv is still written, those rows say
    /// `finished = false`, and the last line counts them; 2 for a bad
    /// folder or option; 1 when study.csv cannot be written.
    Study(commands::study::StudyArgs),
    /// Reproduce the paper's academic studies: every case on the symmetry
    /// basis, the paper's basis and the full wheel, checked against each
    /// other, with a report (exit code 1 if a reduction is not exact).
    Reproduce(commands::reproduce::ReproduceArgs),
    /// Write model files: `mesh fan` writes an open fan-stage sector
    /// (matrices, node coordinates, node sets, a case file, a README).
    Mesh(commands::mesh::MeshArgs),
}

fn main() -> ExitCode {
    #[cfg(unix)]
    // SAFETY: restoring the default action of SIGPIPE before any thread is
    // started; Rust ignores it by default, which turns a closed pipe into a
    // panic on the next print.
    unsafe {
        libc::signal(libc::SIGPIPE, libc::SIG_DFL);
    }
    let cli = Cli::parse();
    // Log lines on stderr (progress when not on a terminal); RUST_LOG overrides.
    // The PNG rasterizer's warnings say nothing a user can act on (the one
    // seen, "path stroking failed" on strokes of zero length, no longer
    // arises: plot/svg_text.rs drops those strokes).
    tracing_subscriber::fmt()
        .with_writer(std::io::stderr)
        .with_ansi(false)
        .with_target(false)
        .with_env_filter(
            tracing_subscriber::EnvFilter::try_from_default_env()
                .unwrap_or_else(|_| tracing_subscriber::EnvFilter::new("info,tiny_skia=error")),
        )
        .init();
    let outcome = match cli.command {
        Command::Plan(args) => commands::plan::execute(args),
        Command::Modes(args) => commands::modes::execute(args),
        Command::Init(args) => commands::init::execute(args),
        Command::Run(args) => commands::run::execute(args),
        Command::Simulate(args) => commands::simulate::execute(args),
        Command::Stability(args) => commands::stability::execute(args),
        Command::Recover(args) => commands::recover::execute(args),
        Command::Branches(args) => commands::branches::execute(args),
        Command::Plot(args) => commands::plot::execute(args),
        Command::Compare(args) => commands::compare::execute(args),
        Command::Study(args) => commands::study::execute(args),
        Command::Reproduce(args) => commands::reproduce::execute(args),
        Command::Mesh(args) => commands::mesh::execute(args),
    };
    match outcome {
        Ok(()) => ExitCode::SUCCESS,
        Err(error) => {
            eprintln!("error: {}", error.message);
            ExitCode::from(error.exit_code)
        }
    }
}
