//! The tracking of exponents from point to point and the crossings it
//! finds (see the parent module's header for the rule).

use super::{crossing_kind, frequency_turns, multiplier_angle, Marker, REAL_ANGLE};
use crate::stability::spectrum::{Exponent, PointStability};
use faer::c64;
use std::f64::consts::PI;

/// The hysteresis band's half-width, in units of `ω` (at least the
/// point's growth tolerance).
const HYSTERESIS: f64 = 1e-6;

/// A sign change of a tracked exponent's real part between two points.
#[derive(Clone, Copy, Debug)]
struct Crossing {
    index: usize,
    before: Exponent,
    after: Exponent,
    class: i64,
}

/// One exponent followed along the branch.
#[derive(Clone, Debug)]
struct Track {
    exponent: Exponent,
    class: i64,
    /// Past the band on the growing side.
    unstable: bool,
    /// The last sign change upwards and downwards.
    rise: Option<Crossing>,
    fall: Option<Crossing>,
}

/// The markers along `points` (in branch order); `classes_known` is false
/// for the whole wheel solved as one block.
pub fn markers(points: &[PointStability], classes_known: bool) -> Vec<Marker> {
    let candidates = tracked_crossings(points, classes_known);
    let candidates = without_swaps(candidates);
    let found = with_class_changes(candidates, points);
    without_conjugates(found, points)
}

/// The hysteresis band of a point: `max(tolerance, 1e-6 ω)`.
fn band(point: &PointStability) -> f64 {
    point.tolerance.max(HYSTERESIS * point.omega)
}

/// A crossing found by tracking: the step at whose end its exponent left
/// the band, the class it counts in, the marker.
struct Candidate {
    step: usize,
    class: i64,
    marker: Marker,
}

/// Every tracked exponent's crossing (see the module's header).
fn tracked_crossings(points: &[PointStability], classes_known: bool) -> Vec<Candidate> {
    let mut found: Vec<Candidate> = Vec::new();
    let Some(first) = points.first() else {
        return found;
    };
    let mut tracks: Vec<Track> = labelled(first)
        .into_iter()
        .map(|(class, exponent)| Track {
            exponent,
            class,
            unstable: exponent.re > band(first),
            rise: None,
            fall: None,
        })
        .collect();
    for (index, pair) in points.windows(2).enumerate() {
        let (a, b) = (&pair[0], &pair[1]);
        let next = labelled(b);
        let pairs = matched(&tracks, a.omega, &next, b.omega);
        let mut continued = Vec::with_capacity(next.len());
        let mut taken = vec![false; next.len()];
        for (t, n) in pairs {
            taken[n] = true;
            let mut track = tracks[t].clone();
            let (class, exponent) = next[n];
            let crossing = Crossing {
                index,
                before: track.exponent,
                after: exponent,
                class,
            };
            if track.exponent.re <= 0.0 && exponent.re > 0.0 {
                track.rise = Some(crossing);
            } else if track.exponent.re > 0.0 && exponent.re <= 0.0 {
                track.fall = Some(Crossing {
                    class: track.class,
                    ..crossing
                });
            }
            track.exponent = exponent;
            track.class = class;
            let left = if !track.unstable && exponent.re > band(b) {
                track.unstable = true;
                track.rise.take().map(|c| (c, true))
            } else if track.unstable && exponent.re < -band(b) {
                track.unstable = false;
                track.fall.take().map(|c| (c, false))
            } else {
                None
            };
            if let Some((c, loses)) = left {
                found.push(Candidate {
                    step: index,
                    class: c.class,
                    marker: marker(points, c, loses, classes_known),
                });
            }
            continued.push(track);
        }
        // Exponents entering the region start their own tracks.
        for (n, &(class, exponent)) in next.iter().enumerate() {
            if !taken[n] {
                continued.push(Track {
                    exponent,
                    class,
                    unstable: exponent.re > band(b),
                    rise: None,
                    fall: None,
                });
            }
        }
        tracks = continued;
    }
    found
}

/// How far a candidate's real part moves over its step.
fn swing(c: &Candidate) -> f64 {
    let before = c.marker.before.unwrap_or(c.marker.exponent);
    let after = c.marker.after.unwrap_or(c.marker.exponent);
    (after.re - before.re).abs()
}

/// The candidates without the pairs of a loss and a regain in one class at
/// one step (a swap of the matching, or crossings the step cannot tell
/// apart): the class's count of growing exponents is unchanged by them.
fn without_swaps(mut candidates: Vec<Candidate>) -> Vec<Candidate> {
    candidates.sort_by_key(|c| (c.step, c.class));
    let mut kept = Vec::with_capacity(candidates.len());
    let mut rest = candidates.into_iter().peekable();
    while let Some(first) = rest.next() {
        let mut group = vec![first];
        while let Some(next) =
            rest.next_if(|n| (n.step, n.class) == (group[0].step, group[0].class))
        {
            group.push(next);
        }
        let (mut losses, mut regains): (Vec<Candidate>, Vec<Candidate>) =
            group.into_iter().partition(|c| c.marker.loses_stability);
        let cancelled = losses.len().min(regains.len());
        // The crossings that net out are the smallest moves.
        losses.sort_by(|x, y| swing(y).total_cmp(&swing(x)));
        regains.sort_by(|x, y| swing(y).total_cmp(&swing(x)));
        losses.truncate(losses.len() - cancelled);
        regains.truncate(regains.len() - cancelled);
        kept.extend(losses);
        kept.extend(regains);
    }
    kept
}

/// The candidates as markers, each saying whether its class's stability
/// changes there (see the module's header). A class's state that changes
/// with no crossing (an exponent leaving one class's strip at its edge and
/// coming back in another's, the same multiplier) gives no marker.
fn with_class_changes(mut candidates: Vec<Candidate>, points: &[PointStability]) -> Vec<Marker> {
    for c in &mut candidates {
        c.marker.class_changes = false;
    }
    let mut classes: Vec<i64> = points
        .iter()
        .flat_map(|p| p.classes.iter().map(|c| c.nodal_diameter))
        .collect();
    classes.sort_unstable();
    classes.dedup();
    for &class in &classes {
        let growth = |p: &PointStability| {
            p.classes
                .iter()
                .filter(|c| c.nodal_diameter == class)
                .flat_map(|c| c.exponents.iter().map(|e| e.re))
                .fold(f64::NEG_INFINITY, f64::max)
        };
        let Some(first) = points.first() else {
            break;
        };
        let mut unstable = growth(first) > band(first);
        for (step, pair) in points.windows(2).enumerate() {
            let b = &pair[1];
            let loses = if !unstable && growth(b) > band(b) {
                true
            } else if unstable && growth(b) < -band(b) {
                false
            } else {
                continue;
            };
            unstable = loses;
            let account = candidates
                .iter_mut()
                .filter(|c| c.step == step && c.class == class && c.marker.loses_stability == loses)
                .max_by(|x, y| swing(x).total_cmp(&swing(y)));
            if let Some(c) = account {
                c.marker.class_changes = true;
            }
        }
    }
    let mut found: Vec<Marker> = candidates.into_iter().map(|c| c.marker).collect();
    found.sort_by(|x, y| {
        (x.index, x.nodal_diameter)
            .cmp(&(y.index, y.nodal_diameter))
            .then(x.fraction.total_cmp(&y.fraction))
    });
    found
}

/// Every exponent of a point with its class; with classes, those of the
/// classes `σ ≥ 0` and their conjugates (the classes `−σ`) as themselves.
fn labelled(point: &PointStability) -> Vec<(i64, Exponent)> {
    point
        .classes
        .iter()
        .flat_map(|c| c.exponents.iter().map(move |e| (c.nodal_diameter, *e)))
        .collect()
}

/// Tracks matched to the next point's exponents by the distance of their
/// multipliers, nearest pairs first; `(track, next)` indices.
fn matched(
    tracks: &[Track],
    omega_a: f64,
    next: &[(i64, Exponent)],
    omega_b: f64,
) -> Vec<(usize, usize)> {
    let za: Vec<c64> = tracks
        .iter()
        .map(|t| t.exponent.multiplier(omega_a))
        .collect();
    let zb: Vec<c64> = next.iter().map(|(_, e)| e.multiplier(omega_b)).collect();
    let mut distances: Vec<(f64, usize, usize)> = Vec::with_capacity(za.len() * zb.len());
    for (i, x) in za.iter().enumerate() {
        for (j, y) in zb.iter().enumerate() {
            distances.push(((x - y).norm(), i, j));
        }
    }
    nearest_first(distances, za.len(), zb.len())
}

/// The greedy matching of `a` items with `b` items by the pairs
/// `(distance, i, j)`, nearest first (ties in `(i, j)` order). The
/// matching rarely reaches past the nearest few pairs per item: those are
/// set apart and sorted first, the others only when items are left on both
/// sides (what was matched is the same as the whole list sorted: on
/// `n24-standing-h4` the tracking took 0.35 s of sorting).
fn nearest_first(
    mut distances: Vec<(f64, usize, usize)>,
    a: usize,
    b: usize,
) -> Vec<(usize, usize)> {
    let order = |p: &(f64, usize, usize), q: &(f64, usize, usize)| {
        p.0.total_cmp(&q.0).then(p.1.cmp(&q.1)).then(p.2.cmp(&q.2))
    };
    let wanted = a.min(b);
    let head = (NEAREST_PER_ITEM * a.max(b)).min(distances.len());
    if head < distances.len() {
        distances.select_nth_unstable_by(head, order);
    }
    let (first, rest) = distances.split_at_mut(head);
    let (mut used_a, mut used_b) = (vec![false; a], vec![false; b]);
    let mut out = Vec::with_capacity(wanted);
    let mut take = |pairs: &mut [(f64, usize, usize)], out: &mut Vec<(usize, usize)>| {
        pairs.sort_unstable_by(order);
        for &(_, i, j) in pairs.iter() {
            if out.len() == wanted {
                break;
            }
            if !used_a[i] && !used_b[j] {
                used_a[i] = true;
                used_b[j] = true;
                out.push((i, j));
            }
        }
    };
    take(first, &mut out);
    if out.len() < wanted {
        take(rest, &mut out);
    }
    out
}

/// Pairs per item sorted before the rest ([`nearest_first`]).
const NEAREST_PER_ITEM: usize = 4;

/// The marker of a crossing, placed where the real part vanishes.
fn marker(points: &[PointStability], c: Crossing, loses: bool, classes_known: bool) -> Marker {
    let (a, b) = (&points[c.index], &points[c.index + 1]);
    let span = c.after.re - c.before.re;
    let fraction = if span.abs() > 0.0 {
        (-c.before.re / span).clamp(0.0, 1.0)
    } else {
        0.5
    };
    let omega = a.omega + fraction * (b.omega - a.omega);
    let exponent = Exponent {
        re: c.before.re + fraction * span,
        im: c.before.im + fraction * (c.after.im - c.before.im),
    };
    // The growing side's multiplier tells the kind.
    let growing = if loses { c.after } else { c.before };
    let class = classes_known.then_some(c.class);
    let turns = frequency_turns(points.len(), |i| points[i].omega, c.index);
    let kind = crossing_kind(multiplier_angle(growing, omega), class, REAL_ANGLE, turns);
    Marker {
        index: c.index,
        fraction,
        frequency_hz: omega / (2.0 * PI),
        kind,
        nodal_diameter: classes_known.then_some(c.class),
        exponent,
        loses_stability: loses,
        before: Some(c.before),
        after: Some(c.after),
        class_changes: true,
        located: None,
    }
}

/// One marker per conjugate pair: a class `σ < 0` crosses with its
/// conjugate `−σ` (kept), and a complex pair within one class crosses
/// together (the exponent of positive imaginary part kept).
fn without_conjugates(found: Vec<Marker>, points: &[PointStability]) -> Vec<Marker> {
    let mirror = |e: Exponent| Exponent {
        re: e.re,
        im: -e.im,
    };
    let conjugate = |m: &Marker| Marker {
        exponent: mirror(m.exponent),
        before: m.before.map(mirror),
        after: m.after.map(mirror),
        ..m.clone()
    };
    let mut kept: Vec<Marker> = Vec::with_capacity(found.len());
    for m in found {
        let m = match m.nodal_diameter {
            Some(s) if s < 0 => Marker {
                nodal_diameter: Some(-s),
                ..conjugate(&m)
            },
            _ => m,
        };
        let twin = conjugate(&m);
        // The twin kept says whether the class changes if either does.
        match kept
            .iter_mut()
            .find(|k| same(k, &m, points) || same(k, &twin, points))
        {
            Some(k) => k.class_changes |= m.class_changes,
            None => kept.push(m),
        }
    }
    kept.sort_by(|x, y| {
        (x.index, x.nodal_diameter)
            .cmp(&(y.index, y.nodal_diameter))
            .then(x.fraction.total_cmp(&y.fraction))
    });
    kept
}

/// Whether two markers are the same crossing (a class and its conjugate's,
/// mirrored).
fn same(a: &Marker, b: &Marker, points: &[PointStability]) -> bool {
    let omega = points[a.index].omega;
    a.index == b.index
        && a.loses_stability == b.loses_stability
        && a.kind == b.kind
        && a.nodal_diameter == b.nodal_diameter
        && (a.exponent.value() - b.exponent.value()).norm() < 1e-6 * omega
        && (a.fraction - b.fraction).abs() < 1e-6
}

#[cfg(test)]
mod tests;
