//! Events of a branch: where it folds, crosses another branch, turns a kink
//! or stops, detected between consecutive points by test functions
//! (BifurcationKit's habit) and stored in [`Branch::events`](super::Branch).
//!
//! A test function is a sign that changes at the event: the frequency
//! component of the unit tangent (a fold), the branch's orientation
//! `sign det [J; tᵀ]` (a branch point). User-defined test functions (a later
//! issue) belong in [`detect`], reported as a new [`EventKind`].

use super::{hertz, StopReason};
use serde::Serialize;

/// Something that happened along a branch.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Event {
    /// Where it lies among the points: just before the point of this index
    /// (a fold, branch point or kink between points `index − 1` and
    /// `index`; a stop after the last point, `index` = the number of
    /// points).
    pub index: usize,
    /// Its frequency, Hz: a fold's is the extremum of the cubic through the
    /// two points' frequencies and tangents; a kink's is where it was located; a branch
    /// point's is that of the point past it; a stop's is the one it names,
    /// or the last point's.
    pub frequency_hz: f64,
    /// What happened.
    #[serde(flatten)]
    pub kind: EventKind,
}

/// What happened. More kinds will come (user-defined test functions): match
/// with a wildcard arm.
#[derive(Clone, Debug, PartialEq, Serialize)]
#[serde(tag = "kind", rename_all = "snake_case")]
#[non_exhaustive]
pub enum EventKind {
    /// A turning point: the frequency component of the tangent changed
    /// sign (the branch turned back in frequency), smooth or at a kink.
    Fold,
    /// The branch's orientation (the sign of `det [J; tᵀ]`) changed: it
    /// crossed another branch. Looked for on smooth residuals, where the
    /// orientation is kept along a regular branch.
    BranchPoint,
    /// A kink of a nonsmooth or piecewise-smooth residual was turned: the
    /// branch went on along the way past it (see the policies).
    Kink,
    /// The branch (or one sweep of it) stopped.
    Stop(StopReason),
}

impl Event {
    /// A stop after `points` points, the last of them at `last_omega`
    /// (rad/s).
    pub(crate) fn stop(reason: &StopReason, points: usize, last_omega: Option<f64>) -> Self {
        let frequency_hz = match reason {
            StopReason::StepUnderflow { frequency_hz, .. }
            | StopReason::NewtonFailure { frequency_hz, .. }
            | StopReason::LeftRange { frequency_hz }
            | StopReason::ClosedLoop { frequency_hz, .. }
            | StopReason::MetOtherSweep { frequency_hz, .. }
            | StopReason::EvaluationError { frequency_hz, .. } => *frequency_hz,
            StopReason::Interrupted { frequency_hz } => frequency_hz.unwrap_or(f64::NAN),
            StopReason::EndReached
            | StopReason::AllFrequenciesDone
            | StopReason::PointCap { .. } => last_omega.map_or(f64::NAN, hertz),
        };
        Self {
            index: points,
            frequency_hz,
            kind: EventKind::Stop(reason.clone()),
        }
    }

    /// The event of a sweep of `count` points followed backward, placed in
    /// a branch that holds that sweep reversed from its point `offset` on.
    pub(crate) fn reversed(&self, count: usize, offset: usize) -> Self {
        Self {
            index: offset + count.saturating_sub(self.index),
            ..self.clone()
        }
    }
}

/// One end of a step, in scaled unknowns: the point and its unit tangent.
pub(crate) struct End<'a> {
    /// The point `z`.
    pub(crate) z: &'a [f64],
    /// The unit tangent there, along the way travelled.
    pub(crate) tangent: &'a [f64],
    /// Its orientation.
    pub(crate) orientation: f64,
}

/// The events of the step from `before` to `after` (the point of index
/// `index`), their frequencies unscaled by `frequency_factor`. Branch
/// points only if `orientation_kept`.
pub(crate) fn detect(
    before: &End<'_>,
    after: &End<'_>,
    index: usize,
    frequency_factor: f64,
    orientation_kept: bool,
) -> Vec<Event> {
    let mut events = Vec::new();
    let last = before.z.len() - 1;
    let (from, to) = (before.tangent[last], after.tangent[last]);
    if from * to < 0.0 {
        events.push(Event {
            index,
            frequency_hz: hertz(fold_frequency(before, after) / frequency_factor),
            kind: EventKind::Fold,
        });
    }
    if orientation_kept && before.orientation * after.orientation < 0.0 {
        events.push(Event {
            index,
            frequency_hz: hertz(after.z[last] / frequency_factor),
            kind: EventKind::BranchPoint,
        });
    }
    events
}

/// The frequency (scaled) of the fold between two points whose tangents'
/// frequency components have opposite signs: the extremum of the cubic
/// Hermite interpolant of the frequency along the chord, which matches the
/// frequencies and their slopes (the tangents' components) at both points,
/// so that it is exact to fourth order in the step on a smooth fold.
pub(crate) fn fold_frequency(before: &End<'_>, after: &End<'_>) -> f64 {
    let last = before.z.len() - 1;
    let h = super::geometry::distance(after.z, before.z);
    let (w0, w1) = (before.z[last], after.z[last]);
    let (d0, d1) = (before.tangent[last] * h, after.tangent[last] * h);
    // p(s) = h00 w0 + h10 d0 + h01 w1 + h11 d1 on s in [0, 1]; p'(s):
    let slope = |s: f64| {
        (6.0 * s * s - 6.0 * s) * (w0 - w1)
            + (3.0 * s * s - 4.0 * s + 1.0) * d0
            + (3.0 * s * s - 2.0 * s) * d1
    };
    // p' changes sign on [0, 1] (it is d0 at 0, d1 at 1): bisect.
    let (mut lo, mut hi) = (0.0, 1.0);
    for _ in 0..60 {
        let middle = 0.5 * (lo + hi);
        if slope(middle) * d0 > 0.0 {
            lo = middle;
        } else {
            hi = middle;
        }
    }
    let s = 0.5 * (lo + hi);
    let (s2, s3) = (s * s, s * s * s);
    (2.0 * s3 - 3.0 * s2 + 1.0) * w0
        + (s3 - 2.0 * s2 + s) * d0
        + (-2.0 * s3 + 3.0 * s2) * w1
        + (s3 - s2) * d1
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_fold_is_placed_at_the_top_of_a_parabola() {
        // ω = 1 − (x − 0.3)², points at x = 0 and x = 0.5 with unit
        // tangents (1, ω').
        let point = |x: f64| -> (Vec<f64>, Vec<f64>) {
            let slope = -2.0 * (x - 0.3);
            let norm = (1.0 + slope * slope).sqrt();
            (
                vec![x, 1.0 - (x - 0.3) * (x - 0.3)],
                vec![1.0 / norm, slope / norm],
            )
        };
        let ((z0, t0), (z1, t1)) = (point(0.0), point(0.5));
        let before = End {
            z: &z0,
            tangent: &t0,
            orientation: 1.0,
        };
        let after = End {
            z: &z1,
            tangent: &t1,
            orientation: -1.0,
        };
        let top = fold_frequency(&before, &after);
        // The chord stands for the arc: close, not exact.
        assert!((top - 1.0).abs() < 1e-2, "{top}");
        let events = detect(&before, &after, 7, 1.0, true);
        let kinds: Vec<_> = events.iter().map(|e| (e.index, e.kind.clone())).collect();
        assert_eq!(kinds, [(7, EventKind::Fold), (7, EventKind::BranchPoint)]);
        assert!((events[0].frequency_hz - hertz(top)).abs() < 1e-12);
        assert!(detect(&before, &after, 7, 1.0, false).len() == 1);
    }

    #[test]
    fn events_serialize_with_their_kind_and_stops_with_their_reason() {
        let fold = Event {
            index: 3,
            frequency_hz: 200.0,
            kind: EventKind::Fold,
        };
        assert_eq!(
            serde_json::to_string(&fold).expect("json"),
            r#"{"index":3,"frequency_hz":200.0,"kind":"fold"}"#
        );
        let stop = Event::stop(&StopReason::PointCap { max_points: 5 }, 5, Some(0.0));
        assert_eq!(
            serde_json::to_string(&stop).expect("json"),
            r#"{"index":5,"frequency_hz":0.0,"kind":"stop","reason":"point_cap","max_points":5}"#
        );
    }

    #[test]
    fn events_of_a_reversed_sweep_come_before_the_same_points() {
        // A sweep back of 5 points; its event before its point 2 lies
        // between its points 1 and 2, which are 3 and 2 of the 5 reversed,
        // 13 and 12 in a branch holding them from 10 on.
        let event = Event {
            index: 2,
            frequency_hz: 1.0,
            kind: EventKind::Fold,
        };
        assert_eq!(event.reversed(5, 10).index, 13);
        // Its stop (after its last point) comes before the reversed sweep.
        let stop = Event::stop(&StopReason::EndReached, 5, Some(1.0));
        assert_eq!(stop.reversed(5, 10).index, 10);
    }
}
