//! Observers: whatever watches a branch go by (a progress bar, a writer
//! that streams points to disk, a stability check) is attached to the
//! driver and told of every converged point as it is accepted, of every
//! event, and of the finished branch.
//!
//! What an observer sees, in order, is every point the continuation
//! accepted, each once, numbered from 0 in the order of acceptance:
//!
//! - one sweep ([`Continuation`](super::Continuation)): the branch's points
//!   in order, the same as [`Branch::points`];
//! - both ends ([`BothEnds`](super::BothEnds)): the sweep from the start,
//!   then, if it stopped short, [`Observer::sweep_back`], then the points of
//!   the sweep back from the end frequency as they come (going *down* the
//!   branch), numbered on after the first sweep's. The joined branch given
//!   to [`Observer::finished`] keeps the first sweep's points up to where
//!   the sweeps met ([`Sweeps::from_start_kept`](super::Sweeps)) and the
//!   sweep back's reversed: an observer that keeps points must drop the
//!   first sweep's after the meeting and reverse the sweep back's, or read
//!   the order from [`Branch::sweeps`] at the end. Events are numbered like
//!   the points the observer saw; the branch's are renumbered along it.

use super::events::Event;
use super::{hertz, Branch, Evaluation, Point, Progress};

/// The driver's state at an accepted point.
#[derive(Clone, Copy, Debug)]
pub struct State<'a> {
    /// The unit tangent at the point, in scaled unknowns `[x̄; ω̄]`, along
    /// the way travelled (`None` in fixed-frequency mode and at the point
    /// solved exactly at the end frequency).
    pub tangent: Option<&'a [f64]>,
    /// The step that reached the point (scaled arc length; the first step
    /// at the first point, 0 in fixed-frequency mode).
    pub step: f64,
    /// The driver's last evaluation, when it holds one (`None` at a point
    /// kept past the end frequency): the residual at the point, and the
    /// Jacobians there or, after Newton steps, at the corrector's last
    /// iterate before it (one converged step away; the tangent is taken
    /// from their factors).
    pub evaluation: Option<&'a Evaluation>,
    /// Whether the point belongs to the sweep back from the end frequency
    /// of a both-ends run.
    pub sweep_back: bool,
}

/// Watches a branch being followed. Every method does nothing by default.
pub trait Observer {
    /// A converged point was accepted: `index` counts the points accepted
    /// before it (see the module's header for a both-ends run).
    fn point(&mut self, index: usize, point: &Point, state: &State<'_>) {
        let _ = (index, point, state);
    }
    /// An event was detected (after the point it comes before, or, for a
    /// stop, after the last point).
    fn event(&mut self, event: &Event) {
        let _ = event;
    }
    /// The sweep from the start stopped short (`first`, as it stopped) and
    /// a sweep back from the end frequency begins.
    fn sweep_back(&mut self, first: &Branch) {
        let _ = first;
    }
    /// The branch is finished, as returned to the caller.
    fn finished(&mut self, branch: &Branch) {
        let _ = branch;
    }
}

/// An observer lent to a driver: the caller keeps it and reads it after.
impl<O: Observer + ?Sized> Observer for &mut O {
    fn point(&mut self, index: usize, point: &Point, state: &State<'_>) {
        (**self).point(index, point, state);
    }
    fn event(&mut self, event: &Event) {
        (**self).event(event);
    }
    fn sweep_back(&mut self, first: &Branch) {
        (**self).sweep_back(first);
    }
    fn finished(&mut self, branch: &Branch) {
        (**self).finished(branch);
    }
}

/// A progress callback `FnMut(&Point, &Progress)` as an observer: called
/// at every accepted point.
pub struct ProgressFn<F>(pub F);

impl<F: FnMut(&Point, &Progress)> Observer for ProgressFn<F> {
    fn point(&mut self, index: usize, point: &Point, state: &State<'_>) {
        (self.0)(
            point,
            &Progress {
                points: index + 1,
                frequency_hz: hertz(point.omega),
                step: state.step,
            },
        );
    }
}

/// The observers of a driver, and the number of points they saw before it
/// (the first sweep's, for the sweep back).
pub(crate) struct Observers<'a> {
    list: Vec<Box<dyn Observer + 'a>>,
    offset: usize,
    sweep_back: bool,
}

impl<'a> Observers<'a> {
    /// No observers.
    pub(crate) fn new() -> Self {
        Self {
            list: Vec::new(),
            offset: 0,
            sweep_back: false,
        }
    }

    /// Adds one.
    pub(crate) fn push(&mut self, observer: Box<dyn Observer + 'a>) {
        self.list.push(observer);
    }

    /// The same observers for a sweep back, after `seen` points.
    pub(crate) fn for_sweep_back(self, seen: usize) -> Self {
        Self {
            offset: seen,
            sweep_back: true,
            ..self
        }
    }

    /// Whether the points belong to a sweep back.
    pub(crate) fn sweep_back(&self) -> bool {
        self.sweep_back
    }

    /// Tells every observer of the point of (local) index `index`.
    pub(crate) fn point(&mut self, index: usize, point: &Point, state: &State<'_>) {
        for observer in &mut self.list {
            observer.point(index + self.offset, point, state);
        }
    }

    /// Tells every observer of `event` (of local index).
    pub(crate) fn event(&mut self, event: &Event) {
        let seen = Event {
            index: event.index + self.offset,
            ..event.clone()
        };
        for observer in &mut self.list {
            observer.event(&seen);
        }
    }

    /// Tells every observer that the first sweep stopped short.
    pub(crate) fn sweep_back_begins(&mut self, first: &Branch) {
        for observer in &mut self.list {
            observer.sweep_back(first);
        }
    }

    /// Tells every observer the branch is finished.
    pub(crate) fn finished(&mut self, branch: &Branch) {
        for observer in &mut self.list {
            observer.finished(branch);
        }
    }
}
