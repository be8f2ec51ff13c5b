//! Time integration of the full wheel with sliding friction (Eqs. 83–84)
//! against the harmonic balance: started on a periodic solution of R-HBM
//! with friction, the integrated wheel comes back to its start after one
//! period, which it does not without the friction forces; and the work of
//! the contact forces (normal and tangential) closes the energy balance.

use cyclorub::case::Case;
use cyclorub::simulate::start::from_harmonic_balance;
use cyclorub::simulate::{Drive, Newmark, NewtonSettings, State, WheelLoads, WheelSetup};
use std::f64::consts::PI;
use std::path::Path;
use std::sync::Arc;

use crate::common;
use common::blade::{contact_point, BLADE};

/// Steps of one period: the trapezoidal rule's phase error `(ωh)²/12`
/// stays near 2e-7 (16384 steps give the same distances to 1 %: the
/// harmonic balance's truncation is what they measure).
const STEPS: usize = 4096;

/// The largest distance, over every dof, between `state` after one period
/// and `start`, in displacement and in velocity over ω, relative to the
/// largest of either at the start.
fn return_distance(start: &State, end: &State, omega: f64) -> f64 {
    let z = |s: &State| -> Vec<f64> {
        s.displacement
            .iter()
            .copied()
            .chain(s.velocity.iter().map(|v| v / omega))
            .collect()
    };
    let (a, b) = (z(start), z(end));
    let scale = a.iter().fold(0.0_f64, |m, v| m.max(v.abs()));
    let distance = a
        .iter()
        .zip(&b)
        .fold(0.0_f64, |m, (x, y)| m.max((x - y).abs()));
    distance / scale
}

/// One period of the implicit scheme from `start` with `loads`: the state
/// at its end, and the work `(input, damping, contact)` over it with the
/// energies at both ends.
fn one_period(
    setup: &WheelSetup,
    loads: Arc<WheelLoads>,
    start: State,
    omega: f64,
) -> (State, [f64; 3], f64) {
    let mut integrator = Newmark::new(
        setup.wheel.clone(),
        loads,
        setup.law(),
        Drive::Fixed { omega },
        2.0 * PI / omega / STEPS as f64,
        NewtonSettings {
            tolerance: 1e-13,
            ..NewtonSettings::default()
        },
        start.clone(),
    )
    .unwrap();
    for _ in 0..STEPS {
        integrator.advance().unwrap();
    }
    let energy = |s: &State| -> f64 {
        let wheel = &setup.wheel;
        let mut scratch = vec![0.0; wheel.size()];
        0.5 * wheel.mass.quadratic(&s.velocity, &s.velocity, &mut scratch)
            + 0.5
                * wheel
                    .stiffness
                    .quadratic(&s.displacement, &s.displacement, &mut scratch)
    };
    let tally = integrator.take_energy();
    let end = integrator.state().clone();
    let change = energy(&end) - energy(&start);
    (end, [tally.input, tally.damping, tally.contact], change)
}

/// How far the integrated wheel is from its start after one period: with
/// friction, and with the same start without the friction forces; with
/// the point's `N_h`, peak normal force and work `(input, damping,
/// contact)` over the period, and the energy balance's relative error.
struct Return {
    with: f64,
    without: f64,
    harmonics: usize,
    peak_force: f64,
    work: [f64; 3],
    balance: f64,
}

fn period_from_the_point(harmonics: usize) -> Return {
    let text = BLADE
        .replace("harmonics = 12", &format!("harmonics = {harmonics}"))
        .replace(
            "time_samples = 1536",
            &format!("time_samples = {}", 128 * harmonics),
        );
    let case = Case::from_toml(&text, Path::new("case.toml")).unwrap();
    let (solution, index) = contact_point(&case);
    let point = &solution.branch.points[index];
    let setup = WheelSetup::from_case(&case, Path::new(".")).unwrap();
    assert!(setup.loads.friction().is_some(), "the case's friction");
    let start = from_harmonic_balance(
        &solution.problem,
        &point.unknowns,
        point.omega,
        &setup.wheel,
        setup.loads.contact_count(),
    )
    .unwrap();
    let (end, work, change) = one_period(&setup, setup.loads.clone(), start.clone(), point.omega);
    // The same wheel, loads and start without the friction forces.
    let frictionless = {
        let case = Case::from_toml(
            &text.replace("friction = 0.3", "friction = 0.0"),
            Path::new("case.toml"),
        )
        .unwrap();
        WheelSetup::from_case(&case, Path::new(".")).unwrap().loads
    };
    let (end_without, ..) = one_period(&setup, frictionless, start.clone(), point.omega);
    let [input, damping, contact] = work;
    let outcome = Return {
        with: return_distance(&start, &end, point.omega),
        without: return_distance(&start, &end_without, point.omega),
        harmonics: solution.problem.layout().harmonics(),
        peak_force: end.contact_force.iter().fold(0.0_f64, |m, f| m.max(*f)),
        work,
        balance: (change - (input - damping - contact)).abs() / input.abs(),
    };
    println!(
        "{:.4} Hz, N_h = {}, {STEPS} steps: back within {:.2e} with friction, {:.2e} \
         without; peak normal force {:.3} N; over the period input {input:.4e} J, damping \
         {damping:.4e} J, contact {contact:.4e} J (balance {:.1e})",
        point.omega / (2.0 * PI),
        outcome.harmonics,
        outcome.with,
        outcome.without,
        outcome.peak_force,
        outcome.balance
    );
    outcome
}

#[test]
fn a_periodic_solution_with_friction_comes_back_after_one_period() {
    let coarse = period_from_the_point(12);
    let fine = period_from_the_point(24);
    for r in [&coarse, &fine] {
        assert!(r.peak_force > 10.0, "in contact: {} N", r.peak_force);
        // Without friction the same start goes elsewhere: the friction
        // forces of the integration are the harmonic balance's.
        assert!(
            r.without > 20.0 * r.with,
            "N_h = {}: friction acts: {:.3e} against {:.3e}",
            r.harmonics,
            r.without,
            r.with
        );
        // The casing drags the nodes along: its friction does work on the
        // wheel (the contact takes negative work), and the scheme's own
        // quadrature closes the balance to round-off.
        assert!(r.work[2] < 0.0, "contact work {:.3e} J", r.work[2]);
        assert!(r.balance < 1e-8, "energy balance {:.3e}", r.balance);
    }
    // What is left is the harmonic balance's truncation: it falls as N_h
    // grows (9.8e-4, 3.9e-4 and 6.9e-5 for N_h = 12, 24, 48).
    assert!(fine.with < 6e-4, "N_h = 24: {:.3e}", fine.with);
    assert!(
        fine.with < 0.6 * coarse.with,
        "the distance falls with N_h: {:.3e} then {:.3e}",
        coarse.with,
        fine.with
    );
}

#[test]
fn a_tangential_dof_used_twice_is_refused_by_name() {
    let text = BLADE.replace("axial_dofs = [3]", "axial_dofs = [2]");
    let case = Case::from_toml(&text, Path::new("case.toml")).unwrap();
    let message = match WheelSetup::from_case(&case, Path::new(".")) {
        Ok(_) => panic!("a node whose axial dof is its circumferential one was accepted"),
        Err(e) => e.to_string(),
    };
    assert!(
        message.contains("contact.axial_dofs") && message.contains("dof 2"),
        "{message}"
    );
}
