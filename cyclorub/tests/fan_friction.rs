//! The open fan (coarse mesh, Craig–Bampton per nodal diameter) rubbing on
//! its casing with sliding friction, 3D contact nodes (radial normal):
//! the reduced problem equals the physical full wheel, traveling and partly
//! standing waves (the paper's Sec. 5.3–5.4 claim, on our open model).

use cyclorub::case::{BasisChoice, Case, ExcitationKind};
use cyclorub::continuation::{solve_at_frequencies, Evaluation, NewtonSettings, Problem};
use cyclorub::hbm::recovery::{dof_coordinates, physical_unknowns};
use cyclorub::hbm::HarmonicBalance;
use cyclorub::mesh::{assemble, fan, write_fan, FanGeometry};
use cyclorub::run::prepare;
use std::f64::consts::PI;
use std::path::{Path, PathBuf};

fn fan_folder() -> PathBuf {
    let dir = std::env::temp_dir().join(format!("cyclorub-fan-friction-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    let fan = fan(16, 1, &FanGeometry::default()).unwrap();
    let matrices = assemble(&fan.mesh).unwrap();
    write_fan(&fan, &matrices, &dir, false).unwrap();
    dir
}

fn converged(problem: &mut HarmonicBalance, omegas: &[f64]) -> Vec<(Vec<f64>, f64)> {
    let start = problem.linear_solution(omegas[0]).unwrap();
    let settings = NewtonSettings {
        tolerance: 1e-9,
        max_iterations: 80,
        ..Default::default()
    };
    solve_at_frequencies(problem, start, omegas, &settings, |_, _| {})
        .points
        .into_iter()
        .map(|p| {
            assert!(p.converged, "no convergence at {} Hz", p.omega / 2.0 / PI);
            (p.unknowns, p.omega)
        })
        .collect()
}

fn largest_relative_difference(a: &[Vec<f64>], b: &[Vec<f64>]) -> f64 {
    let scale = a.iter().flatten().map(|v| v.abs()).fold(0.0, f64::max);
    let difference = a
        .iter()
        .flatten()
        .zip(b.iter().flatten())
        .map(|(x, y)| (x - y).abs())
        .fold(0.0, f64::max);
    difference / scale
}

/// Solves `case` on its symmetry basis and on the physical full wheel at
/// `factors` times the excited first frequency; every reduced point solves
/// the full wheel, and the two agree on the observed dof of every sector.
fn reduced_equals_full(dir: &Path, case: &Case, factors: &[f64]) -> (f64, f64, usize) {
    let reduced = prepare(case, dir, BasisChoice::Symmetry).unwrap();
    let full = prepare(case, dir, BasisChoice::Physical).unwrap();
    let first = reduced.case.continuation.start_hz.unwrap() / 0.95;
    let omegas: Vec<f64> = factors.iter().map(|f| 2.0 * PI * first * f).collect();
    let (mut reduced, mut full) = (reduced.problem, full.problem);
    assert!(reduced.layout().unknowns * 4 <= full.layout().unknowns);
    let observed = case.output.observed_dof - 1;
    let sectors: Vec<usize> = (0..16).collect();
    let (mut worst_residual, mut worst_difference, mut touching) = (0.0_f64, 0.0_f64, 0);
    for ((x, omega), (y, _)) in converged(&mut reduced, &omegas)
        .iter()
        .zip(&converged(&mut full, &omegas))
    {
        let carried = physical_unknowns(&reduced, x);
        let mut at = Evaluation::default();
        full.evaluate(&carried, *omega, false, &mut at).unwrap();
        let residual = at.residual.iter().map(|v| v.abs()).fold(0.0, f64::max);
        worst_residual = worst_residual.max(residual / case.excitation.amplitude);
        let a = dof_coordinates(&reduced, x, *omega, observed, &sectors).unwrap();
        let b = dof_coordinates(&full, y, *omega, observed, &sectors).unwrap();
        worst_difference = worst_difference.max(largest_relative_difference(&a, &b));
        let samples = full.contact_samples(&carried, *omega).unwrap();
        touching += usize::from(samples.penetration.iter().flatten().any(|&p| p > 0.0));
    }
    (worst_residual, worst_difference, touching)
}

/// The coarse fan's case with a short harmonic balance (`N_h = 2`,
/// `N_t = 32`, a multiple of N) and a small gap, so that contact sets in
/// within the short window of the test, a little below the resonance (the
/// 2 N load moves the leading-edge tip node radially by 6.9e-4 m at the
/// ND1 resonance, the mid-chord one by 1.3e-4 m).
fn fan_case(dir: &Path) -> Case {
    let mut case = Case::from_file_checked(&dir.join("fan16.toml")).unwrap();
    case.harmonic_balance.harmonics = 2;
    case.harmonic_balance.time_samples = 32;
    case.casing.gap = cyclorub::case::PerContactDof::One(3e-5);
    case
}

/// Measured: residuals 2.7e-10 and 3.7e-10 of f_ex, differences 3.3e-11
/// and 2.5e-11, every point in contact.
fn check(name: &str, residual: f64, difference: f64, touching: usize) {
    assert!(
        residual < 1e-8,
        "{name}: the reduced points leave {residual:e} of f_ex on the full wheel"
    );
    assert!(
        difference < 1e-8,
        "{name}: reduced and full differ by {difference:e}"
    );
    assert!(
        touching >= 3,
        "{name}: only {touching} points touch the casing"
    );
}

#[test]
fn the_reduced_fan_with_friction_is_the_full_one() {
    let dir = fan_folder();
    let traveling = fan_case(&dir);
    let factors: Vec<f64> = (0..6).map(|i| 0.995 + 0.001 * i as f64).collect();
    let (residual, difference, touching) = reduced_equals_full(&dir, &traveling, &factors);
    println!("traveling h = 1: full residual {residual:e} of f_ex, difference {difference:e}, {touching} points in contact");
    check("traveling h = 1", residual, difference, touching);
    let mut standing = fan_case(&dir);
    standing.excitation.kind = ExcitationKind::Mixed;
    standing.excitation.engine_order = 4;
    standing.excitation.amplitude = 1.0;
    standing.excitation.backward_weight = 0.9;
    standing.excitation.forward_weight = 0.1;
    let (residual, difference, touching) = reduced_equals_full(&dir, &standing, &factors);
    println!("partly standing h = 4: full residual {residual:e} of f_ex, difference {difference:e}, {touching} points in contact");
    check("partly standing h = 4", residual, difference, touching);
    let _ = std::fs::remove_dir_all(&dir);
}
