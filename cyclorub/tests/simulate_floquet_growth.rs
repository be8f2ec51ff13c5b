//! The independent time-domain check of Hill's exponents: from an unstable
//! harmonic balance point, the full wheel is integrated in time unperturbed
//! and perturbed along the Floquet mode of one exponent (Hill's
//! eigenvector on every dof, displacement and velocity); the distance
//! between the two at period ends grows or decays by `|e^{λT}|` a period.
//!
//! The perturbation is complex: the runs perturbed by its real part
//! (phase 0) and by its imaginary part (phase π/2) evolve, to linear
//! order, as the real and imaginary parts of `e^{λt}` times one mode, so
//! the root of the sum of their squared distances to the unperturbed run is
//! `|e^{λt}|` times a constant at every period end: no beat between `λ` and
//! its conjugate to fit around.

use cyclorub::case::Case;
use cyclorub::forced_response::{ForcedResponse, Solution};
use cyclorub::simulate::start::from_harmonic_balance;
use cyclorub::simulate::{
    Drive, Newmark, NewtonSettings, Perturbation, PerturbationPattern, State, WheelSetup,
};
use cyclorub::stability::{FloquetMode, Stability, StabilitySettings};
use std::f64::consts::PI;
use std::path::Path;

/// The default wheel on N = 6 sectors with a softer regularized contact
/// (κ = 5e6 N/m, γ = 5 N): N_h = 12 harmonics, N_t = 600 (a multiple of N),
/// Hill's H = 24.
fn soft() -> String {
    format!(
        "[model]\nsectors = 6\n\
                    [harmonic_balance]\nharmonics = {}\ntime_samples = 600\n\
                    [contact]\nstiffness = 5e6\nregularization = 5.0\n\
                    [continuation]\nmax_points = 200\n",
        env("GROWTH_NH", 12)
    )
}

fn env(key: &str, default: usize) -> usize {
    std::env::var(key)
        .ok()
        .and_then(|v| v.parse().ok())
        .unwrap_or(default)
}

/// Hill's harmonics (the case's `[stability] harmonics`).
const HILL_HARMONICS: usize = 24;

/// Time steps per excitation period.
const STEPS_PER_PERIOD: usize = 2048;

/// Periods integrated; the log of the distance is fitted over all of them.
const PERIODS: usize = 40;

/// Largest contact displacement of the perturbation, m: a thousandth of
/// the regularization length `γ/κ = 1 µm` over which the contact stiffness
/// changes, so that the perturbation stays linear as it grows.
const AMPLITUDE: f64 = 1e-9;

struct Unstable {
    solution: Solution,
    point: usize,
    setup: WheelSetup,
}

/// The branch of `SOFT` and its point near 218.35 Hz on the contact
/// plateau where class 2 is unstable.
fn unstable_point() -> Unstable {
    let case = Case::from_toml(&soft(), Path::new("soft.toml")).unwrap();
    let solution = ForcedResponse::from_case(&case)
        .unwrap()
        .build()
        .unwrap()
        .run(&mut [])
        .unwrap();
    let check = stability(&solution);
    let point = solution
        .branch
        .points
        .iter()
        .enumerate()
        .filter(|(_, p)| p.converged && (p.omega / (2.0 * PI) - 218.35).abs() < 0.3)
        .map(|(i, p)| {
            let mode = &check.modes(&p.unknowns, p.omega, 2, 1).unwrap()[0];
            (i, mode.exponent.re)
        })
        .max_by(|a, b| a.1.total_cmp(&b.1))
        .expect("a point near 218.35 Hz")
        .0;
    let setup = WheelSetup::from_case(&case, Path::new(".")).unwrap();
    Unstable {
        solution,
        point,
        setup,
    }
}

fn stability(solution: &Solution) -> Stability<'_> {
    let settings = StabilitySettings {
        harmonics: Some(env("GROWTH_H", HILL_HARMONICS)),
        ..StabilitySettings::default()
    };
    solution.stability_check(&settings).unwrap()
}

/// The state `z = (x, v/ω)` at the end of each of `PERIODS` periods.
fn period_ends(wheel: &Unstable, start: State) -> Vec<Vec<f64>> {
    let point = &wheel.solution.branch.points[wheel.point];
    let omega = point.omega;
    let newton = NewtonSettings {
        // Corrections of 1e-16 m: far below the perturbation.
        tolerance: 1e-13,
        ..NewtonSettings::default()
    };
    let mut integrator = Newmark::new(
        wheel.setup.wheel.clone(),
        wheel.setup.loads.clone(),
        wheel.setup.law(),
        Drive::Fixed { omega },
        2.0 * PI / omega / env("GROWTH_STEPS", STEPS_PER_PERIOD) as f64,
        newton,
        start,
    )
    .unwrap();
    (0..env("GROWTH_PERIODS", PERIODS))
        .map(|_| {
            for _ in 0..env("GROWTH_STEPS", STEPS_PER_PERIOD) {
                integrator.advance().unwrap();
            }
            let state = integrator.state();
            state
                .displacement
                .iter()
                .copied()
                .chain(state.velocity.iter().map(|v| v / omega))
                .collect()
        })
        .collect()
}

/// The state of the point at `t = 0`, rebuilt on every dof.
fn start(wheel: &Unstable) -> State {
    let point = &wheel.solution.branch.points[wheel.point];
    from_harmonic_balance(
        &wheel.solution.problem,
        &point.unknowns,
        point.omega,
        &wheel.setup.wheel,
        wheel.setup.loads.contact_count(),
    )
    .unwrap()
}

/// `ln(d_p)`, `p = 1..=PERIODS`, of the distance `d_p` between the runs
/// perturbed by the real and imaginary parts of `mode` and the unperturbed
/// run `reference` (the root of the sum of both squared distances).
fn log_distances(wheel: &Unstable, mode: &FloquetMode, reference: &[Vec<f64>]) -> Vec<f64> {
    let perturbation = Perturbation {
        amplitude: AMPLITUDE * env("GROWTH_AMP", 1000) as f64 / 1000.0,
        pattern: PerturbationPattern::Exponent(mode.nodal_diameter),
    };
    let perturbed = |phase: f64| {
        let mut state = start(wheel);
        perturbation
            .apply_mode(&mut state, mode, phase, &wheel.setup.loads)
            .unwrap();
        state
    };
    let (real, imaginary) = (perturbed(0.0), perturbed(PI / 2.0));
    let (real, imaginary) = std::thread::scope(|scope| {
        let a = scope.spawn(|| period_ends(wheel, real));
        (period_ends(wheel, imaginary), a.join().unwrap())
    });
    reference
        .iter()
        .zip(real.iter().zip(&imaginary))
        .map(|(r, (a, b))| {
            let squared: f64 = r
                .iter()
                .zip(a.iter().zip(b))
                .map(|(r, (a, b))| (a - r).powi(2) + (b - r).powi(2))
                .sum();
            0.5 * squared.ln()
        })
        .collect()
}

/// The least-squares slope of `values` against their index.
fn slope(values: &[f64]) -> f64 {
    let n = values.len() as f64;
    let mean_x = (n - 1.0) / 2.0;
    let mean_y = values.iter().sum::<f64>() / n;
    let (mut sxy, mut sxx) = (0.0, 0.0);
    for (i, y) in values.iter().enumerate() {
        let dx = i as f64 - mean_x;
        sxy += dx * (y - mean_y);
        sxx += dx * dx;
    }
    sxy / sxx
}

/// `Re λ T` (Hill) and the fitted growth of `ln d` per period (time).
fn rates(wheel: &Unstable, mode: &FloquetMode, reference: &[Vec<f64>]) -> (f64, f64) {
    let logs = log_distances(wheel, mode, reference);
    let measured = slope(&logs);
    let hill = mode.multiplier().norm().ln();
    let steps: Vec<String> = logs
        .windows(2)
        .map(|w| format!("{:.4}", w[1] - w[0]))
        .collect();
    println!(
        "class {}, λ = {:.4} {:+.3}i 1/s (truncation {:.1e}): ln|μ| per period Hill {hill:.5}, integration {measured:.5} ({:+.2} %); per period: {}",
        mode.nodal_diameter,
        mode.exponent.re,
        mode.exponent.im,
        mode.truncation,
        100.0 * (measured - hill) / hill.abs(),
        steps.join(" ")
    );
    (hill, measured)
}

#[test]
fn a_perturbation_along_a_floquet_mode_grows_or_decays_at_its_exponent() {
    let wheel = unstable_point();
    let point = &wheel.solution.branch.points[wheel.point];
    let check = stability(&wheel.solution);
    println!(
        "point {} at {:.4} Hz; N_h = 12, H = {HILL_HARMONICS}, {STEPS_PER_PERIOD} steps a period, {PERIODS} periods",
        wheel.point,
        point.omega / (2.0 * PI)
    );
    let reference = period_ends(&wheel, start(&wheel));
    let initial: Vec<f64> = {
        let s = start(&wheel);
        s.displacement
            .iter()
            .copied()
            .chain(s.velocity.iter().map(|v| v / point.omega))
            .collect()
    };
    let drift: Vec<String> = reference
        .iter()
        .map(|z| {
            let d: f64 = z.iter().zip(&initial).map(|(a, b)| (a - b).powi(2)).sum();
            format!("{:.2e}", d.sqrt())
        })
        .collect();
    println!(
        "reference's distance to its start at period ends: {}",
        drift.join(" ")
    );
    for class in [2, 0, 3] {
        let mode = &check.modes(&point.unknowns, point.omega, class, 1).unwrap()[0];
        let (hill, measured) = rates(&wheel, mode, &reference);
        println!("class {class}: Hill {hill:.5} measured {measured:.5}");
    }
}
