//! Stability of a mistuned wheel's points (issue 44): one symmetry class,
//! the whole wheel, by the condensed Hill method on the mistuned full
//! wheel, against oracles that do not share its assembly: the dense Hill
//! matrix of the wheel assembled here spring by spring with the contact
//! slope of the regularized law sampled here, and, with δ = 0, the union
//! of the tuned wheel's per-class exponents.

use cyclorub::case::BasisChoice;
use cyclorub::forced_response::{prepare, ForcedResponse, Solution, StabilityOutcome};
use cyclorub::hbm::recovery::physical_unknowns;
use cyclorub::stability::{HillSolver, Stability, StabilitySettings};
use faer::{c64, Mat};
use std::f64::consts::PI;
use std::path::Path;

use crate::common::spectra::{largest_mismatch, values};
use crate::mistuning::{assembled, case, deviations_toml};

/// Four sectors with a few harmonics: the whole wheel's Hill matrix of
/// the oracle stays small (2 · 20 dofs · 7 harmonics).
const SECTORS: usize = 4;
const HARMONICS: usize = 3;
const SAMPLES: usize = 96;
const DEVIATIONS: [f64; SECTORS] = [0.03, -0.02, 0.05, -0.04];
const GAP: f64 = 2e-4;

/// The academic wheel of four sectors, Rayleigh damping (so that the
/// oracle can assemble it), a casing close enough to be touched near the
/// first family's resonance, and `extra` appended.
fn academic(extra: &str) -> String {
    format!(
        "[model]\nsectors = {SECTORS}\n[model.damping]\nkind = \"rayleigh\"\nalpha = 3.0\n\
         beta = 2e-6\n[harmonic_balance]\nharmonics = {HARMONICS}\ntime_samples = {SAMPLES}\n\
         [casing]\ngap = {GAP:e}\n[continuation]\ntolerance = 1e-11\nmax_points = 400\n{extra}"
    )
}

/// The exponents `λ` of the dense Hill matrix of `(M, K, C)` with the
/// contact slope `slope[j][m]` (N/m) of sector `j`'s dof m1 at the time
/// samples `θ_m = 2π m / SAMPLES`, in the condensed solver's region
/// (`Re λ ≥ −0.05 ω`, `Im λ ∈ (−ω/2, ω/2]`).
fn dense_hill(wheel: &(Mat<f64>, Mat<f64>, Mat<f64>), slope: &[Vec<f64>], omega: f64) -> Vec<c64> {
    let (mass, stiffness, damping) = wheel;
    let n = mass.nrows();
    let h = HARMONICS as i64;
    let groups = 2 * HARMONICS + 1;
    // The slope's Fourier coefficients `k_p = (1/N_t) Σ_m s(θ_m) e^{−ipθ_m}`.
    let coefficient = |j: usize, p: i64| -> c64 {
        slope[j]
            .iter()
            .enumerate()
            .map(|(m, s)| c64::cis(-(p as f64) * 2.0 * PI * m as f64 / SAMPLES as f64) * *s)
            .sum::<c64>()
            / SAMPLES as f64
    };
    // The mass is diagonal on the academic wheel: M⁻¹ by entries.
    let inverse_mass: Vec<f64> = (0..n).map(|i| 1.0 / mass[(i, i)]).collect();
    let size = 2 * n * groups;
    let mut a = Mat::<c64>::zeros(size, size);
    // State of group g (harmonic k): [q_k; v_k] with v_k = (μ + ik) q_k,
    // in units of ω (μ = λ/ω): the blocks stay of order one, which keeps
    // the dense eigensolver accurate.
    let w2 = omega * omega;
    for (g, k) in (-h..=h).enumerate() {
        let shift = c64::new(0.0, k as f64);
        let (q, v) = (2 * n * g, 2 * n * g + n);
        for i in 0..n {
            a[(q + i, q + i)] = -shift;
            a[(q + i, v + i)] = c64::new(1.0, 0.0);
            a[(v + i, v + i)] -= shift;
            for c in 0..n {
                a[(v + i, q + c)] -= c64::new(stiffness[(i, c)] * inverse_mass[i] / w2, 0.0);
                a[(v + i, v + c)] -= c64::new(damping[(i, c)] * inverse_mass[i] / omega, 0.0);
            }
        }
        for (l, p) in (-h..=h).enumerate() {
            for j in 0..SECTORS {
                let dof = 5 * j;
                let value = coefficient(j, k - p) * (inverse_mass[dof] / w2);
                a[(v + dof, 2 * n * l + dof)] -= value;
            }
        }
    }
    let eigen = a.eigen().expect("eigenvalues");
    (0..size)
        .map(|i| eigen.S()[i] * omega)
        .filter(|z| z.re >= -0.05 * omega && z.im > -0.5 * omega && z.im <= 0.5 * omega)
        .collect()
}

/// `df/dp` of the regularized law (Eq. 70) at penetration `p`.
fn regularized_slope(p: f64, kappa: f64, gamma: f64) -> f64 {
    let half = 0.5 * kappa * p;
    0.5 * kappa * (1.0 + half / (half * half + gamma * gamma).sqrt())
}

/// The contact slope of each sector's m1 at the time samples, from the
/// physical unknowns `x` (sector by sector, `2H + 1` real coordinates).
fn contact_slopes(x: &[f64], kappa: f64, gamma: f64) -> Vec<Vec<f64>> {
    let size = 2 * HARMONICS + 1;
    (0..SECTORS)
        .map(|j| {
            let c = &x[j * size..(j + 1) * size];
            (0..SAMPLES)
                .map(|m| {
                    let theta = 2.0 * PI * m as f64 / SAMPLES as f64;
                    let mut u = c[0];
                    for k in 1..=HARMONICS {
                        u += 2.0
                            * (c64::new(c[2 * k - 1], c[2 * k]) * c64::cis(k as f64 * theta)).re;
                    }
                    regularized_slope(u - GAP, kappa, gamma)
                })
                .collect()
        })
        .collect()
}

fn solved(text: &str, basis: BasisChoice, at_hz: Option<Vec<f64>>) -> Solution {
    let mut request = ForcedResponse::from_case(&case(text)).unwrap().basis(basis);
    if let Some(list) = at_hz {
        request = request.at_frequencies_hz(list);
    }
    request.build().unwrap().run(&mut []).unwrap()
}

#[test]
fn the_mistuned_wheels_exponents_are_the_dense_hill_of_the_assembled_wheel() {
    let text = academic(&format!(
        "[basis]\nkind = \"physical\"\n{}",
        deviations_toml(&DEVIATIONS)
    ));
    let solution = solved(
        &text,
        BasisChoice::Physical,
        Some(vec![200.0, 204.0, 206.0]),
    );
    // Hill's method at every point (no weak-contact shortcut, whose linear
    // exponents are only within a bound of Hill's).
    let settings = StabilitySettings {
        weak_contact_shortcut: false,
        ..StabilitySettings::default()
    };
    let check = solution.stability_check(&settings).unwrap();
    assert!(check.classes().is_empty(), "one class, the whole wheel");
    let oracle = assembled(&DEVIATIONS, 3.0, 2e-6);
    let mut touched = 0;
    for point in &solution.branch.points {
        assert!(point.converged);
        let slopes = contact_slopes(&point.unknowns, 1e8, 2.5);
        let peak = slopes.iter().flatten().fold(0.0_f64, |m, s| m.max(*s));
        let found = check.point(&point.unknowns, point.omega).unwrap();
        assert_eq!(found.classes.len(), 1);
        let exponents = values(&found.classes[0].exponents);
        let reference = dense_hill(&oracle, &slopes, point.omega);
        assert_eq!(
            exponents.len(),
            reference.len(),
            "{} Hz: {exponents:?} against {reference:?}",
            point.omega / (2.0 * PI)
        );
        let mismatch = largest_mismatch(&exponents, &reference);
        assert!(
            mismatch < 1e-8 * point.omega,
            "{} Hz: {mismatch:e}",
            point.omega / (2.0 * PI)
        );
        if peak > 1e6 {
            touched += 1;
            assert!(found.off_contact_bound.is_none(), "solved by Hill's method");
        }
    }
    assert!(
        touched >= 1,
        "no point in contact: the test would not check it"
    );
}

#[test]
fn with_zero_deviations_the_whole_wheel_is_the_union_of_the_tuned_classes() {
    // The tuned wheel on its symmetry basis, checked per class; each of its
    // points carried to the physical unknowns of the δ = 0 wheel, which is
    // checked as a mistuned wheel (one class): by the default (condensed)
    // solver and by the dense Hill matrix in the same region.
    let tuned = solved(&academic(""), BasisChoice::Symmetry, None);
    let zero = prepare(
        &case(&academic(&format!(
            "[basis]\nkind = \"physical\"\n{}",
            deviations_toml(&[0.0; SECTORS])
        ))),
        Path::new("."),
        BasisChoice::Physical,
    )
    .unwrap();
    assert!(zero.model.is_mistuned());
    let checks = |solver| {
        let settings = StabilitySettings {
            solver,
            ..StabilitySettings::default()
        };
        let by_class = tuned.stability_check(&settings).unwrap();
        let whole = Stability::new(
            &zero.model,
            &zero.problem,
            &zero.case.contact_dofs(),
            &settings,
        )
        .unwrap();
        assert!(by_class.classes().len() > 1 && whole.classes().is_empty());
        (by_class, whole)
    };
    let (by_class, whole) = checks(HillSolver::Condensed);
    let (dense_by_class, dense_whole) = checks(HillSolver::DenseRegion);
    let (mut compared, mut unstable) = (0, 0);
    // Every fourth point of the branch (it has some 500 in contact).
    for point in tuned.branch.points.iter().step_by(4) {
        let classes = by_class.point(&point.unknowns, point.omega).unwrap();
        if classes.off_contact_bound.is_some() {
            continue;
        }
        let x = physical_unknowns(&tuned.problem, &point.unknowns);
        let wheel = whole.point(&x, point.omega).unwrap();
        let union = values(&classes.all_exponents());
        let reference = values(&wheel.classes[0].exponents);
        assert_eq!(
            union.len(),
            reference.len(),
            "{union:?} against {reference:?}"
        );
        // The condensed solver's exponents are good to about 1e-8 ω (its
        // residual test, 1e-9): measured 1.1e-8 ω at most on this branch,
        // where the δ = 0 wheel's spectrum holds the pairs ±s twice.
        let mismatch = largest_mismatch(&union, &reference);
        let hz = point.omega / (2.0 * PI);
        assert!(mismatch < 3e-8 * point.omega, "{hz} Hz: {mismatch:e}");
        assert_eq!(classes.stable(), wheel.stable(), "{hz} Hz");
        assert_eq!(classes.unstable_exponents(), wheel.unstable_exponents());
        compared += 1;
        unstable += usize::from(!classes.stable());
        // The dense Hill matrices of the classes and of the whole wheel, at
        // every fourth point compared (they are slow).
        if compared % 4 != 1 {
            continue;
        }
        let dense_union = values(
            &dense_by_class
                .point(&point.unknowns, point.omega)
                .unwrap()
                .all_exponents(),
        );
        let dense = values(&dense_whole.point(&x, point.omega).unwrap().classes[0].exponents);
        assert_eq!(dense_union.len(), dense.len(), "{hz} Hz");
        let mismatch = largest_mismatch(&dense_union, &dense);
        assert!(
            mismatch < 1e-9 * point.omega,
            "{hz} Hz, dense: {mismatch:e}"
        );
        compared += 1;
        unstable += usize::from(!classes.stable());
    }
    assert!(compared >= 20, "{compared} points in contact");
    // The verdict check: the tuned branch has unstable points (between its
    // folds), and the δ = 0 wheel says so of each.
    assert!(unstable >= 1, "no unstable point on the tuned branch");
}

#[test]
fn a_whole_wheel_beyond_the_largest_eigenproblem_is_not_checked_and_says_what_it_would_cost() {
    // 2 · 1 contact dof · 4 sectors · (2 · 300 + 1) = 4808 > 2000.
    let text = academic(&format!(
        "[basis]\nkind = \"physical\"\n{}",
        deviations_toml(&DEVIATIONS)
    ));
    let settings = StabilitySettings {
        harmonics: Some(300),
        ..StabilitySettings::default()
    };
    let solution = ForcedResponse::from_case(&case(&text))
        .unwrap()
        .basis(BasisChoice::Physical)
        .at_frequencies_hz(vec![206.0])
        .stability(Some(settings))
        .build()
        .unwrap()
        .run(&mut [])
        .unwrap();
    match &solution.stability {
        StabilityOutcome::NotComputed { reason } => {
            for words in [
                "whole wheel",
                "size 4808",
                "2404",
                "s of CPU a point",
                "--point",
            ] {
                assert!(reason.contains(words), "{words}: {reason}");
            }
        }
        other => panic!("{other:?}"),
    }
}

#[test]
fn a_long_mistuned_branch_is_not_checked_where_each_point_costs_seconds() {
    // The default 24-sector wheel mistuned at 1 %: its whole-wheel check
    // (a contact resolvent of 24 × 21 = 504) costs seconds a point, which
    // a continuation of thousands of points cannot afford; at fixed
    // frequencies it is made.
    let text = "[mistuning]\nstandard_deviation = 0.01\nseed = 1\n";
    let solver = |at_hz: Option<Vec<f64>>| {
        let builder = ForcedResponse::from_case(&case(text))
            .unwrap()
            .basis(BasisChoice::Physical)
            .stability(Some(StabilitySettings::default()));
        match at_hz {
            Some(list) => builder.at_frequencies_hz(list),
            None => builder,
        }
        .build()
        .unwrap()
    };
    let reason = solver(None)
        .stability_refusal(&StabilitySettings::default())
        .expect("refused along a branch");
    for words in ["whole wheel", "size 504", "--at-hz", "--point"] {
        assert!(reason.contains(words), "{words}: {reason}");
    }
    assert_eq!(
        solver(Some(vec![128.0])).stability_refusal(&StabilitySettings::default()),
        None
    );
}
