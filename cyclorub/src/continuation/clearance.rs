//! Whether a step lands on a sheet of the branch travelled long before.
//!
//! A long branch that snakes through many folds (the N = 45 deformed-casing
//! case) runs for hundreds of points beside sheets it travelled before,
//! some a few steps away, some a few 1e-6 away (in scaled units) for
//! thousands of points (its DLFT branch near 213.2 Hz). A step can land on
//! such a sheet, and the continuation then goes along it again (its DLFT
//! branch went back from 221.3 Hz to 220.3 Hz along its trail). The turn
//! limits cannot see it when the sheet runs the same way, nor can the
//! recent trail. A part of the trail is *another sheet* when it
//! is much further along the branch than in a straight line; a step lands
//! on one when it ends far closer to it than its own length and than the
//! point it started from was: a branch that runs beside an old sheet, however
//! close, keeps its distance from it.

use super::arc_length::Scaling;
use super::Point;

/// A segment of the trail is another sheet when the arc length along the
/// branch from it to the current point is more than this many times their
/// distance (a fold of radius r: about 2.4 r past its tip; a corner turning
/// by φ: when φ > 166°).
const SHEET_ARC_RATIO: f64 = 8.0;

/// A step lands on another sheet when it ends closer to it than this
/// fraction of the step's length...
const LANDING: f64 = 0.1;
/// ... and than this fraction of the distance its start had from it.
const DROP: f64 = 0.25;

/// The cumulative arc length (scaled) of the points of a branch, to tell
/// other sheets from the recent trail.
#[derive(Default)]
pub(super) struct Clearance {
    arc: Vec<f64>,
}

impl Clearance {
    /// Records the next accepted point, `chord` (scaled) from the last one.
    pub(super) fn push(&mut self, chord: f64) {
        let last = self.arc.last().copied().unwrap_or(0.0);
        self.arc.push(last + chord);
    }

    /// Whether the step from `from` (the last of `points`, scaled) to
    /// `candidate` lands on another sheet of the trail.
    pub(super) fn lands_on_old_sheet(
        &self,
        points: &[Point],
        scaling: &Scaling,
        from: &[f64],
        candidate: &[f64],
    ) -> bool {
        let chord = candidate
            .iter()
            .zip(from)
            .map(|(a, b)| (a - b) * (a - b))
            .sum::<f64>()
            .sqrt();
        let Some(landed) = self.nearest_sheet(points, scaling, candidate, chord, LANDING * chord)
        else {
            return false;
        };
        self.nearest_sheet(points, scaling, from, 0.0, landed / DROP)
            .is_none_or(|before| landed < DROP * before)
    }

    /// The distance (scaled) from `here`, `extra_arc` along the branch past
    /// the last of `points`, to the nearest segment of the trail that is
    /// another sheet, if one lies within `reach`.
    pub(super) fn nearest_sheet(
        &self,
        points: &[Point],
        scaling: &Scaling,
        here: &[f64],
        extra_arc: f64,
        reach: f64,
    ) -> Option<f64> {
        let count = points.len().min(self.arc.len());
        let current_arc = *self.arc.get(count.checked_sub(1)?)? + extra_arc;
        let factors = scaling.factors();
        let frequency = factors.len() - 1;
        let here_frequency = here[frequency];
        let mut nearest: Option<f64> = None;
        for i in 0..count.saturating_sub(1) {
            let (a, b) = (&points[i], &points[i + 1]);
            let arc = current_arc - self.arc[i + 1];
            // Cheap bounds first: the frequency alone, then the arc length.
            let (da, db) = (
                a.omega * factors[frequency] - here_frequency,
                b.omega * factors[frequency] - here_frequency,
            );
            let bound = if da * db <= 0.0 {
                0.0
            } else {
                da.abs().min(db.abs())
            };
            let limit = nearest.unwrap_or(reach).min(reach);
            if bound >= limit || arc <= SHEET_ARC_RATIO * bound {
                continue;
            }
            let distance = segment_distance(a, b, here, factors);
            if distance < limit && arc > SHEET_ARC_RATIO * distance {
                nearest = Some(distance);
            }
        }
        nearest
    }
}

/// Distance from the scaled point `here` to the segment between the points
/// `a` and `b`, scaled by `factors` on the fly (no copy of the trail).
fn segment_distance(a: &Point, b: &Point, here: &[f64], factors: &[f64]) -> f64 {
    let frequency = factors.len() - 1;
    let (mut ab_ab, mut ah_ab, mut ah_ah) = (0.0, 0.0, 0.0);
    let mut add = |a: f64, b: f64, h: f64| {
        let (ab, ah) = (b - a, h - a);
        ab_ab += ab * ab;
        ah_ab += ah * ab;
        ah_ah += ah * ah;
    };
    for (k, factor) in factors[..frequency].iter().enumerate() {
        add(a.unknowns[k] * factor, b.unknowns[k] * factor, here[k]);
    }
    add(
        a.omega * factors[frequency],
        b.omega * factors[frequency],
        here[frequency],
    );
    let t = (ah_ab / ab_ab.max(f64::MIN_POSITIVE)).clamp(0.0, 1.0);
    (ah_ah - 2.0 * t * ah_ab + t * t * ab_ab).max(0.0).sqrt()
}

#[cfg(test)]
mod tests {
    use super::*;

    fn point(x: f64, y: f64) -> Point {
        Point {
            omega: y,
            unknowns: vec![x],
            iterations: 0,
            residual_norm: 0.0,
            converged: true,
        }
    }

    /// A hairpin in the plane (x, ω), unscaled: up along x = 0, across the
    /// top, down along x = `width`, sampled every `spacing`.
    fn hairpin(width: f64, height: f64, spacing: f64) -> Vec<Point> {
        let mut points = Vec::new();
        let up = (height / spacing).round() as usize;
        for i in 0..=up {
            points.push(point(0.0, i as f64 * spacing));
        }
        let across = (width / spacing).round() as usize;
        for i in 1..=across {
            points.push(point(i as f64 * spacing, height));
        }
        for i in 1..=up {
            points.push(point(width, height - i as f64 * spacing));
        }
        points
    }

    fn clearance_of(points: &[Point]) -> Clearance {
        let mut clearance = Clearance::default();
        clearance.push(0.0);
        for pair in points.windows(2) {
            let chord =
                (pair[1].unknowns[0] - pair[0].unknowns[0]).hypot(pair[1].omega - pair[0].omega);
            clearance.push(chord);
        }
        clearance
    }

    #[test]
    fn the_other_leg_of_a_hairpin_is_a_sheet_once_far_enough_along() {
        let scaling = Scaling::identity(1);
        let (width, height, spacing) = (0.01, 1.0, 0.001);
        let points = hairpin(width, height, spacing);
        let clearance = clearance_of(&points);
        // Far down the second leg (its last point): the first leg is
        // `width` away.
        let here = [width, 0.499];
        let far = clearance.nearest_sheet(&points[..points.len() - 499], &scaling, &here, 0.0, 1.0);
        let distance = far.expect("the first leg is another sheet");
        assert!((distance - width).abs() < 1e-12, "distance {distance}");
        // Just past the top, the first leg is as close along the branch as
        // across: not another sheet yet.
        let top = 1001 + 10 + 2;
        let here = [width, height - 2.0 * spacing];
        assert_eq!(
            clearance.nearest_sheet(&points[..top], &scaling, &here, 0.0, 1.0),
            None
        );
        // Beyond reach: not looked for.
        let here = [width, 0.499];
        assert_eq!(
            clearance.nearest_sheet(
                &points[..points.len() - 499],
                &scaling,
                &here,
                0.0,
                0.5 * width
            ),
            None
        );
    }

    #[test]
    fn a_step_onto_the_other_leg_lands_on_it_one_beside_it_does_not() {
        let scaling = Scaling::identity(1);
        // Legs 1e-3 apart, and legs 1e-7 apart (DLFT sheets that differ by
        // one instant's contact state run that close).
        for width in [1e-3, 1e-7] {
            let spacing = 1e-3;
            let points = hairpin(width, 1.0, spacing);
            let clearance = clearance_of(&points[..points.len() - 499]);
            let trail = &points[..points.len() - 499];
            let from = [width, 0.499];
            // On along its own leg, at any distance from the other one.
            assert!(!clearance.lands_on_old_sheet(trail, &scaling, &from, &[width, 0.49]));
            assert!(!clearance.lands_on_old_sheet(trail, &scaling, &from, &[width, 0.3]));
            // Onto the other leg, a step further down or across.
            for candidate in [[0.0, 0.49], [0.0, 0.499], [1e-9 * width, 0.45]] {
                assert!(
                    clearance.lands_on_old_sheet(trail, &scaling, &from, &candidate),
                    "width {width}: {candidate:?}"
                );
            }
            // Halfway across: closer, but not on it (a quarter of the way
            // from where it started is the limit).
            assert!(!clearance.lands_on_old_sheet(trail, &scaling, &from, &[0.5 * width, 0.49]));
        }
    }

    #[test]
    fn a_straight_trail_has_no_other_sheet() {
        let scaling = Scaling::identity(1);
        let points: Vec<Point> = (0..200)
            .map(|i| point(0.3 * i as f64, 0.01 * i as f64))
            .collect();
        let clearance = clearance_of(&points);
        let last = points.last().expect("points");
        let here = [last.unknowns[0], last.omega];
        assert_eq!(
            clearance.nearest_sheet(&points, &scaling, &here, 0.0, 100.0),
            None
        );
    }

    #[test]
    fn the_distance_to_a_segment_is_measured_across_it_and_at_its_ends() {
        let factors = [2.0, 0.5];
        let (a, b) = (point(0.0, 0.0), point(1.0, 0.0));
        // Scaled: a = (0, 0), b = (2, 0).
        let across = segment_distance(&a, &b, &[1.0, 3.0], &factors);
        assert!((across - 3.0).abs() < 1e-14);
        let beyond = segment_distance(&a, &b, &[5.0, 4.0], &factors);
        assert!((beyond - 5.0).abs() < 1e-14);
        let before = segment_distance(&a, &b, &[-3.0, -4.0], &factors);
        assert!((before - 5.0).abs() < 1e-14);
    }
}
