//! A branch followed from both ends of its frequency range.
//!
//! A forced response is linear, hence unique, far from resonance: one curve
//! joins the two ends of the range, and it can be followed from either.
//! A long branch with close sheets (the N = 45 deformed-casing case snakes
//! through hundreds of folds between 211 and 223 Hz, the same ones for
//! `N_t` = 9990 and 19980) can make a sweep step onto a sheet it already
//! travelled or onto a closed curve close by, or (DLFT) come back onto a
//! piece it travelled before, which stops it. The part it
//! did not reach is then followed back from the end frequency until it
//! meets the first sweep, and the two are joined there.

use super::arc_length::{follow, segment_cosine, segment_distance, Scaling};
use super::{hertz, ArcLengthSettings, Branch, Point, Problem, Progress, StopReason};
use serde::Serialize;

/// A point of the sweep back lies on the first sweep when it is within this
/// fraction of a segment's length from one of its segments: under the
/// continuation's turn limits a chord misses its arc by at most a
/// fortieth of its length.
const JOIN_DISTANCE: f64 = 0.05;
/// ... and runs against that segment at least this closely (cosine): the
/// two sweeps travel the same curve in opposite ways. A part of the first
/// sweep that went back along itself runs the other way and is never
/// joined.
const JOIN_COSINE: f64 = 0.95;
/// Consecutive points of the sweep back that must lie on the first sweep,
/// each on the same segment or an earlier one, before the two are joined:
/// a sheet that passes close by does not run along it.
const JOIN_CONFIRMATIONS: usize = 3;

/// How a branch followed from both ends was made.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Sweeps {
    /// Why the sweep from the start frequency stopped short of the end.
    pub from_start: StopReason,
    /// Points of the sweep from the start.
    pub from_start_points: usize,
    /// Of those, how many the branch keeps: its first ones, up to where the
    /// sweep back met it (all of them when the sweeps did not meet, none
    /// when the sweep back reached the start frequency by itself).
    pub from_start_kept: usize,
    /// Why the sweep back from the end stopped: `MetOtherSweep` (joined),
    /// `EndReached` (it reached the start frequency), or why it failed (the
    /// branch then has a gap between the two sweeps).
    pub from_end: StopReason,
    /// Points of the sweep back, all kept, in reverse order after the kept
    /// points of the first sweep.
    pub from_end_points: usize,
}

impl Sweeps {
    /// The last point before the gap of a branch whose two sweeps did not
    /// meet (the last kept point of the first sweep), if it has one.
    pub fn gap_after(&self) -> Option<usize> {
        match self.from_end {
            StopReason::MetOtherSweep { .. } | StopReason::EndReached => None,
            _ => self.from_start_kept.checked_sub(1),
        }
    }

    /// One line for people: how the branch was put together.
    pub fn summary(&self) -> String {
        let first = format!(
            "the sweep from the start stopped after {} points ({})",
            self.from_start_points,
            self.from_start.short()
        );
        match &self.from_end {
            StopReason::MetOtherSweep { frequency_hz, point } => format!(
                "{first}; the sweep back from the end met it at its point {point} ({frequency_hz:.4} Hz) after {} points, and the two are joined",
                self.from_end_points
            ),
            StopReason::EndReached => format!(
                "{first}; the sweep back from the end reached the start by itself ({} points), and is the branch",
                self.from_end_points
            ),
            other => {
                let gap = match self.from_start_kept {
                    0 => "the branch does not reach the start frequency".to_string(),
                    kept => format!("the branch has a gap after its point {}", kept - 1),
                };
                format!(
                    "{first}; the sweep back from the end stopped too after {} points ({}): {gap}",
                    self.from_end_points,
                    other.short(),
                )
            }
        }
    }
}

/// Follows the branch from `settings.start` (from `guess_at_start`) to
/// `settings.end`, like [`continue_branch`](super::continue_branch); if
/// that sweep stops short of the end for any reason but the point cap,
/// follows it back from `settings.end` (from `guess_at_end`) with the points
/// left, until it meets the first sweep or reaches the start. The branch
/// runs from the start to the end frequency: the first sweep up to the
/// meeting, then the sweep back reversed. The cap holds for both sweeps
/// together. Never fails: a branch with a gap keeps both sweeps and says so
/// in [`Branch::sweeps`].
pub fn continue_from_both_ends<P: Problem>(
    problem: &mut P,
    guess_at_start: Vec<f64>,
    guess_at_end: Vec<f64>,
    settings: &ArcLengthSettings,
    mut observer: impl FnMut(&Point, &Progress),
) -> Branch {
    let (first, _) = follow(problem, guess_at_start, settings, &mut observer, None);
    let left = settings.max_points.saturating_sub(first.points.len());
    if matches!(
        first.stop,
        StopReason::EndReached | StopReason::PointCap { .. }
    ) || left == 0
    {
        return first;
    }
    tracing::info!(
        "the sweep from {:.4} Hz stopped after {} points ({}): following the branch back from {:.4} Hz",
        hertz(settings.start),
        first.points.len(),
        first.stop.short(),
        hertz(settings.end),
    );
    let scaling = Scaling::new(problem, settings);
    let mut trail = Trail::new(
        first
            .points
            .iter()
            .map(|p| scaling.scaled(&p.unknowns, p.omega))
            .collect(),
    );
    let back = ArcLengthSettings {
        start: settings.end,
        end: settings.start,
        max_points: left,
        ..*settings
    };
    let offset = first.points.len();
    let (second, met) = follow(
        problem,
        guess_at_end,
        &back,
        |point: &Point, progress: &Progress| {
            observer(
                point,
                &Progress {
                    points: progress.points + offset,
                    ..*progress
                },
            )
        },
        Some(&mut |z: &[f64], tangent: &[f64]| trail.meets(z, tangent)),
    );
    join(first, second, met)
}

/// The branch from the start to the end frequency made of the two sweeps:
/// `met` is the segment of `first` where `second` met it.
fn join(first: Branch, second: Branch, met: Option<usize>) -> Branch {
    let total_iterations = first.total_iterations + second.total_iterations;
    let from_start_points = first.points.len();
    let from_end_points = second.points.len();
    let (kept, from_end, stop) = match met {
        Some(segment) => {
            let frequency_hz = second.points.last().map_or(0.0, |p| hertz(p.omega));
            (
                segment + 1,
                StopReason::MetOtherSweep {
                    frequency_hz,
                    point: segment,
                },
                StopReason::EndReached,
            )
        }
        None if second.stop == StopReason::EndReached => {
            (0, StopReason::EndReached, StopReason::EndReached)
        }
        None => (from_start_points, second.stop, first.stop.clone()),
    };
    let sweeps = Sweeps {
        from_start: first.stop,
        from_start_points,
        from_start_kept: kept,
        from_end,
        from_end_points,
    };
    let mut points = first.points;
    points.truncate(kept);
    points.extend(second.points.into_iter().rev());
    Branch {
        points,
        stop,
        total_iterations,
        sweeps: Some(sweeps),
    }
}

/// The first sweep's points (scaled), and the sweep back's run of points
/// on it so far.
struct Trail {
    points: Vec<Vec<f64>>,
    /// Segment lengths.
    lengths: Vec<f64>,
    /// The segment the last point of the sweep back lay on, and how many
    /// points in a row did.
    run: Option<(usize, usize)>,
}

impl Trail {
    fn new(points: Vec<Vec<f64>>) -> Self {
        let lengths = points
            .windows(2)
            .map(|pair| {
                pair[1]
                    .iter()
                    .zip(&pair[0])
                    .map(|(b, a)| (b - a) * (b - a))
                    .sum::<f64>()
                    .sqrt()
            })
            .collect();
        Self {
            points,
            lengths,
            run: None,
        }
    }

    /// The segment of the first sweep where the sweep back, at `z` going
    /// along `tangent`, has joined it (see [`JOIN_CONFIRMATIONS`]).
    fn meets(&mut self, z: &[f64], tangent: &[f64]) -> Option<usize> {
        let on = self.segment_under(z, tangent);
        self.run = match (on, self.run) {
            (Some(segment), Some((previous, count))) if segment <= previous => {
                Some((segment, count + 1))
            }
            (Some(segment), _) => Some((segment, 1)),
            (None, _) => None,
        };
        self.run
            .filter(|&(_, count)| count >= JOIN_CONFIRMATIONS)
            .map(|(segment, _)| segment)
    }

    /// The segment of the first sweep that `z` lies on (the closest,
    /// relative to its length), running against `tangent`.
    fn segment_under(&self, z: &[f64], tangent: &[f64]) -> Option<usize> {
        let last = z.len() - 1;
        let mut best: Option<(usize, f64)> = None;
        for (index, (pair, &length)) in self.points.windows(2).zip(&self.lengths).enumerate() {
            if length <= 0.0 {
                continue;
            }
            let reach = JOIN_DISTANCE * length;
            // The frequency alone rules out most segments.
            let (low, high) = if pair[0][last] <= pair[1][last] {
                (pair[0][last], pair[1][last])
            } else {
                (pair[1][last], pair[0][last])
            };
            if z[last] < low - reach || z[last] > high + reach {
                continue;
            }
            let (distance, _) = segment_distance(z, &pair[0], &pair[1]);
            if distance > reach || best.is_some_and(|(_, ratio)| ratio <= distance / length) {
                continue;
            }
            if segment_cosine(&pair[0], &pair[1], length, tangent) <= -JOIN_COSINE {
                best = Some((index, distance / length));
            }
        }
        best.map(|(index, _)| index)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    #[test]
    fn only_sweeps_that_did_not_meet_leave_a_gap() {
        let sweeps = |from_end: StopReason, from_start_kept: usize| Sweeps {
            from_start: StopReason::StepUnderflow {
                frequency_hz: 220.0,
                step: 1e-8,
            },
            from_start_points: 10,
            from_start_kept,
            from_end,
            from_end_points: 5,
        };
        let underflow = StopReason::StepUnderflow {
            frequency_hz: 221.0,
            step: 1e-8,
        };
        assert_eq!(sweeps(underflow.clone(), 10).gap_after(), Some(9));
        // The sweep back alone: nothing kept of the first, no gap.
        assert_eq!(sweeps(underflow, 0).gap_after(), None);
        let met = StopReason::MetOtherSweep {
            frequency_hz: 221.0,
            point: 4,
        };
        assert_eq!(sweeps(met, 5).gap_after(), None);
        assert_eq!(sweeps(StopReason::EndReached, 0).gap_after(), None);
    }

    fn line(count: usize) -> Trail {
        // Points along the diagonal (x, ω) = (i, i) / count.
        Trail::new(
            (0..count)
                .map(|i| vec![i as f64 / count as f64, i as f64 / count as f64])
                .collect(),
        )
    }

    #[test]
    fn a_sweep_back_along_the_trail_is_joined_after_three_points() {
        let mut trail = line(10);
        let back = [-1.0 / 2f64.sqrt(), -1.0 / 2f64.sqrt()];
        assert_eq!(trail.meets(&[0.75, 0.75], &back), None);
        assert_eq!(trail.meets(&[0.65, 0.65], &back), None);
        assert_eq!(trail.meets(&[0.55, 0.55], &back), Some(5));
    }

    #[test]
    fn a_sweep_the_same_way_or_beside_the_trail_is_not_joined() {
        let mut trail = line(10);
        let along = [1.0 / 2f64.sqrt(), 1.0 / 2f64.sqrt()];
        for i in 0..6 {
            let s = 0.8 - 0.1 * i as f64;
            assert_eq!(trail.meets(&[s, s], &along), None);
        }
        // Beside the trail by 7 % of a segment's length: not on it.
        let back = [-along[0], -along[1]];
        let off = 0.1 * 0.1 * 2f64.sqrt();
        for i in 0..6 {
            let s = 0.8 - 0.1 * i as f64;
            assert_eq!(trail.meets(&[s + off, s], &back), None);
        }
    }

    #[test]
    fn a_run_broken_or_going_forward_along_the_trail_starts_again() {
        let mut trail = line(10);
        let back = [-1.0 / 2f64.sqrt(), -1.0 / 2f64.sqrt()];
        assert_eq!(trail.meets(&[0.35, 0.35], &back), None);
        assert_eq!(trail.meets(&[0.25, 0.25], &back), None);
        // Off the trail: the run ends.
        assert_eq!(trail.meets(&[0.5, 0.1], &back), None);
        assert_eq!(trail.meets(&[0.75, 0.75], &back), None);
        // Further on along the trail than the last point: starts again.
        assert_eq!(trail.meets(&[0.85, 0.85], &back), None);
        assert_eq!(trail.meets(&[0.65, 0.65], &back), None);
        assert_eq!(trail.meets(&[0.62, 0.62], &back), Some(6));
    }
}
