//! Benchmark: whole forced response curves with the paper's parameters
//! (`N_h = 10`, `N_t = 10000`), academic model N = 24, traveling wave h = 1
//! of 4 N, R-HBM: the symmetry (traveling-wave) basis and the physical full
//! model, through the library's front door, then the recovery of every
//! point on every sector (what the result files are made of). Run with
//! `cargo bench -p cyclorub --bench forced_response`.

use cyclorub::case::{BasisChoice, Case};
use cyclorub::forced_response::ForcedResponse;
use std::time::Instant;

fn curve(case: &Case, basis: BasisChoice) -> Result<(), Box<dyn std::error::Error>> {
    let solution = ForcedResponse::from_case(case)?
        .basis(basis)
        .build()?
        .run(&mut [])?;
    let clock = Instant::now();
    let recovered = solution.point_summaries().len();
    let recovery = clock.elapsed().as_secs_f64();
    let branch = &solution.branch;
    println!(
        "{:<9} unknowns {:>4}  set-up {:>7.3} s  curve {:>8.3} s  recovery {:>7.3} s  points {:>4}  Newton iterations {:>5}  {:>8.3} ms/iteration  stop {:?}",
        basis.name(),
        solution.basis.unknowns,
        solution.setup_s,
        solution.solve_s,
        recovery,
        recovered,
        branch.total_iterations,
        1e3 * solution.solve_s / branch.total_iterations.max(1) as f64,
        branch.stop
    );
    Ok(())
}

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let case = Case::default();
    println!("forced response, N = 24, traveling wave h = 1, 4 N, N_h = 10, N_t = 10000, R-HBM");
    curve(&case, BasisChoice::Symmetry)?;
    curve(&case, BasisChoice::Physical)?;
    Ok(())
}
