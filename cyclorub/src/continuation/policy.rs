//! How a branch is followed depends on how smooth its residual is; each
//! kind has its policy:
//!
//! - [`Smooth`] ([`Problem::is_smooth`], e.g. R-HBM with `γ > 0`): every
//!   turn resolves with a short enough step, so a step is refused when it
//!   turns the tangent by more than 11° or the corrector moves by more than
//!   a tenth of the step, and halved until it passes: every fold is
//!   resolved however sharp, and the corrector cannot reach another sheet
//!   close by. A step is also refused when it reverses the branch's
//!   orientation (`sign det [J; tᵀ]`, kept along a branch through its
//!   folds) unless it is far shorter than the last easy one, or the
//!   branch goes on continuously through the reversal (bisected: see
//!   `driver::crossing`): such a step crosses a branch point (an event);
//!   the others went back along the branch or onto a close sheet that
//!   turns the tangent too little to be seen otherwise.
//! - [`Piecewise`] ([`Problem::piece`] tells the smooth pieces, e.g.
//!   DLFT-HBM, whose contact state changes one sampled instant at a time):
//!   the same tight limits, which follow the branch through its folds
//!   (near a fold tip the other sheet is as close as the step), and a
//!   capped step. Once a short step fails, or the step has collapsed far
//!   below the last easy one, the kink ahead is located by bisection and
//!   turned exactly, the way that keeps the orientation (which a regular
//!   branch keeps through kinks as through smooth folds). Turning kinks
//!   while steps are long chose the wrong way at nearly coincident folds
//!   (and so did turning one as soon as a halved step turned as far
//!   again). Past a kink the step resumes near the last easy one (see
//!   `StepSettings::after_kink`). With the secant predictor
//!   (`PiecewisePredictor::Secant`) steps go along the last chord, up to
//!   the case's largest step, and turn between chords.
//! - [`Nonsmooth`] (kinks, no pieces, e.g. the plain penalty law): lax
//!   limits (a kink turns the tangent by a fixed angle however short the
//!   step); a kink is recognized when a step that turned too far turns as
//!   far again at half the step, or when the step has been halved well
//!   below the last easy one, and the way on is the side where the
//!   residual stays small; a step back onto the recent trail is refused;
//!   and when the step has shrunk far below the last easy one, longer steps
//!   along the tangent pass over small nonsmooth structures.
//!
//! On every residual, a step that lands on a sheet travelled long before is
//! refused (see `guards`), and a kink step whose told way lands there tries
//! the other way.

use super::kinks::{leap, nonsmooth_way, piecewise_way, turn};
use super::settings::{PiecewisePredictor, Settings, TurnLimits};
use super::steps::{Accepted, Around, Refused};
use super::workspace::Workspace;
use super::Problem;
use serde::Serialize;

/// Which policy follows a branch.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum PolicyKind {
    /// A smooth residual: tight turn limits, orientation kept.
    Smooth,
    /// A residual that tells its smooth pieces: tight limits, kinks
    /// located and turned exactly.
    Piecewise,
    /// A residual with kinks and no pieces: lax limits, corners guessed,
    /// leaps.
    Nonsmooth,
}

/// A policy: the limits of an ordinary step and the ways on when one is
/// refused (see the module's header).
pub(crate) trait Policy<P: Problem> {
    /// Which one.
    fn kind(&self) -> PolicyKind;
    /// The largest step.
    fn largest_step(&self, settings: &Settings) -> f64 {
        settings.arc_length.max_step
    }
    /// How far a step may turn.
    fn turn_limits(&self, settings: &Settings) -> TurnLimits {
        settings.guards.tight
    }
    /// Whether the orientation is kept along the branch: a long step that
    /// reverses it is refused, a short one crosses a branch point.
    fn keeps_orientation(&self) -> bool {
        false
    }
    /// Whether a step back along the recent trail is refused.
    fn refuses_retrace(&self) -> bool {
        false
    }
    /// Whether the residual tells its pieces (recorded along the trail).
    fn tells_pieces(&self) -> bool {
        false
    }
    /// Whether steps are predicted along the last chord when it serves
    /// (else along the tangent), and their turn measured between chords
    /// (see [`PiecewisePredictor::Secant`]).
    fn predicts_along_chords(&self, settings: &Settings) -> bool {
        let _ = settings;
        false
    }
    /// After a refused step: another way on, if any, and the corrector
    /// iterations spent looking for it. None by default: the step is
    /// shortened.
    fn recover(
        &mut self,
        work: &mut Workspace<'_, P>,
        around: &Around<'_>,
        refused: &Refused,
    ) -> (Option<Accepted>, usize) {
        let _ = (work, around, refused);
        (None, 0)
    }
    /// A step was accepted.
    fn accepted(&mut self) {}
}

/// The policy for `problem`, whose first point is `(x, ω)`: piecewise if
/// it tells a piece there, else smooth if it says so, else nonsmooth.
pub(crate) fn choose<P: Problem>(problem: &mut P, x: &[f64], omega: f64) -> Box<dyn Policy<P>> {
    if matches!(problem.piece(x, omega), Ok(Some(_))) {
        Box::new(Piecewise)
    } else if problem.is_smooth() {
        Box::new(Smooth)
    } else {
        Box::new(Nonsmooth { last_turn: None })
    }
}

/// The first trial steps past a kink: `first` divided by each divisor.
fn trial_steps(first: f64, settings: &Settings) -> [f64; 3] {
    settings.kinks.trial_divisors.map(|d| first / d)
}

/// A smooth residual.
pub(crate) struct Smooth;

impl<P: Problem> Policy<P> for Smooth {
    fn kind(&self) -> PolicyKind {
        PolicyKind::Smooth
    }
    fn keeps_orientation(&self) -> bool {
        true
    }
}

/// A residual that tells its pieces.
pub(crate) struct Piecewise;

impl<P: Problem> Policy<P> for Piecewise {
    fn kind(&self) -> PolicyKind {
        PolicyKind::Piecewise
    }
    fn largest_step(&self, settings: &Settings) -> f64 {
        match settings.step.piecewise_predictor {
            PiecewisePredictor::Tangent => settings
                .arc_length
                .max_step
                .min(settings.step.piecewise_max_step),
            PiecewisePredictor::Secant => settings.arc_length.max_step,
        }
    }
    fn tells_pieces(&self) -> bool {
        true
    }
    fn predicts_along_chords(&self, settings: &Settings) -> bool {
        settings.step.piecewise_predictor == PiecewisePredictor::Secant
    }
    /// A short refused step, or one collapsed far below the last easy one,
    /// has met a kink: it is located and turned.
    fn recover(
        &mut self,
        work: &mut Workspace<'_, P>,
        around: &Around<'_>,
        refused: &Refused,
    ) -> (Option<Accepted>, usize) {
        let kinks = &around.settings.kinks;
        let step = refused.step;
        if !(step <= kinks.piecewise_fine_step
            || step <= kinks.piecewise_cascade * refused.good_step)
        {
            return (None, 0);
        }
        let steps = trial_steps(step, around.settings);
        match piecewise_way(work, around, step, &steps) {
            Some(way) => turn(work, around, way, &steps),
            None => (None, 0),
        }
    }
}

/// A residual with kinks that does not tell its pieces.
pub(crate) struct Nonsmooth {
    /// The turn of the last step refused for turning since the last
    /// accepted one.
    last_turn: Option<f64>,
}

impl<P: Problem> Policy<P> for Nonsmooth {
    fn kind(&self) -> PolicyKind {
        PolicyKind::Nonsmooth
    }
    fn turn_limits(&self, settings: &Settings) -> TurnLimits {
        settings.guards.lax
    }
    fn refuses_retrace(&self) -> bool {
        true
    }
    /// A corner (a step refused for turning, refused again at half the
    /// step with most of the turn: a smooth turn halves with the step), or
    /// a step collapsed below the last easy one, is a kink: turned from
    /// here toward the side where the residual stays small. Failing that,
    /// and once the step has collapsed further, a leap.
    fn recover(
        &mut self,
        work: &mut Workspace<'_, P>,
        around: &Around<'_>,
        refused: &Refused,
    ) -> (Option<Accepted>, usize) {
        let kinks = &around.settings.kinks;
        let (step, good_step) = (refused.step, refused.good_step);
        let corner = refused.turning_too_fast
            && matches!((refused.turn, self.last_turn), (Some(t), Some(previous)) if t >= kinks.corner_persistence * previous);
        if refused.turning_too_fast {
            self.last_turn = refused.turn;
        }
        let mut outcome = None;
        let mut spent_on_kink = 0;
        if corner || step <= kinks.cascade * good_step {
            let first = step.max(kinks.cascade * good_step);
            if let Some(way) = nonsmooth_way(work, around, step) {
                let steps = trial_steps(first, around.settings);
                (outcome, spent_on_kink) = turn(work, around, way, &steps);
            }
        }
        let mut spent_on_leap = 0;
        if outcome.is_none() && (spent_on_kink > 0 || step <= kinks.leap_cascade * good_step) {
            // Creeping: leap over the small nonsmooth structure ahead.
            let steps = kinks.leap_multiples.map(|m| m * good_step);
            (outcome, spent_on_leap) = leap(work, around, &steps);
        }
        (outcome, spent_on_kink + spent_on_leap)
    }
    fn accepted(&mut self) {
        self.last_turn = None;
    }
}
