//! `cyclorub recover RESULTS --dof D [--sector S]... [--point P | --at-hz F]
//! [--time-samples N] [--output FILE] [--case-dir DIR]`: the displacement
//! and velocity of any dof of any sector at any point of a results folder,
//! recovered from the unknowns `results.h5` stores (the same recovery a run
//! does for the observed dof), written as CSV over one period.
//!
//! A run stores what every point needs; what only some studies need (other
//! dofs, other sectors, other points' time histories) comes from here.

use super::results_folder::{open_point, OpenedPoint};
use super::{outln, CliError};
use cyclorub::results::peak::continuous_peak;
use cyclorub::results::recovery::{dof_histories, harmonic_amplitudes};
use std::f64::consts::PI;
use std::io::Write;
use std::path::PathBuf;

/// Harmonic amplitudes printed per sector.
const SHOWN_HARMONICS: usize = 3;

/// Arguments of `cyclorub recover`.
#[derive(clap::Args)]
pub struct RecoverArgs {
    /// Results folder written by `cyclorub run` (its run.json and results.h5).
    results: PathBuf,
    /// Sector dof, 1-based as `output.observed_dof` counts them.
    #[arg(long)]
    dof: usize,
    /// Sector, 1-based (repeat for several; default: every sector).
    #[arg(long = "sector")]
    sectors: Vec<usize>,
    /// Point (index along the branch, as in branch.csv) (default: the
    /// point of largest amplitude).
    #[arg(long, conflicts_with = "at_hz")]
    point: Option<usize>,
    /// Take the point nearest to this frequency (Hz).
    #[arg(long)]
    at_hz: Option<f64>,
    /// Instants over the period (default: the case's
    /// harmonic_balance.time_samples).
    #[arg(long)]
    time_samples: Option<usize>,
    /// CSV file to write (default: RESULTS/recovered_point<P>_dof<D>.csv).
    #[arg(long)]
    output: Option<PathBuf>,
    /// Folder the case's relative paths (matrix files) start from
    /// (default: the working directory).
    #[arg(long, default_value = ".")]
    case_dir: PathBuf,
}

/// Runs `cyclorub recover`.
pub fn execute(args: RecoverArgs) -> Result<(), CliError> {
    let folder = &args.results;
    let OpenedPoint {
        prepared,
        basis,
        data,
        index,
        choice,
    } = open_point(folder, args.point, args.at_hz, &args.case_dir)?;
    let point = &data.points[index];
    let layout = prepared.problem.layout();
    let dofs = prepared.model.dofs_per_sector();
    if args.dof == 0 || args.dof > dofs {
        return Err(CliError::usage(format!(
            "--dof {}: a sector has dofs 1..={dofs}",
            args.dof
        )));
    }
    if let Some(&bad) = args.sectors.iter().find(|&&s| s == 0 || s > layout.sectors) {
        return Err(CliError::usage(format!(
            "--sector {bad}: the wheel has sectors 1..={}",
            layout.sectors
        )));
    }
    let sectors: Vec<usize> = if args.sectors.is_empty() {
        (0..layout.sectors).collect()
    } else {
        args.sectors.iter().map(|s| s - 1).collect()
    };
    let time_samples = args
        .time_samples
        .unwrap_or_else(|| prepared.problem.time_samples());
    if time_samples > 10_000_000 {
        return Err(CliError::usage(format!(
            "--time-samples {time_samples}: give at most 10000000"
        )));
    }
    let omega = 2.0 * PI * point.frequency_hz;
    let histories = dof_histories(
        &prepared.problem,
        &point.unknowns,
        omega,
        args.dof - 1,
        &sectors,
        time_samples,
    )?;
    let path = args
        .output
        .clone()
        .unwrap_or_else(|| folder.join(format!("recovered_point{index}_dof{}.csv", args.dof)));
    write_csv(&path, &histories, omega, time_samples)?;
    let how = choice.text();
    outln!(
        "point {index} at {:.6} Hz{how}, dof {} on {} sectors ({} basis, N_h = {}):",
        point.frequency_hz,
        args.dof,
        sectors.len(),
        basis.name(),
        layout.harmonics()
    );
    for history in &histories {
        let amplitudes = harmonic_amplitudes(&history.coordinates);
        let shown: Vec<String> = amplitudes
            .iter()
            .skip(1)
            .take(SHOWN_HARMONICS)
            .map(|a| format!("{a:.4e}"))
            .collect();
        outln!(
            "  sector {:>3}: largest displacement {:.6e} m, mean {:.4e} m, harmonics 1..{} {} m",
            history.sector + 1,
            continuous_peak(&history.coordinates),
            amplitudes.first().copied().unwrap_or(0.0),
            shown.len(),
            shown.join(" ")
        );
    }
    outln!("wrote {}", path.display());
    Ok(())
}

/// `time_s` then the displacement (m) and velocity (m/s) of each sector.
fn write_csv(
    path: &std::path::Path,
    histories: &[cyclorub::results::recovery::DofHistory],
    omega: f64,
    time_samples: usize,
) -> Result<(), CliError> {
    let failed =
        |e: std::io::Error| CliError::failure(format!("cannot write {}: {e}", path.display()));
    let file = std::fs::File::create(path).map_err(failed)?;
    let mut out = std::io::BufWriter::new(file);
    let mut header = String::from("time_s");
    for h in histories {
        let s = h.sector + 1;
        header.push_str(&format!(",displacement_sector{s}_m,velocity_sector{s}_m_s"));
    }
    writeln!(out, "{header}").map_err(failed)?;
    let period = 2.0 * PI / omega;
    for n in 0..time_samples {
        let mut line = format!("{:e}", period * n as f64 / time_samples as f64);
        for h in histories {
            line.push_str(&format!(",{:e},{:e}", h.displacement[n], h.velocity[n]));
        }
        writeln!(out, "{line}").map_err(failed)?;
    }
    out.flush().map_err(failed)
}
