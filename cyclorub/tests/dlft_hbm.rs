//! DLFT-HBM (issue 5) against independent computations: finite
//! differences, the closed-form linear response, the explicit wall spring,
//! the contact conditions, the penalty law in its nonsmooth limit, and the
//! full wheel.

use cyclorub::basis::SpectralBasis;
use cyclorub::contact::{ContactModel, DynamicLagrangian, RegularizedPenalty};
use cyclorub::continuation::{
    continue_branch, continue_from_both_ends, solve_at_frequencies, ArcLengthSettings, Branch,
    Evaluation, NewtonSettings, Problem, StopReason,
};
use cyclorub::cyclic::ExcitationPattern;
use cyclorub::hbm::aft::Aft;
use cyclorub::hbm::recovery::{dof_coordinates, wall_coordinates};
use cyclorub::hbm::{Casing, Forcing, Formulation, HarmonicBalance, ProblemSpec};
use cyclorub::model::SectorModel;
use faer::linalg::solvers::Solve;
use faer::{c64, Mat};
use std::f64::consts::PI;

const GAP: f64 = 1e-3;
/// The paper's wall and Lagrangian weight (Sec. 4.1).
const WALL: f64 = 1e8;
const EPSILON: f64 = 1e9;

struct Case {
    model: SectorModel,
    forcing: Forcing,
    casing: Casing,
    contact: ContactModel,
    harmonics: usize,
    time_samples: usize,
}

fn dlft(epsilon: f64, wall: Option<f64>) -> ContactModel {
    ContactModel::Lagrangian(DynamicLagrangian::new(epsilon, wall).unwrap())
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
            contact: dlft(EPSILON, Some(WALL)),
            harmonics: 10,
            time_samples: 480,
        }
    }

    fn spec(&self) -> ProblemSpec<'_> {
        ProblemSpec {
            model: &self.model,
            contact_dofs: &[0],
            forcing: Some(&self.forcing),
            casing: &self.casing,
            contact: self.contact.clone(),
            friction: None,
            preload: None,
            harmonics: self.harmonics,
            time_samples: self.time_samples,
        }
    }

    fn formulation(&self, name: &str) -> Formulation {
        let load = self.spec().load_case();
        let h = self.harmonics;
        match name {
            "symmetry" => Formulation::Cyclic(SpectralBasis::symmetry(&load, h).unwrap()),
            "paper" => Formulation::Cyclic(SpectralBasis::paper(&load, h).unwrap()),
            "nodal_diameter" => {
                Formulation::Cyclic(SpectralBasis::nodal_diameter(&load, h).unwrap())
            }
            "full" => Formulation::Cyclic(SpectralBasis::full(self.model.sectors(), h).unwrap()),
            "physical" => Formulation::Physical,
            other => panic!("no formulation {other}"),
        }
    }

    fn build(&self, name: &str) -> HarmonicBalance {
        self.spec().build(&self.formulation(name)).unwrap()
    }

    fn resonance_hz(&self, nodal_diameter: usize) -> f64 {
        self.model.natural_frequencies().unwrap()[nodal_diameter].1[0]
    }
}

const FORMULATIONS: [&str; 5] = ["symmetry", "paper", "nodal_diameter", "full", "physical"];

fn newton_settings() -> NewtonSettings {
    NewtonSettings {
        tolerance: 1e-10,
        max_iterations: 40,
        ..Default::default()
    }
}

fn norm(v: &[f64]) -> f64 {
    v.iter().map(|x| x * x).sum::<f64>().sqrt()
}

/// The blade tip (dof 0) on every sector.
fn blade(problem: &HarmonicBalance, x: &[f64], omega: f64) -> Vec<Vec<f64>> {
    let sectors: Vec<usize> = (0..problem.layout().sectors).collect();
    dof_coordinates(problem, x, omega, 0, &sectors).unwrap()
}

/// Max over the period of a signal given by its coordinates.
fn peak(coordinates: &[f64], time_samples: usize) -> f64 {
    let harmonics = (coordinates.len() - 1) / 2;
    let mut aft = Aft::new(harmonics, time_samples);
    let mut samples = vec![0.0; time_samples];
    aft.to_time(coordinates, &mut samples);
    samples.iter().cloned().fold(f64::MIN, f64::max)
}

/// The contact mask `λ > 0` at every sampled instant.
fn mask(problem: &mut HarmonicBalance, x: &[f64], omega: f64) -> Vec<bool> {
    let samples = problem.contact_samples(x, omega).unwrap();
    samples
        .multiplier
        .unwrap()
        .iter()
        .flatten()
        .map(|&l| l > 0.0)
        .collect()
}

/// Largest relative difference between two sets of sector coordinates.
fn relative_difference(a: &[Vec<f64>], b: &[Vec<f64>]) -> f64 {
    let scale = b.iter().flatten().map(|v| v.abs()).fold(0.0, f64::max);
    let difference = a
        .iter()
        .flatten()
        .zip(b.iter().flatten())
        .map(|(x, y)| (x - y).abs())
        .fold(0.0, f64::max);
    difference / scale
}

#[test]
fn dlft_jacobians_match_central_differences_on_every_basis() {
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
    for (case, nd) in [(&mut mixed, 6), (&mut standing, 4)] {
        for wall in [Some(WALL), None] {
            case.contact = dlft(EPSILON, wall);
            let omega = 2.0 * PI * case.resonance_hz(nd);
            for name in FORMULATIONS {
                let mut problem = case.build(name);
                // A point in contact: the linear response at resonance,
                // which exceeds the gap, a little off the resonance.
                let x = problem.linear_solution(omega).unwrap();
                let omega = omega * 1.003;
                let here = mask(&mut problem, &x, omega);
                let contact = here.iter().filter(|&&m| m).count();
                assert!(
                    contact > 0 && contact < here.len(),
                    "{name}: the test point must be partly in contact ({contact} of {})",
                    here.len()
                );
                let mut at = Evaluation::default();
                problem.evaluate(&x, omega, true, &mut at).unwrap();
                let n = x.len();
                let (mut plus, mut minus) = (Evaluation::default(), Evaluation::default());
                // Within one contact state the residual is affine in x:
                // central differences are exact but for round-off, which
                // the large ε x terms make a longer step worth taking.
                let step: f64 = 1e-8;
                let (mut worst, mut skipped): (f64, usize) = (0.0, 0);
                for col in 0..n {
                    let mut xp = x.clone();
                    let mut xm = x.clone();
                    xp[col] += step;
                    xm[col] -= step;
                    // Away from contact switches only.
                    if mask(&mut problem, &xp, omega) != here
                        || mask(&mut problem, &xm, omega) != here
                    {
                        skipped += 1;
                        continue;
                    }
                    problem.evaluate(&xp, omega, false, &mut plus).unwrap();
                    problem.evaluate(&xm, omega, false, &mut minus).unwrap();
                    let column: Vec<f64> = (0..n).map(|r| at.jacobian[(r, col)]).collect();
                    let scale = column.iter().map(|v| v.abs()).fold(0.0, f64::max);
                    for ((p, m), c) in plus.residual.iter().zip(&minus.residual).zip(&column) {
                        let fd = (p - m) / (2.0 * step);
                        worst = worst.max((fd - c).abs() / scale);
                    }
                }
                eprintln!(
                    "{name} wall {wall:?}: {skipped} of {n} columns skipped, ∂R/∂x error {worst:e}"
                );
                assert!(skipped * 10 <= n, "{name}: {skipped} of {n} columns switch");
                assert!(
                    worst < 1e-6,
                    "{name} wall {wall:?}: ∂R/∂x relative error {worst:e}"
                );
                let step = omega * 1e-6;
                assert!(mask(&mut problem, &x, omega + step) == here);
                assert!(mask(&mut problem, &x, omega - step) == here);
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
                assert!(
                    worst < 1e-6,
                    "{name} wall {wall:?}: ∂R/∂ω relative error {worst:e}"
                );
            }
        }
    }
}

/// `(K − ω²M + iωC) X = F` on the full wheel, no condensation, no AFT:
/// the blade tip on every sector.
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
    let alpha = 2.0 * PI / n as f64;
    let ExcitationPattern::Traveling { engine_order } = case.forcing.pattern else {
        unreachable!()
    };
    // a cos(ωt + φ_j) = 2 Re(a/2 e^{iφ_j} e^{iωt}).
    let rhs = Mat::from_fn(size, 1, |r, _| {
        let (j, d) = (r / dofs, r % dofs);
        if d == 0 {
            c64::cis(engine_order as f64 * alpha * j as f64) * (0.5 * case.forcing.amplitude)
        } else {
            c64::new(0.0, 0.0)
        }
    });
    let x = z.partial_piv_lu().solve(&rhs);
    (0..n).map(|j| x[(j * dofs, 0)]).collect()
}

#[test]
fn wall_leaves_the_linear_response_unchanged_and_recovers_the_blade() {
    // Far from the casing the wall carries no force: blade and wall node
    // move together, and both equal the closed-form response.
    let mut case = Case::new(24, ExcitationPattern::Traveling { engine_order: 1 }, 4.0);
    case.casing.gaps = vec![10.0];
    let f = case.resonance_hz(1);
    for name in ["symmetry", "physical"] {
        let mut problem = case.build(name);
        for factor in [0.9, 1.0, 1.2] {
            let omega = 2.0 * PI * f * factor;
            let mut x = problem.linear_solution(omega).unwrap();
            x.iter_mut().for_each(|v| *v *= 0.5);
            let branch =
                solve_at_frequencies(&mut problem, x, &[omega], &newton_settings(), |_, _| {});
            let point = &branch.points[0];
            assert!(point.converged, "{name} at {factor}");
            let exact = closed_form_linear(&case, omega);
            let tip = blade(&problem, &point.unknowns, omega);
            let sectors: Vec<usize> = (0..24).collect();
            let node = wall_coordinates(&problem, &point.unknowns, 0, &sectors);
            for (j, e) in exact.iter().enumerate() {
                for c in [&tip[j], &node[j]] {
                    assert!(
                        (c[1] - e.re).abs() <= 1e-9 * e.norm()
                            && (c[2] - e.im).abs() <= 1e-9 * e.norm(),
                        "{name} sector {j} at {factor}: ({}, {}) vs {e}",
                        c[1],
                        c[2]
                    );
                }
            }
        }
    }
}

/// Natural continuation of `case` on `name` over `omegas`; every point converged.
fn sweep(case: &Case, name: &str, omegas: &[f64]) -> (HarmonicBalance, Branch) {
    sweep_with(case, name, omegas, &newton_settings())
}

fn sweep_with(
    case: &Case,
    name: &str,
    omegas: &[f64],
    settings: &NewtonSettings,
) -> (HarmonicBalance, Branch) {
    let mut problem = case.build(name);
    let start = problem.linear_solution(omegas[0]).unwrap();
    let branch = solve_at_frequencies(&mut problem, start, omegas, settings, |_, _| {});
    for point in &branch.points {
        assert!(
            point.converged,
            "{name} at {} Hz: residual {:e}",
            point.omega / 2.0 / PI,
            point.residual_norm
        );
    }
    (problem, branch)
}

fn frequencies(f: f64, from: f64, to: f64, count: usize) -> Vec<f64> {
    (0..count)
        .map(|i| 2.0 * PI * f * (from + (to - from) * i as f64 / (count - 1) as f64))
        .collect()
}

#[test]
fn wall_spring_carries_the_contact_force() {
    // At convergence the spring between blade tip and wall node carries the
    // contact force, harmonic by harmonic: κ (x_b − x_w) = F[f] on each sector.
    let case = Case::new(24, ExcitationPattern::Traveling { engine_order: 1 }, 4.0);
    let f = case.resonance_hz(1);
    let omegas = frequencies(f, 0.995, 1.002, 4);
    let (mut problem, branch) = sweep(&case, "physical", &omegas);
    let sectors: Vec<usize> = (0..24).collect();
    let mut aft = Aft::new(case.harmonics, case.time_samples);
    let mut loaded = 0;
    for point in &branch.points {
        let tip = blade(&problem, &point.unknowns, point.omega);
        let node = wall_coordinates(&problem, &point.unknowns, 0, &sectors);
        let samples = problem
            .contact_samples(&point.unknowns, point.omega)
            .unwrap();
        let mut force = vec![0.0; 2 * case.harmonics + 1];
        let scale = samples
            .force
            .iter()
            .flatten()
            .fold(0.0_f64, |a, &b| a.max(b));
        if scale > 0.0 {
            loaded += 1;
        }
        for j in 0..24 {
            aft.to_frequency(&samples.force[j], &mut force);
            for (h, f) in force.iter().enumerate() {
                let spring = WALL * (tip[j][h] - node[j][h]);
                assert!(
                    (spring - f).abs() <= 1e-8 * scale.max(1.0),
                    "sector {j} coordinate {h}: spring {spring} vs contact {f}"
                );
            }
        }
    }
    assert!(loaded >= 2, "the test must reach contact");
}

/// `P f`: the time samples of the harmonics (up to `N_h`) of `f`.
fn truncated(aft: &mut Aft, f: &[f64]) -> Vec<f64> {
    let mut coordinates = vec![0.0; aft.coordinates()];
    aft.to_frequency(f, &mut coordinates);
    let mut samples = vec![0.0; f.len()];
    aft.to_time(&coordinates, &mut samples);
    samples
}

#[test]
fn complementarity_holds_at_every_sampled_instant() {
    // In the paper's signs: force ≤ 0, gap ≥ −tolerance, force × gap ≈ 0;
    // in ours f ≥ 0, p = −gap. At convergence the prediction is
    // λ = P f + ε p (P: truncation to N_h harmonics), so that contact
    // instants have ε p = f − P f: exact complementarity when the sampling
    // is square (N_t = 2 N_h + 1, P f = f), else a penetration bounded by
    // the truncation error of the force over ε.
    let mut travelling = Case::new(24, ExcitationPattern::Traveling { engine_order: 1 }, 4.0);
    let mut casing = Case::new(24, ExcitationPattern::Traveling { engine_order: 6 }, 3.0);
    casing.casing = Casing {
        gaps: vec![GAP],
        order: 8,
        amplitudes: vec![0.05 * GAP],
    };
    for (case, nd) in [(&mut travelling, 1), (&mut casing, 6)] {
        for (time_samples, wall) in [(21, Some(WALL)), (960, Some(WALL)), (960, None)] {
            case.time_samples = time_samples;
            case.contact = dlft(EPSILON, wall);
            let f = case.resonance_hz(nd);
            let omegas = frequencies(f, 0.996, 1.001, 6);
            let (mut problem, branch) = sweep(case, "symmetry", &omegas);
            let mut aft = Aft::new(case.harmonics, time_samples);
            let mut touched = 0;
            for point in &branch.points {
                let s = problem
                    .contact_samples(&point.unknowns, point.omega)
                    .unwrap();
                let lambda = s.multiplier.as_ref().unwrap();
                let max_force = s.force.iter().flatten().fold(0.0_f64, |a, &b| a.max(b));
                for ((forces, penetrations), lambda) in
                    s.force.iter().zip(&s.penetration).zip(lambda)
                {
                    let smooth = truncated(&mut aft, forces);
                    let truncation = forces
                        .iter()
                        .zip(&smooth)
                        .map(|(f, p)| (f - p).abs())
                        .fold(0.0, f64::max);
                    if time_samples == 2 * case.harmonics + 1 {
                        assert!(truncation <= 1e-9 * max_force.max(1.0));
                    }
                    let slack = truncation / EPSILON + 1e-12 * GAP;
                    for n in 0..forces.len() {
                        let (force, gap) = (forces[n], -penetrations[n]);
                        // λ = P f + ε p at convergence.
                        assert!(
                            (lambda[n] - smooth[n] - EPSILON * penetrations[n]).abs()
                                <= 1e-6 * max_force.max(1.0),
                            "λ {} vs P f + ε p {}",
                            lambda[n],
                            smooth[n] + EPSILON * penetrations[n]
                        );
                        assert!(force >= 0.0);
                        assert!(
                            gap >= -slack,
                            "N_t {time_samples} wall {wall:?}: gap {gap:e} m below −{slack:e}"
                        );
                        assert!(
                            (force * gap).abs() <= max_force * slack,
                            "N_t {time_samples}: force {force} N × gap {gap:e} m"
                        );
                        if force > 0.0 {
                            touched += 1;
                        }
                    }
                }
            }
            assert!(
                touched > 0,
                "nd {nd}, N_t {time_samples}: no contact reached"
            );
        }
    }
}

#[test]
fn converged_solution_does_not_depend_on_epsilon_with_square_sampling() {
    // With N_t = 2 N_h + 1 the sampled contact conditions are exact and ε
    // drops out of the converged solution: two ε a decade apart agree to
    // round-off, at points in and out of contact, rigid wall or not.
    let mut case = Case::new(24, ExcitationPattern::Traveling { engine_order: 1 }, 4.0);
    case.time_samples = 2 * case.harmonics + 1;
    let f = case.resonance_hz(1);
    let omegas = frequencies(f, 0.997, 1.003, 7);
    for wall in [Some(WALL), None] {
        let mut tips = Vec::new();
        for epsilon in [EPSILON, 10.0 * EPSILON] {
            case.contact = dlft(epsilon, wall);
            let (mut problem, branch) = sweep(&case, "symmetry", &omegas);
            let contact = branch
                .points
                .iter()
                .filter(|p| {
                    let s = problem.contact_samples(&p.unknowns, p.omega).unwrap();
                    s.force.iter().flatten().any(|&f| f > 0.0)
                })
                .count();
            assert!(contact >= 3, "only {contact} points in contact");
            tips.push(
                branch
                    .points
                    .iter()
                    .map(|p| blade(&problem, &p.unknowns, p.omega))
                    .collect::<Vec<_>>(),
            );
        }
        let worst = tips[0]
            .iter()
            .zip(&tips[1])
            .map(|(a, b)| relative_difference(a, b))
            .fold(0.0, f64::max);
        eprintln!("square sampling, wall {wall:?}: ε ×10 changes the blade by {worst:e}");
        assert!(
            worst <= 1e-8,
            "wall {wall:?}: relative difference {worst:e}"
        );
    }
}

#[test]
fn epsilon_dependence_with_finer_sampling_vanishes_like_one_over_epsilon() {
    // With N_t > 2 N_h + 1 the converged solution depends on ε through the
    // truncation of the contact force (ε p = f − P f at contact instants):
    // a decade of ε divides the change by ten.
    let mut case = Case::new(24, ExcitationPattern::Traveling { engine_order: 1 }, 4.0);
    case.time_samples = 48;
    let f = case.resonance_hz(1);
    // From before contact (127.47 Hz) into it, 0.5 % of f apart.
    let omegas = frequencies(f, 0.997, 1.002, 11);
    let mut tips = Vec::new();
    for epsilon in [EPSILON, 10.0 * EPSILON, 100.0 * EPSILON] {
        case.contact = dlft(epsilon, Some(WALL));
        let settings = NewtonSettings {
            tolerance: 1e-9,
            max_iterations: 60,
            ..Default::default()
        };
        let (problem, branch) = sweep_with(&case, "symmetry", &omegas, &settings);
        tips.push(
            branch
                .points
                .iter()
                .map(|p| blade(&problem, &p.unknowns, p.omega))
                .collect::<Vec<_>>(),
        );
    }
    // The points past the first contact (at 0.9982 f).
    for (i, ((a, b), c)) in tips[0]
        .iter()
        .zip(&tips[1])
        .zip(&tips[2])
        .enumerate()
        .skip(5)
    {
        let first = relative_difference(a, b);
        let second = relative_difference(b, c);
        assert!(first > 1e-6 && first < 1e-3, "point {i}: {first:e}");
        let ratio = first / second;
        eprintln!(
            "N_t = 48, point {i}: ε 1e9 → 1e10 changes {first:.3e}, 1e10 → 1e11 {second:.3e}"
        );
        assert!((8.0..12.5).contains(&ratio), "point {i}: ratio {ratio}");
    }
}

#[test]
fn regularized_penalty_tends_to_dlft_as_gamma_vanishes() {
    // R-HBM with the wall's stiffness κ against DLFT with the wall. Before
    // contact the regularization force γ²/(κ |p|) is all that differs: the
    // difference shrinks a hundredfold per decade of γ. In contact both
    // laws carry the same continuous model, but the penalty law gives the
    // spring force f(t) = κ max(0, x − g0) sample by sample, the wall only
    // its truncation to N_h harmonics: R-HBM converges (to its γ = 0 law)
    // and stays within the truncation error of DLFT.
    let mut case = Case::new(24, ExcitationPattern::Traveling { engine_order: 1 }, 4.0);
    let f = case.resonance_hz(1);
    // One sweep from before contact (first contact at 0.9982 f) into it.
    let omegas = frequencies(f, 0.996, 1.001, 11);
    let (free, touching) = (0..3, 6..11);
    let settings = NewtonSettings {
        tolerance: 1e-9,
        max_iterations: 60,
        ..Default::default()
    };
    let amplitudes = |case: &Case, omegas: &[f64]| -> Vec<f64> {
        let (problem, branch) = sweep_with(case, "symmetry", omegas, &settings);
        branch
            .points
            .iter()
            .map(|p| peak(&blade(&problem, &p.unknowns, p.omega)[0], 2048))
            .collect()
    };
    let reference = amplitudes(&case, &omegas);
    let (reference_free, reference_touching) =
        (&reference[free.clone()], &reference[touching.clone()]);
    let (mut previous_free, mut previous_touching): (f64, Option<Vec<f64>>) = (f64::MAX, None);
    for gamma in [2.5, 0.25, 0.025] {
        case.contact = ContactModel::Regularized(RegularizedPenalty::new(WALL, gamma).unwrap());
        let all = amplitudes(&case, &omegas);
        let (out, inside) = (&all[free.clone()], all[touching.clone()].to_vec());
        let difference = out
            .iter()
            .zip(reference_free)
            .map(|(a, r)| (a - r).abs() / r)
            .fold(0.0, f64::max);
        let distance = inside
            .iter()
            .zip(reference_touching)
            .map(|(a, r)| (a - r).abs() / r)
            .fold(0.0, f64::max);
        eprintln!(
            "γ = {gamma}: before contact {difference:.3e}, in contact {distance:.3e} from DLFT"
        );
        assert!(
            difference < previous_free / 50.0,
            "γ = {gamma}: {difference:e} after {previous_free:e}"
        );
        previous_free = difference;
        for (a, r) in inside.iter().zip(reference_touching) {
            assert!((a - r).abs() / r < 2e-3, "γ = {gamma}: {a} vs DLFT {r}");
        }
        if let Some(before) = &previous_touching {
            // Converging: the change between decades of γ is far below
            // the distance to DLFT.
            for (a, b) in inside.iter().zip(before) {
                assert!((a - b).abs() / b < 1e-4, "γ = {gamma}: {a} vs {b}");
            }
        }
        previous_touching = Some(inside);
    }
    assert!(previous_free < 1e-8, "{previous_free:e}");
}

/// Natural continuation on every formulation of `names`; every point in
/// agreement with the physical full wheel to 1e-8.
fn reduced_equals_full(
    case: &Case,
    nodal_diameter: usize,
    window: (f64, f64, usize),
    names: &[&str],
) {
    let f = case.resonance_hz(nodal_diameter);
    let omegas = frequencies(f, window.0, window.1, window.2);
    let mut results = Vec::new();
    for &name in names {
        let (mut problem, branch) = sweep(case, name, &omegas);
        let mut contact = false;
        let mut all = Vec::new();
        for point in &branch.points {
            let s = problem
                .contact_samples(&point.unknowns, point.omega)
                .unwrap();
            contact |= s.force.iter().flatten().any(|&f| f > 0.0);
            all.push(blade(&problem, &point.unknowns, point.omega));
        }
        assert!(contact, "{name}: the test never reaches the casing");
        results.push((name, problem.unknowns(), all));
    }
    let (_, _, reference) = results.iter().find(|(n, _, _)| *n == "physical").unwrap();
    for (name, unknowns, result) in &results {
        let worst = result
            .iter()
            .zip(reference)
            .map(|(a, b)| relative_difference(a, b))
            .fold(0.0, f64::max);
        eprintln!("{name} ({unknowns} unknowns) vs physical: {worst:e}");
        for (point, (a, b)) in result.iter().zip(reference).enumerate() {
            let d = relative_difference(a, b);
            assert!(
                d <= 1e-8,
                "{name} ({unknowns} unknowns) point {point}: relative difference {d:e}"
            );
        }
    }
}

#[test]
fn dlft_reduced_equals_full_traveling_wave_h1() {
    let case = Case::new(24, ExcitationPattern::Traveling { engine_order: 1 }, 4.0);
    reduced_equals_full(
        &case,
        1,
        (0.996, 1.002, 7),
        &["symmetry", "paper", "physical"],
    );
}

#[test]
fn dlft_reduced_equals_full_standing_wave_h4() {
    let case = Case::new(24, ExcitationPattern::Standing { engine_order: 4 }, 1.0);
    reduced_equals_full(
        &case,
        4,
        (0.996, 1.002, 7),
        &["symmetry", "paper", "physical"],
    );
}

/// Arc-length continuation of `case` over `[0.95, 1.10]` times the first
/// resonance of `nodal_diameter`, with the case file's default settings.
fn continue_case(case: &Case, nodal_diameter: usize, name: &str) -> (HarmonicBalance, Branch) {
    continue_case_capped(case, nodal_diameter, name, 3000)
}

/// [`continue_case`] with a cap on the number of points.
fn continue_case_capped(
    case: &Case,
    nodal_diameter: usize,
    name: &str,
    max_points: usize,
) -> (HarmonicBalance, Branch) {
    let mut problem = case.build(name);
    let settings = case_settings(case, nodal_diameter, max_points);
    let guess = problem.linear_solution(settings.start).unwrap();
    let branch = continue_branch(&mut problem, guess, &settings, |_, _| {});
    (problem, branch)
}

/// [`continue_case_capped`], following the branch back from the end
/// frequency if the sweep from the start stops short.
fn continue_case_from_both_ends(
    case: &Case,
    nodal_diameter: usize,
    name: &str,
    max_points: usize,
) -> (HarmonicBalance, Branch) {
    let mut problem = case.build(name);
    let settings = case_settings(case, nodal_diameter, max_points);
    let guess = problem.linear_solution(settings.start).unwrap();
    let guess_at_end = problem.linear_solution(settings.end).unwrap();
    let branch = continue_from_both_ends(&mut problem, guess, guess_at_end, &settings, |_, _| {});
    (problem, branch)
}

/// The case file's default continuation settings over `[0.95, 1.10]` times
/// the first resonance of `nodal_diameter`.
fn case_settings(case: &Case, nodal_diameter: usize, max_points: usize) -> ArcLengthSettings {
    let f = case.resonance_hz(nodal_diameter);
    ArcLengthSettings {
        start: 2.0 * PI * f * 0.95,
        end: 2.0 * PI * f * 1.10,
        initial_step: 0.01,
        min_step: 1e-7,
        max_step: 0.1,
        length_scale: GAP,
        newton: NewtonSettings {
            tolerance: 1e-8,
            max_iterations: 15,
            ..Default::default()
        },
        max_points,
    }
}

#[test]
fn continuation_runs_through_the_nonsmooth_resonances_to_the_end() {
    use ExcitationPattern::{Standing, Traveling};
    // The paper's settings (N_h = 10, N_t = 10000, κ = 1e8, ε = 1e9) on
    // reduced bases, and a coarse sampling whose branch is a sawtooth of
    // kinks and small folds.
    for (n, pattern, amplitude, nd, time_samples) in [
        (24, Traveling { engine_order: 1 }, 4.0, 1, 10_000),
        (24, Traveling { engine_order: 1 }, 4.0, 1, 960),
        (24, Traveling { engine_order: 3 }, 1.75, 3, 10_000),
        (24, Standing { engine_order: 4 }, 1.0, 4, 10_000),
        (45, Traveling { engine_order: 2 }, 6.0, 2, 10_000),
    ] {
        let mut case = Case::new(n, pattern.clone(), amplitude);
        case.time_samples = time_samples;
        let (mut problem, branch) = continue_case(&case, nd, "symmetry");
        let label = format!("N = {n}, {pattern:?}, N_t = {time_samples}");
        assert_eq!(branch.stop, StopReason::EndReached, "{label}");
        let reversals = branch
            .points
            .windows(3)
            .filter(|w| (w[1].omega - w[0].omega) * (w[2].omega - w[1].omega) < 0.0)
            .count();
        assert!(reversals >= 2, "{label}: {reversals} turning points");
        let mut evaluation = Evaluation::default();
        let mut highest: f64 = 0.0;
        for point in &branch.points {
            problem
                .evaluate(&point.unknowns, point.omega, false, &mut evaluation)
                .unwrap();
            let r = norm(&evaluation.residual) / problem.force_scale();
            assert!(r <= 1e-8, "{label}: residual {r:e}");
            highest = highest.max(point.omega);
        }
        eprintln!(
            "{label}: {} points, {} iterations, {reversals} turning points",
            branch.points.len(),
            branch.total_iterations
        );
        // The resonance bends well to the right of the linear one (a
        // branch turning back early would not).
        let f = case.resonance_hz(nd);
        assert!(
            highest > 2.0 * PI * f * 1.01,
            "{label}: peak at {} Hz",
            highest / 2.0 / PI
        );
    }
}

#[test]
fn the_deformed_casing_branch_runs_through_its_folds_to_the_end() {
    // N = 24, traveling wave h = 6, casing h_c = 8 (Sec. 4.3.3): the branch
    // folds back and forth between 211 and 221 Hz, two of its folds nearly
    // coincide near 218.7 Hz, and it must come out at the end of the range.
    let mut case = Case::new(24, ExcitationPattern::Traveling { engine_order: 6 }, 3.0);
    case.time_samples = 10_008;
    case.casing = Casing {
        gaps: vec![GAP],
        order: 8,
        amplitudes: vec![0.05 * GAP],
    };
    let (mut problem, branch) = continue_case(&case, 6, "symmetry");
    assert_eq!(branch.stop, StopReason::EndReached);
    let turning: Vec<f64> = branch
        .points
        .windows(3)
        .filter(|w| (w[1].omega - w[0].omega) * (w[2].omega - w[1].omega) < 0.0)
        .map(|w| w[1].omega / 2.0 / PI)
        .collect();
    eprintln!("turning points (Hz): {turning:.3?}");
    assert!(turning.len() >= 10, "{turning:?}");
    // Every point is a solution (the kink turns included).
    let mut evaluation = Evaluation::default();
    for p in &branch.points {
        problem
            .evaluate(&p.unknowns, p.omega, false, &mut evaluation)
            .unwrap();
        let r = evaluation
            .residual
            .iter()
            .map(|v| v * v)
            .sum::<f64>()
            .sqrt();
        assert!(
            r / problem.force_scale() < 1e-7,
            "{} Hz: {r}",
            p.omega / 2.0 / PI
        );
    }
}

#[test]
fn the_n45_deformed_casing_branch_goes_on_past_its_first_fold() {
    // N = 45, traveling wave h = 12, casing h_c = 3 (Appendix C.3): the
    // branch folds near 212.5 Hz, comes back down to 211.3 Hz on another
    // sheet (the blades' amplitudes spread apart: the response localizes)
    // and climbs again. Near the fold tip the two sheets are as close as
    // a step; with lax turn limits the continuation slipped back onto the
    // sheet it came along and returned to the start of the range.
    let mut case = Case::new(45, ExcitationPattern::Traveling { engine_order: 12 }, 2.0);
    case.time_samples = 9990;
    case.casing = Casing {
        gaps: vec![GAP],
        order: 3,
        amplitudes: vec![0.05 * GAP],
    };
    let (mut problem, branch) = continue_case_capped(&case, 12, "symmetry", 400);
    assert_eq!(branch.stop, StopReason::PointCap { max_points: 400 });
    let hertz: Vec<f64> = branch.points.iter().map(|p| p.omega / 2.0 / PI).collect();
    // The first fold: the highest frequency before the branch first turns
    // back by more than 0.5 Hz.
    let (fold, lowest) = {
        let mut highest = 0.0_f64;
        let mut fold = None;
        for (i, &f) in hertz.iter().enumerate() {
            highest = highest.max(f);
            if f < highest - 0.5 {
                fold = Some(i);
                break;
            }
        }
        let fold = fold.expect("the branch never turns back");
        let lowest = (fold..hertz.len())
            .min_by(|&a, &b| hertz[a].total_cmp(&hertz[b]))
            .unwrap();
        (highest, lowest)
    };
    eprintln!(
        "first fold {fold:.3} Hz, back down to {:.3} Hz (point {lowest}), last point {:.3} Hz",
        hertz[lowest],
        hertz[hertz.len() - 1]
    );
    assert!((212.0..213.0).contains(&fold), "first fold at {fold} Hz");
    assert!(
        (211.0..211.6).contains(&hertz[lowest]),
        "back down to {} Hz",
        hertz[lowest]
    );
    assert!(
        hertz[hertz.len() - 1] > hertz[lowest] + 0.5,
        "does not climb again"
    );
    let mut evaluation = Evaluation::default();
    for (p, f) in branch.points.iter().zip(&hertz) {
        problem
            .evaluate(&p.unknowns, p.omega, false, &mut evaluation)
            .unwrap();
        let r = norm(&evaluation.residual) / problem.force_scale();
        assert!(r < 1e-7, "{f} Hz: {r}");
    }
}

#[test]
#[ignore = "takes about 40 min on 2 cores in release; the N = 45 deformed-casing case (h = 12, h_c = 3) still fails, issue 5 is blocked on it: with DLFT the sweep from the start goes round a loop through a neck at 221.2874 Hz where its passes come within 1.7e-11 m (the same for largest steps 0.1 and 0.003 and N_t 9990 and 19980) and the sweep back stalls at 220.48 Hz, leaving a gap; with R-HBM the branch is longer than 80000 points; run with --release -- --ignored --nocapture"]
fn paper_academic_cases_reach_the_end_of_their_range() {
    use ExcitationPattern::{Standing, Traveling};
    let cases: Vec<(usize, ExcitationPattern, f64, usize, usize)> = vec![
        (24, Traveling { engine_order: 1 }, 4.0, 0, 1),
        (24, Traveling { engine_order: 3 }, 1.75, 0, 3),
        (24, Standing { engine_order: 1 }, 2.0, 0, 1),
        (24, Standing { engine_order: 4 }, 1.0, 0, 4),
        (24, Traveling { engine_order: 6 }, 3.0, 8, 6),
        (45, Traveling { engine_order: 2 }, 6.0, 0, 2),
        (45, Traveling { engine_order: 17 }, 4.0, 0, 17),
        (45, Standing { engine_order: 9 }, 1.0, 0, 9),
        (45, Standing { engine_order: 15 }, 1.0, 0, 15),
        (45, Traveling { engine_order: 12 }, 2.0, 3, 12),
    ];
    let mut failed = Vec::new();
    for (n, pattern, amplitude, order, nd) in cases {
        let mut case = Case::new(n, pattern.clone(), amplitude);
        case.time_samples = 10_000;
        if order > 0 {
            case.casing = Casing {
                gaps: vec![GAP],
                order,
                amplitudes: vec![0.05 * GAP],
            };
        }
        let clock = std::time::Instant::now();
        let (problem, branch) = continue_case_from_both_ends(&case, nd, "symmetry", 40_000);
        let reversals = branch
            .points
            .windows(3)
            .filter(|w| (w[1].omega - w[0].omega) * (w[2].omega - w[1].omega) < 0.0)
            .count();
        eprintln!(
            "N = {n}, {pattern:?}, {amplitude} N, casing h_c = {order}: {} unknowns, {:?}, {} points, {} iterations, {reversals} turning points, {:.2} s",
            problem.unknowns(),
            branch.stop,
            branch.points.len(),
            branch.total_iterations,
            clock.elapsed().as_secs_f64()
        );
        if let Some(sweeps) = &branch.sweeps {
            eprintln!("    followed from both ends: {}", sweeps.summary());
        }
        if branch.stop != StopReason::EndReached {
            failed.push(format!("N = {n}, {pattern:?}"));
        }
    }
    assert!(failed.is_empty(), "{failed:?}");
}
