//! The harmonic balance core against independent computations: finite
//! differences, the closed-form linear response, and the full wheel.

use cyclorub::basis::SpectralBasis;
use cyclorub::contact::{ContactModel, RegularizedPenalty};
use cyclorub::continuation::{
    continue_branch, solve_at_frequencies, ArcLengthSettings, Evaluation, NewtonSettings, Problem,
};
use cyclorub::cyclic::ExcitationPattern;
use cyclorub::hbm::aft::Aft;
use cyclorub::hbm::recovery::dof_coordinates;
use cyclorub::hbm::{Casing, Forcing, Formulation, HarmonicBalance, ProblemSpec};
use cyclorub::model::SectorModel;
use faer::linalg::solvers::Solve;
use faer::{c64, Mat};
use std::f64::consts::PI;

const GAP: f64 = 1e-3;

struct Case {
    model: SectorModel,
    forcing: Forcing,
    casing: Casing,
    gamma: f64,
    harmonics: usize,
    time_samples: usize,
}

impl Case {
    fn new(sectors: usize, pattern: ExcitationPattern, amplitude: f64) -> Self {
        Self {
            model: SectorModel::academic(sectors).unwrap(),
            forcing: Forcing {
                pattern,
                amplitude,
                dofs: vec![0],
                static_force: 0.0,
            },
            casing: Casing {
                gaps: vec![GAP],
                order: 0,
                amplitudes: vec![0.0],
            },
            gamma: 2.5,
            harmonics: 10,
            time_samples: 960,
        }
    }

    fn spec(&self) -> ProblemSpec<'_> {
        ProblemSpec {
            model: &self.model,
            contact_dofs: &[0],
            forcing: Some(&self.forcing),
            casing: &self.casing,
            contact: ContactModel::Regularized(RegularizedPenalty::new(1e8, self.gamma).unwrap()),
            friction: None,
            preload: None,
            harmonics: self.harmonics,
            time_samples: self.time_samples,
        }
    }

    fn formulations(&self) -> Vec<(&'static str, Formulation)> {
        let spec = self.spec();
        let load = spec.load_case();
        let h = self.harmonics;
        vec![
            (
                "symmetry",
                Formulation::Cyclic(SpectralBasis::symmetry(&load, h).unwrap()),
            ),
            (
                "paper",
                Formulation::Cyclic(SpectralBasis::paper(&load, h).unwrap()),
            ),
            (
                "nodal_diameter",
                Formulation::Cyclic(SpectralBasis::nodal_diameter(&load, h).unwrap()),
            ),
            (
                "full",
                Formulation::Cyclic(SpectralBasis::full(self.model.sectors(), h).unwrap()),
            ),
            ("physical", Formulation::Physical),
        ]
    }
}

fn resonance_hz(model: &SectorModel, nodal_diameter: usize) -> f64 {
    model.natural_frequencies().unwrap()[nodal_diameter].1[0]
}

fn newton_settings() -> NewtonSettings {
    NewtonSettings {
        tolerance: 1e-10,
        max_iterations: 60,
        ..Default::default()
    }
}

/// Max over the period of the dof-0 displacement on every sector.
fn sector_coordinates(problem: &HarmonicBalance, x: &[f64], omega: f64) -> Vec<Vec<f64>> {
    let sectors: Vec<usize> = (0..problem.layout().sectors).collect();
    dof_coordinates(problem, x, omega, 0, &sectors).unwrap()
}

fn peak(coordinates: &[f64], time_samples: usize) -> f64 {
    let harmonics = (coordinates.len() - 1) / 2;
    let mut aft = Aft::new(harmonics, time_samples);
    let mut samples = vec![0.0; time_samples];
    aft.to_time(coordinates, &mut samples);
    samples.iter().cloned().fold(f64::MIN, f64::max)
}

#[test]
fn jacobians_match_central_differences_on_every_basis() {
    let mut mixed = Case::new(24, ExcitationPattern::Traveling { engine_order: 6 }, 3.0);
    mixed.casing = Casing {
        gaps: vec![GAP],
        order: 8,
        amplitudes: vec![0.05 * GAP],
    };
    mixed.harmonics = 4;
    mixed.time_samples = 48;
    let mut standing = Case::new(24, ExcitationPattern::Standing { engine_order: 4 }, 1.0);
    standing.harmonics = 3;
    standing.time_samples = 48;
    // A single traveling load: the symmetry and paper bases are the
    // traveling-wave hypothesis (one signed pair per harmonic).
    let mut traveling = Case::new(24, ExcitationPattern::Traveling { engine_order: 1 }, 4.0);
    traveling.harmonics = 4;
    traveling.time_samples = 48;
    for (case, nd) in [(&mixed, 6), (&standing, 4), (&traveling, 1)] {
        let omega = 2.0 * PI * resonance_hz(&case.model, nd);
        for (name, formulation) in case.formulations() {
            let mut problem = case.spec().build(&formulation).unwrap();
            // A point in contact: the linear response at resonance, which
            // exceeds the gap, a little off the resonance frequency.
            let x = problem.linear_solution(omega).unwrap();
            let omega = omega * 1.003;
            let mut at = Evaluation::default();
            problem.evaluate(&x, omega, true, &mut at).unwrap();
            let n = x.len();
            let mut plus = Evaluation::default();
            let mut minus = Evaluation::default();
            let step: f64 = 1e-10; // round-off dominates below, truncation above
            let mut worst: f64 = 0.0;
            for col in 0..n {
                let mut xp = x.clone();
                let mut xm = x.clone();
                xp[col] += step;
                xm[col] -= step;
                problem.evaluate(&xp, omega, false, &mut plus).unwrap();
                problem.evaluate(&xm, omega, false, &mut minus).unwrap();
                let column: Vec<f64> = (0..n).map(|r| at.jacobian[(r, col)]).collect();
                let scale = column.iter().map(|v| v.abs()).fold(0.0, f64::max);
                for ((p, m), c) in plus.residual.iter().zip(&minus.residual).zip(&column) {
                    let fd = (p - m) / (2.0 * step);
                    worst = worst.max((fd - c).abs() / scale);
                }
            }
            assert!(worst < 1e-6, "{name}: ∂R/∂x relative error {worst:e}");
            let step = omega * 1e-7;
            problem
                .evaluate(&x, omega + step, false, &mut plus)
                .unwrap();
            problem
                .evaluate(&x, omega - step, false, &mut minus)
                .unwrap();
            let scale = at
                .derivative_omega
                .iter()
                .map(|v| v.abs())
                .fold(0.0, f64::max);
            let worst = (0..n)
                .map(|r| {
                    let fd = (plus.residual[r] - minus.residual[r]) / (2.0 * step);
                    (fd - at.derivative_omega[r]).abs() / scale
                })
                .fold(0.0, f64::max);
            assert!(worst < 1e-6, "{name}: ∂R/∂ω relative error {worst:e}");
            // The point really is in contact on some sampled sector.
            let peaks = sector_coordinates(&problem, &x, omega);
            assert!(
                peaks.iter().any(|c| peak(c, 64) > GAP),
                "{name}: no contact at the test point"
            );
        }
    }
}

/// `(K − ω²M + iωC) X = F` on the full wheel, no condensation, no AFT.
fn closed_form_linear(case: &Case, omega: f64) -> Vec<c64> {
    let wheel = case.model.full_wheel().unwrap();
    let n = case.model.sectors();
    let dofs = case.model.dofs_per_sector();
    let size = n * dofs;
    let z = Mat::from_fn(size, size, |r, c| {
        c64::new(
            wheel.stiffness[(r, c)] - omega * omega * wheel.mass[(r, c)],
            omega * wheel.damping[(r, c)],
        )
    });
    // Per-sector forcing of the pattern: a_j cos(ωt + φ_j) = 2 Re(a_j/2 e^{iφ_j} e^{iωt}).
    let alpha = 2.0 * PI / n as f64;
    let rhs = Mat::from_fn(size, 1, |r, _| {
        let (j, d) = (r / dofs, r % dofs);
        if d != 0 {
            return c64::new(0.0, 0.0);
        }
        let phase = |h: f64| c64::cis(h * alpha * j as f64) * 0.5;
        match case.forcing.pattern {
            ExcitationPattern::Traveling { engine_order } => {
                phase(engine_order as f64) * case.forcing.amplitude
            }
            ExcitationPattern::Standing { engine_order } => {
                (phase(engine_order as f64) + phase(-(engine_order as f64)))
                    * case.forcing.amplitude
            }
            _ => unreachable!(),
        }
    });
    let x = z.partial_piv_lu().solve(&rhs);
    (0..n).map(|j| x[(j * dofs, 0)]).collect()
}

#[test]
fn linear_limit_equals_the_closed_form_response() {
    for (pattern, nd) in [
        (ExcitationPattern::Traveling { engine_order: 1 }, 1),
        (ExcitationPattern::Standing { engine_order: 4 }, 4),
    ] {
        let mut case = Case::new(24, pattern, 4.0);
        case.casing.gaps = vec![10.0]; // far away: no contact
        case.gamma = 0.0; // plain penalty: exactly zero force off contact
        let f = resonance_hz(&case.model, nd);
        for (name, formulation) in case.formulations() {
            let mut problem = case.spec().build(&formulation).unwrap();
            for factor in [0.9, 0.999, 1.0, 1.01, 1.2] {
                let omega = 2.0 * PI * f * factor;
                let mut x = problem.linear_solution(omega).unwrap();
                x.iter_mut().for_each(|v| *v *= 0.5); // Newton must find it
                let branch =
                    solve_at_frequencies(&mut problem, x, &[omega], &newton_settings(), |_, _| {});
                let point = &branch.points[0];
                assert!(point.converged, "{name} at {factor}");
                let exact = closed_form_linear(&case, omega);
                let coordinates = sector_coordinates(&problem, &point.unknowns, omega);
                for (j, (c, e)) in coordinates.iter().zip(&exact).enumerate() {
                    // Harmonic 1 only: u = 2 Re(X e^{iωt}), peak 2|X|.
                    let amplitude = 2.0 * c[1].hypot(c[2]);
                    let reference = 2.0 * e.norm();
                    assert!(
                        (amplitude - reference).abs() <= 1e-9 * reference,
                        "{name} sector {j} at {factor}: {amplitude} vs {reference}"
                    );
                    assert!(
                        (c[1] - e.re).abs() <= 1e-9 * e.norm()
                            && (c[2] - e.im).abs() <= 1e-9 * e.norm()
                    );
                    let rest: f64 = c[3..]
                        .iter()
                        .chain(&c[..1])
                        .map(|v| v.abs())
                        .fold(0.0, f64::max);
                    assert!(rest <= 1e-9 * e.norm(), "{name}: other harmonics {rest:e}");
                }
            }
        }
    }
}

#[test]
fn static_preload_gives_the_closed_form_static_response() {
    // A static force on every blade tip and a small traveling load, far
    // from the casing: harmonic 0 is K⁻¹ f0 on the whole wheel, on every
    // sector and every basis.
    let mut case = Case::new(24, ExcitationPattern::Traveling { engine_order: 1 }, 0.5);
    case.forcing.static_force = 40.0;
    case.casing.gaps = vec![10.0];
    case.gamma = 0.0;
    case.harmonics = 3;
    case.time_samples = 48;
    let wheel = case.model.full_wheel().unwrap();
    let dofs = case.model.dofs_per_sector();
    let size = case.model.sectors() * dofs;
    let rhs = Mat::from_fn(size, 1, |r, _| if r % dofs == 0 { 40.0 } else { 0.0 });
    let exact = wheel.stiffness.partial_piv_lu().solve(&rhs);
    let omega = 2.0 * PI * 0.9 * resonance_hz(&case.model, 1);
    for (name, formulation) in case.formulations() {
        let mut problem = case.spec().build(&formulation).unwrap();
        let x = problem.linear_solution(omega).unwrap();
        for dof in [0, 3] {
            let sectors: Vec<usize> = (0..case.model.sectors()).collect();
            let coordinates = dof_coordinates(&problem, &x, omega, dof, &sectors).unwrap();
            for (j, c) in coordinates.iter().enumerate() {
                let reference = exact[(j * dofs + dof, 0)];
                assert!(reference.abs() > 1e-7, "a static deflection to check");
                assert!(
                    (c[0] - reference).abs() <= 1e-9 * reference.abs(),
                    "{name}, dof {dof}, sector {j}: {} vs {reference}",
                    c[0]
                );
            }
        }
    }
}

/// Natural continuation over `count` frequencies from `from` to `to` times
/// the first resonance of `nodal_diameter`, on every formulation of `kinds`.
fn reduced_equals_full(
    case: &Case,
    nodal_diameter: usize,
    (from, to, count): (f64, f64, usize),
    kinds: &[&str],
) {
    let f = resonance_hz(&case.model, nodal_diameter);
    let omegas: Vec<f64> = (0..count)
        .map(|i| 2.0 * PI * f * (from + (to - from) * i as f64 / (count - 1) as f64))
        .collect();
    let mut results = Vec::new();
    for (name, formulation) in case.formulations() {
        if !kinds.contains(&name) {
            continue;
        }
        let mut problem = case.spec().build(&formulation).unwrap();
        let start = problem.linear_solution(omegas[0]).unwrap();
        let branch =
            solve_at_frequencies(&mut problem, start, &omegas, &newton_settings(), |_, _| {});
        let mut all = Vec::new();
        let mut contact = false;
        for point in &branch.points {
            assert!(point.converged, "{name} at {} Hz", point.omega / 2.0 / PI);
            let c = sector_coordinates(&problem, &point.unknowns, point.omega);
            contact |= c.iter().any(|c| peak(c, 256) > GAP);
            all.push(c);
        }
        assert!(contact, "{name}: the test never reaches the casing");
        results.push((name, problem.unknowns(), all));
    }
    let (_, _, reference) = results.iter().find(|(n, _, _)| *n == "physical").unwrap();
    for (name, unknowns, result) in &results {
        for (point, (a, b)) in result.iter().zip(reference).enumerate() {
            let scale = b.iter().flatten().map(|v| v.abs()).fold(0.0, f64::max);
            let difference = a
                .iter()
                .flatten()
                .zip(b.iter().flatten())
                .map(|(x, y)| (x - y).abs())
                .fold(0.0, f64::max);
            assert!(
                difference <= 1e-8 * scale,
                "{name} ({unknowns} unknowns) point {point}: relative difference {:e}",
                difference / scale
            );
        }
    }
}

#[test]
fn reduced_equals_full_traveling_wave_h1() {
    let case = Case::new(24, ExcitationPattern::Traveling { engine_order: 1 }, 4.0);
    reduced_equals_full(
        &case,
        1,
        (0.99, 1.01, 21),
        &["symmetry", "paper", "physical"],
    );
}

#[test]
fn reduced_equals_full_standing_wave_h4() {
    let case = Case::new(24, ExcitationPattern::Standing { engine_order: 4 }, 1.0);
    reduced_equals_full(
        &case,
        4,
        (0.99, 1.004, 15),
        &["symmetry", "paper", "physical"],
    );
}

#[test]
fn reduced_equals_full_traveling_wave_h6_with_casing_h8() {
    let mut case = Case::new(24, ExcitationPattern::Traveling { engine_order: 6 }, 3.0);
    case.casing = Casing {
        gaps: vec![GAP],
        order: 8,
        amplitudes: vec![0.05 * GAP],
    };
    reduced_equals_full(
        &case,
        6,
        (0.99, 1.01, 21),
        &["symmetry", "paper", "physical"],
    );
}

#[test]
fn continuation_goes_through_turning_points() {
    let mut case = Case::new(24, ExcitationPattern::Traveling { engine_order: 1 }, 4.0);
    case.time_samples = 960;
    let f = resonance_hz(&case.model, 1);
    let basis = SpectralBasis::symmetry(&case.spec().load_case(), case.harmonics).unwrap();
    let mut problem = case.spec().build(&Formulation::Cyclic(basis)).unwrap();
    let start = 2.0 * PI * f * 0.9;
    let settings = ArcLengthSettings {
        start,
        end: 2.0 * PI * f * 1.3,
        initial_step: 0.01,
        min_step: 1e-6,
        max_step: 0.2,
        length_scale: GAP,
        newton: NewtonSettings {
            tolerance: 1e-8,
            max_iterations: 12,
            ..Default::default()
        },
        max_points: 3000,
    };
    let guess = problem.linear_solution(start).unwrap();
    let branch = continue_branch(&mut problem, guess, &settings, |_, _| {});
    assert_eq!(
        branch.stop,
        cyclorub::continuation::StopReason::EndReached,
        "{:?}",
        branch.stop
    );
    let reversals = branch
        .points
        .windows(3)
        .filter(|w| (w[1].omega - w[0].omega) * (w[2].omega - w[1].omega) < 0.0)
        .count();
    assert!(
        reversals >= 1,
        "no turning point in {} points",
        branch.points.len()
    );
    let mut evaluation = Evaluation::default();
    for point in &branch.points {
        problem
            .evaluate(&point.unknowns, point.omega, false, &mut evaluation)
            .unwrap();
        let r = evaluation
            .residual
            .iter()
            .map(|v| v * v)
            .sum::<f64>()
            .sqrt()
            / problem.force_scale();
        assert!(r <= 1e-8, "residual {r:e} at {} Hz", point.omega / 2.0 / PI);
    }
}

/// `a` equals `b` to 1e-12 of `b`'s largest entry (which is not zero).
fn assert_close(a: &[f64], b: &[f64], what: &str) {
    let scale = b.iter().fold(0.0_f64, |m, v| m.max(v.abs()));
    let worst = a
        .iter()
        .zip(b)
        .fold(0.0_f64, |m, (x, y)| m.max((x - y).abs()));
    assert!(scale > 0.0 && a.len() == b.len(), "{what}");
    assert!(worst <= 1e-12 * scale, "{what}: {:e}", worst / scale);
}

/// The linear solution at any frequency from a shared problem (what the
/// linear response of a results folder reads, in parallel, block by block)
/// is the dense solve of the cached `Z` to rounding, rigid casing or wall,
/// across the resonance, and leaves the cache alone.
#[test]
fn the_linear_solution_at_any_frequency_is_the_cached_one() {
    use cyclorub::contact::DynamicLagrangian;
    let case = Case::new(24, ExcitationPattern::Traveling { engine_order: 1 }, 4.0);
    let f = resonance_hz(&case.model, 1);
    for wall in [None, Some(1e8)] {
        for (name, formulation) in case.formulations() {
            let mut spec = case.spec();
            spec.contact = ContactModel::Lagrangian(DynamicLagrangian::new(1e9, wall).unwrap());
            let mut problem = spec.build(&formulation).unwrap();
            for factor in [0.5, 0.999, 1.3] {
                let omega = 2.0 * PI * f * factor;
                let shared = problem
                    .linear()
                    .solution_at(problem.layout(), 0.7 * omega)
                    .unwrap();
                let cached = problem.linear_solution(0.7 * omega).unwrap();
                assert_close(&shared, &cached, &format!("{name}, wall {wall:?}"));
                // The cache holds 0.7 ω; a solution elsewhere does not move it.
                let before = problem.linear().dynamic.clone();
                let elsewhere = problem
                    .linear()
                    .solution_at(problem.layout(), omega)
                    .unwrap();
                assert_eq!(problem.linear().dynamic, before, "{name}");
                let dense = problem.linear_solution(omega).unwrap();
                assert_close(&elsewhere, &dense, &format!("{name}, wall {wall:?}"));
            }
        }
    }
}

/// The linear response solved on each loaded block's own dofs (what the
/// linear curve of `results.h5` reads, no condensation) equals the
/// condensed solution recovered, on every basis, with a rigid casing and
/// with a wall, a static force and a standing load, across the resonance,
/// for a contact dof and an interior one: to 1e-10 of the largest
/// coordinate (measured 1.6e-12 at most: the wall's series condensation
/// loses a few digits).
#[test]
fn the_linear_response_solved_on_whole_blocks_equals_the_condensed_one_recovered() {
    use cyclorub::contact::DynamicLagrangian;
    use cyclorub::hbm::recovery::linear_dof_coordinates;
    for pattern in [
        ExcitationPattern::Traveling { engine_order: 1 },
        ExcitationPattern::Standing { engine_order: 2 },
    ] {
        let mut case = Case::new(8, pattern.clone(), 4.0);
        case.forcing.static_force = 25.0;
        let f = resonance_hz(&case.model, 1);
        let sectors: Vec<usize> = (0..case.model.sectors()).collect();
        for wall in [None, Some(1e8)] {
            for (name, formulation) in case.formulations() {
                let mut spec = case.spec();
                spec.contact = ContactModel::Lagrangian(DynamicLagrangian::new(1e9, wall).unwrap());
                let problem = spec.build(&formulation).unwrap();
                for factor in [0.5, 0.999, 1.3] {
                    let omega = 2.0 * PI * f * factor;
                    let x = problem
                        .linear()
                        .solution_at(problem.layout(), omega)
                        .unwrap();
                    for dof in [0, 3] {
                        let what = format!("{pattern:?}, {name}, wall {wall:?}, dof {dof}");
                        let condensed =
                            dof_coordinates(&problem, &x, omega, dof, &sectors).unwrap();
                        let whole =
                            linear_dof_coordinates(&problem, omega, dof, &sectors, |_| true)
                                .unwrap();
                        let (a, b) = (whole.concat(), condensed.concat());
                        let scale = b.iter().fold(0.0_f64, |m, v| m.max(v.abs()));
                        let worst = a
                            .iter()
                            .zip(&b)
                            .fold(0.0_f64, |m, (x, y)| m.max((x - y).abs()));
                        assert!(scale > 0.0 && a.len() == b.len(), "{what}");
                        assert!(worst <= 1e-10 * scale, "{what}: {:e}", worst / scale);
                    }
                }
            }
        }
    }
}
