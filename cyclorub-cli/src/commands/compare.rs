//! `cyclorub compare A B [--tolerance T] [--frequency-tolerance R]`:
//! compares two results folders of the same case point by point at the
//! same frequencies. Exit code 0 within the tolerance, 1 above it, 2 on
//! bad input (unreadable folders, different cases, no common frequency).

use super::{outln, CliError};
use cyclorub_app::compare::{compare_folders, CompareOptions, Difference, Unmatched};
use std::path::PathBuf;

/// Arguments of `cyclorub compare`.
#[derive(clap::Args)]
pub struct CompareArgs {
    /// First results folder (e.g. a reduced basis).
    a: PathBuf,
    /// Second results folder (e.g. the physical full model).
    b: PathBuf,
    /// Largest relative difference accepted (amplitudes and displacements).
    #[arg(long, default_value = "1e-6")]
    tolerance: f64,
    /// Points match when their frequencies differ by at most this fraction.
    #[arg(long, default_value = "1e-9")]
    frequency_tolerance: f64,
    /// Fail (exit 1) when a point of either folder has no counterpart in
    /// the other, as a check that two runs agree everywhere needs; by
    /// default those points are listed and the matched ones compared.
    #[arg(long)]
    all_points: bool,
}

fn listing(list: &[Unmatched]) -> String {
    const SHOWN: usize = 8;
    let mut text: Vec<String> = list
        .iter()
        .take(SHOWN)
        .map(|u| format!("{} ({:.6} Hz, {})", u.point, u.frequency_hz, u.reason))
        .collect();
    if list.len() > SHOWN {
        text.push(format!("and {} more", list.len() - SHOWN));
    }
    text.join(", ")
}

fn describe(what: &str, difference: &Option<Difference>) -> String {
    match difference {
        Some(d) => format!(
            "largest relative difference of {what}: {:.3e} (sector {}, point {} of A / {} of B, {:.6} Hz)",
            d.value, d.sector, d.point_a, d.point_b, d.frequency_hz
        ),
        None => format!("largest relative difference of {what}: nothing to compare"),
    }
}

/// Runs `cyclorub compare`.
pub fn execute(args: CompareArgs) -> Result<(), CliError> {
    for (name, value) in [
        ("--tolerance", args.tolerance),
        ("--frequency-tolerance", args.frequency_tolerance),
    ] {
        if !(value.is_finite() && value >= 0.0) {
            return Err(CliError::usage(format!(
                "{name} {value}: give a finite number ≥ 0"
            )));
        }
    }
    let options = CompareOptions {
        frequency_tolerance: args.frequency_tolerance,
    };
    let comparison = compare_folders(&args.a, &args.b, &options)?;
    outln!(
        "A: {} ({} basis, {} points)",
        args.a.display(),
        comparison.bases.0,
        comparison.points.0
    );
    outln!(
        "B: {} ({} basis, {} points)",
        args.b.display(),
        comparison.bases.1,
        comparison.points.1
    );
    outln!(
        "{} points matched at the same frequency (relative tolerance {:.1e}), on {} common sectors",
        comparison.matched.len(),
        args.frequency_tolerance,
        comparison.sectors.len()
    );
    if !comparison.unmatched_a.is_empty() {
        outln!(
            "{} points of A not compared: {}",
            comparison.unmatched_a.len(),
            listing(&comparison.unmatched_a)
        );
    }
    if !comparison.unmatched_b.is_empty() {
        outln!(
            "{} points of B not compared: {}",
            comparison.unmatched_b.len(),
            listing(&comparison.unmatched_b)
        );
    }
    if comparison.matched.is_empty() || comparison.sectors.is_empty() {
        return Err(CliError::usage(
            "nothing to compare: no converged point of A has a point of B at the same frequency on a common sector \
             (arc-length runs place their points differently: run both with `cyclorub run --at-hz F1,F2,...`)",
        ));
    }
    outln!("{}", describe("observed amplitudes", &comparison.amplitude));
    outln!(
        "{}",
        describe("recovered displacements", &comparison.displacement)
    );
    let worst = comparison.worst();
    if worst.is_nan() || worst > args.tolerance {
        return Err(CliError::failure(format!(
            "the folders differ by {worst:.3e}, above the tolerance {:.1e}",
            args.tolerance
        )));
    }
    let unmatched = comparison.unmatched_a.len() + comparison.unmatched_b.len();
    if unmatched == 0 {
        outln!("within the tolerance {:.1e}", args.tolerance);
        return Ok(());
    }
    let partly = format!(
        "within the tolerance {:.1e} on the {} matched points only: {} of A and {} of B not compared",
        args.tolerance,
        comparison.matched.len(),
        comparison.unmatched_a.len(),
        comparison.unmatched_b.len()
    );
    if args.all_points {
        return Err(CliError::failure(format!("{partly} (--all-points)")));
    }
    outln!("{partly} (--all-points to fail on them)");
    Ok(())
}
