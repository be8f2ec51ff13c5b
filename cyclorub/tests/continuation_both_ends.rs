//! A branch followed from both ends of its range, independent of harmonic
//! balance, on the S-shaped curve `x³ − x/2 = λ` (`λ = ω − 2`, ω from 1 to
//! 3): one solution at each end, two folds between, `x` growing along it.
//!
//! The sweep from the start is made to stop short by a fault: evaluations
//! fail in a band of `x` on the middle sheet (a test double for whatever
//! stops a real sweep: a jump onto a travelled sheet, a step underflow).
//! The fault lasts until the sweep back from the end begins, or for ever.

use crate::common;

use common::scalar_branch::{
    assert_x_grows, s_curve, s_curve_root as root, settings, Faulty, ScalarBranch,
};
use cyclorub::continuation::{continue_from_both_ends, ArcLengthSettings, Branch, StopReason};
use std::cell::Cell;
use std::rc::Rc;

/// Follows the S curve from both ends with a fault in `band`; the fault
/// ends when the sweep back starts if `transient`.
fn follow(band: (f64, f64), transient: bool, max_points: usize) -> Branch {
    let active = Rc::new(Cell::new(true));
    let mut problem = Faulty {
        curve: ScalarBranch::smooth(s_curve),
        band,
        active: active.clone(),
    };
    let settings = ArcLengthSettings {
        max_points,
        ..settings(1.0, 3.0)
    };
    continue_from_both_ends(
        &mut problem,
        vec![root(-1.0)],
        vec![root(1.0)],
        &settings,
        |point, _| {
            if transient && point.omega == 3.0 {
                active.set(false);
            }
        },
    )
}

fn assert_on_the_curve(branch: &Branch) {
    for p in &branch.points {
        let (r, _, _) = s_curve(p.unknowns[0], p.omega);
        assert!(r.abs() < 1e-11, "residual {r} at x = {}", p.unknowns[0]);
    }
}

#[test]
fn a_sweep_stopped_short_is_joined_by_the_sweep_back_from_the_end() {
    let branch = follow((0.1, 0.2), true, 100_000);
    assert_eq!(branch.stop, StopReason::EndReached);
    let sweeps = branch.sweeps.as_ref().expect("followed from both ends");
    assert!(
        matches!(sweeps.from_start, StopReason::StepUnderflow { .. }),
        "{:?}",
        sweeps.from_start
    );
    let StopReason::MetOtherSweep { point, .. } = sweeps.from_end else {
        panic!("the sweeps did not meet: {:?}", sweeps.from_end);
    };
    assert_eq!(sweeps.from_start_kept, point + 1);
    assert!(sweeps.from_start_kept < sweeps.from_start_points);
    assert_eq!(
        branch.points.len(),
        sweeps.from_start_kept + sweeps.from_end_points
    );
    // From the start to the end, in order, with no hole and nothing twice.
    assert_eq!(branch.points[0].omega, 1.0);
    assert_eq!(branch.points.last().map(|p| p.omega), Some(3.0));
    assert_on_the_curve(&branch);
    assert_x_grows(&branch.points, "joined");
    // No hole longer than a step (0.05, and the corrector's few percent).
    for pair in branch.points.windows(2) {
        let dx = pair[1].unknowns[0] - pair[0].unknowns[0];
        assert!(dx <= 0.055, "a hole of {dx} at x = {}", pair[0].unknowns[0]);
    }
    // The join is below the band, where the first sweep stopped.
    let junction = &branch.points[sweeps.from_start_kept - 1];
    assert!(
        junction.unknowns[0] <= 0.1,
        "joined at x = {}",
        junction.unknowns[0]
    );
    assert!(sweeps.summary().contains("joined"), "{}", sweeps.summary());
}

#[test]
fn two_sweeps_that_stop_at_a_lasting_fault_keep_both_with_a_gap() {
    let branch = follow((0.1, 0.2), false, 100_000);
    assert!(
        matches!(branch.stop, StopReason::StepUnderflow { .. }),
        "{:?}",
        branch.stop
    );
    let sweeps = branch.sweeps.as_ref().expect("followed from both ends");
    assert!(matches!(sweeps.from_end, StopReason::StepUnderflow { .. }));
    assert_eq!(sweeps.from_start_kept, sweeps.from_start_points);
    assert_eq!(
        branch.points.len(),
        sweeps.from_start_points + sweeps.from_end_points
    );
    assert_on_the_curve(&branch);
    assert_x_grows(&branch.points, "gap");
    let before = &branch.points[sweeps.from_start_kept - 1];
    let after = &branch.points[sweeps.from_start_kept];
    assert!(before.unknowns[0] <= 0.1 && after.unknowns[0] >= 0.2);
    assert_eq!(branch.points.last().map(|p| p.omega), Some(3.0));
    assert!(sweeps.summary().contains("gap"), "{}", sweeps.summary());
}

#[test]
fn a_sweep_that_fails_at_once_leaves_the_branch_to_the_sweep_back() {
    // The fault covers the start: the first point cannot be computed.
    let branch = follow((-2.0, -1.0), true, 100_000);
    assert_eq!(branch.stop, StopReason::EndReached);
    let sweeps = branch.sweeps.as_ref().expect("followed from both ends");
    assert_eq!(sweeps.from_start_points, 0);
    assert_eq!(sweeps.from_end, StopReason::EndReached);
    assert_eq!(branch.points[0].omega, 1.0);
    assert_eq!(branch.points.last().map(|p| p.omega), Some(3.0));
    assert_on_the_curve(&branch);
    assert_x_grows(&branch.points, "sweep back alone");
}

#[test]
fn a_sweep_back_that_stops_before_the_start_says_so() {
    // The fault covers the start for good: neither sweep reaches it.
    let branch = follow((-2.0, -1.0), false, 100_000);
    let sweeps = branch.sweeps.as_ref().expect("followed from both ends");
    assert_eq!(sweeps.from_start_points, 0);
    assert!(matches!(sweeps.from_end, StopReason::StepUnderflow { .. }));
    assert!(branch.points[0].unknowns[0] >= -1.0);
    assert_eq!(branch.points.last().map(|p| p.omega), Some(3.0));
    assert_on_the_curve(&branch);
    assert_x_grows(&branch.points, "sweep back stopped");
    assert!(
        sweeps.summary().contains("does not reach the start"),
        "{}",
        sweeps.summary()
    );
}

#[test]
fn a_branch_that_reaches_its_end_or_its_cap_is_one_sweep() {
    let branch = follow((5.0, 6.0), true, 100_000);
    assert_eq!(branch.stop, StopReason::EndReached);
    assert!(branch.sweeps.is_none());
    let capped = follow((0.1, 0.2), true, 10);
    assert_eq!(capped.stop, StopReason::PointCap { max_points: 10 });
    assert!(capped.sweeps.is_none());
    assert_eq!(capped.points.len(), 10);
}
