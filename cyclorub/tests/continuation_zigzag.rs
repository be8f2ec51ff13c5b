//! Continuation through nonsmooth folds, independent of harmonic balance:
//! the piecewise-linear branch `ω = g(x)` climbs with slope 1, turns back
//! (slope −1/2) over a short interval of `x`, and climbs again, several
//! times, the backward intervals shorter and shorter (down to 1e-6 of the
//! length scale: two kinks nearly on top of each other, as when two
//! sampled instants of DLFT-HBM switch together). Each turn is a
//! nonsmooth fold: past the kink the tangent reverses its frequency, and
//! the branch goes on only the way that keeps its orientation
//! (`det [J; tᵀ]`); the other way runs back along the sheet it came from.
//!
//! A curve parametrized by `x` is checked point by point: `x` must grow
//! along the whole branch, and every point must lie on it. The widest
//! backward interval (longer than the largest step) must be followed;
//! narrower ones may be stepped over, as a step lands on the climbing
//! piece beyond with its tangent unchanged.

use crate::common;

use common::scalar_branch::{assert_x_grows, settings, ScalarBranch};
use cyclorub::continuation::{continue_branch, ArcLengthSettings, StopReason};

/// Where each backward interval starts, and its length (in x).
const BACKWARD: [(f64, f64); 4] = [(0.5, 0.05), (1.0, 1e-3), (1.5, 1e-5), (2.0, 1e-6)];
const BACKWARD_SLOPE: f64 = -0.5;

/// The zigzag branch, by its pieces.
struct Zigzag;

impl Zigzag {
    /// The index of the linear piece holding `x`, counted from the left.
    fn piece_of(x: f64) -> usize {
        BACKWARD
            .iter()
            .map(|&(start, length)| usize::from(x >= start) + usize::from(x >= start + length))
            .sum()
    }

    fn slope(x: f64) -> f64 {
        if Self::piece_of(x) % 2 == 1 {
            BACKWARD_SLOPE
        } else {
            1.0
        }
    }

    /// `g(x)`: the integral of the slope from 0.
    fn frequency(x: f64) -> f64 {
        let backward: f64 = BACKWARD
            .iter()
            .map(|&(start, length)| (x - start).clamp(0.0, length))
            .sum();
        2.0 + x + (BACKWARD_SLOPE - 1.0) * backward
    }
}

impl Zigzag {
    fn branch() -> ScalarBranch {
        ScalarBranch::piecewise(
            |x, omega| (omega - Self::frequency(x), -Self::slope(x), 1.0),
            |x| Self::piece_of(x) as u64,
        )
    }
}

#[test]
fn nonsmooth_folds_are_turned_the_way_that_keeps_the_orientation() {
    let (start_x, end_x) = (-0.5, 3.0);
    let settings = ArcLengthSettings {
        max_step: 0.03,
        ..settings(Zigzag::frequency(start_x), Zigzag::frequency(end_x))
    };
    let branch = continue_branch(&mut Zigzag::branch(), vec![start_x], &settings, |_, _| {});
    assert_eq!(branch.stop, StopReason::EndReached);
    assert_x_grows(&branch.points, "zigzag");
    for p in &branch.points {
        let r = p.omega - Zigzag::frequency(p.unknowns[0]);
        assert!(r.abs() < 1e-10, "residual {r} at x = {}", p.unknowns[0]);
    }
    // The widest backward interval holds points of the branch, with the
    // frequency going down there.
    for &(start, length) in &BACKWARD[..1] {
        let inside = branch
            .points
            .windows(2)
            .filter(|pair| {
                pair.iter().all(|p| {
                    let x = p.unknowns[0];
                    x >= start && x <= start + length
                }) && pair[1].omega < pair[0].omega
            })
            .count();
        assert!(
            inside >= 1,
            "the backward interval at x = {start} was stepped over"
        );
    }
    eprintln!(
        "{} points, {} iterations",
        branch.points.len(),
        branch.total_iterations
    );
}
