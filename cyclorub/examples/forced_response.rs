//! The forced response of the paper's default case (N = 24, traveling wave
//! h = 1, R-HBM) from Rust, in memory: `cargo run --release -p cyclorub
//! --example forced_response`. Prints the resonance of sector 1 and how the
//! branch stopped.

use cyclorub::case::{BasisChoice, Case};
use cyclorub::forced_response::ForcedResponse;

fn main() -> Result<(), Box<dyn std::error::Error>> {
    // A lighter case than the paper's (N_t = 10000) so that it runs in a
    // second in debug builds too.
    let mut case = Case::default();
    case.harmonic_balance.harmonics = 5;
    case.harmonic_balance.time_samples = 240;
    let solution = ForcedResponse::from_case(&case)?
        .basis(BasisChoice::Symmetry)
        .build()?
        .run(&mut [])?;
    let summaries = solution.point_summaries();
    let (peak_hz, peak_m) = solution
        .branch
        .points
        .iter()
        .zip(&summaries)
        .filter_map(|(point, summary)| {
            let amplitude = summary.as_ref().ok()?.observed.peak[0];
            Some((point.omega / (2.0 * std::f64::consts::PI), amplitude))
        })
        .fold((0.0, f64::NEG_INFINITY), |best, p| {
            if p.1 > best.1 {
                p
            } else {
                best
            }
        });
    println!(
        "{} points on the {} basis ({} unknowns); largest amplitude of sector 1: {:.4e} m at {:.3} Hz; {}",
        solution.branch.points.len(),
        solution.basis.kind,
        solution.basis.unknowns,
        peak_m,
        peak_hz,
        solution.branch.stop
    );
    Ok(())
}
