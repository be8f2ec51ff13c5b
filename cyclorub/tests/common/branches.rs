//! Branch switching on a solved symmetric branch, as the tests call it:
//! the crossings of a class along the branch's own points, and the switch
//! between two consecutive ones.

use cyclorub::branches::{real_crossings, switch_at, BifurcatedBranch, BranchError};
use cyclorub::case::Case;
use cyclorub::continuation::Point;
use cyclorub::continuation::Settings;
use cyclorub::forced_response::{ForcedResponse, Solution};

/// `case`'s symmetric branch, solved as the case says.
pub fn solved(case: &Case) -> Solution {
    ForcedResponse::from_case(case)
        .unwrap()
        .build()
        .unwrap()
        .run(&mut [])
        .unwrap()
}

/// The brackets `(i, i + 1)` of `points` where class `class`'s least
/// eigenvalue of the enlarged Jacobian changes sign ([`real_crossings`]).
pub fn crossings(solution: &mut Solution, class: i64, points: &[Point]) -> Vec<usize> {
    real_crossings(
        &solution.case,
        &solution.model,
        &mut solution.problem,
        class,
        points,
    )
    .unwrap()
}

/// The bifurcated branch of class `class` switched at between points `i`
/// and `i + 1` of `points` ([`switch_at`]).
pub fn switch_between(
    solution: &mut Solution,
    class: i64,
    points: &[Point],
    i: usize,
    settings: &Settings,
) -> Result<BifurcatedBranch, BranchError> {
    switch_at(
        &solution.case,
        &solution.model,
        &mut solution.problem,
        class,
        (&points[i].unknowns, points[i].omega),
        (&points[i + 1].unknowns, points[i + 1].omega),
        settings,
    )
}
