//! Continuation past two sheets that come close, independent of harmonic
//! balance: the hyperbola `x² − λ² = ε` (`λ = ω − 2`) has an upper sheet
//! `x = √(λ² + ε)` that turns sharply at `λ = 0`, a gap `2 √ε` above the
//! lower sheet, which goes on straight where the upper one came from. A
//! step much longer than the gap lands on the lower sheet with hardly any
//! turn or correction; only the branch's orientation (the sign of
//! `det [J; tᵀ]`, kept along a branch) tells the jump.
//!
//! With `ε = 0` the two sheets cross (a branch point): the orientation
//! changes there for real, and the branch must go straight through.
//!
//! The regularized contact law makes such sheets: the N = 45
//! deformed-casing branch jumped at 221.4 Hz onto a closed curve that it
//! then went round for ever.

use crate::common;

use common::scalar_branch::{settings, ScalarBranch};
use cyclorub::continuation::{
    continue_branch, ArcLengthSettings, Branch, NewtonSettings, StopReason,
};

/// Follows the hyperbola with gap `ε` from `ω = 1` (`x = start_x`) to 3.
fn follow(gap: f64, start_x: f64, max_step: f64) -> Branch {
    let hyperbola = move |x: f64, omega: f64| {
        let lambda = omega - 2.0;
        (x * x - lambda * lambda - gap, 2.0 * x, -2.0 * lambda)
    };
    let settings = ArcLengthSettings {
        max_step,
        newton: NewtonSettings {
            tolerance: 1e-13,
            max_iterations: 20,
            ..Default::default()
        },
        ..settings(1.0, 3.0)
    };
    continue_branch(
        &mut ScalarBranch::smooth(hyperbola),
        vec![start_x],
        &settings,
        |_, _| {},
    )
}

#[test]
fn a_long_step_does_not_jump_onto_a_close_sheet() {
    for gap in [1e-4, 1e-6, 1e-8] {
        for max_step in [0.05, 0.2] {
            let branch = follow(gap, (1.0 + gap).sqrt(), max_step);
            assert_eq!(branch.stop, StopReason::EndReached, "ε = {gap}");
            let last = branch.points.last().expect("points");
            assert!(
                (last.omega - 3.0).abs() < 1e-12,
                "ε = {gap}: ends at {}",
                last.omega
            );
            for p in &branch.points {
                let lambda = p.omega - 2.0;
                let upper = (lambda * lambda + gap).sqrt();
                assert!(
                    (p.unknowns[0] - upper).abs() < 1e-9,
                    "ε = {gap}, max step {max_step}: x = {} at λ = {lambda}, the upper sheet is at {upper}",
                    p.unknowns[0]
                );
            }
            // The sharp turn is followed, not stepped over: a point within
            // a few gaps of its tip.
            let nearest = branch
                .points
                .iter()
                .map(|p| (p.omega - 2.0).abs())
                .fold(f64::INFINITY, f64::min);
            assert!(
                nearest < 10.0 * gap.sqrt(),
                "ε = {gap}: closest λ {nearest}"
            );
        }
    }
}

#[test]
fn a_branch_goes_straight_through_a_branch_point() {
    // On x = −λ from λ = −1: it crosses x = λ at the origin.
    let branch = follow(0.0, 1.0, 0.2);
    assert_eq!(branch.stop, StopReason::EndReached);
    for p in &branch.points {
        let lambda = p.omega - 2.0;
        assert!(
            (p.unknowns[0] + lambda).abs() < 1e-9,
            "x = {} at λ = {lambda}: left the line x = −λ",
            p.unknowns[0]
        );
    }
    let last = branch.points.last().expect("points");
    assert!((last.unknowns[0] + 1.0).abs() < 1e-9);
    // It crosses with the step that reversed the orientation, once the
    // branch is seen to go on continuously there, instead of creeping up
    // to the branch point (where, on the full wheel, the points drifted
    // onto the other branch): no two points within a hundredth of it.
    let near = branch
        .points
        .iter()
        .filter(|p| (p.omega - 2.0).abs() < 0.01)
        .count();
    assert!(near <= 1, "{near} points within 0.01 of the branch point");
}
