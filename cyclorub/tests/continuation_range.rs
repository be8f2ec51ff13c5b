//! Continuation on a closed curve, independent of harmonic balance: the
//! branch of `x² + (ω − 2)² = 1` turns at ω = 3 and comes back; it must
//! stop when it passes its start frequency, not go on toward ω ≤ 0.

use crate::common;

use common::scalar_branch::{settings, ScalarBranch};
use cyclorub::continuation::{continue_branch, ArcLengthSettings, StopReason};

fn circle() -> ScalarBranch {
    ScalarBranch::new(|x, omega| {
        (
            x * x + (omega - 2.0).powi(2) - 1.0,
            2.0 * x,
            2.0 * (omega - 2.0),
        )
    })
}

#[test]
fn a_branch_that_turns_back_stops_past_its_start() {
    let start = 1.5;
    let branch = continue_branch(
        &mut circle(),
        vec![0.75_f64.sqrt()],
        &ArcLengthSettings {
            min_step: 1e-9,
            ..settings(start, 10.0)
        },
        |_, _| {},
    );
    let StopReason::LeftRange { frequency_hz } = branch.stop else {
        panic!("expected a stop past the start, got {:?}", branch.stop);
    };
    let last = branch.points.last().unwrap();
    assert!(last.omega < start && last.omega > 1.0, "{}", last.omega);
    assert!((frequency_hz - last.omega / (2.0 * std::f64::consts::PI)).abs() < 1e-12);
    // It went round the turning point at ω = 3 on the way, every point on the circle.
    let highest = branch.points.iter().map(|p| p.omega).fold(0.0, f64::max);
    assert!(highest > 2.99, "{highest}");
    for p in &branch.points {
        let r = p.unknowns[0].powi(2) + (p.omega - 2.0).powi(2) - 1.0;
        assert!(r.abs() < 1e-10, "{r}");
    }
    assert!(branch.points.iter().all(|p| p.omega > 0.0));
}

#[test]
fn a_branch_that_reaches_its_end_stops_there_going_down() {
    // Downward from ω = 2.9 to 2.2 on the upper half: no turning point.
    let start = 2.9;
    let x0 = (1.0 - 0.9_f64.powi(2)).sqrt();
    let settings = ArcLengthSettings {
        min_step: 1e-9,
        ..settings(start, 2.2)
    };
    let branch = continue_branch(&mut circle(), vec![x0], &settings, |_, _| {});
    assert_eq!(branch.stop, StopReason::EndReached);
    let last = branch.points.last().unwrap();
    assert!((last.omega - 2.2).abs() < 1e-12, "{}", last.omega);
    assert!((last.unknowns[0] - (1.0 - 0.04_f64).sqrt()).abs() < 1e-9);
}
