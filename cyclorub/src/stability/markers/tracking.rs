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
mod tests {
    use super::*;
    use crate::stability::markers::MarkerKind;
    use crate::stability::spectrum::ClassSpectrum;

    const OMEGA: f64 = 100.0;

    /// A point with one class per entry of `classes`: `(σ, exponents)`.
    fn point(omega: f64, classes: &[(i64, Vec<(f64, f64)>)]) -> PointStability {
        PointStability {
            omega,
            classes: classes
                .iter()
                .map(|(sigma, exponents)| ClassSpectrum {
                    nodal_diameter: *sigma,
                    exponents: exponents
                        .iter()
                        .map(|&(re, im)| Exponent { re, im })
                        .collect(),
                    truncation: 0.0,
                    dense: false,
                })
                .collect(),
            tolerance: 1e-8 * omega,
            peak_contact_stiffness: 1.0,
            off_contact_bound: None,
        }
    }

    /// An exponent's real part along a branch of points 1 rad/s apart, in
    /// class 2, with a second, steady exponent beside it.
    fn branch(real_parts: &[f64], im: f64) -> Vec<PointStability> {
        real_parts
            .iter()
            .enumerate()
            .map(|(i, &re)| {
                point(
                    OMEGA + i as f64,
                    &[(0, vec![(-1.0, 20.0)]), (2, vec![(re, im), (-3.0, -30.0)])],
                )
            })
            .collect()
    }

    #[test]
    fn a_crossing_is_placed_where_the_tracked_real_part_vanishes() {
        let found = markers(&branch(&[-2.0, -1.0, 3.0, 4.0], 10.0), true);
        assert_eq!(found.len(), 1, "{found:?}");
        let m = &found[0];
        assert_eq!((m.index, m.nodal_diameter), (1, Some(2)));
        assert!(m.loses_stability);
        assert_eq!(m.kind, MarkerKind::NeimarkSacker);
        assert!((m.fraction - 0.25).abs() < 1e-12);
        assert!((m.frequency_hz - (OMEGA + 1.25) / (2.0 * PI)).abs() < 1e-12);
        assert!(m.before.unwrap().re < 0.0 && m.after.unwrap().re > 0.0);
    }

    #[test]
    fn an_exponent_hovering_in_the_band_gives_no_marker() {
        // ±1e-5 1/s against a band of 1e-6 ω = 1e-4 1/s: noise, not a crossing.
        let noise = [-1e-5, 1e-5, -1e-5, 2e-5, -5e-6, 1e-5, -1e-5];
        assert!(markers(&branch(&noise, 10.0), true).is_empty());
    }

    #[test]
    fn a_crossing_through_the_band_is_one_marker_where_it_last_changed_sign() {
        // Down to the band, wavering in it, then out above: one marker, at
        // the last sign change (between points 4 and 5).
        let found = markers(
            &branch(&[-1.0, -1e-5, 1e-5, 2e-5, -1e-5, 5e-5, 2.0], 10.0),
            true,
        );
        assert_eq!(found.len(), 1, "{found:?}");
        assert_eq!(found[0].index, 4);
        // Out and back beyond the band both ways: a pair.
        let found = markers(&branch(&[-1.0, 1.0, -1.0], 10.0), true);
        assert_eq!(found.len(), 2);
        assert!(found[0].loses_stability && !found[1].loses_stability);
    }

    #[test]
    fn the_nearest_first_matching_is_the_whole_list_sorted() {
        // Pseudo-random distances with ties, against the stable sort of
        // the whole list and the same greedy pass.
        let mut state = 12345_u64;
        let mut next = || {
            state = state
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            (state >> 33) as f64 / (1u64 << 31) as f64
        };
        for (a, b) in [(1, 1), (3, 7), (20, 20), (40, 9), (60, 61)] {
            let distances: Vec<(f64, usize, usize)> = (0..a)
                .flat_map(|i| (0..b).map(move |j| (i, j)))
                .map(|(i, j)| ((8.0 * next()).floor() / 8.0, i, j))
                .collect();
            let mut sorted = distances.clone();
            sorted.sort_by(|p, q| p.0.total_cmp(&q.0));
            let (mut used_a, mut used_b) = (vec![false; a], vec![false; b]);
            let mut expected = Vec::new();
            for (_, i, j) in sorted {
                if !used_a[i] && !used_b[j] {
                    used_a[i] = true;
                    used_b[j] = true;
                    expected.push((i, j));
                }
            }
            assert_eq!(super::nearest_first(distances, a, b), expected, "{a} × {b}");
        }
    }

    #[test]
    fn the_frequency_turns_where_the_steps_about_a_step_go_opposite_ways() {
        let turns = |omegas: &[f64], index: usize| {
            super::super::frequency_turns(omegas.len(), |i| omegas[i], index)
        };
        assert!(turns(&[0.0, 1.0, 2.0, 1.0], 1));
        assert!(!turns(&[0.0, 1.0, 2.0, 3.0], 1));
        // A step between two turns (a zig-zag): a turn at either end.
        assert!(turns(&[0.0, 2.0, 1.0, 3.0], 1));
        // At the ends, the step itself and its one neighbour.
        assert!(turns(&[0.0, 1.0, 0.0], 0));
        assert!(!turns(&[0.0, 1.0, 2.0], 0));
        assert!(turns(&[0.0, 1.0, 0.0], 1));
        assert!(!turns(&[0.0, 1.0, 2.0], 1));
        // Two points: nothing tells, a turn.
        assert!(turns(&[0.0, 1.0], 0));
    }

    #[test]
    fn a_real_crossing_is_a_fold_in_class_0_and_a_branch_point_elsewhere() {
        let found = markers(&branch(&[-1.0, 1.0], 0.0), true);
        assert_eq!(found[0].kind, MarkerKind::BranchPoint);
        let fold: Vec<PointStability> = [-1.0, 1.0]
            .iter()
            .enumerate()
            .map(|(i, &re)| point(OMEGA + i as f64, &[(0, vec![(re, 0.0)])]))
            .collect();
        assert_eq!(markers(&fold, true)[0].kind, MarkerKind::Fold);
        assert_eq!(markers(&fold, false)[0].kind, MarkerKind::RealCrossing);
        // Class 0 where the branch goes on in frequency through the
        // crossing: a branch point; where it turns about it: a fold.
        let class_zero = |omegas: &[f64], res: &[f64]| {
            let points: Vec<PointStability> = omegas
                .iter()
                .zip(res)
                .map(|(&w, &re)| point(w, &[(0, vec![(re, 0.0)])]))
                .collect();
            markers(&points, true)[0].kind
        };
        let through = [OMEGA, OMEGA + 1.0, OMEGA + 2.0, OMEGA + 3.0];
        let turning = [OMEGA, OMEGA + 2.0, OMEGA + 3.0, OMEGA + 1.0];
        let res = [-2.0, -1.0, 1.0, 2.0];
        assert_eq!(class_zero(&through, &res), MarkerKind::BranchPoint);
        assert_eq!(class_zero(&turning, &res), MarkerKind::Fold);
        // At −1: period doubling.
        let found = markers(&branch(&[-1.0, 1.0], 0.5 * OMEGA), true);
        assert_eq!(found[0].kind, MarkerKind::PeriodDoubling);
    }

    #[test]
    fn an_exponent_is_followed_across_classes_by_its_multiplier() {
        // The exponent leaves class 2's strip at its top edge and comes back
        // in class 3 at the bottom (the same multiplier): no crossing is
        // made up by pairing it with class 2's other exponent.
        let half = 0.5 * OMEGA;
        let points = vec![
            point(
                OMEGA,
                &[(2, vec![(0.5, half - 0.5), (-3.0, -30.0)]), (3, vec![])],
            ),
            point(
                OMEGA,
                &[(2, vec![(-3.0, -30.0)]), (3, vec![(0.6, -half + 0.5)])],
            ),
        ];
        assert!(markers(&points, true).is_empty());
    }

    #[test]
    fn a_conjugate_pair_crosses_as_one_marker() {
        // Class 0 holds λ and λ̄; classes 1 and −1 hold conjugate copies.
        let points: Vec<PointStability> = [-1.0, 1.0]
            .iter()
            .enumerate()
            .map(|(i, &re)| {
                point(
                    OMEGA + i as f64,
                    &[
                        (-1, vec![(re, -7.0)]),
                        (0, vec![(re, 12.0), (re, -12.0)]),
                        (1, vec![(re, 7.0)]),
                    ],
                )
            })
            .collect();
        let found = markers(&points, true);
        let classes: Vec<Option<i64>> = found.iter().map(|m| m.nodal_diameter).collect();
        assert_eq!(classes, vec![Some(0), Some(1)], "{found:?}");
    }

    #[test]
    fn a_swap_of_the_matching_within_one_step_gives_no_marker() {
        // Two exponents of class 2 close in the multiplier plane trade
        // places: tracking may read one rising and one falling through 0
        // at the same step; the class keeps one growing exponent.
        let points = vec![
            point(OMEGA, &[(2, vec![(0.3, 10.0), (-0.3, 11.0)])]),
            point(OMEGA + 1.0, &[(2, vec![(-0.05, 10.0), (0.6, 11.0)])]),
        ];
        // Tracked alone, that is a regain and a loss.
        let tracked = tracked_crossings(&points, true);
        assert_eq!(tracked.len(), 2);
        let found = markers(&points, true);
        assert!(found.is_empty(), "{found:?}");
    }

    #[test]
    fn a_second_growing_exponent_does_not_change_its_class() {
        // Class 2: one exponent grows at the first step, a second at the
        // third, the first falls back at the fifth; the class is stable
        // again only when the second does too.
        let points: Vec<PointStability> = [
            (-1.0, -2.0),
            (1.0, -2.0),
            (1.5, -1.0),
            (1.5, 1.0),
            (1.2, 1.5),
            (-1.0, 1.5),
            (-1.0, -1.0),
        ]
        .iter()
        .enumerate()
        .map(|(i, &(x, y))| point(OMEGA + i as f64, &[(2, vec![(x, 10.0), (y, 30.0)])]))
        .collect();
        let found = markers(&points, true);
        let read: Vec<(usize, bool, bool)> = found
            .iter()
            .map(|m| (m.index, m.loses_stability, m.class_changes))
            .collect();
        assert_eq!(
            read,
            vec![
                (0, true, true),
                (2, true, false),
                (4, false, false),
                (5, false, true)
            ],
            "{found:?}"
        );
    }
}
