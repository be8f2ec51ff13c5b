//! Time integration of the full wheel period by period, as the tests on
//! periodic orbits read it: the state `(x, v/ω)` at each period's end.

use cyclorub::simulate::{Drive, Newmark, NewtonSettings, State, WheelSetup};
use std::f64::consts::PI;

/// The state `(x, v/ω)` at each period end, `periods` periods of `steps`
/// Newmark steps at `omega` from `start` (the start first).
pub fn period_ends(
    setup: &WheelSetup,
    start: State,
    omega: f64,
    steps: usize,
    periods: usize,
) -> Vec<Vec<f64>> {
    let mut ends = vec![state_vector(&start, omega)];
    let mut integrator = Newmark::new(
        setup.wheel.clone(),
        setup.loads.clone(),
        setup.law(),
        Drive::Fixed { omega },
        2.0 * PI / omega / steps as f64,
        NewtonSettings {
            tolerance: 1e-13,
            ..NewtonSettings::default()
        },
        start,
    )
    .unwrap();
    for _ in 0..periods {
        for _ in 0..steps {
            integrator.advance().unwrap();
        }
        ends.push(state_vector(integrator.state(), omega));
    }
    ends
}

/// `(x, v/ω)`: displacements and velocities in one unit.
pub fn state_vector(s: &State, omega: f64) -> Vec<f64> {
    s.displacement
        .iter()
        .copied()
        .chain(s.velocity.iter().map(|v| v / omega))
        .collect()
}

/// `|a − b| / |b|`.
pub fn relative_distance(a: &[f64], b: &[f64]) -> f64 {
    let difference: f64 = a.iter().zip(b).map(|(x, y)| (x - y) * (x - y)).sum();
    let size: f64 = b.iter().map(|y| y * y).sum();
    (difference / size).sqrt()
}

/// Values in one line, `1.2e-4 3.4e-5 …`.
pub fn listed(values: &[f64]) -> String {
    values
        .iter()
        .map(|v| format!("{v:.1e}"))
        .collect::<Vec<_>>()
        .join(" ")
}
