//! The secant predictor on a finely kinked branch, independent of harmonic
//! balance: `ω = g(x)`, a smooth rising curve plus a sawtooth of slope
//! ±0.3 on pieces of width 1e-3, as DLFT-HBM's branch is smooth at the
//! scale of a step but made of short pieces (one per change of the contact
//! state at a sampled instant), the tangent of each tilted from its
//! neighbours' by 10° to 27°, beyond the 11° a step may turn. Along the
//! tangent every long step turns too far and meets a kink; along the last
//! chord the branch is followed with long steps.
//!
//! Every point is checked against the curve in closed form, and `x` must
//! grow along the whole branch (a graph over `x`: going back means a jump).

use crate::common;

use common::scalar_branch::{assert_x_grows, settings, ScalarBranch};
use cyclorub::continuation::{
    Branch, Continuation, PiecewisePredictor, Settings, StepSettings, StopReason,
};

/// The width of a piece, in `x`.
const PIECE: f64 = 1e-3;
/// The sawtooth's slope on each piece (+ on even pieces, − on odd ones).
const SAWTOOTH: f64 = 0.3;
/// The last `x` of the sweep.
const END_X: f64 = 2.0;

/// The index of the piece holding `x`.
fn piece_of(x: f64) -> u64 {
    (x / PIECE).floor().max(0.0) as u64
}

/// `g(x)`: the smooth part `2 + x + sin(3x) / 6` (slope 0.5 to 1.5) and the
/// sawtooth, continuous at each piece's ends.
fn frequency(x: f64) -> f64 {
    let phase = x / PIECE;
    let within = phase - phase.floor();
    let tooth = if piece_of(x).is_multiple_of(2) {
        within
    } else {
        1.0 - within
    };
    2.0 + x + (3.0 * x).sin() / 6.0 + SAWTOOTH * PIECE * tooth
}

/// `g'(x)`, from 0.2 to 1.8: the branch never folds.
fn slope(x: f64) -> f64 {
    let sign = if piece_of(x).is_multiple_of(2) {
        1.0
    } else {
        -1.0
    };
    1.0 + 0.5 * (3.0 * x).cos() + sign * SAWTOOTH
}

fn follow(predictor: PiecewisePredictor) -> Branch {
    let mut problem =
        ScalarBranch::piecewise(|x, omega| (omega - frequency(x), -slope(x), 1.0), piece_of);
    let arc_length = settings(frequency(0.0), frequency(END_X));
    let settings = Settings {
        step: StepSettings {
            piecewise_predictor: predictor,
            ..StepSettings::default()
        },
        ..Settings::from(arc_length)
    };
    Continuation::new(&mut problem, vec![0.0], settings)
        .expect("valid settings")
        .finish()
}

/// Every point lies on the curve, `x` grows, and the end is reached.
fn check(branch: &Branch, case: &str) {
    assert_eq!(branch.stop, StopReason::EndReached, "{case}");
    assert_x_grows(&branch.points, case);
    for p in &branch.points {
        let x = p.unknowns[0];
        assert!(
            (p.omega - frequency(x)).abs() <= 1e-11,
            "{case}: ({x}, {}) is off the curve by {:e}",
            p.omega,
            p.omega - frequency(x)
        );
    }
    let last = branch.points.last().expect("points").unknowns[0];
    assert!((last - END_X).abs() < 1e-9, "{case}: ends at x = {last}");
}

#[test]
fn the_secant_predictor_follows_a_finely_kinked_branch_with_long_steps() {
    let tangent = follow(PiecewisePredictor::Tangent);
    check(&tangent, "tangent");
    let secant = follow(PiecewisePredictor::Secant);
    check(&secant, "secant");
    for (name, branch) in [("tangent", &tangent), ("secant", &secant)] {
        println!(
            "{name}: {} points, {} iterations",
            branch.points.len(),
            branch.total_iterations
        );
    }
    // The sweep is about 3 long in scaled arc length: 60 steps of the
    // largest, 0.05, at most (measured: 49 points, 117 iterations). Along
    // the tangent, steps of at most 0.03 and the kinks (measured: 1813
    // points, 5516 iterations).
    assert!(
        secant.points.len() <= 60,
        "secant: {} points",
        secant.points.len()
    );
    assert!(
        20 * secant.total_iterations <= tangent.total_iterations,
        "secant: {} iterations, tangent: {}",
        secant.total_iterations,
        tangent.total_iterations
    );
}
