//! A marker located by the count of its class's growing exponents
//! (docs/design.md §10, "Located"), where following one exponent through
//! 0 fails: the followed exponent jumps inside the bracket. Two exponents
//! colliding swap their roles (their real parts meet and part within a
//! few thousandths of the chord), and near a fold the branch's solutions
//! on the chord can jump between the two sheets the plane through the
//! chord's point cuts; either way the class's count of growing exponents
//! still changes once between the marker's two points, and bisection on
//! that count places the change to [`BRACKET_HZ`] whatever the exponents
//! do inside. Where the bracket closes to [`BRACKET_FRACTION`] with a newly
//! growing exponent that already holds most of the marker's change, the
//! exponents jump there ([`MarkerKind::Jump`]): at a point the
//! continuation placed on a change of contact (a kink), the plane through
//! the chord cuts both sheets beside it and the bisection closes on the
//! point itself.

use super::chord::{
    contact_changes, marker_points, Chord, ChordMetric, BRACKET_FRACTION, BRACKET_HZ,
    FOLD_FRACTION, JUMP_SHARE, REAL_AT_LOCATION,
};
use super::locate_error::LocateError;
use crate::continuation::{NewtonSettings, Point};
use crate::hbm::HarmonicBalance;
use crate::stability::{
    crossing_kind, frequency_turns, multiplier_angle, Exponent, Following, Location, Marker,
    MarkerKind, Stability,
};
use std::f64::consts::PI;

/// The growth (in `ω`) above which an exponent counts as growing here: the
/// markers' own band, far above the exponents that hover at the growth
/// tolerance on a plateau.
pub(super) const GROWING: f64 = 1e-6;

/// Trial points solved at most (bisection from the whole chord).
const MOST_SOLVES: usize = 40;

/// One end of the bracket: where on the chord, its frequency, the class's
/// exponents there, the branch's solution.
struct End {
    fraction: f64,
    omega: f64,
    exponents: Vec<Exponent>,
    solution: Vec<f64>,
}

impl End {
    fn growing(&self) -> usize {
        self.exponents
            .iter()
            .filter(|e| e.re > GROWING * self.omega)
            .count()
    }
}

/// `marker` located by bisection on its class's count of growing exponents
/// between its two points of `points`; with the trial points solved.
pub(super) fn located_by_count(
    check: &Stability<'_>,
    problem: &mut HarmonicBalance,
    points: &[Point],
    marker: &Marker,
    (newton, metric): (&NewtonSettings, ChordMetric),
) -> Result<(Marker, usize), LocateError> {
    let (a, b) = marker_points(points, marker.index)?;
    let class = marker.nodal_diameter.unwrap_or(0);
    // Each trial's exponents follow the last trial's (the bracket shrinks
    // about them; the contour runs where the following cannot vouch).
    let mut following: Option<Following> = None;
    let mut end = |fraction: f64, x: &[f64], omega: f64| -> Result<End, LocateError> {
        let (exponents, next) =
            check.class_exponents_following(x, omega, class, following.as_ref())?;
        following = Some(next);
        Ok(End {
            fraction,
            omega,
            exponents,
            solution: x.to_vec(),
        })
    };
    let mut lo = end(0.0, &a.unknowns, a.omega)?;
    let mut hi = end(1.0, &b.unknowns, b.omega)?;
    let below = lo.growing();
    if below == hi.growing() {
        return Err(LocateError::SameCount {
            class,
            growing: below,
        });
    }
    let chord = Chord::new(problem, a, b, metric);
    let closed = |lo: &End, hi: &End| {
        let width = hi.fraction - lo.fraction;
        ((hi.omega - lo.omega).abs() / (2.0 * PI) <= BRACKET_HZ && width <= FOLD_FRACTION)
            || width <= BRACKET_FRACTION
    };
    let mut solves = 0;
    let mut last: Option<(f64, Vec<f64>)> = None;
    while !closed(&lo, &hi) {
        if solves == MOST_SOLVES {
            return Err(LocateError::NotClosed {
                trials: solves,
                bracket_hz: (hi.omega - lo.omega).abs() / (2.0 * PI),
                bracket_fraction: hi.fraction - lo.fraction,
                real_part: slowest_growing(&lo).min(slowest_growing(&hi)),
            });
        }
        let s = 0.5 * (lo.fraction + hi.fraction);
        let start = last.as_ref().map(|(f, x)| (*f, x.as_slice()));
        let ends = [(lo.fraction, &lo.solution[..]), (hi.fraction, &hi.solution)];
        let (x, omega) = chord.solve_or_walk(problem, s, start, ends, newton)?;
        let trial = end(s, &x, omega)?;
        solves += 1;
        last = Some((s, x));
        if trial.growing() == below {
            lo = trial;
        } else {
            hi = trial;
        }
    }
    // The growing side, and its slowest growing exponent: the one that
    // crossed, as near as the bracket tells.
    let growing = if hi.growing() > lo.growing() {
        &hi
    } else {
        &lo
    };
    let exponent = growing
        .exponents
        .iter()
        .copied()
        .filter(|e| e.re > GROWING * growing.omega)
        .min_by(|x, y| x.re.total_cmp(&y.re))
        .ok_or(LocateError::NoExponents)?;
    // The kind read again with the located point's tight angle, as a
    // followed crossing's is: a slow complex pair keeps a finite angle.
    let angle = multiplier_angle(exponent, growing.omega);
    let kind = crossing_kind(
        angle,
        check.classes_tell_kinds().then_some(class),
        REAL_AT_LOCATION,
        frequency_turns(points.len(), |i| points[i].omega, marker.index),
    );
    // A bracket closed to the chord's resolution across a change of contact
    // whose newly growing exponent already holds most of the marker's
    // change is a jump: placed at the marker's own point it touches (that
    // point is on the change of contact), else inside it.
    let whole_change = match (marker.before, marker.after) {
        (Some(before), Some(after)) => (after.re - before.re).abs(),
        _ => f64::INFINITY,
    };
    let jump = hi.fraction - lo.fraction <= BRACKET_FRACTION
        && exponent.re - GROWING * growing.omega > JUMP_SHARE * whole_change
        && contact_changes(problem, &lo.solution, lo.omega, &hi.solution, hi.omega);
    let (fraction, omega) = match (lo.fraction, hi.fraction) {
        (f, _) if jump && f <= 0.0 => (0.0, a.omega),
        (_, f) if jump && f >= 1.0 => (1.0, b.omega),
        // The change lies inside the bracket: its middle.
        _ => (
            0.5 * (lo.fraction + hi.fraction),
            0.5 * (lo.omega + hi.omega),
        ),
    };
    let kind = if jump { MarkerKind::Jump } else { kind };
    let located = Marker {
        fraction,
        frequency_hz: omega / (2.0 * PI),
        exponent,
        kind,
        located: Some(Location {
            bracket_hz: (hi.omega - lo.omega).abs() / (2.0 * PI),
            bracket_fraction: hi.fraction - lo.fraction,
            solves,
            angle,
            by_count: true,
        }),
        ..marker.clone()
    };
    Ok((located, solves))
}

/// The real part of the slowest growing exponent at `end` (0 without one),
/// 1/s: how far the crossing is from 0 there.
fn slowest_growing(end: &End) -> f64 {
    end.exponents
        .iter()
        .map(|e| e.re)
        .filter(|&re| re > GROWING * end.omega)
        .min_by(f64::total_cmp)
        .unwrap_or(0.0)
}
