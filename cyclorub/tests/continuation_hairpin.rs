//! Continuation through a hairpin fold, independent of harmonic balance:
//! the smooth branch `ω = 2 + x + A / (1 + (x/w)²)` climbs a narrow spike
//! (width `w` = 1 % of the length scale, two sheets a few `w` apart and
//! running against each other) and comes down again. A curve parametrized
//! by `x` can be checked point by point: `x` must grow along the whole
//! branch (going back means the continuation jumped onto the sheet it came
//! along), and the top of the spike must be visited (not stepped over).
//!
//! A spike much narrower than the largest step may be stepped over (its
//! tails do not turn the tangent): the largest step is ten widths.
//!
//! The regularized contact law makes such folds: the N = 24 deformed-casing
//! case of the paper has folds whose two sheets are 1e-5 gaps apart.

use crate::common;

use common::scalar_branch::{assert_x_grows, settings, ScalarBranch};
use cyclorub::continuation::{continue_branch, ArcLengthSettings, StopReason};

/// The spike's height (in ω) and width (in x).
const HEIGHT: f64 = 1.0;

fn frequency(x: f64, width: f64) -> f64 {
    2.0 + x + HEIGHT / (1.0 + (x / width).powi(2))
}

fn hairpin(width: f64) -> ScalarBranch {
    ScalarBranch::smooth(move |x, omega| {
        let u = x / width;
        let slope = 1.0 - HEIGHT * 2.0 * u / width / (1.0 + u * u).powi(2);
        (omega - frequency(x, width), -slope, 1.0)
    })
}

#[test]
fn a_narrow_fold_is_followed_around_its_tip_without_jumping_across() {
    for width in [1e-2, 1e-3, 1e-4] {
        let start_x = -1.0;
        let settings = ArcLengthSettings {
            min_step: 1e-9,
            max_step: 10.0 * width,
            ..settings(frequency(start_x, width), 3.5)
        };
        let branch = continue_branch(&mut hairpin(width), vec![start_x], &settings, |_, _| {});
        assert_eq!(branch.stop, StopReason::EndReached, "w = {width}");
        assert_x_grows(&branch.points, &format!("w = {width}"));
        for p in &branch.points {
            let r = p.omega - frequency(p.unknowns[0], width);
            assert!(r.abs() < 1e-10, "w = {width}: residual {r}");
        }
        // The tip (the spike's part of ω reaches HEIGHT at x = 0): visited
        // to within 1 %, not stepped over.
        let highest = branch
            .points
            .iter()
            .map(|p| p.omega - 2.0 - p.unknowns[0])
            .fold(0.0, f64::max);
        assert!(highest > 0.99 * HEIGHT, "w = {width}: highest {highest}");
        eprintln!(
            "w = {width}: {} points, {} iterations",
            branch.points.len(),
            branch.total_iterations
        );
    }
}
