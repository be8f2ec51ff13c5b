//! Time integration on a bifurcated branch (docs/design.md §11, issue 42):
//! a measuring tool on four sectors (ignored), and on six sectors what the
//! wheel does where no bifurcated point is stable (a test). Where one is
//! stable: `tests/pitchfork/time.rs`.
//!
//! The measuring tool's case: four sectors, engine order 2 (the pattern
//! (−1)^j traveling), whose symmetric branch loses stability to class 1 at
//! 212.702 Hz; the
//! bifurcated branch from there is unstable almost everywhere (as on 6 and
//! 8 sectors, docs/branches.md) but for two points near 223.5 Hz, where two
//! sectors move at about 1.0e-3 m and two at 1e-4 m, that Hill's method
//! (`N_h = H = 10`) calls stable by a small margin (−0.82 1/s).
//!
//! Measured (2026-11-28): started there, the full wheel does not stay: its
//! distance to the start is 2.8e-2 of the state after one period (the
//! harmonic balance's own error at this localized contact) and grows to
//! 0.5–1.2 within 30 periods; started on the symmetric branch at
//! 223.514 Hz (stable, past the plateau) it stays within 1.2e-4. So the
//! stable verdict there is not converged (the sizes at the default
//! truncation are 10–16 % off, docs/stability.md), and the test "stays on
//! a stable bifurcated point" needs a converged stable part first.
//!
//! That test is on the two-sector pitchfork (`tests/pitchfork/time.rs`),
//! regularized and damped so that the harmonic balance orbit is the
//! periodic one to a few 1e-6 and Hill's margin is the damping's own
//! (−5 1/s): there the wheel stays on the bifurcated point, and leaves
//! the unstable symmetric one for it. Here the two stable points are the
//! truncation's: with `N_h = H = 20` (`N_t = 10000`) the side followed for
//! 150 points (212.731 to 223.801 Hz) has no stable point, its leading
//! real part 434–480 1/s near 223.5 Hz; with 40, 148 points to 223.574 Hz
//! (where it rejoins the symmetric branch), none stable, 403–439 1/s there;
//! at 10 it rejoins at 223.431 Hz, its last two points stable (−0.34 and
//! −0.82 1/s) and their neighbours growing at up to +9.6 1/s (measured
//! 2026-11-28; about 25 s at 20 and 19 min at 40, test profile). With 4096
//! steps a period instead of 1024 the symmetric point stays within 7.7e-6
//! (1.2e-4 with 1024: the trapezoidal rule's phase error), and the
//! bifurcated one leaves as before (2.8e-2 after one period).

use crate::bifurcated::{case, settings};
use crate::common::branches::{crossings, solved, switch_between};
use crate::common::periods::{self, listed};
use cyclorub::continuation::Point;
use cyclorub::hbm::HarmonicBalance;
use cyclorub::simulate::start::from_harmonic_balance;
use cyclorub::simulate::{
    Drive, Newmark, NewtonSettings, Perturbation, PerturbationPattern, WheelSetup,
};
use cyclorub::stability::{Stability, StabilitySettings};
use std::f64::consts::PI;
use std::path::Path;

const FOUR_SECTORS: &str = "[model]\nsectors = 4\n[excitation]\nengine_order = 2\n\
                            [stability]\nenabled = false\n";

/// Steps per period: a multiple of the 4 sectors (the traveling wave's
/// symmetry is then one of the time-discrete system too).
const STEPS: usize = 1024;

/// The periods integrated.
const PERIODS: usize = 30;

/// `(x, v/ω)` of every dof at the end of each period, from the harmonic
/// balance point `point` of `problem` rebuilt on the wheel.
fn period_ends(setup: &WheelSetup, problem: &HarmonicBalance, point: &Point) -> Vec<Vec<f64>> {
    let omega = point.omega;
    let start = from_harmonic_balance(
        problem,
        &point.unknowns,
        omega,
        &setup.wheel,
        setup.loads.contact_count(),
    )
    .unwrap();
    periods::period_ends(setup, start, omega, STEPS, PERIODS)
}

fn norm(z: &[f64]) -> f64 {
    z.iter().map(|z| z * z).sum::<f64>().sqrt()
}

/// Each period end's distance to the start, relative to the start's size.
fn drift(ends: &[Vec<f64>]) -> Vec<f64> {
    let size = norm(&ends[0]);
    ends[1..]
        .iter()
        .map(|z| {
            let d: Vec<f64> = z.iter().zip(&ends[0]).map(|(a, b)| a - b).collect();
            norm(&d) / size
        })
        .collect()
}

#[test]
#[ignore = "a measuring tool (issue 42): the Hill-stable bifurcated point of the four-sector wheel is left by time integration (see the module's header); about 5 s"]
fn time_integration_from_the_hill_stable_bifurcated_point_and_from_the_symmetric_one() {
    let case = case(FOUR_SECTORS);
    let mut solution = solved(&case);
    let points = solution.branch.points.clone();
    let crossings = crossings(&mut solution, 1, &points);
    let hz = |p: &Point| p.omega / (2.0 * PI);
    // The crossings near 212.70 Hz; the simple real one is switched at (a
    // neighbour there is not: its least eigenvalue is not real).
    let settings = settings(&solution, 150);
    let branch = crossings
        .iter()
        .copied()
        .filter(|&i| (hz(&points[i]) - 212.702).abs() < 0.05)
        .find_map(|i| switch_between(&mut solution, 1, &points, i, &settings).ok())
        .expect("a simple real class-1 crossing near 212.702 Hz");
    // The stable points of the first side, by Hill's method in the enlarged
    // basis's classes; the one of largest margin.
    let check = Stability::new(
        &solution.model,
        &branch.problem,
        &case.contact_dofs(),
        &StabilitySettings::default(),
    )
    .unwrap();
    let side = &branch.sides[0].points;
    let (stable, margin) = side
        .iter()
        .enumerate()
        .filter(|(_, p)| hz(p) > 222.0)
        .filter_map(|(k, p)| {
            let s = check.point(&p.unknowns, p.omega).unwrap();
            let leading = s
                .classes
                .iter()
                .flat_map(|c| c.exponents.iter().map(|e| e.re))
                .fold(f64::NEG_INFINITY, f64::max);
            s.stable().then_some((k, leading))
        })
        .min_by(|a, b| a.1.total_cmp(&b.1))
        .expect("a stable point of the bifurcated branch above 222 Hz");
    let point = &side[stable];
    println!(
        "stable bifurcated point {stable} at {:.4} Hz, leading Re λ {margin:.3} 1/s",
        hz(point)
    );
    let setup = WheelSetup::from_case(&case, Path::new(".")).unwrap();
    let on_branch = drift(&period_ends(&setup, &branch.problem, point));
    println!("bifurcated point, drift per period: {}", listed(&on_branch));
    // The symmetric branch's point nearest in frequency (on the plateau,
    // unstable in class 1).
    let symmetric = points
        .iter()
        .min_by(|a, b| {
            (hz(a) - hz(point))
                .abs()
                .total_cmp(&(hz(b) - hz(point)).abs())
        })
        .unwrap();
    let symmetric_check = solution
        .stability_check(&StabilitySettings::default())
        .unwrap();
    let unstable = !symmetric_check
        .point(&symmetric.unknowns, symmetric.omega)
        .unwrap()
        .stable();
    let off_branch = drift(&period_ends(&setup, &solution.problem, symmetric));
    println!(
        "symmetric point at {:.4} Hz (unstable: {unstable}), drift per period: {}",
        hz(symmetric),
        listed(&off_branch)
    );
    // What was measured (the header): the symmetric point stays, the
    // bifurcated one, Hill-stable at this truncation, does not.
    assert!(!unstable);
    assert!(off_branch.iter().all(|&d| d < 1e-3), "{off_branch:?}");
    assert!(on_branch[PERIODS - 1] > 1e-2, "{on_branch:?}");
}

/// The six-sector chain, traveling h = 2: its symmetric branch loses
/// stability to class 3 at 211.247 Hz, and the class-3 bifurcated branch
/// from there is unstable at every point but one (221.059 Hz,
/// docs/branches.md). `N_t` a multiple of 6.
const SIX_SECTORS: &str = "[model]\nsectors = 6\n[excitation]\nengine_order = 2\n\
                           [harmonic_balance]\ntime_samples = 9996\n\
                           [stability]\nenabled = false\n";

/// Where no stable bifurcated point exists at the frequency, the wheel
/// started on the unstable symmetric point perturbed along the class-3
/// Floquet mode leaves it and settles on no periodic response: at
/// 211.947 Hz (class 3 grows at +93.7 1/s, a real exponent; classes ±1
/// grow too, a complex pair) every point of the bifurcated branch within
/// 0.3 Hz is unstable (the two there), and over the last 50 of 300
/// periods (1200 steps each) the sectors' largest contact displacements
/// per period spread over 0.071–1.115 mm and change from one period to
/// the next by up to 14 % of the largest: localized and modulated, not
/// periodic. `cyclorub simulate --perturb 1e-6:EXPONENT=3` from the same
/// point shows the same after 2000 periods (no steady state, 56 % spread
/// across sectors, 43 % over periods), and so from 211.255 Hz, between
/// the branch point and the branch's first point (3000 periods). About
/// 2.5 s.
#[test]
fn where_no_bifurcated_point_is_stable_the_perturbed_wheel_settles_on_no_periodic_response() {
    let case = case(SIX_SECTORS);
    let mut solution = solved(&case);
    let points = solution.branch.points.clone();
    let hz = |p: &Point| p.omega / (2.0 * PI);
    let crossings = crossings(&mut solution, 3, &points);
    let settings = settings(&solution, 150);
    let i = crossings
        .iter()
        .copied()
        .find(|&i| (hz(&points[i]) - 211.247).abs() < 0.05)
        .expect("the class-3 crossing near 211.247 Hz");
    let branch = switch_between(&mut solution, 3, &points, i, &settings).unwrap();
    // The symmetric point of fastest growth on the unstable stretch.
    let symmetric = points
        .iter()
        .min_by(|a, b| (hz(a) - 211.947).abs().total_cmp(&(hz(b) - 211.947).abs()))
        .unwrap();
    assert!((hz(symmetric) - 211.947).abs() < 1e-3, "{}", hz(symmetric));
    let check = Stability::new(
        &solution.model,
        &branch.problem,
        &case.contact_dofs(),
        &StabilitySettings::default(),
    )
    .unwrap();
    let near: Vec<&Point> = branch.sides[0]
        .points
        .iter()
        .filter(|p| (hz(p) - hz(symmetric)).abs() < 0.3)
        .collect();
    assert!(!near.is_empty());
    for p in &near {
        let verdict = check.point(&p.unknowns, p.omega).unwrap();
        assert!(!verdict.stable(), "stable at {} Hz", hz(p));
    }
    let mode = solution
        .stability_check(&StabilitySettings::default())
        .unwrap()
        .modes(&symmetric.unknowns, symmetric.omega, 3, 1)
        .unwrap()
        .remove(0);
    assert!(
        mode.exponent.re > 50.0 && mode.exponent.im.abs() < 1e-6,
        "{:?}",
        mode.exponent
    );
    let setup = WheelSetup::from_case(&case, Path::new(".")).unwrap();
    let omega = symmetric.omega;
    let mut start = from_harmonic_balance(
        &solution.problem,
        &symmetric.unknowns,
        omega,
        &setup.wheel,
        setup.loads.contact_count(),
    )
    .unwrap();
    Perturbation {
        amplitude: 1e-6,
        pattern: PerturbationPattern::Exponent(3),
    }
    .apply_mode(&mut start, &mode, 0.0, &setup.loads)
    .unwrap();
    let (steps, periods) = (1200, 300);
    let mut integrator = Newmark::new(
        setup.wheel.clone(),
        setup.loads.clone(),
        setup.law(),
        Drive::Fixed { omega },
        2.0 * PI / omega / steps as f64,
        NewtonSettings::default(),
        start,
    )
    .unwrap();
    // Each sector's largest contact displacement over each period.
    let sectors = setup.wheel.sectors();
    let mut maxima = Vec::with_capacity(periods);
    for _ in 0..periods {
        let mut largest = vec![0.0_f64; sectors];
        for _ in 0..steps {
            integrator.advance().unwrap();
            let x = &integrator.state().displacement;
            for (j, m) in largest.iter_mut().enumerate() {
                *m = m.max(x[setup.loads.contact_index(j, 0)].abs());
            }
        }
        maxima.push(largest);
    }
    let last = &maxima[periods - 50..];
    let (lowest, highest) = last
        .iter()
        .flatten()
        .fold((f64::INFINITY, 0.0_f64), |(l, h), &m| (l.min(m), h.max(m)));
    // How much the sectors' maxima change from one period to the next.
    let change = last
        .windows(2)
        .map(|w| {
            w[0].iter()
                .zip(&w[1])
                .map(|(a, b)| (a - b).abs())
                .fold(0.0, f64::max)
                / highest
        })
        .fold(0.0, f64::max);
    println!(
        "{} bifurcated points within 0.3 Hz, all unstable; last 50 of {periods} periods: \
         sectors' maxima {lowest:.3e} to {highest:.3e} m, change a period up to {change:.2}",
        near.len()
    );
    // Localized (the sectors far apart) and not periodic.
    assert!(lowest < 0.5 * highest, "{lowest} {highest}");
    assert!(change > 0.05, "{change}");
}
