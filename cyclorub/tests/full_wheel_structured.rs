//! The physical full wheel with its Jacobian kept structured (products
//! from the condensed harmonic blocks and the contact blocks, solves by
//! GMRES preconditioned in the frame of the traveling wave) against the
//! same problem with the dense Jacobian, on a 6-sector wheel with
//! three-direction contact nodes and sliding friction, with both laws: the
//! products agree, the approximation is exact (solution and sign of the
//! determinant) at a solution of the traveling wave, GMRES solves exactly
//! at a point that is not one, and a continuation gives the same branch.

use cyclorub::case::{BasisChoice, Case};
use cyclorub::continuation::{
    continue_branch, ArcLengthSettings, Evaluation, NewtonSettings, Problem,
};
use cyclorub::forced_response::prepare;
use cyclorub::hbm::residual::HarmonicBalance;
use faer::linalg::solvers::Solve;
use faer::Mat;
use std::path::Path;

use crate::common;
use common::blade::{contact_point_on, BLADE};

/// The blade wheel with `N_h = 6` (`N_t` a multiple of `N`) and `law`.
fn case(dlft: bool) -> Case {
    let mut text = BLADE
        .replace("harmonics = 12", "harmonics = 6")
        .replace("time_samples = 1536", "time_samples = 288");
    if dlft {
        text = text
            .replace("law = \"regularized\"", "law = \"dlft\"\nepsilon = 2e6")
            .replace("stiffness = 2e6\nregularization = 0.5\n", "");
    }
    Case::from_toml(&text, Path::new("case.toml")).unwrap()
}

/// The physical problem of `case`, dense and structured.
fn problems(case: &Case) -> (HarmonicBalance, HarmonicBalance) {
    let build = || {
        prepare(case, Path::new("."), BasisChoice::Physical)
            .unwrap()
            .problem
    };
    let dense = build();
    assert!(!dense.is_structured(), "a small wheel is dense by default");
    (dense, build().with_structured_jacobian(1))
}

/// A converged point of the full wheel in contact, past first contact
/// below the resonance of nodal diameter 1.
fn contact_point(case: &Case) -> (Vec<f64>, f64) {
    let (solution, index) = contact_point_on(case, BasisChoice::Physical);
    let point = &solution.branch.points[index];
    (point.unknowns.clone(), point.omega)
}

/// The largest entry's modulus.
pub(crate) fn largest(v: &[f64]) -> f64 {
    v.iter().fold(0.0_f64, |m, x| m.max(x.abs()))
}

/// The largest entrywise difference.
pub(crate) fn distance(a: &[f64], b: &[f64]) -> f64 {
    a.iter()
        .zip(b)
        .fold(0.0_f64, |m, (x, y)| m.max((x - y).abs()))
}

/// `jacobian⁻¹ rhs` by a dense LU.
pub(crate) fn dense_solve(jacobian: &Mat<f64>, rhs: &[f64]) -> Vec<f64> {
    let n = rhs.len();
    let x = jacobian
        .partial_piv_lu()
        .solve(Mat::from_fn(n, 1, |r, _| rhs[r]));
    (0..n).map(|r| x[(r, 0)]).collect()
}

fn check(dlft: bool) {
    let case = case(dlft);
    let (mut dense, mut structured) = problems(&case);
    let (x, omega) = contact_point(&case);
    let n = x.len();
    let (mut full, mut kept) = (Evaluation::default(), Evaluation::default());
    dense.evaluate(&x, omega, true, &mut full).unwrap();
    structured.evaluate(&x, omega, true, &mut kept).unwrap();
    assert_eq!(kept.jacobian.nrows(), 0, "no dense Jacobian");
    let operator = kept.structured.clone().expect("a structured Jacobian");
    // The same residual and ∂R/∂ω.
    let scale = largest(&full.residual).max(largest(&full.derivative_omega));
    assert!(distance(&full.residual, &kept.residual) <= 1e-12 * dense.force_scale());
    assert!(distance(&full.derivative_omega, &kept.derivative_omega) <= 1e-12 * scale.max(1.0));
    // The same products.
    let v: Vec<f64> = (0..n).map(|i| (i as f64 * 0.731).sin()).collect();
    let mut product = vec![0.0; n];
    operator.apply(&v, &mut product);
    let reference: Vec<f64> = (0..n)
        .map(|r| (0..n).map(|c| full.jacobian[(r, c)] * v[c]).sum())
        .collect();
    let product_error = distance(&product, &reference) / largest(&reference);
    // At a solution of the traveling wave the approximation is the Jacobian.
    let rhs: Vec<f64> = (0..n).map(|i| (i as f64 * 1.37).cos()).collect();
    let approximation = operator.approximation().unwrap();
    let mut solved = rhs.clone();
    approximation.solve_in_place(&mut solved);
    let exact = dense_solve(&full.jacobian, &rhs);
    let exact_error = distance(&solved, &exact) / largest(&exact);
    let sign = full.jacobian.determinant().signum();
    // Off the wave's solutions GMRES still solves the exact Jacobian.
    let off: Vec<f64> = x
        .iter()
        .enumerate()
        .map(|(i, v)| v * (1.0 + 0.05 * (i as f64 * 2.1).sin()))
        .collect();
    dense.evaluate(&off, omega, true, &mut full).unwrap();
    structured.evaluate(&off, omega, true, &mut kept).unwrap();
    let operator = kept.structured.clone().unwrap();
    let mut approximate = rhs.clone();
    operator
        .approximation()
        .unwrap()
        .solve_in_place(&mut approximate);
    let exact_off = dense_solve(&full.jacobian, &rhs);
    let approximation_off = distance(&approximate, &exact_off) / largest(&exact_off);
    let step = cyclorub::continuation::solve_structured(&kept, &rhs).expect("a structured solve");
    let gmres_error = distance(&step, &exact_off) / largest(&exact_off);
    println!(
        "{}: products {product_error:.1e}, wave frame at the solution {exact_error:.1e} \
         (determinant sign {sign} / {}), off it {approximation_off:.1e} and GMRES {gmres_error:.1e}",
        if dlft { "DLFT" } else { "R-HBM" },
        approximation.determinant_sign()
    );
    assert!(
        product_error < 1e-13,
        "products differ by {product_error:e}"
    );
    assert!(
        exact_error < 1e-10,
        "the wave frame is not exact: {exact_error:e}"
    );
    assert_eq!(sign, approximation.determinant_sign());
    assert!(
        approximation_off > 1e-6,
        "the perturbed point is off the wave"
    );
    assert!(gmres_error < 1e-9, "GMRES off the wave: {gmres_error:e}");
}

#[test]
fn with_friction_and_rhbm_the_structured_full_wheel_is_the_dense_one() {
    check(false);
}

#[test]
fn with_friction_and_dlft_the_structured_full_wheel_is_the_dense_one() {
    check(true);
}

/// A continuation of the full wheel gives the same branch with the
/// structured Jacobian as with the dense one.
#[test]
fn the_structured_full_wheel_follows_the_dense_branch() {
    let case = case(false);
    let (mut dense, mut structured) = problems(&case);
    let model = case.model.build(Path::new(".")).unwrap();
    let first = model.natural_frequencies().unwrap()[1].1[0] * 2.0 * std::f64::consts::PI;
    let settings = ArcLengthSettings {
        start: 0.95 * first,
        end: 1.01 * first,
        initial_step: 0.01,
        min_step: 1e-9,
        max_step: 0.05,
        // The gap: the unknowns' length scale.
        length_scale: 1e-3,
        newton: NewtonSettings {
            tolerance: 1e-10,
            max_iterations: 20,
            ..Default::default()
        },
        max_points: 60,
    };
    let run = |problem: &mut HarmonicBalance| {
        let guess = problem.linear_solution(settings.start).unwrap();
        continue_branch(problem, guess, &settings, |_, _| {})
    };
    let (a, b) = (run(&mut dense), run(&mut structured));
    assert!(a.points.len() > 20, "{} points", a.points.len());
    assert_eq!(a.points.len(), b.points.len());
    let scale = a
        .points
        .iter()
        .map(|p| largest(&p.unknowns))
        .fold(0.0, f64::max);
    let worst = a
        .points
        .iter()
        .zip(&b.points)
        .map(|(p, q)| {
            distance(&p.unknowns, &q.unknowns) / scale + (p.omega - q.omega).abs() / p.omega
        })
        .fold(0.0, f64::max);
    println!("{} points, largest difference {worst:.1e}", a.points.len());
    assert!(worst < 1e-8, "branches differ by {worst:e}");
}
