//! The continuation driver: a branch followed one converged point at a
//! time (argmin's state + `next`, BifurcationKit's `iterate`).
//!
//! A step predicts along the tangent, corrects on the plane through the
//! prediction, and judges the result: refused if it turns too far for the
//! policy, reverses the orientation (smooth residuals, unless short or
//! continuous through the reversal: a branch point), goes back along the
//! trail (nonsmooth residuals) or lands on an old sheet; a refused step lets the policy look for another way
//! (a kink, a leap), and failing that is shrunk. The branch stops at the
//! end frequency (solved there exactly), past its start frequency (it
//! would go on toward ω ≤ 0), at a point it has passed before (a closed
//! loop), at the cap on points, or when the step underflows.

mod attempt;
mod crossing;
mod place;

use super::corrector::Corrector;
use super::events::Event;
use super::geometry::Scaling;
use super::guards::{OldSheets, Trail};
use super::interrupt::Interrupt;
use super::linear::LinearSolver;
use super::observer::{Observer, Observers, ProgressFn, State};
use super::policy::{self, Policy, PolicyKind};
use super::settings::{ArcLengthSettings, Settings, SettingsError};
use super::step_control::StepControl;
use super::structured::KrylovSolver;
use super::workspace::Workspace;
use super::{hertz, Branch, Point, Problem, StopReason};

/// What a step of the driver gave.
#[derive(Debug)]
pub enum Step<'d> {
    /// The next converged point of the branch.
    Point(&'d Point),
    /// The branch has stopped (on this and every later call).
    Stopped(&'d StopReason),
}

impl<'d> Step<'d> {
    /// The point of `index` in `points`, or, for `None`, the stop (set by
    /// then: a driver advances to `None` only once stopped).
    pub(crate) fn of(
        index: Option<usize>,
        points: &'d [Point],
        stop: &'d Option<StopReason>,
    ) -> Self {
        match (index, stop) {
            (Some(index), _) => Step::Point(&points[index]),
            (None, Some(stop)) => Step::Stopped(stop),
            (None, None) => unreachable!("a driver advances to None only once stopped"),
        }
    }
}

/// Checks that a guess has the problem's number of unknowns.
pub(crate) fn check_guess(expected: usize, guess: &[f64]) -> Result<(), ContinuationError> {
    if guess.len() == expected {
        Ok(())
    } else {
        Err(ContinuationError::GuessLength {
            expected,
            got: guess.len(),
        })
    }
}

/// Why a driver could not be built.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum ContinuationError {
    /// A setting cannot be used.
    #[error(transparent)]
    Settings(#[from] SettingsError),
    /// The guess does not have the problem's number of unknowns.
    #[error("the guess has {got} unknowns, the problem {expected}")]
    GuessLength {
        /// The problem's unknowns.
        expected: usize,
        /// The guess's.
        got: usize,
    },
}

/// Where the branch is, once its first point is found.
struct Running<P: Problem> {
    policy: Box<dyn Policy<P>>,
    /// The last point, scaled.
    z: Vec<f64>,
    /// The unit tangent there, along the way travelled.
    tangent: Vec<f64>,
    /// The sign of `det [J; tᵀ]` there.
    orientation: f64,
    control: StepControl,
    trail: Trail,
    sheets: OldSheets,
}

/// Asked at every accepted point, in scaled unknowns with the unit tangent
/// there: the index of a point of another branch that this one has joined.
pub(crate) type Meeting<'a> = Box<dyn FnMut(&[f64], &[f64]) -> Option<usize> + 'a>;

/// Pseudo-arc-length continuation of one branch, step by step:
///
/// ```
/// # use cyclorub::continuation::*;
/// # use faer::Mat;
/// # struct Circle;
/// # #[derive(Debug, thiserror::Error)] #[error("never")] struct Never;
/// # impl Problem for Circle {
/// #     type Error = Never;
/// #     fn unknowns(&self) -> usize { 1 }
/// #     fn force_scale(&self) -> f64 { 1.0 }
/// #     fn is_smooth(&self) -> bool { true }
/// #     fn evaluate(&mut self, x: &[f64], w: f64, _: bool, out: &mut Evaluation) -> Result<(), Never> {
/// #         out.residual = vec![x[0] * x[0] + (w - 2.0).powi(2) - 1.0];
/// #         out.jacobian = Mat::from_fn(1, 1, |_, _| 2.0 * x[0]);
/// #         out.derivative_omega = vec![2.0 * (w - 2.0)];
/// #         Ok(())
/// #     }
/// # }
/// let arc_length = ArcLengthSettings {
///     start: 1.5, end: 10.0, initial_step: 0.01, min_step: 1e-9, max_step: 0.05,
///     length_scale: 1.0, max_points: 1000,
///     newton: NewtonSettings { tolerance: 1e-12, max_iterations: 20, ..Default::default() },
/// };
/// let mut problem = Circle;
/// let mut driver = Continuation::new(&mut problem, vec![0.8], arc_length.into())?;
/// while let Step::Point(point) = driver.step() {
///     assert!(point.omega > 0.0);
/// }
/// let branch = driver.finish();
/// assert!(matches!(branch.stop, StopReason::LeftRange { .. }));
/// assert!(branch.events.iter().any(|e| e.kind == EventKind::Fold));
/// # Ok::<(), ContinuationError>(())
/// ```
pub struct Continuation<'a, P: Problem> {
    work: Workspace<'a, P>,
    settings: Settings,
    corrector: Corrector,
    /// +1 going up in frequency, −1 going down.
    direction: f64,
    guess: Option<Vec<f64>>,
    running: Option<Running<P>>,
    points: Vec<Point>,
    events: Vec<Event>,
    total_iterations: usize,
    stop: Option<StopReason>,
    /// The stop due after the point just given.
    pending: Option<StopReason>,
    observers: Observers<'a>,
    meeting: Option<Meeting<'a>>,
    interrupt: Option<Interrupt>,
    /// A first point given instead of solved at the start frequency: its
    /// frequency and the point the branch leaves it away from.
    given_start: Option<GivenStart>,
}

/// A first point given (a point off a branch point): its frequency, and
/// the point the first tangent is oriented away from.
struct GivenStart {
    omega: f64,
    away_from: (Vec<f64>, f64),
}

impl<'a, P: Problem> Continuation<'a, P> {
    /// A driver that follows the branch of `problem` from `guess` (an
    /// approximate solution at the start frequency) with `settings`, solving
    /// with dense LU. Nothing is computed until the first step.
    pub fn new(
        problem: &'a mut P,
        guess: Vec<f64>,
        settings: Settings,
    ) -> Result<Self, ContinuationError> {
        settings.validate()?;
        check_guess(problem.unknowns(), &guess)?;
        let scaling = Scaling::new(problem, &settings);
        let a = &settings.arc_length;
        Ok(Self {
            work: Workspace::new(problem, scaling, Box::new(KrylovSolver::default())),
            corrector: Corrector {
                newton: a.newton,
                line_search: settings.corrector,
            },
            direction: if a.end >= a.start { 1.0 } else { -1.0 },
            settings,
            guess: Some(guess),
            running: None,
            points: Vec::new(),
            events: Vec::new(),
            total_iterations: 0,
            stop: None,
            pending: None,
            observers: Observers::new(),
            meeting: None,
            interrupt: None,
            given_start: None,
        })
    }

    /// A driver that follows the branch of `problem` through the solution
    /// `x` at `omega` (inside the settings' range, Newton-polished there),
    /// its first tangent oriented away from the point `away_from`
    /// (`(unknowns, omega)`): how a branch is entered off a branch point
    /// (the point on the branch just off it, and the branch point), where
    /// the frequency alone cannot tell which way to go. The range's ends
    /// still stop it (leaving below `start` or reaching `end`).
    pub fn from_point(
        problem: &'a mut P,
        x: Vec<f64>,
        omega: f64,
        away_from: (Vec<f64>, f64),
        settings: Settings,
    ) -> Result<Self, ContinuationError> {
        check_guess(problem.unknowns(), &away_from.0)?;
        let mut driver = Self::new(problem, x, settings)?;
        driver.given_start = Some(GivenStart { omega, away_from });
        Ok(driver)
    }

    /// Attaches an observer (see [`Observer`]).
    pub fn with_observer(mut self, observer: impl Observer + 'a) -> Self {
        self.observers.push(Box::new(observer));
        self
    }

    /// Stops before the next point once `interrupt` is raised, and gives up
    /// the point being computed before its next evaluation.
    pub fn with_interrupt(mut self, interrupt: Interrupt) -> Self {
        self.work.set_interrupt(interrupt.clone());
        self.interrupt = Some(interrupt);
        self
    }

    /// Solves the bordered systems with `solver` instead of dense LU.
    pub fn with_linear_solver(mut self, solver: impl LinearSolver + 'a) -> Self {
        self.work.solver = Box::new(solver);
        self
    }

    /// The observers, replacing the driver's.
    pub(crate) fn with_observers(mut self, observers: Observers<'a>) -> Self {
        self.observers = observers;
        self
    }

    /// Stops the branch where `meeting` says it joined another.
    pub(crate) fn with_meeting(mut self, meeting: Meeting<'a>) -> Self {
        self.meeting = Some(meeting);
        self
    }

    /// The settings.
    pub fn settings(&self) -> &Settings {
        &self.settings
    }

    /// The points so far.
    pub fn points(&self) -> &[Point] {
        &self.points
    }

    /// The events so far.
    pub fn events(&self) -> &[Event] {
        &self.events
    }

    /// Why the branch stopped, once it has.
    pub fn stop(&self) -> Option<&StopReason> {
        self.stop.as_ref()
    }

    /// Newton iterations so far, failed attempts included.
    pub fn total_iterations(&self) -> usize {
        self.total_iterations
    }

    /// The policy following the branch (known from the first point on).
    pub fn policy(&self) -> Option<PolicyKind> {
        self.running.as_ref().map(|r| r.policy.kind())
    }

    /// The step the next attempt will try (scaled arc length), once the
    /// first point is found.
    pub fn step_length(&self) -> Option<f64> {
        self.running.as_ref().map(|r| r.control.step())
    }

    /// The scaling of the unknowns.
    pub(crate) fn scaling(&self) -> &Scaling {
        &self.work.scaling
    }

    /// Advances to the next converged point, or to the stop.
    pub fn step(&mut self) -> Step<'_> {
        let index = self.advance();
        Step::of(index, &self.points, &self.stop)
    }

    /// Runs the remaining steps (none once stopped) and returns the branch;
    /// observers are told it is finished.
    pub fn finish(self) -> Branch {
        let (branch, mut observers) = self.into_sweep();
        observers.finished(&branch);
        branch
    }

    /// Runs the remaining steps and returns the branch and the observers,
    /// without telling them it is finished (a sweep of a longer run).
    pub(crate) fn into_sweep(self) -> (Branch, Observers<'a>) {
        let (branch, observers, _) = self.into_parts();
        (branch, observers)
    }

    /// [`Self::into_sweep`], and the problem back for another sweep.
    pub(crate) fn into_parts(mut self) -> (Branch, Observers<'a>, &'a mut P) {
        while self.advance().is_some() {}
        let stop = self.stop.expect("advance returns None only once stopped");
        let branch = Branch::sweep(self.points, stop, self.total_iterations, self.events);
        (branch, self.observers, self.work.problem)
    }

    /// The index of the next point, or `None` once stopped.
    pub(crate) fn advance(&mut self) -> Option<usize> {
        if self.stop.is_some() {
            return None;
        }
        if let Some(reason) = self.pending.take() {
            return self.halt(reason);
        }
        if self.running.is_none() {
            return match self.interrupted() {
                Some(reason) => self.halt(reason),
                None => self.start(),
            };
        }
        loop {
            if let Some(reason) = self.interrupted() {
                return self.halt(reason);
            }
            let max_points = self.settings.arc_length.max_points;
            if self.points.len() >= max_points {
                return self.halt(StopReason::PointCap { max_points });
            }
            let Some(accepted) = self.attempt() else {
                if let Some(reason) = self.interrupted() {
                    return self.halt(reason);
                }
                let running = self.running.as_mut()?;
                if !running.control.refused() {
                    let step = running.control.step();
                    let omega = self.work.scaling.unscaled(&running.z).1;
                    return self.halt(StopReason::StepUnderflow {
                        frequency_hz: hertz(omega),
                        step,
                    });
                }
                continue;
            };
            return self.accept(accepted);
        }
    }

    /// The first point, at fixed frequency, and the tangent there.
    fn start(&mut self) -> Option<usize> {
        let a = self.settings.arc_length;
        let mut x = self.guess.take()?;
        let given = self.given_start.take();
        let start = given.as_ref().map_or(a.start, |g| g.omega);
        let outcome = self.work.newton(&mut x, start, &a.newton);
        if let Some(reason) = self.interrupted() {
            return self.halt(reason);
        }
        let (converged, iterations, residual_norm) = match outcome {
            Ok(result) => result,
            Err(error) => {
                return self.halt(StopReason::EvaluationError {
                    frequency_hz: hertz(start),
                    message: error.to_string(),
                })
            }
        };
        self.total_iterations += iterations;
        if !converged {
            return self.halt(StopReason::NewtonFailure {
                frequency_hz: hertz(start),
                residual_norm,
            });
        }
        let n = x.len();
        let seed = match &given {
            Some(g) => {
                let here = self.work.scaling.scaled(&x, start);
                let there = self.work.scaling.scaled(&g.away_from.0, g.away_from.1);
                here.iter().zip(&there).map(|(a, b)| a - b).collect()
            }
            None => {
                let mut seed = vec![0.0; n + 1];
                seed[n] = self.direction;
                seed
            }
        };
        let tangent = self.work.null_vector(&seed);
        let first = Point::converged(start, x, iterations, residual_norm);
        let state = State {
            tangent: tangent.as_ref().map(|(t, _)| t.as_slice()),
            step: a.initial_step,
            evaluation: Some(&self.work.evaluation),
            sweep_back: self.observers.sweep_back(),
        };
        self.observers.point(0, &first, &state);
        self.points.push(first);
        let Some((tangent, orientation)) = tangent else {
            return self.stop_after(StopReason::EvaluationError {
                frequency_hz: hertz(start),
                message: "the tangent could not be computed (singular augmented Jacobian)".into(),
            });
        };
        let x = &self.points[0].unknowns;
        let z = self.work.scaling.scaled(x, start);
        let policy = policy::choose(self.work.problem, x, start);
        self.work.forget_evaluated();
        if policy.predicts_along_chords(&self.settings) {
            // The tangent only checks the chord and serves short steps:
            // that of the corrector's last iterate (a piece or two away)
            // does, and saves a factorization a point.
            self.work.reuse_factors_across_pieces();
        }
        let control = StepControl::new(
            a.initial_step.min(a.max_step),
            a.min_step,
            policy.largest_step(&self.settings),
            self.settings.step,
        );
        let guards = &self.settings.guards;
        let mut trail = Trail::new(&z, guards.trail);
        if let Some(piece) = self.work.piece_at(&z) {
            trail.push_piece(piece);
        }
        self.running = Some(Running {
            policy,
            sheets: OldSheets::new(self.work.scaling.clone(), guards.old_sheet),
            z,
            tangent,
            orientation,
            control,
            trail,
        });
        Some(0)
    }

    /// The stop asked for from outside, if any.
    fn interrupted(&self) -> Option<StopReason> {
        let raised = self.interrupt.as_ref().is_some_and(Interrupt::raised);
        raised.then(|| StopReason::Interrupted {
            frequency_hz: self.points.last().map(|p| hertz(p.omega)),
        })
    }

    /// Records events and tells the observers.
    fn record(&mut self, found: Vec<Event>) {
        for event in found {
            self.observers.event(&event);
            self.events.push(event);
        }
    }

    /// The point just placed is the last: the branch stops for `reason` at
    /// the next call.
    fn stop_after(&mut self, reason: StopReason) -> Option<usize> {
        self.pending = Some(reason);
        self.points.len().checked_sub(1)
    }

    /// Stops the branch for `reason` (recorded as an event).
    fn halt(&mut self, reason: StopReason) -> Option<usize> {
        let last = self.points.last().map(|p| p.omega);
        self.record(vec![Event::stop(&reason, self.points.len(), last)]);
        self.stop = Some(reason);
        None
    }
}

impl<P: Problem> Iterator for Continuation<'_, P> {
    type Item = Point;

    /// The next converged point (a copy), `None` once stopped.
    fn next(&mut self) -> Option<Point> {
        let index = self.advance()?;
        Some(self.points[index].clone())
    }
}

/// Continues from `guess` (an approximate solution at `settings.start`) to
/// `settings.end` with the default tuning (see [`Continuation`]), calling
/// `observer` on each accepted point. Never fails: the branch holds every
/// point computed and says why it stopped.
pub fn continue_branch<P: Problem>(
    problem: &mut P,
    guess: Vec<f64>,
    settings: &ArcLengthSettings,
    observer: impl FnMut(&Point, &super::Progress),
) -> Branch {
    match Continuation::new(problem, guess, Settings::from(*settings)) {
        Ok(driver) => driver.with_observer(ProgressFn(observer)).finish(),
        Err(error) => Branch::refused(settings.start, &error),
    }
}
