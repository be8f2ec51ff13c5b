//! Continuation along a snake, independent of harmonic balance: the branch
//! `ω = A sin(2π x / P) − D x` folds back and forth many times, each sheet
//! running beside the ones before it, a fraction of a period away, and each
//! fold a little lower than the one before (`D > 0`). A long step over a
//! top fold would overshoot it where only the older, higher folds are, and
//! a corrector landing there, with hardly any turn, would send the branch
//! round the same sheets again; the turn limits and the refusal of steps
//! that land on old sheets must prevent it. The N = 45 deformed-casing
//! branch snakes like this through hundreds of folds.
//!
//! A graph over `x` is checked point by point: `x` must grow along the whole
//! branch (a point on an older sheet lies at a smaller `x`), every point
//! must lie on it, and no fold may be stepped over.

use crate::common;

use common::scalar_branch::{assert_x_grows, settings, ScalarBranch};
use cyclorub::continuation::{continue_branch, ArcLengthSettings, StopReason};
use std::f64::consts::PI;

const AMPLITUDE: f64 = 0.15;
const PERIOD: f64 = 0.02;
const DRIFT: f64 = 4.0;

fn frequency(x: f64) -> f64 {
    AMPLITUDE * (2.0 * PI * x / PERIOD).sin() - DRIFT * x
}

fn slope(x: f64) -> f64 {
    AMPLITUDE * 2.0 * PI / PERIOD * (2.0 * PI * x / PERIOD).cos() - DRIFT
}

fn residual(x: f64, omega: f64) -> (f64, f64, f64) {
    (omega - frequency(x), -slope(x), 1.0)
}

/// The snake told in pieces of width [`CELL`] in `x`, as DLFT-HBM tells its
/// contact states: continuation locates and turns their kinks.
const CELL: f64 = 1e-3;

fn piecewise_snake() -> ScalarBranch {
    ScalarBranch::piecewise(residual, |x| (x / CELL).floor() as i64 as u64)
}

#[test]
fn a_snake_is_followed_fold_after_fold_without_landing_on_its_old_sheets() {
    // From just past the first top (above every later fold), down over
    // 20 periods.
    let start_x = 0.3 * PERIOD;
    let end_x = start_x + 20.0 * PERIOD;
    for (kind, max_step) in [("smooth", 0.05), ("smooth", 0.1), ("piecewise", 0.03)] {
        let mut snake = if kind == "smooth" {
            ScalarBranch::smooth(residual)
        } else {
            piecewise_snake()
        };
        let settings = ArcLengthSettings {
            max_step,
            ..settings(frequency(start_x), frequency(end_x))
        };
        let branch = continue_branch(&mut snake, vec![start_x], &settings, |_, _| {});
        assert_eq!(
            branch.stop,
            StopReason::EndReached,
            "{kind}, largest step {max_step}: {} points",
            branch.points.len()
        );
        assert_x_grows(&branch.points, &format!("{kind}, largest step {max_step}"));
        for p in &branch.points {
            let r = p.omega - frequency(p.unknowns[0]);
            assert!(r.abs() < 1e-10, "residual {r} at x = {}", p.unknowns[0]);
        }
        // No fold stepped over: consecutive points are less than a quarter
        // period apart in x (x grows, so every sheet holds points).
        for pair in branch.points.windows(2) {
            let gap = pair[1].unknowns[0] - pair[0].unknowns[0];
            assert!(
                gap < PERIOD / 4.0,
                "{kind}, largest step {max_step}: stepped over a fold from x = {}",
                pair[0].unknowns[0]
            );
        }
    }
}
