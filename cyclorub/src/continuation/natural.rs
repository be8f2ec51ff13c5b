//! Natural continuation over a list of frequencies: each solved from the
//! previous converged one, with a tangent predictor `dx/dω = −J⁻¹ ∂R/∂ω`,
//! the frequency step subdivided internally when Newton fails.

use super::driver::{check_guess, ContinuationError, Step};
use super::events::Event;
use super::interrupt::Interrupt;
use super::newton::{newton_until, NewtonSettings};
use super::observer::{Observer, Observers, State};
use super::structured::solve_structured;
use super::{hertz, Branch, Evaluation, Point, Problem, Progress, StopReason};
use faer::linalg::solvers::Solve;
use faer::Mat;

/// Settings of a fixed-frequency run.
#[derive(Clone, Copy, Debug)]
pub struct AtFrequenciesSettings {
    /// Newton at each frequency.
    pub newton: NewtonSettings,
    /// Halvings of the step from the last converged frequency tried before
    /// a point is declared failed. 10: down to 1/1024 of the step between
    /// two frequencies asked for.
    pub max_halvings: usize,
}

impl From<NewtonSettings> for AtFrequenciesSettings {
    fn from(newton: NewtonSettings) -> Self {
        Self {
            newton,
            max_halvings: 10,
        }
    }
}

/// `dx/dω = −J⁻¹ ∂R/∂ω` from an evaluation with its Jacobian.
fn frequency_derivative(evaluation: &Evaluation) -> Option<Vec<f64>> {
    let n = evaluation.residual.len();
    let negative: Vec<f64> = evaluation.derivative_omega.iter().map(|d| -d).collect();
    let d = solve_structured(evaluation, &negative).unwrap_or_else(|| {
        let rhs = Mat::from_fn(n, 1, |r, _| negative[r]);
        let d = evaluation.jacobian.partial_piv_lu().solve(&rhs);
        (0..n).map(|r| d[(r, 0)]).collect()
    });
    d.iter().all(|v| v.is_finite()).then_some(d)
}

/// Natural continuation from the converged `(x, from)` to `to`: tangent
/// predictor and Newton, the step halved (up to `max_halvings` times) when
/// Newton fails. Returns (converged, iterations, residual, x at `to`).
fn advance<P: Problem>(
    problem: &mut P,
    (x, from): (&[f64], f64),
    to: f64,
    settings: &AtFrequenciesSettings,
    evaluation: &mut Evaluation,
    interrupt: Option<&Interrupt>,
) -> Result<(bool, usize, f64, Vec<f64>), P::Error> {
    #[allow(clippy::float_cmp)] // the same frequency listed twice
    if from == to {
        // Nothing to step: Newton at `to` from `x` measures its residual
        // (converged at once), rather than none.
        let mut guess = x.to_vec();
        let (converged, iterations, residual) = newton_until(
            problem,
            &mut guess,
            to,
            &settings.newton,
            evaluation,
            interrupt,
        )?;
        return Ok((converged, iterations, residual, guess));
    }
    let mut current = x.to_vec();
    let mut omega = from;
    let mut step = to - omega;
    let mut total = 0;
    let mut halvings = 0;
    let mut last_residual = f64::INFINITY;
    #[allow(clippy::float_cmp)] // the loop ends exactly on the target
    while omega != to {
        let target = if (omega + step - to) * (to - from).signum() >= 0.0 {
            to
        } else {
            omega + step
        };
        problem.evaluate(&current, omega, true, evaluation)?;
        let mut guess = current.clone();
        if let Some(derivative) = frequency_derivative(evaluation) {
            for (g, d) in guess.iter_mut().zip(&derivative) {
                *g += (target - omega) * d;
            }
        }
        let (converged, iterations, residual) = newton_until(
            problem,
            &mut guess,
            target,
            &settings.newton,
            evaluation,
            interrupt,
        )?;
        total += iterations;
        last_residual = residual;
        if interrupt.is_some_and(Interrupt::raised) {
            return Ok((false, total, last_residual, guess));
        }
        if converged {
            current = guess;
            omega = target;
        } else {
            halvings += 1;
            if halvings > settings.max_halvings {
                return Ok((false, total, last_residual, guess));
            }
            step = (target - omega) * 0.5;
        }
    }
    Ok((true, total, last_residual, current))
}

/// Solves at each frequency of a list in turn, step by step like
/// [`Continuation`](super::Continuation). The first from the start guess by
/// plain Newton, each next from the last converged one. A point that does
/// not converge is kept, marked `converged = false`, and the next starts
/// from the last converged one.
pub struct AtFrequencies<'a, P: Problem> {
    problem: &'a mut P,
    start: Vec<f64>,
    omegas: Vec<f64>,
    settings: AtFrequenciesSettings,
    evaluation: Evaluation,
    /// The last converged point.
    last: Option<(Vec<f64>, f64)>,
    points: Vec<Point>,
    events: Vec<Event>,
    total_iterations: usize,
    stop: Option<StopReason>,
    observers: Observers<'a>,
    interrupt: Option<Interrupt>,
}

impl<'a, P: Problem> AtFrequencies<'a, P> {
    /// A run of `problem` at `omegas` (rad/s) from `start` (an approximate
    /// solution at the first).
    pub fn new(
        problem: &'a mut P,
        start: Vec<f64>,
        omegas: &[f64],
        settings: AtFrequenciesSettings,
    ) -> Result<Self, ContinuationError> {
        check_guess(problem.unknowns(), &start)?;
        Ok(Self {
            problem,
            start,
            omegas: omegas.to_vec(),
            settings,
            evaluation: Evaluation::default(),
            last: None,
            points: Vec::new(),
            events: Vec::new(),
            total_iterations: 0,
            stop: None,
            observers: Observers::new(),
            interrupt: None,
        })
    }

    /// Attaches an observer (see [`Observer`]).
    pub fn with_observer(mut self, observer: impl Observer + 'a) -> Self {
        self.observers.push(Box::new(observer));
        self
    }

    /// Stops before the next frequency once `interrupt` is raised.
    pub fn with_interrupt(mut self, interrupt: Interrupt) -> Self {
        self.interrupt = Some(interrupt);
        self
    }

    /// Solves at the next frequency (the point may not have converged), or
    /// gives the stop.
    pub fn step(&mut self) -> Step<'_> {
        let index = self.advance();
        Step::of(index, &self.points, &self.stop)
    }

    /// Runs the remaining frequencies and returns the branch; observers are
    /// told it is finished.
    pub fn finish(mut self) -> Branch {
        while self.advance().is_some() {}
        let stop = self.stop.expect("advance returns None only once stopped");
        let branch = Branch::sweep(self.points, stop, self.total_iterations, self.events);
        self.observers.finished(&branch);
        branch
    }

    fn advance(&mut self) -> Option<usize> {
        if self.stop.is_some() {
            return None;
        }
        if self.interrupt.as_ref().is_some_and(Interrupt::raised) {
            let last = self.points.last().map(|p| hertz(p.omega));
            return self.halt(StopReason::Interrupted { frequency_hz: last });
        }
        let index = self.points.len();
        let Some(&omega) = self.omegas.get(index) else {
            return self.halt(StopReason::AllFrequenciesDone);
        };
        let outcome = match &self.last {
            Some((x, from)) => advance(
                self.problem,
                (x, *from),
                omega,
                &self.settings,
                &mut self.evaluation,
                self.interrupt.as_ref(),
            ),
            None => {
                let mut x = self.start.clone();
                newton_until(
                    self.problem,
                    &mut x,
                    omega,
                    &self.settings.newton,
                    &mut self.evaluation,
                    self.interrupt.as_ref(),
                )
                .map(|(c, i, r)| (c, i, r, x))
            }
        };
        // Stopped from outside during the point: it is not kept.
        if self.interrupt.as_ref().is_some_and(Interrupt::raised) {
            let last = self.points.last().map(|p| hertz(p.omega));
            return self.halt(StopReason::Interrupted { frequency_hz: last });
        }
        match outcome {
            Ok((converged, iterations, residual_norm, x)) => {
                self.total_iterations += iterations;
                let point = Point {
                    converged,
                    ..Point::converged(omega, x.clone(), iterations, residual_norm)
                };
                let state = State {
                    tangent: None,
                    step: 0.0,
                    evaluation: converged.then_some(&self.evaluation),
                    sweep_back: false,
                };
                self.observers.point(index, &point, &state);
                self.points.push(point);
                if converged {
                    self.last = Some((x, omega));
                }
                Some(index)
            }
            Err(error) => self.halt(StopReason::EvaluationError {
                frequency_hz: hertz(omega),
                message: error.to_string(),
            }),
        }
    }

    fn halt(&mut self, reason: StopReason) -> Option<usize> {
        let last = self.points.last().map(|p| p.omega);
        let event = Event::stop(&reason, self.points.len(), last);
        self.observers.event(&event);
        self.events.push(event);
        self.stop = Some(reason);
        None
    }
}

/// Solves at each frequency in turn (rad/s), each from the previous
/// converged solution (the first from `start` by plain Newton): see
/// [`AtFrequencies`]. Never fails: the branch says why it stopped.
pub fn solve_at_frequencies<P: Problem>(
    problem: &mut P,
    start: Vec<f64>,
    omegas: &[f64],
    settings: &NewtonSettings,
    observer: impl FnMut(&Point, &Progress),
) -> Branch {
    let first = omegas.first().copied().unwrap_or(0.0);
    match AtFrequencies::new(problem, start, omegas, (*settings).into()) {
        Ok(run) => run.with_observer(super::ProgressFn(observer)).finish(),
        Err(error) => Branch::refused(first, &error),
    }
}
