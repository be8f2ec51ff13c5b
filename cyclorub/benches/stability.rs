//! Benchmark: the stability check (Hill's method per symmetry class) of the
//! default case (academic N = 24, traveling wave h = 1 of 4 N, R-HBM,
//! `N_h = 10`, `N_t = 10000`): every class of one contact point, and the
//! whole branch with and without the check. Run with
//! `cargo bench -p cyclorub --bench stability`.

use cyclorub::case::{BasisChoice, Case};
use cyclorub::forced_response::ForcedResponse;
use cyclorub::stability::{ContactStiffness, StabilitySettings};
use std::time::Instant;

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let case = Case::default();
    let clock = Instant::now();
    let solution = ForcedResponse::from_case(&case)?
        .basis(BasisChoice::Symmetry)
        .build()?
        .run(&mut [])?;
    let solve = clock.elapsed().as_secs_f64();
    let points = &solution.branch.points;
    let time_samples = solution.problem.time_samples();
    let stiffest = points
        .iter()
        .enumerate()
        .map(|(i, p)| {
            let d = ContactStiffness::sample(&solution.problem, &p.unknowns, p.omega, time_samples);
            (i, d.map(|d| d.peak()).unwrap_or(0.0))
        })
        .max_by(|a, b| a.1.total_cmp(&b.1))
        .map(|(i, _)| i)
        .unwrap_or(0);
    let check = solution.stability_check(&StabilitySettings::default())?;
    let point = &points[stiffest];
    let repeats = 10;
    let clock = Instant::now();
    for _ in 0..repeats {
        check.point(&point.unknowns, point.omega)?;
    }
    let one = clock.elapsed().as_secs_f64() / repeats as f64;
    println!(
        "stability, default case: {} classes, one contact point (all classes) {:.1} ms",
        check.classes().len(),
        1e3 * one
    );
    let clock = Instant::now();
    let branch = check.branch(points)?;
    let all = clock.elapsed().as_secs_f64();
    println!(
        "branch of {} points: solve {:.3} s, stability {:.3} s ({} points by Hill, {} off contact), ratio {:.2}",
        points.len(),
        solve,
        all,
        branch.solved_by_hill,
        points.len() - branch.solved_by_hill,
        (solve + all) / solve
    );
    Ok(())
}
