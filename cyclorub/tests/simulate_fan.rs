//! The open fan (coarse mesh, Craig–Bampton per nodal diameter, 16 × 53
//! dofs, 432 contact unknowns with friction) integrated with the
//! regularized law: Newton's matrix kept between iterations and steps
//! (chord iterations, the default) gives the wheel that plain Newton
//! (factorized at every iteration) gives.

use cyclorub::case::{Case, LawKind, PerContactDof};
use cyclorub::mesh::{assemble, fan, write_fan, FanGeometry};
use cyclorub::simulate::{
    Drive, NewtonSettings, Simulation, SimulationOutcome, SimulationSettings, State, WheelSetup,
};
use std::f64::consts::PI;

/// The coarse fan under engine order 4 with friction and the regularized
/// law, with a 0.1 mm gap after the centrifugal preload: from rest the
/// preload, applied at once, throws the blades onto the casing in the
/// first period (the force reaches ~300 times its value at zero
/// penetration), then they vibrate clear of it at 290 Hz (a little above
/// the first family, 282 Hz), the regularized force small but never 0.
fn coarse_fan() -> WheelSetup {
    let dir = std::env::temp_dir().join(format!("cyclorub-simulate-fan-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    let mesh = fan(16, 1, &FanGeometry::default()).unwrap();
    let matrices = assemble(&mesh.mesh).unwrap();
    write_fan(&mesh, &matrices, &dir, false).unwrap();
    let mut case = Case::from_file_checked(&dir.join("fan16.toml")).unwrap();
    case.excitation.engine_order = 4;
    case.contact.law = LawKind::Regularized;
    case.casing.gap = PerContactDof::One(1e-4);
    let setup = WheelSetup::from_case(&case, &dir).unwrap();
    let _ = std::fs::remove_dir_all(&dir);
    setup
}

fn run(setup: &WheelSetup, periods: usize, keep_jacobian: bool) -> SimulationOutcome {
    let settings = SimulationSettings {
        periods,
        steps_per_period: 128,
        steady_tolerance: None,
        history_periods: 0,
        newton: NewtonSettings {
            keep_jacobian,
            ..NewtonSettings::default()
        },
        ..SimulationSettings::default()
    };
    Simulation::new(
        setup.wheel.clone(),
        setup.loads.clone(),
        setup.law(),
        Drive::Fixed {
            omega: 2.0 * PI * 290.0,
        },
        settings,
        State::at_rest(setup.wheel.size(), setup.loads.contact_count()),
        None,
    )
    .unwrap()
    .run(|_| {})
    .unwrap()
}

/// 10 periods at 128 steps a period (the check; ~9 s in the dev
/// profile, most of it the two integrations). Measured: 9.6e-12 of the
/// largest displacement, 3.3e-12 of the largest velocity (Newton's
/// tolerance is 1e-10 of the gap on the contact unknowns); 8
/// factorizations for 1289 iterations against 1282.
#[test]
fn the_kept_newton_matrix_integrates_the_fan_as_plain_newton_does() {
    let setup = coarse_fan();
    assert_eq!(3 * setup.loads.contact_count(), 432);
    let periods = 10;
    let kept = run(&setup, periods, true);
    let plain = run(&setup, periods, false);
    // It rubs: the regularized force (never exactly 0) is ten times its
    // value at zero penetration (the first period's impact).
    let at_zero = setup.law().force(0.0).0;
    let rubbing = plain
        .periods
        .iter()
        .filter(|p| p.peak_force.iter().any(|f| *f > 10.0 * at_zero))
        .count();
    let relative = |a: &[f64], b: &[f64]| {
        let scale = b.iter().fold(0.0_f64, |m, v| m.max(v.abs()));
        a.iter()
            .zip(b)
            .fold(0.0_f64, |m, (x, y)| m.max((x - y).abs()))
            / scale
    };
    let (a, b) = (&kept.last_state, &plain.last_state);
    let displacement = relative(&a.displacement, &b.displacement);
    let velocity = relative(&a.velocity, &b.velocity);
    println!(
        "{rubbing} of {periods} periods rubbing; kept: {} iterations, {} factorizations, {} \
         halvings; plain: {} iterations, {} halvings; differences {displacement:.2e} \
         (displacement), {velocity:.2e} (velocity)",
        kept.newton_iterations,
        kept.factorizations,
        kept.halvings,
        plain.newton_iterations,
        plain.halvings
    );
    assert!(rubbing >= 1, "{rubbing} periods rubbing");
    assert_eq!(plain.factorizations, plain.newton_iterations);
    assert!(
        2 * kept.factorizations < kept.newton_iterations,
        "kept: {} factorizations for {} iterations",
        kept.factorizations,
        kept.newton_iterations
    );
    assert!(
        displacement < 1e-10,
        "displacements differ by {displacement:e}"
    );
    assert!(velocity < 1e-10, "velocities differ by {velocity:e}");
    // The per-period maxima of every sector agree as well.
    for (p, q) in kept.periods.iter().zip(&plain.periods) {
        assert!(
            relative(&p.maxima, &q.maxima) < 1e-10,
            "period {}",
            p.period
        );
    }
}
