//! A branch followed from both ends of its frequency range.
//!
//! A forced response is linear, hence unique, far from resonance: one curve
//! joins the two ends of the range, and it can be followed from either. A
//! long branch with close sheets can make a sweep step onto a sheet it
//! already travelled or onto a closed curve close by, or (DLFT) come back
//! onto a piece it travelled before, which stops it. The part it did not
//! reach is then followed back from the end frequency until it meets the
//! first sweep, and the two are joined there.

use super::driver::{check_guess, Continuation, ContinuationError, Step};
use super::events::{Event, EventKind};
use super::geometry::{distance, segment_cosine, segment_distance};
use super::interrupt::Interrupt;
use super::observer::Observer;
use super::settings::{ArcLengthSettings, JoinSettings, Settings};
use super::{hertz, Branch, Problem, StopReason};
use serde::Serialize;

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
            self.from_start_points, self.from_start
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
                    other,
                )
            }
        }
    }
}

/// Where a both-ends run is.
enum Phase<'a, P: Problem> {
    /// The sweep from the start.
    First(Continuation<'a, P>),
    /// The sweep back from the end, and the first sweep as it stopped.
    Back {
        first: Branch,
        driver: Continuation<'a, P>,
    },
    /// The branch.
    Done(Branch),
    /// Between two phases (never seen outside `next_phase`).
    Moving,
}

/// A branch followed from `start` to `end`, and, if that sweep stops short
/// of the end for any reason but the point cap, back from `end` with the
/// points left, until it meets the first sweep or reaches the start. The
/// branch runs from the start to the end frequency: the first sweep up to
/// the meeting, then the sweep back reversed. The cap holds for both sweeps
/// together. A branch with a gap keeps both sweeps and says so in
/// [`Branch::sweeps`]. Step by step like [`Continuation`]; what observers
/// see is told in [`Observer`]'s module.
pub struct BothEnds<'a, P: Problem> {
    phase: Phase<'a, P>,
    settings: Settings,
    guess_at_end: Option<Vec<f64>>,
    interrupt: Option<Interrupt>,
}

impl<'a, P: Problem> BothEnds<'a, P> {
    /// A run of `problem` from `guess_at_start` (an approximate solution at
    /// the start frequency), and if needed from `guess_at_end` (at the end
    /// frequency), with `settings`.
    pub fn new(
        problem: &'a mut P,
        guess_at_start: Vec<f64>,
        guess_at_end: Vec<f64>,
        settings: Settings,
    ) -> Result<Self, ContinuationError> {
        check_guess(problem.unknowns(), &guess_at_end)?;
        Ok(Self {
            phase: Phase::First(Continuation::new(problem, guess_at_start, settings)?),
            settings,
            guess_at_end: Some(guess_at_end),
            interrupt: None,
        })
    }

    /// Attaches an observer (see [`Observer`]).
    pub fn with_observer(mut self, observer: impl Observer + 'a) -> Self {
        self.phase = match self.phase {
            Phase::First(driver) => Phase::First(driver.with_observer(observer)),
            other => other,
        };
        self
    }

    /// Stops before the next point, of either sweep, once `interrupt` is
    /// raised (no sweep back begins after it).
    pub fn with_interrupt(mut self, interrupt: Interrupt) -> Self {
        self.phase = match self.phase {
            Phase::First(driver) => Phase::First(driver.with_interrupt(interrupt.clone())),
            other => other,
        };
        self.interrupt = Some(interrupt);
        self
    }

    /// Advances to the next converged point of the current sweep (the sweep
    /// back's come from the end frequency down), or to the stop of the
    /// branch.
    pub fn step(&mut self) -> Step<'_> {
        let index = self.advance();
        match (&self.phase, index) {
            (Phase::First(driver) | Phase::Back { driver, .. }, Some(index)) => {
                Step::Point(&driver.points()[index])
            }
            (Phase::Done(branch), _) => Step::Stopped(&branch.stop),
            _ => unreachable!("a sweep gives points, a finished run its branch"),
        }
    }

    /// Runs the remaining steps and returns the branch; observers are told
    /// it is finished.
    pub fn finish(mut self) -> Branch {
        while self.advance().is_some() {}
        match self.phase {
            Phase::Done(branch) => branch,
            _ => unreachable!("advance returns None only when done"),
        }
    }

    /// The index of the next point in the current sweep, `None` when done.
    fn advance(&mut self) -> Option<usize> {
        loop {
            let index = match &mut self.phase {
                Phase::First(driver) | Phase::Back { driver, .. } => driver.advance(),
                Phase::Done(_) | Phase::Moving => return None,
            };
            if index.is_some() {
                return index;
            }
            self.next_phase();
        }
    }

    /// The current sweep has stopped: on to the sweep back, or done.
    fn next_phase(&mut self) {
        self.phase = match std::mem::replace(&mut self.phase, Phase::Moving) {
            Phase::First(driver) => self.after_first(driver),
            Phase::Back { first, driver } => {
                let (second, mut observers) = driver.into_sweep();
                let branch = join(first, second);
                observers.finished(&branch);
                Phase::Done(branch)
            }
            done => done,
        };
    }

    /// The sweep back after the first sweep, unless that one is the branch.
    fn after_first(&mut self, driver: Continuation<'a, P>) -> Phase<'a, P> {
        let scaling = driver.scaling().clone();
        let (first, mut observers, problem) = driver.into_parts();
        let a = self.settings.arc_length;
        let left = a.max_points.saturating_sub(first.points.len());
        let guess = self.guess_at_end.take();
        let done = matches!(
            first.stop,
            StopReason::EndReached | StopReason::PointCap { .. } | StopReason::Interrupted { .. }
        ) || left == 0;
        let Some(guess) = guess.filter(|_| !done) else {
            observers.finished(&first);
            return Phase::Done(first);
        };
        tracing::info!(
            "the sweep from {:.4} Hz stopped after {} points ({}): following the branch back from {:.4} Hz",
            hertz(a.start),
            first.points.len(),
            first.stop,
            hertz(a.end),
        );
        let mut trail = JoinTrail::new(
            first
                .points
                .iter()
                .map(|p| scaling.scaled(&p.unknowns, p.omega))
                .collect(),
            self.settings.join,
        );
        let back = Settings {
            arc_length: ArcLengthSettings {
                start: a.end,
                end: a.start,
                max_points: left,
                ..a
            },
            ..self.settings
        };
        let driver = match Continuation::new(problem, guess, back) {
            Ok(driver) => match &self.interrupt {
                Some(interrupt) => driver.with_interrupt(interrupt.clone()),
                None => driver,
            },
            Err(error) => {
                // Not met: the settings and the guess were checked when the
                // run was made, and the sweep back swaps the range only.
                tracing::warn!("no sweep back from the end: {error}");
                observers.finished(&first);
                return Phase::Done(first);
            }
        };
        observers.sweep_back_begins(&first);
        let observers = observers.for_sweep_back(first.points.len());
        Phase::Back {
            driver: driver
                .with_observers(observers)
                .with_meeting(Box::new(move |z, tangent| trail.meets(z, tangent))),
            first,
        }
    }
}

/// Follows the branch of `problem` from both ends (see [`BothEnds`]),
/// calling `observer` at every accepted point of either sweep. Never fails:
/// a branch that cannot start says why in its stop.
pub fn continue_from_both_ends<P: Problem>(
    problem: &mut P,
    guess_at_start: Vec<f64>,
    guess_at_end: Vec<f64>,
    settings: &ArcLengthSettings,
    observer: impl FnMut(&super::Point, &super::Progress),
) -> Branch {
    match BothEnds::new(
        problem,
        guess_at_start,
        guess_at_end,
        Settings::from(*settings),
    ) {
        Ok(run) => run.with_observer(super::ProgressFn(observer)).finish(),
        Err(error) => Branch::refused(settings.start, &error),
    }
}

/// The branch from the start to the end frequency made of the two sweeps:
/// the first up to where the second met it, then the second reversed; the
/// events of the points kept, renumbered along the branch.
fn join(first: Branch, second: Branch) -> Branch {
    let total_iterations = first.total_iterations + second.total_iterations;
    let from_start_points = first.points.len();
    let from_end_points = second.points.len();
    let (kept, from_end, stop) = match second.stop {
        StopReason::MetOtherSweep { point, .. } => {
            (point + 1, second.stop.clone(), StopReason::EndReached)
        }
        StopReason::EndReached => (0, StopReason::EndReached, StopReason::EndReached),
        // Stopped from outside: the branch says so, not why the first stopped.
        StopReason::Interrupted { .. } => {
            (from_start_points, second.stop.clone(), second.stop.clone())
        }
        _ => (from_start_points, second.stop.clone(), first.stop.clone()),
    };
    let mut events: Vec<Event> = first
        .events
        .into_iter()
        .filter(|e| e.index < kept || (matches!(e.kind, EventKind::Stop(_)) && e.index <= kept))
        .collect();
    events.extend(
        second
            .events
            .iter()
            .rev()
            .map(|e| e.reversed(from_end_points, kept)),
    );
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
        events,
    }
}

/// The first sweep's points (scaled), and the sweep back's run of points
/// on it so far.
struct JoinTrail {
    points: Vec<Vec<f64>>,
    /// Segment lengths.
    lengths: Vec<f64>,
    /// The segment the last point of the sweep back lay on, and how many
    /// points in a row did.
    run: Option<(usize, usize)>,
    settings: JoinSettings,
}

impl JoinTrail {
    fn new(points: Vec<Vec<f64>>, settings: JoinSettings) -> Self {
        let lengths = points
            .windows(2)
            .map(|pair| distance(&pair[1], &pair[0]))
            .collect();
        Self {
            points,
            lengths,
            run: None,
            settings,
        }
    }

    /// The segment of the first sweep where the sweep back, at `z` going
    /// along `tangent`, has joined it: the last `confirmations` points lay
    /// on it, each on the same segment or an earlier one.
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
            .filter(|&(_, count)| count >= self.settings.confirmations)
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
            let reach = self.settings.distance * length;
            // The frequency alone rules out most segments.
            let (low, high) = if pair[0][last] <= pair[1][last] {
                (pair[0][last], pair[1][last])
            } else {
                (pair[1][last], pair[0][last])
            };
            if z[last] < low - reach || z[last] > high + reach {
                continue;
            }
            let (a, b) = (pair[0].iter().copied(), pair[1].iter().copied());
            let (distance, _) = segment_distance(z, a, b);
            if distance > reach || best.is_some_and(|(_, ratio)| ratio <= distance / length) {
                continue;
            }
            if segment_cosine(&pair[0], &pair[1], length, tangent) <= -self.settings.cosine {
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

    fn line(count: usize) -> JoinTrail {
        // Points along the diagonal (x, ω) = (i, i) / count.
        JoinTrail::new(
            (0..count)
                .map(|i| vec![i as f64 / count as f64, i as f64 / count as f64])
                .collect(),
            JoinSettings::default(),
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
