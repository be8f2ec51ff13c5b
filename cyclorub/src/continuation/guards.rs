//! Guards against steps that leave the branch for another part of it:
//!
//! - [`Trail`]: the recent points, to refuse a step that goes back along
//!   the way it came (on a nonsmooth residual, where the turn limits are
//!   lax);
//! - [`revisited_point`]: a point that repeats an earlier one ends the
//!   branch (a closed loop, or a cycle through the corners of a nonsmooth
//!   branch), which would otherwise go round for ever;
//! - [`OldSheets`]: a step that lands on a sheet travelled long before is
//!   refused. A long branch that snakes through many folds runs for
//!   hundreds of points beside sheets it travelled before, some a few
//!   steps away, some 1e-6 away (scaled); the turn limits cannot see a
//!   landing there when the sheet runs the same way, nor can the recent
//!   trail. A part of the trail is *another sheet* when it is much further
//!   along the branch than in a straight line; a step lands on one when it
//!   ends far closer to it than its own length and than its start was: a
//!   branch that runs beside an old sheet, however close, keeps its
//!   distance from it and goes on.
//!
//! They depend on geometry only, in scaled unknowns.

use super::geometry::{distance, segment_cosine, segment_distance, Scaling};
use super::settings::{ClosedLoopSettings, OldSheetSettings, RetraceSettings};
use super::Point;
use std::collections::VecDeque;

/// The recent points (scaled), oldest first, and their pieces when the
/// residual tells them.
pub(crate) struct Trail {
    points: VecDeque<Vec<f64>>,
    pieces: VecDeque<u64>,
    capacity: usize,
}

impl Trail {
    /// A trail of at most `capacity` points, starting at `z`.
    pub(crate) fn new(z: &[f64], capacity: usize) -> Self {
        Self {
            points: VecDeque::from([z.to_vec()]),
            pieces: VecDeque::new(),
            capacity,
        }
    }

    /// Records the next point.
    pub(crate) fn push(&mut self, z: &[f64]) {
        self.points.push_back(z.to_vec());
        if self.points.len() > self.capacity {
            self.points.pop_front();
        }
    }

    /// Records the piece of the next point.
    pub(crate) fn push_piece(&mut self, piece: u64) {
        self.pieces.push_back(piece);
        if self.pieces.len() > self.capacity {
            self.pieces.pop_front();
        }
    }

    /// The points and the pieces, each oldest first.
    pub(crate) fn slices(&mut self) -> (&[Vec<f64>], &[u64]) {
        (self.points.make_contiguous(), self.pieces.make_contiguous())
    }
}

/// Whether `candidate`, leaving along `tangent`, goes back the way we came:
/// it lies near a segment of `trail` (within a fraction of the segment's
/// length, which a chord of a curved branch misses by its sagitta) and runs
/// against it. Near a fold the two sheets are close too, but the branch
/// runs on through the fold (the displacement keeps its way, only the
/// frequency turns), so the direction tells them apart.
pub(crate) fn retraces(
    candidate: &[f64],
    tangent: &[f64],
    trail: &[Vec<f64>],
    step: f64,
    settings: &RetraceSettings,
) -> bool {
    trail.windows(2).any(|pair| {
        let (distance, length) =
            segment_distance(candidate, pair[0].iter().copied(), pair[1].iter().copied());
        if distance >= settings.segment_fraction * length + settings.step_fraction * step {
            return false;
        }
        segment_cosine(&pair[0], &pair[1], length, tangent) < -settings.cosine
    })
}

/// The index of an earlier point (not one of the last two) that `point`
/// repeats, to `same_point` relative in frequency and unknowns and to
/// `step_fraction` of `step` (scaled by `scaling`): the continuation has
/// come back on its own trail and would go round for ever.
pub(crate) fn revisited_point(
    points: &[Point],
    point: &Point,
    scaling: &Scaling,
    step: f64,
    settings: &ClosedLoopSettings,
) -> Option<usize> {
    let same = settings.same_point;
    let scale = point
        .unknowns
        .iter()
        .fold(0.0_f64, |m, v| m.max(v.abs()))
        .max(f64::MIN_POSITIVE);
    let here = scaling.scaled(&point.unknowns, point.omega);
    let earlier = points.len().checked_sub(2)?;
    points[..earlier].iter().position(|p| {
        (p.omega - point.omega).abs() <= same * point.omega.abs()
            && p.unknowns
                .iter()
                .zip(&point.unknowns)
                .all(|(a, b)| (a - b).abs() <= same * scale)
            && distance(&scaling.scaled(&p.unknowns, p.omega), &here)
                <= settings.step_fraction * step
    })
}

/// The cumulative arc length (scaled) of the points of a branch, to tell
/// other sheets from the recent trail.
pub(crate) struct OldSheets {
    arc: Vec<f64>,
    scaling: Scaling,
    settings: OldSheetSettings,
}

impl OldSheets {
    /// For a branch starting at its first point.
    pub(crate) fn new(scaling: Scaling, settings: OldSheetSettings) -> Self {
        Self {
            arc: vec![0.0],
            scaling,
            settings,
        }
    }

    /// Records the next accepted point, `chord` (scaled) from the last one.
    pub(crate) fn push(&mut self, chord: f64) {
        let last = self.arc.last().copied().unwrap_or(0.0);
        self.arc.push(last + chord);
    }

    /// Whether the step from `from` (the last of `points`, scaled) to
    /// `candidate` lands on another sheet of the trail.
    pub(crate) fn lands(&self, points: &[Point], from: &[f64], candidate: &[f64]) -> bool {
        let chord = distance(candidate, from);
        let drop = self.settings.drop;
        let Some(landed) =
            self.nearest_sheet(points, candidate, chord, self.settings.landing * chord)
        else {
            return false;
        };
        self.nearest_sheet(points, from, 0.0, landed / drop)
            .is_none_or(|before| landed < drop * before)
    }

    /// The distance (scaled) from `here`, `extra_arc` along the branch past
    /// the last of `points`, to the nearest segment of the trail that is
    /// another sheet, if one lies within `reach`.
    pub(crate) fn nearest_sheet(
        &self,
        points: &[Point],
        here: &[f64],
        extra_arc: f64,
        reach: f64,
    ) -> Option<f64> {
        let ratio = self.settings.arc_ratio;
        let count = points.len().min(self.arc.len());
        let current_arc = *self.arc.get(count.checked_sub(1)?)? + extra_arc;
        let factors = self.scaling.factors();
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
            if bound >= limit || arc <= ratio * bound {
                continue;
            }
            let (distance, _) = segment_distance(
                here,
                self.scaling.scaled_iter(&a.unknowns, a.omega),
                self.scaling.scaled_iter(&b.unknowns, b.omega),
            );
            if distance < limit && arc > ratio * distance {
                nearest = Some(distance);
            }
        }
        nearest
    }
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

    fn sheets_of(points: &[Point]) -> OldSheets {
        let mut sheets = OldSheets::new(Scaling::identity(1), OldSheetSettings::default());
        for pair in points.windows(2) {
            let chord =
                (pair[1].unknowns[0] - pair[0].unknowns[0]).hypot(pair[1].omega - pair[0].omega);
            sheets.push(chord);
        }
        sheets
    }

    #[test]
    fn the_other_leg_of_a_hairpin_is_a_sheet_once_far_enough_along() {
        let (width, height, spacing) = (0.01, 1.0, 0.001);
        let points = hairpin(width, height, spacing);
        let sheets = sheets_of(&points);
        // Far down the second leg (its last point): the first leg is
        // `width` away.
        let here = [width, 0.499];
        let far = sheets.nearest_sheet(&points[..points.len() - 499], &here, 0.0, 1.0);
        let distance = far.expect("the first leg is another sheet");
        assert!((distance - width).abs() < 1e-12, "distance {distance}");
        // Just past the top, the first leg is as close along the branch as
        // across: not another sheet yet.
        let top = 1001 + 10 + 2;
        let here = [width, height - 2.0 * spacing];
        assert_eq!(sheets.nearest_sheet(&points[..top], &here, 0.0, 1.0), None);
        // Beyond reach: not looked for.
        let here = [width, 0.499];
        let trail = &points[..points.len() - 499];
        assert_eq!(sheets.nearest_sheet(trail, &here, 0.0, 0.5 * width), None);
    }

    #[test]
    fn a_step_onto_the_other_leg_lands_on_it_one_beside_it_does_not() {
        // Legs 1e-3 apart, and legs 1e-7 apart (DLFT sheets that differ by
        // one instant's contact state run that close).
        for width in [1e-3, 1e-7] {
            let spacing = 1e-3;
            let points = hairpin(width, 1.0, spacing);
            let sheets = sheets_of(&points[..points.len() - 499]);
            let trail = &points[..points.len() - 499];
            let from = [width, 0.499];
            // On along its own leg, at any distance from the other one.
            assert!(!sheets.lands(trail, &from, &[width, 0.49]));
            assert!(!sheets.lands(trail, &from, &[width, 0.3]));
            // Onto the other leg, a step further down or across.
            for candidate in [[0.0, 0.49], [0.0, 0.499], [1e-9 * width, 0.45]] {
                assert!(
                    sheets.lands(trail, &from, &candidate),
                    "width {width}: {candidate:?}"
                );
            }
            // Halfway across: closer, but not on it (a quarter of the way
            // from where it started is the limit).
            assert!(!sheets.lands(trail, &from, &[0.5 * width, 0.49]));
        }
    }

    #[test]
    fn a_straight_trail_has_no_other_sheet() {
        let points: Vec<Point> = (0..200)
            .map(|i| point(0.3 * i as f64, 0.01 * i as f64))
            .collect();
        let sheets = sheets_of(&points);
        let last = points.last().expect("points");
        let here = [last.unknowns[0], last.omega];
        assert_eq!(sheets.nearest_sheet(&points, &here, 0.0, 100.0), None);
    }

    #[test]
    fn going_back_along_the_trail_retraces_it_going_on_does_not() {
        let mut trail = Trail::new(&[0.0, 0.0], 3);
        for i in 1..5 {
            trail.push(&[i as f64, 0.0]);
        }
        let (points, _) = trail.slices();
        // Only the last three points are kept.
        assert_eq!(points.len(), 3);
        let settings = RetraceSettings::default();
        assert!(retraces(&[2.5, 0.0], &[-1.0, 0.0], points, 0.1, &settings));
        assert!(!retraces(&[2.5, 0.0], &[1.0, 0.0], points, 0.1, &settings));
        // Beside the trail by more than a quarter of a segment.
        assert!(!retraces(&[2.5, 0.3], &[-1.0, 0.0], points, 0.1, &settings));
        // Back over a segment no longer kept.
        assert!(!retraces(&[0.5, 0.0], &[-1.0, 0.0], points, 0.1, &settings));
    }

    #[test]
    fn a_repeated_point_is_found_but_not_the_last_ones() {
        let trail: Vec<Point> = (0..6)
            .map(|i| point(1e-3 * i as f64, 100.0 + i as f64))
            .map(|mut p| {
                p.unknowns.push(2e-3);
                p
            })
            .collect();
        let at = |omega: f64, x: f64| Point {
            unknowns: vec![x, 2e-3],
            ..point(0.0, omega)
        };
        // Unknowns in units of 1e-3, frequency in units of 10.
        let scaling = Scaling::from_factors(vec![1e3, 1e3, 0.1]);
        let settings = ClosedLoopSettings::default();
        let revisited = |p: &Point| revisited_point(&trail, p, &scaling, 0.1, &settings);
        // The same as point 1, up to round-off: a loop.
        let again = at(101.0 * (1.0 + 1e-12), 1e-3 * (1.0 + 1e-11));
        assert_eq!(revisited(&again), Some(1));
        // Close to the last two points is normal progress, not a loop.
        assert_eq!(revisited(&at(105.0, 5e-3)), None);
        assert_eq!(revisited(&at(104.0, 4e-3)), None);
        // Same frequency, another state (a branch crossing in ω only).
        assert_eq!(revisited(&at(101.0, 1.1e-3)), None);
        assert_eq!(
            revisited_point(&trail[..1], &again, &scaling, 0.1, &settings),
            None
        );
        // Within the relative tolerance but not much closer than a (tiny)
        // step: the other sheet of a sharp fold, not a repetition.
        let near = at(101.0 * (1.0 + 5e-8), 1e-3 * (1.0 + 5e-8));
        assert_eq!(revisited(&near), Some(1));
        assert_eq!(
            revisited_point(&trail, &near, &scaling, 1e-7, &settings),
            None
        );
    }
}
