//! Benchmark: whole forced response curves with the paper's parameters
//! (`N_h = 10`, `N_t = 10000`), academic model N = 24, traveling wave h = 1
//! of 4 N, R-HBM: the symmetry (traveling-wave) basis and the physical full
//! model. Run with `cargo bench -p cyclorub --bench forced_response`.

use cyclorub::case::{BasisChoice, Case};
use cyclorub::continuation::{continue_branch, ArcLengthSettings, NewtonSettings};
use cyclorub::run::prepare;
use std::f64::consts::PI;
use std::path::Path;
use std::time::Instant;

fn curve(case: &Case, basis: BasisChoice) -> Result<(), Box<dyn std::error::Error>> {
    let clock = Instant::now();
    let mut prepared = prepare(case, Path::new("."), basis)?;
    let setup = clock.elapsed().as_secs_f64();
    let k = &prepared.case.continuation;
    let settings = ArcLengthSettings {
        start: 2.0 * PI * k.start_hz.unwrap_or(120.0),
        end: 2.0 * PI * k.end_hz.unwrap_or(140.0),
        initial_step: k.initial_step,
        min_step: k.min_step,
        max_step: k.max_step,
        length_scale: prepared.case.length_scale(),
        newton: NewtonSettings {
            tolerance: k.tolerance,
            max_iterations: k.max_iterations,
        },
        max_points: k.max_points,
    };
    let clock = Instant::now();
    let guess = prepared.problem.linear_solution(settings.start)?;
    let branch = continue_branch(&mut prepared.problem, guess, &settings, |_, _| {});
    let wall = clock.elapsed().as_secs_f64();
    println!(
        "{:<9} unknowns {:>4}  set-up {:>7.3} s  curve {:>8.3} s  points {:>4}  Newton iterations {:>5}  {:>8.3} ms/iteration  stop {:?}",
        basis.name(),
        prepared.basis.unknowns,
        setup,
        wall,
        branch.points.len(),
        branch.total_iterations,
        1e3 * wall / branch.total_iterations.max(1) as f64,
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
