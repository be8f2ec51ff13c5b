//! Markers located on the branch (docs/design.md §10, "Located"): each
//! marker's crossing, placed by interpolation between its two points, is
//! brought to where the tracked exponent's real part vanishes on the
//! branch itself.
//!
//! The branch between the two points is parametrized by the fraction `s`
//! of the chord joining them (not by frequency: a fold turns in
//! frequency). At a trial `s` the harmonic balance is solved by Newton from
//! the chord's point, closed by the plane through it orthogonal to the
//! chord ([`ChordMetric`]: in the continuation's metric under a smooth
//! law, with the chord's two parts alike under one with pieces or kinks,
//! the other where Newton does not converge on the first's planes); the marker's
//! class is solved there
//! ([`Stability::class_exponents`]) and its exponent nearest in multiplier
//! to the one expected is the tracked one. Regula falsi (Illinois) on its
//! real part shrinks the bracket until it spans less than [`BRACKET_HZ`]
//! in frequency with the real part within the growth tolerance, or less
//! than [`BRACKET_FRACTION`] of the chord.
//!
//! At the located point the multiplier's angle tells a real crossing from
//! a complex pair: a real multiplier's angle goes to 0 (or π) with the
//! location, a slowly modulated pair keeps a finite one. The marker's kind
//! is read again there with [`REAL_AT_LOCATION`], which Hill's label on the
//! interpolated growing side (within 0.05 rad) cannot do.
//!
//! After each secant trial a guard trial just past it toward the crossing
//! closes the bracket in two trials where the secant was good. Where one
//! end has not moved in two trials and the real part at the other end is
//! already the far point's (`FLAT`), a probe `chord::PROBE` beside that point
//! and bisection there find a change that sits at the point. At a change
//! of contact (a law with pieces, DLFT, or the plain penalty) the exponent
//! can jump across 0: a bracket closed to [`BRACKET_FRACTION`] with both
//! ends clear of the band, most of the change inside and the contact
//! different at its ends is a jump ([`MarkerKind::Jump`](crate::stability::MarkerKind::Jump)) when the class's
//! count of growing exponents differs at its ends
//! ([`LocateError::PairedAtAJump`] otherwise); with the contact the same
//! and the bracket on a marker's point, the chord's solutions lie on two
//! sheets there ([`LocateError::AtAnEnd`]).
//!
//! Where the followed exponent jumps otherwise, the class's count of growing
//! exponents locates the event ([`located_by_count`]); where the exponent
//! found between the points continues neither of the marker's two, that
//! count is the same at both, the class's stability does not change there
//! and both exponents are outside the band, the event is no crossing (the
//! tracking paired two exponents) and is removed ([`Located::unmatched`]).
//!
//! The harmonic balance sits above `stability` in the library's order
//! (docs/design.md §1): this is why locating lives in the front door.

use super::chord::{contact_changes, marker_points, Chord, ChordMetric, FOLD_FRACTION, PROBE};
pub use super::chord::{BRACKET_FRACTION, BRACKET_HZ, REAL_AT_LOCATION};
use super::locate_by_count::{located_by_count, GROWING};
pub use super::locate_error::LocateError;
use super::locate_trial::{jump_at, jumps, located, nearest, Trial};
use crate::continuation::{NewtonSettings, Point};
use crate::hbm::HarmonicBalance;
use crate::stability::{
    crossing_kind, frequency_turns, multiplier_angle, Exponent, Location, Marker, Stability,
};
use faer::c64;
use rayon::prelude::*;
use std::f64::consts::PI;

/// Trial points of the branch solved per marker at most.
const MAX_SOLVES: usize = 20;

/// The share of the change of the real part between a marker's two points
/// within which a trial's real part is already the far point's: the change
/// sits at the near point (a probe beside it tells a jump there).
const FLAT: f64 = 0.1;

/// How far (a share of the distance between the bracket's ends, in
/// multiplier) the exponent found at a trial point may be from the one
/// expected there (the ends interpolated).
const CONTINUITY: f64 = 1.0;

/// What locating the markers of a branch did.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Located {
    /// Markers tried: the events.
    pub events: usize,
    /// Markers located.
    pub located: usize,
    /// Markers left where interpolation placed them, with why.
    pub failed: Vec<(usize, String)>,
    /// Events that are not crossings, with why: the tracking paired two
    /// different exponents at the marker's step (the one found between
    /// its points continues neither), the class grows as many exponents
    /// (faster than `1e-6 ω`) at both points, the marker does not change
    /// its class's stability and both its exponents are outside that
    /// band (also where the exponent jumps across 0 at a change of contact
    /// with the count the same on both sides, [`LocateError::PairedAtAJump`]).
    /// [`locate_branch_markers`] removes them. Indices (here and in
    /// [`Self::failed`]) are the markers' before the removal.
    pub unmatched: Vec<(usize, String)>,
    /// Trial points solved in all.
    pub solves: usize,
}

/// The events among `markers` ([`Marker::is_event`]) of the branch
/// `points` (of `problem`, checked by `check`) located on the branch (see
/// the module's header), in parallel; a marker
/// that cannot be located keeps its interpolated place (said in the
/// returned [`Located`] and the log), and an event that is not a crossing
/// is listed in [`Located::unmatched`] (left in `markers`; the caller
/// removes it). `newton` solves the trial points, on planes square to the
/// chords in the first of `metrics`, then in the second where the first
/// does not converge at one of its trials ([`ChordMetric::in_order`]).
pub fn locate_markers(
    check: &Stability<'_>,
    problem: &HarmonicBalance,
    points: &[Point],
    markers: &mut [Marker],
    newton: &NewtonSettings,
    metrics: [ChordMetric; 2],
) -> Located {
    let classes_known = check.classes_tell_kinds();
    // The events only (every crossing at ±1, and the Neimark–Sacker
    // crossings that change their class's stability): a further exponent
    // of a class already unstable keeps its interpolated place.
    let results: Vec<Option<Outcome>> = markers
        .par_iter()
        .map_init(
            || problem.clone(),
            |copy, marker| {
                marker.is_event().then(|| {
                    outcome(
                        check,
                        copy,
                        points,
                        marker,
                        (newton, metrics),
                        classes_known,
                    )
                })
            },
        )
        .collect();
    let mut report = Located::default();
    for (i, (marker, result)) in markers.iter_mut().zip(results).enumerate() {
        let Some(result) = result else {
            continue;
        };
        report.events += 1;
        match result {
            Outcome::Located(located, solves) => {
                report.located += 1;
                report.solves += solves;
                *marker = located;
            }
            Outcome::Failed(error) => {
                tracing::debug!(
                    "marker at {:.6} Hz not located: {error}",
                    marker.frequency_hz
                );
                report.failed.push((i, error.to_string()));
            }
            Outcome::Unmatched(why) => {
                tracing::debug!(
                    "marker at {:.6} Hz is not a crossing: {why}",
                    marker.frequency_hz
                );
                report.unmatched.push((i, why));
            }
        }
    }
    report
}

/// What locating one event found.
enum Outcome {
    /// Located, with the trial points solved.
    Located(Marker, usize),
    /// Left where interpolation placed it, with why.
    Failed(LocateError),
    /// Not a crossing (see [`Located::unmatched`]), with why.
    Unmatched(String),
}

/// [`outcome_in`] the metric `first`, and where Newton does not converge
/// at one of its trials, in the `other`: taken only where it locates the
/// event (the first metric's failure is said otherwise, and its trials are
/// not counted in [`Located::solves`]).
fn outcome(
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

/// One marker located; with the trial points solved.
fn locate_one(
    check: &Stability<'_>,
    problem: &mut HarmonicBalance,
    points: &[Point],
    marker: &Marker,
    (newton, metric): (&NewtonSettings, ChordMetric),
    classes_known: bool,
) -> Result<(Marker, usize), LocateError> {
    let (a, b) = marker_points(points, marker.index)?;
    let (Some(before), Some(after)) = (marker.before, marker.after) else {
        return Err(LocateError::NoExponents);
    };
    let class = marker.nodal_diameter.unwrap_or(0);
    let tolerance = check.tolerance();
    let chord = Chord::new(problem, a, b, metric);
    let mut lo = Trial {
        fraction: 0.0,
        omega: a.omega,
        exponent: before,
        solution: a.unknowns.clone(),
    };
    let mut hi = Trial {
        fraction: 1.0,
        omega: b.omega,
        exponent: after,
        solution: b.unknowns.clone(),
    };
    if lo.exponent.re.signum() == hi.exponent.re.signum() {
        return Err(LocateError::NoExponents);
    }
    // Each trial's exponent, and its vector for the next trial's.
    let mut vector: Option<Vec<c64>> = None;
    let mut solves = 0;
    // The last solution, the next trial's start when it is nearer.
    let mut last: Option<(f64, Vec<f64>)> = None;
    // The trial due next whatever the secant says: a guard just past a
    // secant trial, or a probe at an end (see the module's header).
    let mut due: Option<f64> = None;
    let mut probed_ends = (false, false);
    // Illinois: the weight of each end's value in the secant, halved for
    // the end a secant trial has twice not replaced.
    let (mut weight_lo, mut weight_hi) = (1.0, 1.0);
    let mut last_side: Option<bool> = None;
    let whole_change = (after.re - before.re).abs();
    let slope_hz = ((b.omega - a.omega) / (2.0 * PI)).abs();
    while solves < MAX_SOLVES && (solves == 0 || !located(&lo, &hi, tolerance)) {
        let width = hi.fraction - lo.fraction;
        let scheduled = due.take();
        // A bracket a probe closed to within [`PROBE`] of a point: the
        // change sits there (a jump, where the secant crawls): bisection.
        let beside_a_point = width <= PROBE && (lo.fraction <= 0.0 || hi.fraction >= 1.0);
        let s = match scheduled {
            Some(s) => s,
            None if beside_a_point => 0.5 * (lo.fraction + hi.fraction),
            None => {
                let (l, h) = (weight_lo * lo.exponent.re, weight_hi * hi.exponent.re);
                let secant = (lo.fraction * h - hi.fraction * l) / (h - l);
                // Off the bracket's ends (round-off of the secant).
                secant.clamp(lo.fraction + 1e-3 * width, hi.fraction - 1e-3 * width)
            }
        };
        let start = last.as_ref().map(|(f, x)| (*f, x.as_slice()));
        let ends = [(lo.fraction, &lo.solution[..]), (hi.fraction, &hi.solution)];
        let (x, omega) = chord.solve_or_walk(problem, s, start, ends, newton)?;
        // The exponent expected: the bracket's ends interpolated.
        let t = (s - lo.fraction) / width;
        let expected = Exponent {
            re: lo.exponent.re + t * (hi.exponent.re - lo.exponent.re),
            im: lo.exponent.im + t * (hi.exponent.im - lo.exponent.im),
        };
        // The first trial solves the whole class and takes the exponent
        // nearest in multiplier; the next ones follow that one alone.
        let followed = match (&vector, solves) {
            (Some(q), n) if n > 0 => check.exponent_near(&x, omega, class, expected, Some(q))?,
            _ => None,
        };
        let exponent = match followed {
            Some((e, q)) => {
                vector = Some(q);
                e
            }
            None => {
                let exponents = check.class_exponents(&x, omega, class)?;
                let e = nearest(&exponents, expected, omega).ok_or(LocateError::Lost {
                    frequency_hz: omega / (2.0 * PI),
                })?;
                // Its vector, for the next trials.
                vector = check
                    .exponent_near(&x, omega, class, e, None)?
                    .map(|(_, q)| q);
                e
            }
        };
        solves += 1;
        tracing::trace!(
            "marker at {:.6} Hz, class {class}: trial at {s:.9} of the chord ({:.6} Hz): exponent {:.4e} {:+.4e}i",
            marker.frequency_hz,
            omega / (2.0 * PI),
            exponent.re,
            exponent.im
        );
        // The exponent found must continue the bracket's ends: within half
        // their distance of the expected one (in multiplier), else the
        // marker's two exponents are not one exponent moving (a matching
        // across a cluster) and there is no crossing to locate.
        let (za, zb) = (lo.exponent.multiplier(omega), hi.exponent.multiplier(omega));
        let off = (exponent.multiplier(omega) - expected.multiplier(omega)).norm();
        if off > CONTINUITY * (zb - za).norm() {
            return Err(LocateError::NotContinuous {
                frequency_hz: omega / (2.0 * PI),
                off,
                apart: (zb - za).norm(),
            });
        }
        let trial = Trial {
            fraction: s,
            omega,
            exponent,
            solution: x.clone(),
        };
        last = Some((s, x));
        let below = trial.exponent.re.signum() == lo.exponent.re.signum();
        if below {
            lo = trial;
            weight_lo = 1.0;
        } else {
            hi = trial;
            weight_hi = 1.0;
        }
        if scheduled.is_none() {
            if last_side == Some(below) {
                if below {
                    weight_hi *= 0.5;
                } else {
                    weight_lo *= 0.5;
                }
            }
            last_side = Some(below);
        }
        if located(&lo, &hi, tolerance) {
            continue;
        }
        let width = hi.fraction - lo.fraction;
        // An end of the marker's own two points that two trials have not
        // moved, the real part at the bracket's other end already (within
        // [`FLAT`] of the change) the far point's: the change sits at that
        // end. Probe just beside it, where an exponent that jumps at the
        // point itself (the point on a change of contact) closes the
        // bracket at once.
        let flat = |t: &Trial, far: Exponent| (t.exponent.re - far.re).abs() < FLAT * whole_change;
        if solves >= 2
            && lo.fraction <= 0.0
            && hi.fraction > PROBE
            && !probed_ends.0
            && flat(&hi, after)
        {
            probed_ends.0 = true;
            due = Some(PROBE);
        } else if solves >= 2
            && hi.fraction >= 1.0
            && lo.fraction < 1.0 - PROBE
            && !probed_ends.1
            && flat(&lo, before)
        {
            probed_ends.1 = true;
            due = Some(1.0 - PROBE);
        } else if scheduled.is_none() && width > PROBE {
            // After a secant trial, a guard just past it toward the
            // crossing: the bracket closes in two trials where the secant
            // was good.
            let per_hz = if slope_hz > 0.0 {
                1.0 / slope_hz
            } else {
                f64::INFINITY
            };
            let step = (0.5 * BRACKET_HZ * per_hz)
                .min(0.4 * FOLD_FRACTION)
                .min(0.5 * width)
                .max(0.5 * BRACKET_FRACTION);
            due = Some(if below { s + step } else { s - step });
        }
    }
    // Not closed within the trials allowed: the real part does not go to 0
    // continuously (it jumps inside the bracket, or moves too slowly).
    if !located(&lo, &hi, tolerance) {
        return Err(LocateError::NotClosed {
            trials: solves,
            bracket_hz: (hi.omega - lo.omega).abs() / (2.0 * PI),
            bracket_fraction: hi.fraction - lo.fraction,
            real_part: lo.exponent.re.abs().min(hi.exponent.re.abs()),
        });
    }
    // A bracket closed to the chord's resolution with both ends clear of
    // the markers' band and most of the change inside: a jump where the
    // contact changes across it, else (a smooth law, the same contact) the
    // chord's solutions on two sheets beside one of the marker's points.
    let outside = |t: &Trial| t.exponent.re.abs() > GROWING * t.omega;
    if outside(&lo) && outside(&hi) && jumps(&lo, &hi, whole_change) {
        if contact_changes(problem, &lo.solution, lo.omega, &hi.solution, hi.omega) {
            // A jump changes the class's count of growing exponents across
            // the bracket; where the count is the same on both sides, the
            // marker's two exponents are two exponents paired by the
            // tracking (no crossing there).
            let growing = |t: &Trial| -> Result<usize, LocateError> {
                Ok(check
                    .class_exponents(&t.solution, t.omega, class)?
                    .iter()
                    .filter(|e| e.re > GROWING * t.omega)
                    .count())
            };
            let count = growing(&lo)?;
            if count == growing(&hi)? {
                return Err(LocateError::PairedAtAJump {
                    frequency_hz: hi.omega / (2.0 * PI),
                    growing: count,
                });
            }
            return Ok((jump_at(marker, &lo, &hi, solves), solves));
        }
        if lo.fraction <= 0.0 || hi.fraction >= 1.0 {
            let end = if lo.fraction <= 0.0 { &lo } else { &hi };
            return Err(LocateError::AtAnEnd {
                frequency_hz: end.omega / (2.0 * PI),
            });
        }
    }
    let best = if lo.exponent.re.abs() <= hi.exponent.re.abs() {
        lo.clone()
    } else {
        hi.clone()
    };
    let angle = multiplier_angle(best.exponent, best.omega);
    // Read again at the located point, with the tight angle.
    let turns = frequency_turns(points.len(), |i| points[i].omega, marker.index);
    let kind = crossing_kind(
        angle,
        classes_known.then_some(class),
        REAL_AT_LOCATION,
        turns,
    );
    let located = Marker {
        fraction: best.fraction,
        frequency_hz: best.omega / (2.0 * PI),
        kind,
        exponent: best.exponent,
        located: Some(Location {
            bracket_hz: (hi.omega - lo.omega).abs() / (2.0 * PI),
            bracket_fraction: hi.fraction - lo.fraction,
            solves,
            angle,
            by_count: false,
        }),
        ..marker.clone()
    };
    Ok((located, solves))
}
