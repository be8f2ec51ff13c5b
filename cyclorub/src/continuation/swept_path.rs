//! The path a fixed-frequency sweep has travelled since its last jump or
//! turn (its points at the frequencies asked for, and the points of the
//! bridges that reached one), and the test that stops a bridge come back
//! onto it (docs/design.md §7, "bridges").
//!
//! The path is one arc of the branch ending at the bridge's start, so a
//! bridge from there that meets one of its points has gone round a loop
//! through it (from there it runs along the path back to where it
//! started), and no frequency it reaches after that is new. On the
//! default case mistuned at 1 %, 6 of 20 patterns' sheet ends are such
//! loops, which the bridge followed to its cap of points before the fresh
//! start it ends in anyway.

use super::driver::Meeting;
use super::geometry::{segment_distance, Scaling};

/// The sweep's path, unscaled: `(x, ω)` in the order travelled.
#[derive(Debug, Default)]
pub(crate) struct SweptPath {
    points: Vec<(Vec<f64>, f64)>,
}

/// A bridge's segment passes a point of the path when it comes within this
/// fraction of its length (the driver's turn limits keep a chord within a
/// fortieth of its length from its arc; the join of two sweeps uses the
/// same).
const WITHIN: f64 = 0.05;

impl SweptPath {
    /// Adds a point reached (in place of the last one at the same
    /// frequency: a frequency asked for twice).
    pub(crate) fn push(&mut self, x: &[f64], omega: f64) {
        #[allow(clippy::float_cmp)] // the same frequency asked for again
        if self.points.last().is_some_and(|(_, w)| *w == omega) {
            self.points.pop();
        }
        self.points.push((x.to_vec(), omega));
    }

    /// Forgets the path: the sweep jumped (a fresh start) or turned back.
    pub(crate) fn restart(&mut self) {
        self.points.clear();
    }

    /// The frequency (Hz) of the path's point `index`.
    pub(crate) fn frequency_hz(&self, index: usize) -> Option<f64> {
        self.points
            .get(index)
            .map(|(_, omega)| super::hertz(*omega))
    }

    /// The test a bridge's driver runs at each point (scaled by `scaling`,
    /// the bridge's): the index of the path's point that the segment from
    /// the bridge's previous point passes, once the bridge has turned back
    /// (a fold: before it, the bridge runs away from every point behind
    /// it); for the path's last point, the bridge's own start, once it has
    /// turned twice (it leaves that point, so it can only come back to it
    /// round a loop).
    pub(crate) fn meeting<'a>(&'a self, scaling: &Scaling, start: (&[f64], f64)) -> Meeting<'a> {
        let scaled: Vec<Vec<f64>> = self
            .points
            .iter()
            .map(|(x, omega)| scaling.scaled(x, *omega))
            .collect();
        let last = scaled.len().checked_sub(1);
        let frequency = start.0.len();
        let mut previous = scaling.scaled(start.0, start.1);
        let mut rising: Option<bool> = None;
        let mut folds = 0_usize;
        Box::new(move |z: &[f64], _tangent: &[f64]| {
            let step = z[frequency] - previous[frequency];
            if step != 0.0 {
                let up = step > 0.0;
                if rising.is_some_and(|r| r != up) {
                    folds += 1;
                }
                rising = Some(up);
            }
            let before = std::mem::replace(&mut previous, z.to_vec());
            if folds == 0 {
                return None;
            }
            let length = before
                .iter()
                .zip(z)
                .map(|(a, b)| (b - a) * (b - a))
                .sum::<f64>()
                .sqrt();
            let reach = WITHIN * length;
            let (low, high) = if before[frequency] <= z[frequency] {
                (before[frequency], z[frequency])
            } else {
                (z[frequency], before[frequency])
            };
            scaled.iter().enumerate().position(|(index, point)| {
                (Some(index) != last || folds >= 2)
                    && point[frequency] >= low - reach
                    && point[frequency] <= high + reach
                    && segment_distance(point, before.iter().copied(), z.iter().copied()).0 <= reach
            })
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A unit circle `(x, ω) = (−cos a, sin a)` in steps of 0.1 rad: the
    /// path holds `a` from −1.5 to 0, the bridge starts at `a = 0`, turns
    /// back at `a = π/2` (fold 1) and forward at `3π/2` (fold 2), and meets
    /// the path's first point, not before (on the way down it passes the
    /// path's side at the other `x`).
    #[test]
    fn a_bridge_round_a_loop_meets_the_path_where_it_joins_it() {
        let scaling = Scaling::identity(1);
        let at = |angle: f64| (vec![-angle.cos()], angle.sin());
        let mut path = SweptPath::default();
        let angles: Vec<f64> = (0..=15).map(|i| -1.5 + 0.1 * i as f64).collect();
        for &a in &angles {
            let (x, omega) = at(a);
            path.push(&x, omega);
        }
        let (start, omega) = at(0.0);
        let mut meeting = path.meeting(&scaling, (&start, omega));
        let mut met = None;
        for i in 1..70 {
            let (x, omega) = at(0.0 + 0.1 * i as f64);
            let z = scaling.scaled(&x, omega);
            if let Some(index) = meeting(&z, &z) {
                met = Some((i, index));
                break;
            }
        }
        let (step, index) = met.expect("the loop meets the path");
        // The path's first point, at the angle 2π − 1.5 = 4.78, between
        // the bridge's 47th and 48th.
        assert_eq!(index, 0);
        assert_eq!(
            step,
            ((2.0 * std::f64::consts::PI - 1.5) / 0.1).round() as usize
        );
    }

    /// The stops of `meeting` over a bridge through `points` (`(x, ω)`).
    fn stops(path: &SweptPath, start: (f64, f64), points: &[(f64, f64)]) -> Option<usize> {
        let scaling = Scaling::identity(1);
        let mut meeting = path.meeting(&scaling, (&[start.0], start.1));
        points.iter().find_map(|&(x, omega)| {
            let z = scaling.scaled(&[x], omega);
            meeting(&z, &z)
        })
    }

    /// A hairpin: up from the start along `x = 0`, one fold at ω = 1, back
    /// down along `x = 0.001`, past the start within a hundredth of a step:
    /// the start counts only once the bridge has turned twice.
    #[test]
    fn a_bridge_past_its_start_after_one_fold_goes_on() {
        let mut path = SweptPath::default();
        path.push(&[0.0], 0.0);
        let up = (1..=10).map(|i| (0.0, 0.1 * i as f64));
        let down = (0..=20).map(|i| (0.001, 1.0 - 0.1 * i as f64));
        let points: Vec<(f64, f64)> = up.chain(down).collect();
        assert_eq!(stops(&path, (0.0, 0.0), &points), None);
    }

    /// A path point ahead of a bridge that has not turned (a sweep that
    /// came down to its start): passed through, not met.
    #[test]
    fn a_bridge_that_has_not_turned_meets_nothing() {
        let mut path = SweptPath::default();
        path.push(&[0.0], 0.55);
        path.push(&[0.0], 0.0);
        let points: Vec<(f64, f64)> = (1..=10).map(|i| (0.0, 0.1 * i as f64)).collect();
        assert_eq!(stops(&path, (0.0, 0.0), &points), None);
    }

    /// A frequency asked for twice keeps one point there.
    #[test]
    fn a_point_at_the_same_frequency_replaces_the_last() {
        let mut path = SweptPath::default();
        path.push(&[0.0], 1.0);
        path.push(&[2.0], 1.0);
        assert_eq!(path.points, vec![(vec![2.0], 1.0)]);
        path.restart();
        assert!(path.points.is_empty());
    }
}
