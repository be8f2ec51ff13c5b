//! What locating one event found (docs/design.md §10, "Located"): its
//! followed exponent located in one chord metric, then in the other where
//! Newton fails on the first's planes, else its class's count; or no
//! crossing at all (the tracking paired two exponents).

use super::chord::{marker_points, ChordMetric};
use super::locate_by_count::{located_by_count, GROWING};
use super::locate_markers::{locate_one, LocateError};
use crate::continuation::{NewtonSettings, Point};
use crate::hbm::HarmonicBalance;
use crate::stability::{Exponent, Marker, Stability};

/// What locating one event found.
pub(super) enum Outcome {
    /// Located, with the trial points solved.
    Located(Marker, usize),
    /// Left where interpolation placed it, with why.
    Failed(LocateError),
    /// Not a crossing (see [`Located::unmatched`](super::Located::unmatched)), with why.
    Unmatched(String),
}

/// [`outcome_in`] the metric `first`, and where Newton does not converge
/// at one of its trials, in the `other`: taken only where it locates the
/// event (the first metric's failure is said otherwise, and its trials are
/// not counted in [`Located::solves`](super::Located::solves)).
pub(super) fn outcome(
    check: &Stability<'_>,
    problem: &mut HarmonicBalance,
    points: &[Point],
    marker: &Marker,
    (newton, [first, other]): (&NewtonSettings, [ChordMetric; 2]),
    classes_known: bool,
) -> Outcome {
    match outcome_in(
        check,
        problem,
        points,
        marker,
        (newton, first),
        classes_known,
    ) {
        // Newton did not converge on a plane of the first metric: the
        // other's planes cut the branch elsewhere. (A bracket that does not
        // close, or a count the same at both points, is no matter of the
        // metric: on the open fan's DLFT branch a second try of its one
        // such event cost 170 s for nothing.)
        Outcome::Failed(error @ LocateError::Newton { .. }) => {
            match outcome_in(
                check,
                problem,
                points,
                marker,
                (newton, other),
                classes_known,
            ) {
                located @ Outcome::Located(..) => located,
                _ => Outcome::Failed(error),
            }
        }
        found => found,
    }
}

/// One event located on planes square to its chord in `metric`: by its
/// followed exponent, else (where that exponent jumps or does not close)
/// by its class's count of growing exponents; an event that is
/// [`unmatched`] is [`Outcome::Unmatched`].
fn outcome_in(
    check: &Stability<'_>,
    problem: &mut HarmonicBalance,
    points: &[Point],
    marker: &Marker,
    (newton, metric): (&NewtonSettings, ChordMetric),
    classes_known: bool,
) -> Outcome {
    let error = match locate_one(
        check,
        problem,
        points,
        marker,
        (newton, metric),
        classes_known,
    ) {
        Ok((located, solves)) => return Outcome::Located(located, solves),
        Err(error) => error,
    };
    // The followed exponent does not go through 0 continuously (it jumps,
    // or the two exponents are not one): the class's count of growing
    // exponents still changes once where there is a crossing.
    let jumped = match &error {
        LocateError::NotContinuous { .. } | LocateError::PairedAtAJump { .. } => true,
        LocateError::NotClosed { .. } => false,
        _ => return Outcome::Failed(error),
    };
    match located_by_count(check, problem, points, marker, (newton, metric)) {
        Ok((located, solves)) => Outcome::Located(located, solves),
        Err(by_count @ LocateError::SameCount { .. }) if jumped && unmatched(marker, points) => {
            Outcome::Unmatched(format!("{error}; {by_count}"))
        }
        Err(by_count) => {
            tracing::debug!(
                "marker at {:.6} Hz not located by the count either: {by_count}",
                marker.frequency_hz
            );
            Outcome::Failed(error)
        }
    }
}

/// Whether an event whose two exponents are not one exponent moving and
/// whose class grows as many exponents at both points is no crossing: it
/// does not change its class's stability, and both its exponents are
/// outside the markers' band (growing faster than `1e-6 ω` on one side,
/// damped as fast on the other). A crossing whose exponent is inside the
/// band at one of its points also leaves the count unchanged there (the
/// count changes where the exponent leaves the band, a later step): it is
/// kept.
fn unmatched(marker: &Marker, points: &[Point]) -> bool {
    let (Some(before), Some(after)) = (marker.before, marker.after) else {
        return false;
    };
    let Ok((a, b)) = marker_points(points, marker.index) else {
        return false;
    };
    let outside = |e: Exponent, omega: f64| e.re.abs() > GROWING * omega;
    !marker.class_changes && outside(before, a.omega) && outside(after, b.omega)
}
