//! Benchmark: the stability check (Hill's method per symmetry class) of the
//! default case (academic N = 24, traveling wave h = 1 of 4 N, R-HBM,
//! `N_h = 10`, `N_t = 10000`): every class of one contact point, and the
//! whole branch with and without the check, by each solver (the dense
//! eigenproblem, the targeted one, the condensed one: the default). Run with
//! `cargo bench -p cyclorub --bench stability`.

use cyclorub::case::{BasisChoice, Case};
use cyclorub::forced_response::ForcedResponse;
use cyclorub::stability::{ContactStiffness, HillSolver, StabilitySettings};
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
    // The stiffest point, and the first contact point where the targeted
    // solver vouches for every class.
    let targeted = solution.stability_check(&StabilitySettings {
        solver: HillSolver::Targeted,
        ..StabilitySettings::default()
    })?;
    let vouched = points
        .iter()
        .position(|p| {
            targeted
                .point(&p.unknowns, p.omega)
                .is_ok_and(|s| s.off_contact_bound.is_none() && s.classes.iter().all(|c| !c.dense))
        })
        .unwrap_or(stiffest);
    for (what, point) in [
        ("stiffest", &points[stiffest]),
        ("first vouched", &points[vouched]),
    ] {
        println!(
            "{what} point, {:.3} Hz:",
            point.omega / (2.0 * std::f64::consts::PI)
        );
        for solver in [
            HillSolver::Dense,
            HillSolver::Targeted,
            HillSolver::Condensed,
        ] {
            let check = solution.stability_check(&StabilitySettings {
                solver,
                ..StabilitySettings::default()
            })?;
            let repeats = 10;
            let clock = Instant::now();
            let mut dense = 0;
            for _ in 0..repeats {
                let stability = check.point(&point.unknowns, point.omega)?;
                dense = stability.classes.iter().filter(|c| c.dense).count();
            }
            let one = clock.elapsed().as_secs_f64() / repeats as f64;
            println!(
            "stability ({solver:?}), default case: {} classes, one contact point (all classes) {:.1} ms, {dense} classes solved densely",
            check.classes().len(),
            1e3 * one
        );
        }
    }
    // Points where the dense pick itself lacks families (Hill's truncation
    // loses them): the targeted solver cannot vouch there.
    let dense = solution.stability_check(&StabilitySettings {
        solver: HillSolver::Dense,
        ..StabilitySettings::default()
    })?;
    let families = 2 * solution.model.dofs_per_sector() * solution.model.sectors();
    let short = points
        .iter()
        .filter_map(|p| dense.point(&p.unknowns, p.omega).ok())
        .filter(|s| s.off_contact_bound.is_none())
        .filter(|s| s.classes.iter().map(|c| c.exponents.len()).sum::<usize>() != families)
        .count();
    println!("{short} points whose dense pick lacks some of the {families} families");
    let clock = Instant::now();
    dense.branch(points)?;
    println!(
        "branch of {} points, dense only: stability {:.3} s",
        points.len(),
        clock.elapsed().as_secs_f64()
    );
    let clock = Instant::now();
    targeted.branch(points)?;
    println!(
        "branch of {} points, targeted: stability {:.3} s",
        points.len(),
        clock.elapsed().as_secs_f64()
    );
    // The default: the condensed solver.
    let check = solution.stability_check(&StabilitySettings::default())?;
    let clock = Instant::now();
    let branch = check.branch(points)?;
    let all = clock.elapsed().as_secs_f64();
    let (classes, dense) = branch
        .points
        .iter()
        .filter(|p| p.off_contact_bound.is_none())
        .flat_map(|p| &p.classes)
        .fold((0, 0), |(n, d), c| (n + 1, d + usize::from(c.dense)));
    println!(
        "branch of {} points: solve {:.3} s, stability {:.3} s ({} points by Hill, {} off contact; {dense} of {classes} classes solved densely), ratio {:.2}",
        points.len(),
        solve,
        all,
        branch.solved_by_hill,
        points.len() - branch.solved_by_hill,
        (solve + all) / solve
    );
    Ok(())
}
