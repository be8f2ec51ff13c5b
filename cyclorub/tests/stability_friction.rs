//! Stability by Hill's method with sliding friction (Eqs. 83–84), whose
//! linearization adds a stiffness from the normal dof onto the tangential
//! ones and a damping between the tangential velocities: the symmetry
//! classes together are the whole wheel's Hill spectrum, and the Floquet
//! multipliers agree with the monodromy matrix of the variational
//! equations integrated in time, with the friction linearized here again.

use cyclorub::case::Case;
use cyclorub::forced_response::Solution;
use cyclorub::hbm::recovery::wall_coordinates;
use cyclorub::stability::{HillSolver, Stability, StabilitySettings};
use faer::linalg::solvers::DenseSolveCore;
use faer::{c64, Mat};
use std::f64::consts::PI;
use std::path::Path;

use crate::common;
use common::blade::{contact_point, BLADE};
use common::spectra::{largest_mismatch, values};

/// The blade wheel with Hill's truncation `hill` and the orbit's `N_h`
/// (`N_t` a multiple of `N`, so that the sampled terms keep the solution's
/// symmetry).
fn blade(harmonics: usize) -> Case {
    let text = BLADE
        .replace("harmonics = 12", &format!("harmonics = {harmonics}"))
        .replace(
            "time_samples = 1536",
            &format!("time_samples = {}", 48 * harmonics),
        )
        // A smoother law: Hill's truncation converges faster.
        .replace("regularization = 0.5", "regularization = 20.0");
    Case::from_toml(&text, Path::new("case.toml")).unwrap()
}

fn settings(hill: usize) -> StabilitySettings {
    StabilitySettings {
        harmonics: Some(hill),
        ..StabilitySettings::default()
    }
}

fn settings_by(hill: usize, solver: HillSolver) -> StabilitySettings {
    StabilitySettings {
        solver,
        ..settings(hill)
    }
}

/// The classes' exponents at `case`'s contact point by `by_classes`
/// against Hill's method on the whole wheel by `reference` (same `H`): the
/// largest mismatch relative to the largest |λ| (the dense pick) or to `ω`
/// (the condensed solver's region), and the number of exponents.
fn classes_against_whole_wheel(
    case: &Case,
    hill: usize,
    by_classes: HillSolver,
    reference: HillSolver,
) -> (f64, usize) {
    let (solution, index) = contact_point(case);
    let point = &solution.branch.points[index];
    let check = solution
        .stability_check(&settings_by(hill, by_classes))
        .unwrap();
    assert_eq!(check.classes().len(), 6);
    let by_class = check.point(&point.unknowns, point.omega).unwrap();
    assert!(by_class.peak_contact_stiffness > 1e6, "a contact point");
    assert!(by_class
        .classes
        .iter()
        .all(|c| c.dense == (by_classes != HillSolver::Condensed)));
    let full = Stability::full_wheel(
        &solution.model,
        &solution.problem,
        &solution.case.contact_dofs(),
        &settings_by(hill, reference),
    )
    .unwrap();
    let whole = full.point(&point.unknowns, point.omega).unwrap();
    let union = values(&by_class.all_exponents());
    let reference = values(&whole.classes[0].exponents);
    let scale = if by_classes == HillSolver::Condensed {
        point.omega
    } else {
        union.iter().map(|z| z.norm()).fold(0.0, f64::max)
    };
    let mismatch = largest_mismatch(&union, &reference);
    println!(
        "{} at {:.4} Hz: {} exponents, classes against the whole wheel {mismatch:.2e} \
         (largest |λ| {scale:.3e}); {} unstable",
        case.contact.law.name(),
        point.omega / (2.0 * PI),
        union.len(),
        whole.unstable_exponents()
    );
    assert_eq!(by_class.unstable_exponents(), whole.unstable_exponents());
    (mismatch / scale, union.len())
}

#[test]
fn with_friction_the_classes_together_are_the_full_wheel() {
    let (mismatch, exponents) =
        classes_against_whole_wheel(&blade(6), 6, HillSolver::Dense, HillSolver::Dense);
    assert_eq!(exponents, 2 * 4 * 6, "2 · dofs · N exponents");
    assert!(mismatch < 1e-8, "classes vs whole wheel: {mismatch:e}");
    // The condensed solver against the dense whole wheel in its region.
    let (mismatch, exponents) =
        classes_against_whole_wheel(&blade(6), 6, HillSolver::Condensed, HillSolver::DenseRegion);
    assert!(exponents >= 4 * 6, "{exponents} exponents");
    assert!(
        mismatch < 1e-8,
        "condensed vs dense whole wheel: {mismatch:e}"
    );
}

/// The blade wheel with friction and DLFT (a rigid casing), `N_h = H = 6`.
fn dlft_blade() -> Case {
    let text = BLADE
        .replace("harmonics = 12", "harmonics = 6")
        .replace("time_samples = 1536", "time_samples = 288")
        .replace("law = \"regularized\"", "law = \"dlft\"\nepsilon = 2e6")
        .replace("stiffness = 2e6\nregularization = 0.5\n", "");
    Case::from_toml(&text, Path::new("case.toml")).unwrap()
}

/// Off the casing the linearized contact vanishes, friction's terms with
/// it: the condensed solver gives the linear wheel's exponents exactly,
/// without a contour (bound 0), and they are the dense whole wheel's.
#[test]
fn with_friction_a_point_off_the_casing_has_the_linear_wheels_exponents() {
    let case = dlft_blade();
    let (solution, _) = contact_point(&case);
    let point = &solution.branch.points[0];
    let check = solution
        .stability_check(&settings_by(6, HillSolver::Condensed))
        .unwrap();
    let by_class = check.point(&point.unknowns, point.omega).unwrap();
    assert_eq!(
        by_class.peak_contact_stiffness, 0.0,
        "a point off the casing"
    );
    assert_eq!(by_class.off_contact_bound, Some(0.0));
    let full = Stability::full_wheel(
        &solution.model,
        &solution.problem,
        &solution.case.contact_dofs(),
        &settings_by(6, HillSolver::DenseRegion),
    )
    .unwrap();
    let whole = full.point(&point.unknowns, point.omega).unwrap();
    let union = values(&by_class.all_exponents());
    let reference = values(&whole.classes[0].exponents);
    assert_eq!(union.len(), reference.len());
    let mismatch = largest_mismatch(&union, &reference) / point.omega;
    assert!(mismatch < 1e-8, "linear vs dense whole wheel: {mismatch:e}");
}

/// With DLFT the terms are sampled from the law's multiplier (its force)
/// and its linearized stiffness, on a rigid casing.
#[test]
fn with_friction_and_dlft_the_classes_together_are_the_full_wheel() {
    let case = dlft_blade();
    let (mismatch, exponents) =
        classes_against_whole_wheel(&case, 6, HillSolver::Dense, HillSolver::Dense);
    // Hill's truncation at H = 6 may pick a few more than 2 · dofs · N.
    assert!(exponents >= 2 * 4 * 6, "{exponents} exponents");
    assert!(mismatch < 1e-8, "classes vs whole wheel: {mismatch:e}");
    let (mismatch, exponents) =
        classes_against_whole_wheel(&case, 6, HillSolver::Condensed, HillSolver::DenseRegion);
    assert!(exponents >= 4 * 6, "{exponents} exponents");
    assert!(
        mismatch < 1e-8,
        "condensed vs dense whole wheel: {mismatch:e}"
    );
}

/// `x(τ) = a0 + Σ_k 2 (Re X_k cos kτ − Im X_k sin kτ)` and `dx/dτ` from
/// real harmonic coordinates.
fn evaluate(coordinates: &[f64], tau: f64) -> (f64, f64) {
    let harmonics = (coordinates.len() - 1) / 2;
    let (mut value, mut rate) = (coordinates[0], 0.0);
    for k in 1..=harmonics {
        let (sin, cos) = (k as f64 * tau).sin_cos();
        let (re, im) = (coordinates[2 * k - 1], coordinates[2 * k]);
        value += 2.0 * (re * cos - im * sin);
        rate -= 2.0 * k as f64 * (re * sin + im * cos);
    }
    (value, rate)
}

/// The multipliers `e^{λT}` of the variational equations about the orbit of
/// `solution`'s point `index`, integrated by RK4 over one period on the
/// whole wheel: the normal law's slope at every instant, and the friction
/// force `μ f_N w/|w|` linearized here (`∂(w/|w|)/∂w = (I − t tᵀ)/|w|`).
fn monodromy_multipliers(solution: &Solution, index: usize) -> Vec<c64> {
    let point = &solution.branch.points[index];
    let (model, problem) = (&solution.model, &solution.problem);
    let wheel = model.full_wheel().unwrap();
    let (sectors, dofs) = (model.sectors(), model.dofs_per_sector());
    let size = sectors * dofs;
    let all: Vec<usize> = (0..sectors).collect();
    // Contact dofs of the layout: normal 1, then circumferential 2, axial 3.
    let (normal, theta, axial) = (0, 1, 2);
    let signals: Vec<Vec<Vec<f64>>> = (0..3)
        .map(|c| wall_coordinates(problem, &point.unknowns, c, &all))
        .collect();
    let law = problem.law();
    let gap = problem.casing().gaps[0];
    let (mu, radius, speed) = (0.3, 0.4, 30.0);
    let mass_inverse = wheel.mass.partial_piv_lu().inverse();
    let omega = point.omega;
    let derivative = |t: f64, phi: &Mat<f64>| -> Mat<f64> {
        let tau = omega * t;
        let mut stiffness = wheel.stiffness.clone();
        let mut damping = wheel.damping.clone();
        let nodes = signals[0].iter().zip(&signals[1]).zip(&signals[2]);
        for (j, ((radial, circumferential), along_axis)) in nodes.enumerate() {
            let at = |d: usize| j * dofs + d;
            let (u, _) = evaluate(radial, tau);
            let (force, slope) = law.force(u - gap);
            let k = law.linearized_stiffness(slope);
            let w = [
                omega * evaluate(circumferential, tau).1 + radius * speed,
                omega * evaluate(along_axis, tau).1,
            ];
            let length = w[0].hypot(w[1]);
            let t = [w[0] / length, w[1] / length];
            stiffness[(at(normal), at(normal))] += k;
            for (r, dof) in [(0, theta), (1, axial)] {
                stiffness[(at(dof), at(normal))] += mu * k * t[r];
                for (c, other) in [(0, theta), (1, axial)] {
                    let identity = if r == c { 1.0 } else { 0.0 };
                    damping[(at(dof), at(other))] += mu * force * (identity - t[r] * t[c]) / length;
                }
            }
        }
        let stiffness = &mass_inverse * &stiffness;
        let damping = &mass_inverse * &damping;
        let mut out = Mat::<f64>::zeros(2 * size, phi.ncols());
        for col in 0..phi.ncols() {
            for r in 0..size {
                out[(r, col)] = phi[(size + r, col)];
                let mut acceleration = 0.0;
                for q in 0..size {
                    acceleration -=
                        stiffness[(r, q)] * phi[(q, col)] + damping[(r, q)] * phi[(size + q, col)];
                }
                out[(size + r, col)] = acceleration;
            }
        }
        out
    };
    let period = 2.0 * PI / omega;
    let steps = 3000;
    let h = period / steps as f64;
    let mut phi = Mat::<f64>::identity(2 * size, 2 * size);
    for step in 0..steps {
        let t = step as f64 * h;
        let k1 = derivative(t, &phi);
        let k2 = derivative(t + h / 2.0, &(&phi + &k1 * (h / 2.0)));
        let k3 = derivative(t + h / 2.0, &(&phi + &k2 * (h / 2.0)));
        let k4 = derivative(t + h, &(&phi + &k3 * h));
        phi = &phi + (&k1 + &k2 * 2.0 + &k3 * 2.0 + &k4) * (h / 6.0);
    }
    phi.eigenvalues()
        .unwrap()
        .into_iter()
        .map(|z| c64::new(z.re, z.im))
        .collect()
}

#[test]
fn with_friction_the_floquet_multipliers_of_the_monodromy_matrix_agree() {
    let (solution, index) = contact_point(&blade(10));
    let point = &solution.branch.points[index];
    let reference = monodromy_multipliers(&solution, index);
    let check = solution.stability_check(&settings(30)).unwrap();
    let hill = check.point(&point.unknowns, point.omega).unwrap();
    let from_hill: Vec<c64> = hill
        .all_exponents()
        .iter()
        .map(|e| e.multiplier(point.omega))
        .collect();
    let mismatch = largest_mismatch(&from_hill, &reference);
    let largest = reference.iter().map(|z| z.norm()).fold(0.0, f64::max);
    println!(
        "{:.4} Hz, N_h = 10, Hill's H = 30: multipliers agree to {mismatch:.2e} (largest |ρ| \
         {largest:.4})",
        point.omega / (2.0 * PI)
    );
    assert!(hill.peak_contact_stiffness > 1e6, "a contact point");
    // 5.9e-6 with H = 30 (1.6e-4 with H = 20); leaving out the velocity
    // terms' `i k_h` gives 5.4e-4, the velocity terms altogether 3e-3.
    assert!(mismatch < 5e-5, "multipliers differ by {mismatch:e}");
}
