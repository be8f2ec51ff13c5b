//! Natural continuation over a list of frequencies: each solved from the
//! previous converged one, with a tangent predictor `dx/dω = −J⁻¹ ∂R/∂ω`,
//! the frequency step subdivided internally when Newton fails.
//!
//! A sheet of the response can end between two frequencies (a fold: the
//! plateau of a rubbing wheel ends, a mistuned wheel's sectors leave the
//! casing one by one). No frequency step passes it, however small: Newton
//! is drawn to the fold, where the residual's norm has a local minimum.
//! With [`AtFrequenciesSettings::bridge`] the branch is followed in arc
//! length from the last point reached as soon as Newton fails from it
//! (no halvings first: the arc length adapts its own step, through a
//! contact's onset as through a fold), through the fold and back if there
//! is one, until it crosses the frequency asked for (what a slow sweep
//! does when it jumps, the jump followed on the branch itself rather than
//! guessed).
//! Where the branch through the fold does not come back (it leaves the
//! frequencies asked for behind it, or reaches its cap of points), Newton
//! starts again at the frequency asked for from the problem's
//! [`Problem::fresh_guess`] (a harmonic balance's linear response, or its
//! continuation in the load where Newton does not converge from that): a
//! jump to whatever solution that finds, said in the log.

use super::bridge::bridge;
use super::driver::{check_guess, ContinuationError, Step};
use super::events::Event;
use super::interrupt::Interrupt;
use super::newton::{newton_until, NewtonSettings};
use super::observer::{Observer, Observers, State};
use super::settings::ArcLengthSettings;
use super::structured::solve_structured;
use super::swept_path::SweptPath;
use super::{hertz, Branch, Evaluation, Point, Problem, Progress, StopReason};
use faer::linalg::solvers::Solve;
use faer::Mat;

/// Settings of a fixed-frequency run.
#[derive(Clone, Copy, Debug)]
pub struct AtFrequenciesSettings {
    /// Newton at each frequency.
    pub newton: NewtonSettings,
    /// Halvings of the step from the last converged frequency tried before
    /// a point is declared failed, or before a fresh start where a bridge
    /// from that point failed. 10: down to 1/1024 of the step between two
    /// frequencies asked for.
    pub max_halvings: usize,
    /// When Newton fails from the last converged frequency (a fold or a
    /// contact's onset between two frequencies), the branch is followed in
    /// arc length with these settings from it to the frequency asked for
    /// ([`bridge`]; `start`, `end` and `max_points` are set for each
    /// bridge, and its corrector's tolerance loosened by
    /// [`bridge_tolerance`](super::bridge::bridge_tolerance): the point reached is then solved to `newton`'s),
    /// without halving the step first (on the default case
    /// mistuned at 1 %, seeds 1 and 15, 90 frequencies: the same
    /// solutions in 19 and 29 s against 23 and 44 s); where that does not
    /// reach it, Newton starts again from [`Problem::fresh_guess`].
    /// `None`: neither; the step is halved and then the point fails.
    pub bridge: Option<ArcLengthSettings>,
}

impl From<NewtonSettings> for AtFrequenciesSettings {
    fn from(newton: NewtonSettings) -> Self {
        Self {
            newton,
            max_halvings: 10,
            bridge: None,
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
/// predictor and Newton; when Newton fails, with
/// [`AtFrequenciesSettings::bridge`] the branch followed in arc length
/// within `range` (the frequencies asked for), else (or where a bridge
/// from `from` failed before) the step halved up to `max_halvings` times.
/// What it reached at `to` ([`Solved`]).
#[allow(clippy::too_many_arguments)] // the run's state, passed down
fn advance<P: Problem>(
    problem: &mut P,
    (x, from): (&[f64], f64),
    to: f64,
    range: (f64, f64),
    settings: &AtFrequenciesSettings,
    (evaluation, evaluated): (&mut Evaluation, bool),
    interrupt: Option<&Interrupt>,
    (failed_bridge, path): (&mut Option<f64>, &mut SweptPath),
) -> Result<Solved, P::Error> {
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
        return Ok(Solved::by_newton(converged, iterations, residual, guess));
    }
    let mut current = x.to_vec();
    // Whether `evaluation` holds `(current, omega)` with its Jacobians.
    let mut evaluated = evaluated;
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
        if !evaluated {
            problem.evaluate(&current, omega, true, evaluation)?;
        }
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
            return Ok(Solved::by_newton(false, total, last_residual, guess));
        }
        // Newton's last evaluation is at its last iterate.
        evaluated = converged;
        if converged {
            current = guess;
            omega = target;
        } else {
            halvings += 1;
            // A bridge from this point failed before: the next frequency
            // would follow the same branch the same way.
            #[allow(clippy::float_cmp)] // the same point, bit for bit
            let tried = *failed_bridge == Some(from);
            let bridging = settings.bridge.is_some() && !tried;
            if bridging || halvings > settings.max_halvings {
                if let (Some(arc_length), false) = (settings.bridge, tried) {
                    // Behind the last point reached: the frequency asked
                    // for before, or (no step taken) the same state a step
                    // behind.
                    #[allow(clippy::float_cmp)] // no step taken: exactly `from`
                    let behind = if omega == from {
                        (x.to_vec(), from - (to - from))
                    } else {
                        (x.to_vec(), from)
                    };
                    let bridged = bridge(
                        problem,
                        (&current, omega),
                        behind,
                        to,
                        range,
                        arc_length,
                        (interrupt, path),
                    );
                    if let Some((iterations, mut solution, travelled)) = bridged {
                        // The bridge's points are a path, solved to its own
                        // tolerance; the frequency asked for gets the run's.
                        let (converged, polish, residual) = newton_until(
                            problem,
                            &mut solution,
                            to,
                            &settings.newton,
                            evaluation,
                            interrupt,
                        )?;
                        if converged {
                            // Travelled by the sweep, up to the point at
                            // `to` (which the run adds).
                            let before_to = travelled.len().saturating_sub(1);
                            for point in &travelled[..before_to] {
                                path.push(&point.unknowns, point.omega);
                            }
                            return Ok(Solved::by_newton(
                                true,
                                total + iterations + polish,
                                residual,
                                solution,
                            ));
                        }
                        tracing::info!(
                            "{:.4} Hz: reached by the bridge, but Newton from there did not converge to the run's tolerance (residual {residual:.2e}): taken as a failed bridge",
                            hertz(to)
                        );
                    }
                    *failed_bridge = Some(from);
                }
                let steps = settings
                    .bridge
                    .filter(|_| !interrupt.is_some_and(Interrupt::raised));
                if let Some(steps) = steps {
                    let mut fresh_residual = None;
                    if let Some(mut fresh) = problem.fresh_guess(to, &steps)? {
                        let (converged, iterations, residual) = newton_until(
                            problem,
                            &mut fresh,
                            to,
                            &settings.newton,
                            evaluation,
                            interrupt,
                        )?;
                        fresh_residual = Some(residual);
                        if converged {
                            // A jump: the path travelled so far is not
                            // joined to the point found.
                            path.restart();
                            tracing::info!(
                                "{:.4} Hz: solved again from a fresh start (a jump: the branch from {:.4} Hz does not come back to it)",
                                hertz(to),
                                hertz(omega)
                            );
                            return Ok(Solved::by_newton(
                                true,
                                total + iterations,
                                residual,
                                fresh,
                            ));
                        }
                    }
                    // Said, not only counted: the point is kept unconverged.
                    tracing::info!(
                        "{:.4} Hz: not solved: Newton did not converge from {:.4} Hz (relative residual {last_residual:.2e}), the branch from there does not reach it, and {}",
                        hertz(to),
                        hertz(omega),
                        match fresh_residual {
                            Some(r) => format!(
                                "Newton from a fresh start did not converge either (relative residual {r:.2e})"
                            ),
                            None => "no fresh start was found".to_string(),
                        }
                    );
                }
                return Ok(Solved::by_newton(false, total, last_residual, guess));
            }
            step = (target - omega) * 0.5;
        }
    }
    Ok(Solved::by_newton(true, total, last_residual, current))
}

/// A frequency's outcome.
struct Solved {
    converged: bool,
    iterations: usize,
    /// `‖R‖ / force scale`.
    residual: f64,
    x: Vec<f64>,
    /// Whether the evaluation passed in holds `x` at the frequency with
    /// its Jacobians (Newton's last evaluation is at its last iterate, a
    /// bridged point's too: Newton solves it again at the end): the next
    /// frequency's tangent is taken from
    /// it without evaluating the point again.
    evaluated: bool,
}

impl Solved {
    /// Newton's outcome: its evaluation is at `x` when it converged.
    fn by_newton(converged: bool, iterations: usize, residual: f64, x: Vec<f64>) -> Self {
        Self {
            converged,
            iterations,
            residual,
            x,
            evaluated: converged,
        }
    }
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
    /// The frequency of the last converged point from which a bridge
    /// failed (not tried again from it).
    failed_bridge: Option<f64>,
    /// The points reached so far and the bridges' points: a bridge that
    /// comes back onto them has gone round a loop.
    path: SweptPath,
    /// Whether the sweep went up in frequency at its last step.
    rising: Option<bool>,
    /// Whether `evaluation` holds the last converged point, with its
    /// Jacobians (its tangent is then taken without evaluating it again).
    evaluated: bool,
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
            failed_bridge: None,
            path: SweptPath::default(),
            rising: None,
            evaluated: false,
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
        let range = self
            .omegas
            .iter()
            .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), &w| {
                (lo.min(w), hi.max(w))
            });
        // The path a bridge checks is one arc, travelled one way: a sweep
        // that turns back starts it again from its last point.
        if let Some((x, from)) = &self.last {
            let up = if omega > *from {
                Some(true)
            } else if omega < *from {
                Some(false)
            } else {
                None
            };
            if let Some(up) = up {
                if self.rising.is_some_and(|r| r != up) {
                    self.path.restart();
                    self.path.push(x, *from);
                }
                self.rising = Some(up);
            }
        }
        let outcome = match &self.last {
            Some((x, from)) => advance(
                self.problem,
                (x, *from),
                omega,
                range,
                &self.settings,
                (&mut self.evaluation, self.evaluated),
                self.interrupt.as_ref(),
                (&mut self.failed_bridge, &mut self.path),
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
                .map(|(c, i, r)| Solved::by_newton(c, i, r, x))
            }
        };
        // Stopped from outside during the point: it is not kept.
        if self.interrupt.as_ref().is_some_and(Interrupt::raised) {
            let last = self.points.last().map(|p| hertz(p.omega));
            return self.halt(StopReason::Interrupted { frequency_hz: last });
        }
        match outcome {
            Ok(Solved {
                converged,
                iterations,
                residual: residual_norm,
                x,
                evaluated,
            }) => {
                self.total_iterations += iterations;
                let point = Point {
                    converged,
                    ..Point::converged(omega, x.clone(), iterations, residual_norm)
                };
                // A point that failed left its trials in `evaluation`.
                self.evaluated = converged && evaluated;
                let state = State {
                    tangent: None,
                    step: 0.0,
                    evaluation: (converged && evaluated).then_some(&self.evaluation),
                    sweep_back: false,
                };
                self.observers.point(index, &point, &state);
                self.points.push(point);
                if converged {
                    self.path.push(&x, omega);
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
