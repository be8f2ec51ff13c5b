//! Sliding friction (Eqs. 83–84) against independent computations: central
//! differences of the residual (both laws, in and out of contact), the
//! frictionless path (μ = 0 is the normal-only problem), the full wheel
//! (reduced = full with friction, traveling and partly standing waves), and
//! a time integration written here of a sliding oscillator.

use cyclorub::basis::SpectralBasis;
use cyclorub::contact::{
    ContactModel, DynamicLagrangian, FrictionNode, RegularizedPenalty, RotationSpeed,
    SlidingFriction,
};
use cyclorub::continuation::{solve_at_frequencies, Evaluation, NewtonSettings, Problem};
use cyclorub::cyclic::ExcitationPattern;
use cyclorub::hbm::aft::Aft;
use cyclorub::hbm::recovery::{dof_coordinates, physical_unknowns};
use cyclorub::hbm::{Casing, Forcing, Formulation, HarmonicBalance, ProblemSpec};
use cyclorub::model::{BlockCirculantSector, Damping, SectorModel};
use faer::Mat;
use std::f64::consts::PI;

const GAP: f64 = 1e-3;

/// A sector of four dofs: the contact node's normal (toward the casing),
/// circumferential and axial dofs, and a blade dof that holds them; coupled
/// to the next sector through the blade dof and the normal dof.
fn blade_model(sectors: usize) -> SectorModel {
    let k = [
        [3.0e5, -2.0e4, 1.0e4, -1.0e5],
        [-2.0e4, 2.0e5, -3.0e4, -6.0e4],
        [1.0e4, -3.0e4, 2.5e5, -5.0e4],
        [-1.0e5, -6.0e4, -5.0e4, 4.0e5],
    ];
    let m = [
        [0.3, 0.0, 0.0, 0.05],
        [0.0, 0.25, 0.0, 0.0],
        [0.0, 0.0, 0.28, 0.0],
        [0.05, 0.0, 0.0, 1.0],
    ];
    let coupling = Mat::from_fn(4, 4, |r, c| match (r, c) {
        (3, 3) => -5.0e4,
        (0, 0) => -1.0e4,
        _ => 0.0,
    });
    SectorModel::block_circulant(
        sectors,
        BlockCirculantSector {
            mass: Mat::from_fn(4, 4, |r, c| m[r][c]),
            stiffness: Mat::from_fn(4, 4, |r, c| k[r][c]),
            mass_coupling: None,
            stiffness_coupling: Some(coupling),
        },
        Damping::Rayleigh {
            alpha: 2.0,
            beta: 1e-6,
        },
    )
    .unwrap()
}

struct Setup {
    model: SectorModel,
    forcing: Forcing,
    casing: Casing,
    friction: SlidingFriction,
    law: ContactModel,
    harmonics: usize,
    time_samples: usize,
}

impl Setup {
    fn new(
        sectors: usize,
        pattern: ExcitationPattern,
        speed: RotationSpeed,
        law: ContactModel,
    ) -> Self {
        Self {
            model: blade_model(sectors),
            forcing: Forcing {
                pattern,
                amplitude: 20.0,
                dofs: vec![3],
                static_force: 0.0,
            },
            casing: Casing {
                gaps: vec![GAP],
                order: 0,
                amplitudes: vec![0.0],
            },
            friction: SlidingFriction::new(
                0.3,
                speed,
                vec![FrictionNode {
                    circumferential: 1,
                    axial: 2,
                    radius: 0.4,
                }],
            )
            .unwrap(),
            law,
            harmonics: 4,
            time_samples: 8 * sectors,
        }
    }

    fn spec(&self, friction: bool) -> ProblemSpec<'_> {
        ProblemSpec {
            model: &self.model,
            contact_dofs: &[0],
            forcing: Some(&self.forcing),
            casing: &self.casing,
            contact: self.law.clone(),
            friction: friction.then_some(&self.friction),
            preload: None,
            harmonics: self.harmonics,
            time_samples: self.time_samples,
        }
    }

    fn symmetry(&self) -> Formulation {
        let spec = self.spec(true);
        Formulation::Cyclic(SpectralBasis::symmetry(&spec.load_case(), self.harmonics).unwrap())
    }
}

fn regularized() -> ContactModel {
    ContactModel::Regularized(RegularizedPenalty::new(2e6, 0.5).unwrap())
}

fn lagrangian() -> ContactModel {
    ContactModel::Lagrangian(DynamicLagrangian::new(2e6, None).unwrap())
}

fn first_frequency(model: &SectorModel, nodal_diameter: usize) -> f64 {
    2.0 * PI * model.natural_frequencies().unwrap()[nodal_diameter].1[0]
}

/// The largest relative difference between the analytic `∂R/∂x`, `∂R/∂ω`
/// and central differences at `(x, omega)`.
fn jacobian_errors(problem: &mut HarmonicBalance, x: &[f64], omega: f64) -> (f64, f64) {
    let mut at = Evaluation::default();
    problem.evaluate(x, omega, true, &mut at).unwrap();
    let n = x.len();
    let scale_x = x.iter().map(|v| v.abs()).fold(0.0, f64::max);
    let step = 1e-7 * scale_x;
    let (mut plus, mut minus) = (Evaluation::default(), Evaluation::default());
    let mut worst: f64 = 0.0;
    for col in 0..n {
        let (mut xp, mut xm) = (x.to_vec(), x.to_vec());
        xp[col] += step;
        xm[col] -= step;
        problem.evaluate(&xp, omega, false, &mut plus).unwrap();
        problem.evaluate(&xm, omega, false, &mut minus).unwrap();
        let scale = (0..n)
            .map(|r| at.jacobian[(r, col)].abs())
            .fold(0.0, f64::max);
        for r in 0..n {
            let fd = (plus.residual[r] - minus.residual[r]) / (2.0 * step);
            worst = worst.max((fd - at.jacobian[(r, col)]).abs() / scale);
        }
    }
    let step = omega * 1e-7;
    problem.evaluate(x, omega + step, false, &mut plus).unwrap();
    problem
        .evaluate(x, omega - step, false, &mut minus)
        .unwrap();
    let scale = at
        .derivative_omega
        .iter()
        .map(|v| v.abs())
        .fold(0.0, f64::max);
    let worst_omega = (0..n)
        .map(|r| {
            let fd = (plus.residual[r] - minus.residual[r]) / (2.0 * step);
            (fd - at.derivative_omega[r]).abs() / scale
        })
        .fold(0.0, f64::max);
    (worst, worst_omega)
}

/// How many sampled instants of a point penetrate the casing.
fn instants_in_contact(problem: &mut HarmonicBalance, x: &[f64], omega: f64) -> usize {
    let samples = problem.contact_samples(x, omega).unwrap();
    samples
        .penetration
        .iter()
        .flatten()
        .filter(|&&p| p > 0.0)
        .count()
}

#[test]
fn friction_jacobians_match_central_differences() {
    let traveling = ExcitationPattern::Traveling { engine_order: 1 };
    for (law_name, law) in [("regularized", regularized()), ("dlft", lagrangian())] {
        for speed in [RotationSpeed::Fixed(30.0), RotationSpeed::Synchronous] {
            let setup = Setup::new(6, traveling.clone(), speed, law.clone());
            let omega = first_frequency(&setup.model, 1);
            for (basis, formulation) in [
                ("symmetry", setup.symmetry()),
                ("physical", Formulation::Physical),
            ] {
                let mut problem = setup.spec(true).build(&formulation).unwrap();
                let linear = problem.linear_solution(omega).unwrap();
                // In contact (the linear response exceeds the gap) and out
                // of it (a tenth of it, no instant touches).
                for (scale, touching) in [(1.0, true), (0.1, false)] {
                    let x: Vec<f64> = linear.iter().map(|v| v * scale).collect();
                    let omega = omega * 1.002;
                    let contact = instants_in_contact(&mut problem, &x, omega);
                    assert_eq!(
                        contact > 0,
                        touching,
                        "{law_name} {basis}: {contact} instants"
                    );
                    let (dx, domega) = jacobian_errors(&mut problem, &x, omega);
                    assert!(
                        dx < 1e-6 && domega < 1e-6,
                        "{law_name} {speed:?} {basis} scale {scale}: ∂R/∂x {dx:e}, ∂R/∂ω {domega:e}"
                    );
                }
            }
        }
    }
}

/// Converged points `(unknowns, ω)` at `omegas`, from the linear solution
/// at the first.
fn converged(problem: &mut HarmonicBalance, omegas: &[f64]) -> Vec<(Vec<f64>, f64)> {
    let start = problem.linear_solution(omegas[0]).unwrap();
    let settings = NewtonSettings {
        tolerance: 1e-11,
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

/// The coordinates of sector dof `dof` on every sector of converged points
/// at `omegas`.
fn solve(problem: &mut HarmonicBalance, omegas: &[f64], dof: usize) -> Vec<Vec<Vec<f64>>> {
    let sectors: Vec<usize> = (0..problem.layout().sectors).collect();
    converged(problem, omegas)
        .iter()
        .map(|(x, omega)| dof_coordinates(problem, x, *omega, dof, &sectors).unwrap())
        .collect()
}

fn largest_difference(a: &[Vec<Vec<f64>>], b: &[Vec<Vec<f64>>]) -> (f64, f64) {
    let flat =
        |v: &[Vec<Vec<f64>>]| -> Vec<f64> { v.iter().flatten().flatten().copied().collect() };
    let (a, b) = (flat(a), flat(b));
    let scale = a.iter().map(|v| v.abs()).fold(0.0, f64::max);
    let difference = a
        .iter()
        .zip(&b)
        .map(|(x, y)| (x - y).abs())
        .fold(0.0, f64::max);
    (difference / scale, scale)
}

#[test]
fn no_friction_coefficient_is_the_normal_only_problem() {
    let setup = {
        let mut s = Setup::new(
            6,
            ExcitationPattern::Traveling { engine_order: 1 },
            RotationSpeed::Fixed(30.0),
            regularized(),
        );
        s.friction =
            SlidingFriction::new(0.0, RotationSpeed::Fixed(30.0), s.friction.nodes().to_vec())
                .unwrap();
        s
    };
    let omega = first_frequency(&setup.model, 1);
    let omegas: Vec<f64> = [0.98, 0.985, 0.99].iter().map(|f| f * omega).collect();
    for formulation in [setup.symmetry(), Formulation::Physical] {
        let mut with = setup.spec(true).build(&formulation).unwrap();
        let mut without = setup.spec(false).build(&formulation).unwrap();
        assert_eq!(with.layout().contact_dofs, 3);
        assert_eq!(without.layout().contact_dofs, 1);
        for dof in [0, 1, 3] {
            let (difference, scale) = largest_difference(
                &solve(&mut with, &omegas, dof),
                &solve(&mut without, &omegas, dof),
            );
            assert!(scale > 0.0);
            assert!(difference < 1e-10, "dof {}: {difference:e}", dof + 1);
        }
    }
}

#[test]
fn the_reduced_problem_with_friction_is_the_full_one() {
    // Steps short enough that each Newton solve stays on the branch it
    // continues: with a partly standing wave the full wheel has other
    // solutions near first contact, which a long step can reach.
    let factors = [0.984, 0.985, 0.986, 0.987, 0.988, 0.989, 0.99];
    for (name, pattern, nodal_diameter) in [
        (
            "traveling h = 1",
            ExcitationPattern::Traveling { engine_order: 1 },
            1,
        ),
        (
            "partly standing h = 2 (Eq. 86 weights)",
            ExcitationPattern::Mixed {
                engine_order: 2,
                backward_weight: 0.9,
                forward_weight: 0.1,
            },
            2,
        ),
    ] {
        for law in [regularized(), lagrangian()] {
            let setup = Setup::new(6, pattern.clone(), RotationSpeed::Synchronous, law);
            let omega = first_frequency(&setup.model, nodal_diameter);
            let omegas: Vec<f64> = factors.iter().map(|f| f * omega).collect();
            let mut reduced = setup.spec(true).build(&setup.symmetry()).unwrap();
            let mut full = setup.spec(true).build(&Formulation::Physical).unwrap();
            assert!(reduced.layout().unknowns < full.layout().unknowns);
            let reduced_points = converged(&mut reduced, &omegas);
            let full_points = converged(&mut full, &omegas);
            let sectors: Vec<usize> = (0..6).collect();
            let mut touching = 0;
            for ((x, omega), (y, _)) in reduced_points.iter().zip(&full_points) {
                // Each reduced point, carried to the full wheel, solves it.
                let carried = physical_unknowns(&reduced, x);
                let mut at = Evaluation::default();
                full.evaluate(&carried, *omega, false, &mut at).unwrap();
                let residual = at.residual.iter().map(|v| v.abs()).fold(0.0, f64::max);
                let a = dof_coordinates(&reduced, x, *omega, 3, &sectors).unwrap();
                let b = dof_coordinates(&full, y, *omega, 3, &sectors).unwrap();
                let (difference, _) = largest_difference(&[a], &[b]);
                let hz = omega / 2.0 / PI;
                assert!(
                    residual < 1e-10 * setup.forcing.amplitude,
                    "{name} {hz} Hz: {residual:e} N"
                );
                assert!(difference < 1e-8, "{name} {hz} Hz: {difference:e}");
                touching += usize::from(instants_in_contact(&mut full, &carried, *omega) > 0);
            }
            assert!(touching >= 3, "{name}: {touching} points in contact");
        }
    }
}

/// One sector, no neighbours: the contact node pressed on the casing by an
/// interference `δ` (a negative gap) through a plain penalty law, so that
/// the normal force is constant, `N0 = κ k_n δ / (k_n + κ)`; the tangential
/// dofs `(θ, z)` oscillate under an axial force `F cos ωt` and the friction
/// `−μ N0 w/|w|`, `w = (θ̇ + ρΩ, ż)`.
struct Slider {
    mass: f64,
    stiffness: f64,
    damping: f64,
    normal_stiffness: f64,
    contact_stiffness: f64,
    interference: f64,
    mu: f64,
    sliding_speed: f64,
    force: f64,
}

impl Slider {
    fn normal_force(&self) -> f64 {
        let (k, kappa) = (self.normal_stiffness, self.contact_stiffness);
        kappa * k * self.interference / (k + kappa)
    }

    /// The time integration written for this test: classical RK4 on
    /// `(θ, z, θ̇, ż)` over `periods` periods of `steps` steps, returning the
    /// last period's axial displacement and the friction's dissipated
    /// energy over it.
    fn integrate(&self, omega: f64, periods: usize, steps: usize) -> (Vec<f64>, f64) {
        let friction = self.mu * self.normal_force();
        let acceleration = |t: f64, s: [f64; 4]| -> [f64; 4] {
            let w = [s[2] + self.sliding_speed, s[3]];
            let norm = w[0].hypot(w[1]);
            let f = [-friction * w[0] / norm, -friction * w[1] / norm];
            [
                s[2],
                s[3],
                (f[0] - self.stiffness * s[0] - self.damping * s[2]) / self.mass,
                (self.force * (omega * t).cos() + f[1]
                    - self.stiffness * s[1]
                    - self.damping * s[3])
                    / self.mass,
            ]
        };
        let dt = 2.0 * PI / omega / steps as f64;
        let mut s = [-friction / self.stiffness, 0.0, 0.0, 0.0];
        let mut t = 0.0;
        let mut last = Vec::with_capacity(steps);
        let mut dissipated = 0.0;
        let power = |s: [f64; 4]| {
            let w = [s[2] + self.sliding_speed, s[3]];
            let norm = w[0].hypot(w[1]);
            // The friction's power on the structure's own motion.
            -friction * (w[0] * s[2] + w[1] * s[3]) / norm
        };
        for period in 0..periods {
            for _ in 0..steps {
                let add = |a: [f64; 4], b: [f64; 4], h: f64| -> [f64; 4] {
                    [
                        a[0] + h * b[0],
                        a[1] + h * b[1],
                        a[2] + h * b[2],
                        a[3] + h * b[3],
                    ]
                };
                let k1 = acceleration(t, s);
                let k2 = acceleration(t + dt / 2.0, add(s, k1, dt / 2.0));
                let k3 = acceleration(t + dt / 2.0, add(s, k2, dt / 2.0));
                let k4 = acceleration(t + dt, add(s, k3, dt));
                if period + 1 == periods {
                    last.push(s[1]);
                    dissipated += power(s) * dt;
                }
                for i in 0..4 {
                    s[i] += dt / 6.0 * (k1[i] + 2.0 * k2[i] + 2.0 * k3[i] + k4[i]);
                }
                t += dt;
            }
        }
        (last, -dissipated)
    }

    fn model(&self) -> SectorModel {
        let (m, k) = (self.mass, self.stiffness);
        SectorModel::block_circulant(
            1,
            BlockCirculantSector {
                mass: Mat::from_fn(3, 3, |r, c| if r == c { m } else { 0.0 }),
                stiffness: Mat::from_fn(3, 3, |r, c| match (r, c) {
                    (0, 0) => self.normal_stiffness,
                    (r, c) if r == c => k,
                    _ => 0.0,
                }),
                mass_coupling: None,
                stiffness_coupling: None,
            },
            Damping::Rayleigh {
                alpha: self.damping / m,
                beta: 0.0,
            },
        )
        .unwrap()
    }
}

#[test]
fn a_sliding_oscillator_matches_its_time_integration() {
    let slider = Slider {
        mass: 1.0,
        stiffness: (2.0 * PI * 10.0).powi(2),
        damping: 1.2,
        normal_stiffness: 1e4,
        contact_stiffness: 1e6,
        interference: 2e-4,
        mu: 0.25,
        sliding_speed: 1.5,
        force: 1.0,
    };
    let model = slider.model();
    let forcing = Forcing {
        pattern: ExcitationPattern::Traveling { engine_order: 0 },
        amplitude: slider.force,
        dofs: vec![2],
        static_force: 0.0,
    };
    let casing = Casing {
        gaps: vec![-slider.interference],
        order: 0,
        amplitudes: vec![0.0],
    };
    let radius = 0.5;
    let friction = SlidingFriction::new(
        slider.mu,
        RotationSpeed::Fixed(slider.sliding_speed / radius),
        vec![FrictionNode {
            circumferential: 1,
            axial: 2,
            radius,
        }],
    )
    .unwrap();
    let (harmonics, time_samples) = (15, 256);
    let spec = ProblemSpec {
        model: &model,
        contact_dofs: &[0],
        forcing: Some(&forcing),
        casing: &casing,
        contact: ContactModel::Regularized(
            RegularizedPenalty::new(slider.contact_stiffness, 0.0).unwrap(),
        ),
        friction: Some(&friction),
        preload: None,
        harmonics,
        time_samples,
    };
    let mut problem = spec.build(&Formulation::Physical).unwrap();
    let mut aft = Aft::new(harmonics, time_samples);
    for factor in [0.9, 1.0, 1.05] {
        let omega = 2.0 * PI * 10.0 * factor;
        let (x, _) = converged(&mut problem, &[omega]).remove(0);
        let coordinates = |dof| {
            dof_coordinates(&problem, &x, omega, dof, &[0])
                .unwrap()
                .remove(0)
        };
        let mut axial = vec![0.0; time_samples];
        aft.to_time(&coordinates(2), &mut axial);
        let steps = time_samples * 8;
        let (integrated, dissipated) = slider.integrate(omega, 300, steps);
        let amplitude = axial.iter().fold(0.0_f64, |m, v| m.max(v.abs()));
        let mut worst: f64 = 0.0;
        for (n, a) in axial.iter().enumerate() {
            worst = worst.max((a - integrated[8 * n]).abs() / amplitude);
        }
        assert!(
            worst < 1e-5,
            "{factor}: HBM and RK4 differ by {worst:e} of the amplitude"
        );
        // The friction's energy per cycle from the HBM samples.
        let (mut theta_rate, mut axial_rate) = (vec![0.0; time_samples], vec![0.0; time_samples]);
        aft.to_time(&rate(&coordinates(1), omega), &mut theta_rate);
        aft.to_time(&rate(&coordinates(2), omega), &mut axial_rate);
        let friction_force = slider.mu * slider.normal_force();
        let hbm_dissipated: f64 = theta_rate
            .iter()
            .zip(&axial_rate)
            .map(|(vt, vz)| {
                let w = [vt + slider.sliding_speed, *vz];
                friction_force * (w[0] * vt + w[1] * vz) / w[0].hypot(w[1])
            })
            .sum::<f64>()
            * (2.0 * PI / omega / time_samples as f64);
        assert!(dissipated > 0.0);
        assert!(
            (hbm_dissipated - dissipated).abs() < 1e-8 * dissipated,
            "{factor}: dissipated per cycle {hbm_dissipated:e} J (HBM) vs {dissipated:e} J (RK4)"
        );
    }
}

/// Coordinates of the velocity `ω du/dτ`.
fn rate(coordinates: &[f64], omega: f64) -> Vec<f64> {
    let mut out = vec![0.0; coordinates.len()];
    for k in 1..=(coordinates.len() - 1) / 2 {
        out[2 * k - 1] = -omega * k as f64 * coordinates[2 * k];
        out[2 * k] = omega * k as f64 * coordinates[2 * k - 1];
    }
    out
}
