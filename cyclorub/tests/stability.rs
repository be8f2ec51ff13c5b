//! Stability by Hill's method per symmetry class, against independent
//! references: the full wheel's Hill matrix without symmetry, the damped
//! modes of a linear wheel, Floquet multipliers of the monodromy matrix
//! integrated in time, and the folds the continuation finds.

use cyclorub::case::{BasisChoice, Case};
use cyclorub::forced_response::{ForcedResponse, Solution};
use cyclorub::hbm::recovery::wall_coordinates;
use cyclorub::stability::{
    markers, ContactStiffness, HillSolver, MarkerKind, PointStability, Stability, StabilitySettings,
};
use faer::linalg::solvers::DenseSolveCore;
use faer::{c64, Mat};
use std::f64::consts::PI;
use std::path::Path;

use crate::common;
use common::spectra::{largest_mismatch, values};

fn case(text: &str) -> Case {
    Case::from_toml(text, Path::new("test.toml")).expect("case")
}

pub(crate) fn solve(text: &str, basis: BasisChoice) -> Solution {
    ForcedResponse::from_case(&case(text))
        .unwrap()
        .basis(basis)
        .build()
        .unwrap()
        .run(&mut [])
        .unwrap()
}

pub(crate) const SMALL: &str =
    "[model]\nsectors = 6\n[harmonic_balance]\nharmonics = 3\ntime_samples = 60\n\
                     [continuation]\nmax_points = 400\n";

/// The index of the point with the stiffest contact.
pub(crate) fn stiffest_contact(solution: &Solution) -> usize {
    let time_samples = solution.problem.time_samples();
    solution
        .branch
        .points
        .iter()
        .enumerate()
        .map(|(i, p)| {
            let stiffness =
                ContactStiffness::sample(&solution.problem, &p.unknowns, p.omega, time_samples);
            (i, stiffness.unwrap().peak())
        })
        .max_by(|a, b| a.1.total_cmp(&b.1))
        .unwrap()
        .0
}

/// At the stiffest contact point of `text`'s branch, the classes by
/// `by_classes` against the whole wheel in physical coordinates by
/// `reference` (no symmetry): the same exponents. The dense pick holds
/// `2 · dofs · N` in all; the condensed solver's region, each multiplier of
/// modulus above `e^{−2π·margin}` once.
fn union_equals_the_full_wheel(
    text: &str,
    classes_expected: usize,
    by_classes: HillSolver,
    reference: HillSolver,
) {
    let solution = solve(text, BasisChoice::Symmetry);
    let settings = |solver| StabilitySettings {
        solver,
        ..StabilitySettings::default()
    };
    let check = solution.stability_check(&settings(by_classes)).unwrap();
    assert_eq!(check.classes().len(), classes_expected);
    let full = Stability::full_wheel(
        &solution.model,
        &solution.problem,
        &solution.case.contact_dofs(),
        &settings(reference),
    )
    .unwrap();
    let point = &solution.branch.points[stiffest_contact(&solution)];
    let by_class = check.point(&point.unknowns, point.omega).unwrap();
    assert!(by_class.peak_contact_stiffness > 1e6, "a contact point");
    let whole = full.point(&point.unknowns, point.omega).unwrap();
    let truncation = by_class
        .classes
        .iter()
        .map(|c| c.truncation)
        .fold(0.0, f64::max);
    let union = values(&by_class.all_exponents());
    let reference_values = values(&whole.classes[0].exponents);
    let sectors = solution.model.sectors();
    let scale = if by_classes == HillSolver::Dense {
        assert!(truncation < 1e-3, "resolved: {truncation:e}");
        assert_eq!(union.len(), 2 * 5 * sectors, "2 · dofs · N exponents");
        union.iter().map(|z| z.norm()).fold(0.0, f64::max)
    } else {
        assert_eq!(union.len(), reference_values.len(), "{union:?}");
        assert!(union.len() >= 5 * sectors, "{} exponents", union.len());
        point.omega
    };
    let mismatch = largest_mismatch(&union, &reference_values);
    assert!(
        mismatch < 1e-8 * scale,
        "classes vs whole wheel: {mismatch:e} (scale {scale:e})"
    );
    assert_eq!(by_class.stable(), whole.stable());
    assert_eq!(by_class.unstable_exponents(), whole.unstable_exponents());
}

/// A softer contact, resolved by 8 harmonics; `N_t` a multiple of `N`, so
/// that the sampled contact stiffness has exactly the solution's symmetry
/// (otherwise the classes and the whole wheel differ by the aliasing).
pub(crate) const RESOLVED: &str =
    "[model]\nsectors = 6\n[harmonic_balance]\nharmonics = 8\ntime_samples = 120\n\
                        [contact]\nstiffness = 2e6\nregularization = 20.0\n\
                        [continuation]\nmax_points = 400\n";

#[test]
fn the_classes_together_are_the_full_wheel_traveling() {
    union_equals_the_full_wheel(RESOLVED, 6, HillSolver::Dense, HillSolver::Dense);
}

#[test]
fn the_classes_together_are_the_full_wheel_standing() {
    // A standing wave h = 1 on 6 sectors: P₀ = {0, ±2}, two classes.
    let text = format!("{RESOLVED}[excitation]\nkind = \"standing\"\n");
    union_equals_the_full_wheel(&text, 2, HillSolver::Dense, HillSolver::Dense);
}

#[test]
fn the_condensed_classes_are_the_dense_whole_wheel_in_the_region_traveling() {
    union_equals_the_full_wheel(RESOLVED, 6, HillSolver::Condensed, HillSolver::DenseRegion);
}

#[test]
fn the_condensed_classes_are_the_dense_whole_wheel_in_the_region_standing() {
    let text = format!("{RESOLVED}[excitation]\nkind = \"standing\"\n");
    union_equals_the_full_wheel(&text, 2, HillSolver::Condensed, HillSolver::DenseRegion);
}

#[test]
fn the_condensed_classes_are_the_dense_classes_on_the_stiff_default_contact() {
    // The N = 6 chain with the default stiff contact (1e8 N/m), at every
    // contact point of its branch: the condensed solver and the dense
    // eigenproblem of each class, restricted to the same region, agree.
    let solution = solve(SMALL, BasisChoice::Symmetry);
    let settings = |solver| StabilitySettings {
        solver,
        ..StabilitySettings::default()
    };
    let condensed = solution
        .stability_check(&settings(HillSolver::Condensed))
        .unwrap();
    let dense = solution
        .stability_check(&settings(HillSolver::DenseRegion))
        .unwrap();
    let mut checked = 0;
    for point in solution.branch.points.iter().step_by(3) {
        let a = condensed.point(&point.unknowns, point.omega).unwrap();
        if a.peak_contact_stiffness < 1e6 {
            continue;
        }
        let b = dense.point(&point.unknowns, point.omega).unwrap();
        for (x, y) in a.classes.iter().zip(&b.classes) {
            assert_eq!(x.nodal_diameter, y.nodal_diameter);
            let (x, y) = (values(&x.exponents), values(&y.exponents));
            assert_eq!(x.len(), y.len(), "{x:?} vs {y:?}");
            let mismatch = largest_mismatch(&x, &y);
            assert!(mismatch < 1e-8 * point.omega, "{mismatch:e}");
        }
        assert_eq!(a.unstable_exponents(), b.unstable_exponents());
        checked += 1;
    }
    assert!(checked >= 5, "{checked} contact points");
}

#[test]
fn a_wheel_off_its_casing_has_the_damped_modes_of_every_nodal_diameter() {
    // Far from the casing and with the plain penalty law, the contact adds
    // nothing: the exponents are −ξω_n ± iω_n√(1 − ξ²) of every mode of
    // every diameter, class σ holding diameter σ's.
    let text = format!(
        "{SMALL}[casing]\ngap = 1.0\n[contact]\nregularization = 0.0\n\
         [model.damping]\nratio = 0.02\n"
    );
    let mut solution = ForcedResponse::from_case(&case(&text))
        .unwrap()
        .basis(BasisChoice::Symmetry)
        .at_frequencies_hz(vec![110.0])
        .build()
        .unwrap()
        .run(&mut [])
        .unwrap();
    let point = solution.branch.points.remove(0);
    let xi = 0.02_f64;
    // Hill's method, and the shortcut that gives the linear exponents.
    for shortcut in [false, true] {
        let settings = StabilitySettings {
            weak_contact_shortcut: shortcut,
            solver: HillSolver::Dense,
            ..Default::default()
        };
        let check = solution.stability_check(&settings).unwrap();
        let stability = check.point(&point.unknowns, point.omega).unwrap();
        assert!(stability.stable());
        assert_eq!(stability.peak_contact_stiffness, 0.0);
        assert_eq!(stability.off_contact_bound, shortcut.then_some(0.0));
        for (diameter, frequencies) in solution.model.natural_frequencies().unwrap() {
            for sigma in [diameter as i64, -(diameter as i64)] {
                // σ = N/2 is its own conjugate, listed once.
                let class = stability
                    .class(sigma)
                    .or_else(|| stability.class(-sigma))
                    .unwrap();
                let expected: Vec<c64> = frequencies
                    .iter()
                    .flat_map(|hz| {
                        let w = 2.0 * PI * hz;
                        let damped = w * (1.0 - xi * xi).sqrt();
                        [c64::new(-xi * w, damped), c64::new(-xi * w, -damped)]
                    })
                    .collect();
                let got = values(&class.exponents);
                let scale = expected.iter().map(|z| z.norm()).fold(0.0, f64::max);
                let mismatch = largest_mismatch(&got, &expected);
                assert!(
                    mismatch < 1e-9 * scale,
                    "diameter {sigma}, shortcut {shortcut}: {mismatch:e} of {scale:e}"
                );
            }
        }
    }
}

#[test]
fn weak_contact_moves_the_linear_exponents_less_than_the_bound() {
    // The regularized law touches at a distance: before contact its slope
    // is small but not 0. Hill's exponents there lie within the bound of
    // the linear ones that the shortcut gives, for the dense pick and for
    // the condensed solver's region alike.
    let solution = solve(SMALL, BasisChoice::Symmetry);
    for solver in [HillSolver::Targeted, HillSolver::Condensed] {
        let shortcut = solution
            .stability_check(&StabilitySettings {
                solver,
                ..Default::default()
            })
            .unwrap();
        let hill = solution
            .stability_check(&StabilitySettings {
                weak_contact_shortcut: false,
                solver,
                ..Default::default()
            })
            .unwrap();
        let mut checked = 0;
        for point in &solution.branch.points {
            let quick = shortcut.point(&point.unknowns, point.omega).unwrap();
            let Some(bound) = quick.off_contact_bound else {
                continue;
            };
            let full = hill.point(&point.unknowns, point.omega).unwrap();
            assert!(full.peak_contact_stiffness > 0.0);
            for (a, b) in quick.classes.iter().zip(&full.classes) {
                assert_eq!(a.nodal_diameter, b.nodal_diameter);
                let mismatch = largest_mismatch(&values(&a.exponents), &values(&b.exponents));
                assert!(
                    mismatch <= bound,
                    "{solver:?}: {mismatch:e} > bound {bound:e}"
                );
            }
            assert_eq!(quick.stable(), full.stable());
            checked += 1;
        }
        assert!(checked > 10, "{checked} points off contact");
    }
}

#[test]
fn the_trivial_class_crosses_zero_at_the_folds_of_the_branch() {
    let solution = solve(SMALL, BasisChoice::Symmetry);
    let check = solution
        .stability_check(&StabilitySettings::default())
        .unwrap();
    let points: Vec<PointStability> = solution
        .branch
        .points
        .iter()
        .map(|p| check.point(&p.unknowns, p.omega).unwrap())
        .collect();
    let found = markers(&points, true);
    let folds: Vec<usize> = found
        .iter()
        .filter(|m| m.kind == MarkerKind::Fold)
        .map(|m| m.index)
        .collect();
    // The continuation's folds: where the frequency turns back.
    let turns: Vec<usize> = solution
        .branch
        .points
        .windows(3)
        .enumerate()
        .filter(|(_, w)| (w[1].omega - w[0].omega) * (w[2].omega - w[1].omega) < 0.0)
        .map(|(i, _)| i + 1)
        .collect();
    assert!(!turns.is_empty(), "the small case's branch turns");
    assert_eq!(folds.len(), turns.len(), "folds {folds:?}, turns {turns:?}");
    for (fold, turn) in folds.iter().zip(&turns) {
        // A fold marker lies between points i and i + 1; the turn is at the
        // point where ω is extreme: one of the two, within a step.
        assert!(
            *fold + 1 >= *turn && *fold <= *turn,
            "fold between {fold} and {}, turn at {turn}",
            fold + 1
        );
    }
}

/// `x(τ) = a0 + Σ_k 2 (Re X_k cos kτ − Im X_k sin kτ)` from real harmonic
/// coordinates.
fn evaluate(coordinates: &[f64], tau: f64) -> f64 {
    let harmonics = (coordinates.len() - 1) / 2;
    let mut value = coordinates[0];
    for k in 1..=harmonics {
        let (sin, cos) = (k as f64 * tau).sin_cos();
        value += 2.0 * (coordinates[2 * k - 1] * cos - coordinates[2 * k] * sin);
    }
    value
}

#[test]
fn floquet_multipliers_of_the_monodromy_matrix_agree() {
    // An independent reference: the variational equations of the whole
    // wheel (4 sectors, physical coordinates) about the harmonic balance
    // orbit, integrated over one period by RK4 with the law's slope taken
    // at every instant of the continuous orbit; the eigenvalues of the
    // monodromy matrix are the multipliers e^{λT}. The orbit has N_h = 10;
    // Hill needs H = 20 to hold the perturbations it excites (with H = 10
    // the worst multiplier is off by 1.5e-2, with H = 20 by 6e-4).
    let text = "[model]\nsectors = 4\n[harmonic_balance]\nharmonics = 10\ntime_samples = 400\n\
                [contact]\nstiffness = 2e6\nregularization = 20.0\n\
                [continuation]\nmax_points = 400\n";
    let solution = solve(text, BasisChoice::Symmetry);
    let point = &solution.branch.points[stiffest_contact(&solution)];
    let settings = StabilitySettings {
        harmonics: Some(20),
        ..Default::default()
    };
    let check = solution.stability_check(&settings).unwrap();
    let hill = check.point(&point.unknowns, point.omega).unwrap();
    assert!(hill.peak_contact_stiffness > 1e6, "a contact point");

    let (model, problem) = (&solution.model, &solution.problem);
    let wheel = model.full_wheel().unwrap();
    let (sectors, dofs) = (model.sectors(), model.dofs_per_sector());
    let size = sectors * dofs;
    let contact_dofs = solution.case.contact_dofs();
    let all: Vec<usize> = (0..sectors).collect();
    let coordinates: Vec<Vec<Vec<f64>>> = (0..contact_dofs.len())
        .map(|c| wall_coordinates(problem, &point.unknowns, c, &all))
        .collect();
    let casing = problem.casing();
    let law = problem.law();
    let mass_inverse = wheel.mass.partial_piv_lu().inverse();
    let stiffness = &mass_inverse * &wheel.stiffness;
    let damping = &mass_inverse * &wheel.damping;
    let omega = point.omega;
    let alpha = 2.0 * PI / sectors as f64;
    // ż = A(t) z, z = [y; ẏ]: the derivative of the columns of Φ.
    let derivative = |t: f64, phi: &Mat<f64>| -> Mat<f64> {
        let tau = omega * t;
        let mut contact = Mat::<f64>::zeros(size, size);
        for j in 0..sectors {
            for (c, &dof) in contact_dofs.iter().enumerate() {
                let order = casing.order as f64;
                let gap = casing.gaps[c]
                    + casing.amplitudes[c] * (order * tau - order * alpha * (j + 1) as f64).cos();
                let penetration = evaluate(&coordinates[c][j], tau) - gap;
                let (_, slope) = law.force(penetration);
                contact[(j * dofs + dof, j * dofs + dof)] = law.linearized_stiffness(slope);
            }
        }
        let contact = &mass_inverse * &contact;
        let mut out = Mat::<f64>::zeros(2 * size, phi.ncols());
        for col in 0..phi.ncols() {
            for r in 0..size {
                out[(r, col)] = phi[(size + r, col)];
                let mut acceleration = 0.0;
                for q in 0..size {
                    acceleration -= (stiffness[(r, q)] + contact[(r, q)]) * phi[(q, col)]
                        + damping[(r, q)] * phi[(size + q, col)];
                }
                out[(size + r, col)] = acceleration;
            }
        }
        out
    };
    let period = 2.0 * PI / omega;
    let steps = 4000;
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
    let monodromy: Vec<c64> = phi
        .eigenvalues()
        .unwrap()
        .into_iter()
        .map(|z| c64::new(z.re, z.im))
        .collect();
    let from_hill: Vec<c64> = hill
        .all_exponents()
        .iter()
        .map(|e| e.multiplier(omega))
        .collect();
    assert_eq!(from_hill.len(), monodromy.len());
    let mismatch = largest_mismatch(&from_hill, &monodromy);
    assert!(mismatch < 1e-3, "multipliers differ by {mismatch:e}");
}

#[test]
fn the_leading_exponent_converges_with_the_harmonics() {
    // The default case (N = 24, traveling h = 1, R-HBM) at 128 Hz on its
    // contact plateau, solved and checked with N_h = H = 10, 15, 20: the
    // reduced solution has no fold, the wheel is unstable, and the leading
    // exponent settles (its changes shrink).
    let mut leading = Vec::new();
    for harmonics in [10, 15, 20] {
        let text = format!(
            "[harmonic_balance]\nharmonics = {harmonics}\n[continuation]\nend_hz = 128.0\n"
        );
        let solution = solve(&text, BasisChoice::Symmetry);
        let point = solution.branch.points.last().unwrap();
        assert!((point.omega / (2.0 * PI) - 128.0).abs() < 1e-9);
        let check = solution
            .stability_check(&StabilitySettings::default())
            .unwrap();
        let stability = check.point(&point.unknowns, point.omega).unwrap();
        assert!(stability.peak_contact_stiffness > 1e7, "on the plateau");
        // No fold: class 0 holds no growing real exponent. (A growing
        // complex one there is a quasi-periodic perturbation, whose class is
        // a convention: the strip's, see `stability::condensed`.)
        let class_0 = stability.class(0).unwrap();
        assert!(class_0
            .exponents
            .iter()
            .all(|e| e.re <= stability.tolerance || e.im.abs() > 1e-6 * point.omega));
        assert!(!stability.stable());
        leading.push(stability.leading().unwrap());
    }
    let classes: Vec<i64> = leading.iter().map(|(c, _)| c.abs()).collect();
    assert!(classes.iter().all(|&c| c == classes[0]), "{leading:?}");
    let first = (leading[1].1.value() - leading[0].1.value()).norm();
    let second = (leading[2].1.value() - leading[1].1.value()).norm();
    assert!(second < 0.6 * first, "{leading:?}");
    assert!(second < 0.05 * leading[2].1.value().norm(), "{leading:?}");
}

#[test]
fn a_run_writes_its_stability_and_reads_it_back() {
    let solution = ForcedResponse::from_case(&case(SMALL))
        .unwrap()
        .stability(Some(StabilitySettings::default()))
        .build()
        .unwrap()
        .run(&mut [])
        .unwrap();
    let computed = solution.stability.computed().expect("computed");
    assert_eq!(computed.points.len(), solution.branch.points.len());
    assert!(computed.points.iter().any(|p| !p.stable()), "the plateau");
    let folder = std::env::temp_dir().join(format!("cyclorub-stability-{}", std::process::id()));
    let (record, data) = cyclorub::run::write(&solution, &folder).unwrap();
    assert_eq!(
        record.stability.status,
        cyclorub::run::StabilityStatus::Computed
    );
    assert_eq!(record.stability.markers.len(), computed.markers.len());
    let table = cyclorub::results::folder::BranchTable::read(&folder.join("branch.csv")).unwrap();
    for (row, point) in table.rows.iter().zip(&computed.points) {
        assert_eq!(
            row.stability,
            Some((point.stable(), point.unstable_exponents()))
        );
    }
    let written = data.stability.expect("in the results data");
    assert_eq!(written.stable.len(), computed.points.len());
    #[cfg(feature = "hdf5")]
    {
        let back = cyclorub::results::hdf5::read(&folder.join("results.h5"))
            .unwrap()
            .stability
            .expect("in results.h5");
        assert_eq!(back.classes, written.classes);
        assert_eq!(back.stable, written.stable);
        assert_eq!(back.unstable_exponents, written.unstable_exponents);
        assert_eq!(back.markers, written.markers);
        let bits = |v: &Vec<Vec<Vec<f64>>>| -> Vec<u64> {
            v.iter().flatten().flatten().map(|x| x.to_bits()).collect()
        };
        assert_eq!(bits(&back.leading_re), bits(&written.leading_re));
        assert_eq!(bits(&back.leading_im), bits(&written.leading_im));
    }
    #[cfg(feature = "plot")]
    assert!(folder.join("plots/stability_exponents.svg").is_file());
    let _ = std::fs::remove_dir_all(&folder);
}

#[test]
fn a_class_mode_mapped_to_the_wheel_is_the_whole_wheel_eigenvector() {
    // The oracle of the mapping from a class's pairs to the sectors
    // (`Stability::modes`): Hill's method on the whole wheel in physical
    // coordinates, which knows nothing of pairs or signs. The leading
    // exponents of classes 0 and 2 at a contact point are simple in the
    // whole wheel's spectrum; their modes at t = 0, displacement and
    // velocity on every dof, are the same vectors up to a complex factor
    // (with the sector phase of the wrong sign, class 2's pairs would give
    // the mode of class −2, whose exponent is the conjugate).
    let solution = solve(RESOLVED, BasisChoice::Symmetry);
    let settings = StabilitySettings::default();
    let check = solution.stability_check(&settings).unwrap();
    let full = Stability::full_wheel(
        &solution.model,
        &solution.problem,
        &solution.case.contact_dofs(),
        &settings,
    )
    .unwrap();
    let point = &solution.branch.points[stiffest_contact(&solution)];
    let whole = full
        .modes(&point.unknowns, point.omega, 0, usize::MAX)
        .unwrap();
    let state = |m: &cyclorub::stability::FloquetMode| -> Vec<c64> {
        let w = 1.0 / point.omega;
        m.displacement
            .iter()
            .copied()
            .chain(m.velocity.iter().map(|v| v * w))
            .collect()
    };
    for sigma in [0, 2] {
        let mode = check
            .modes(&point.unknowns, point.omega, sigma, 1)
            .unwrap()
            .remove(0);
        let lambda = mode.exponent.value();
        let nearest: Vec<_> = whole
            .iter()
            .filter(|m| (m.exponent.value() - lambda).norm() < 1e-6 * lambda.norm().max(1.0))
            .collect();
        assert_eq!(
            nearest.len(),
            1,
            "class {sigma}: λ = {lambda} is simple in the whole wheel"
        );
        let (a, b) = (state(&mode), state(nearest[0]));
        let dot: c64 = a.iter().zip(&b).map(|(x, y)| x.conj() * y).sum();
        let norm = |v: &[c64]| v.iter().map(|z| z.norm_sqr()).sum::<f64>().sqrt();
        let alignment = dot.norm() / (norm(&a) * norm(&b));
        println!(
            "class {sigma}: λ = {lambda:.6}, |cos| between the modes 1 − {:.1e}",
            1.0 - alignment
        );
        assert!(
            1.0 - alignment < 1e-8,
            "class {sigma}: 1 − |cos| = {:e}",
            1.0 - alignment
        );
    }
    assert!(matches!(
        check.modes(&point.unknowns, point.omega, 7, 1),
        Err(cyclorub::stability::StabilityError::NoClass { .. })
    ));
}
