//! Newton's method at fixed frequency, and natural continuation over a list
//! of frequencies.

use super::{hertz, norm, Branch, Evaluation, Point, Problem, Progress, StopReason};
use faer::linalg::solvers::Solve;
use faer::Mat;

/// Newton settings.
#[derive(Clone, Copy, Debug)]
pub struct NewtonSettings {
    /// Convergence: `‖R‖ / force scale ≤ tolerance`.
    pub tolerance: f64,
    /// Iterations before giving up.
    pub max_iterations: usize,
}

/// Newton at fixed `omega` from `x` (updated in place), with backtracking
/// on the residual norm. Returns (converged, iterations, relative residual).
pub(crate) fn newton<P: Problem>(
    problem: &mut P,
    x: &mut [f64],
    omega: f64,
    settings: &NewtonSettings,
    evaluation: &mut Evaluation,
) -> Result<(bool, usize, f64), P::Error> {
    let scale = problem.force_scale();
    let n = x.len();
    problem.evaluate(x, omega, true, evaluation)?;
    let mut residual = norm(&evaluation.residual) / scale;
    let mut trial = vec![0.0; n];
    for iteration in 0..=settings.max_iterations {
        if residual <= settings.tolerance {
            return Ok((true, iteration, residual));
        }
        if iteration == settings.max_iterations {
            break;
        }
        let rhs = Mat::from_fn(n, 1, |r, _| -evaluation.residual[r]);
        let step = evaluation.jacobian.partial_piv_lu().solve(&rhs);
        if (0..n).any(|r| !step[(r, 0)].is_finite()) {
            return Ok((false, iteration, residual));
        }
        // Backtrack (at most 6 halvings) if the full step makes things worse.
        let mut factor = 1.0;
        let mut accepted = false;
        for _ in 0..7 {
            for r in 0..n {
                trial[r] = x[r] + factor * step[(r, 0)];
            }
            problem.evaluate(&trial, omega, true, evaluation)?;
            let new_residual = norm(&evaluation.residual) / scale;
            if new_residual.is_finite() && new_residual < residual * (1.0 - 1e-4 * factor) {
                residual = new_residual;
                accepted = true;
                break;
            }
            factor *= 0.5;
        }
        x.copy_from_slice(&trial);
        if !accepted {
            problem.evaluate(x, omega, true, evaluation)?;
            residual = norm(&evaluation.residual) / scale;
        }
    }
    Ok((
        residual <= settings.tolerance,
        settings.max_iterations,
        residual,
    ))
}

/// Newton at fixed `omega` from `x` (updated in place): returns whether it
/// converged, the iterations and the relative residual `‖R‖ / force scale`.
pub fn correct<P: Problem>(
    problem: &mut P,
    x: &mut [f64],
    omega: f64,
    settings: &NewtonSettings,
) -> Result<(bool, usize, f64), P::Error> {
    newton(problem, x, omega, settings, &mut Evaluation::default())
}

/// Halvings of a frequency step tried before a point is declared failed.
const MAX_SUBDIVISIONS: usize = 10;

/// `dx/dω = −J⁻¹ ∂R/∂ω` from an evaluation with its Jacobian.
fn frequency_derivative(evaluation: &Evaluation) -> Option<Vec<f64>> {
    let n = evaluation.residual.len();
    let rhs = Mat::from_fn(n, 1, |r, _| -evaluation.derivative_omega[r]);
    let d = evaluation.jacobian.partial_piv_lu().solve(&rhs);
    let d: Vec<f64> = (0..n).map(|r| d[(r, 0)]).collect();
    d.iter().all(|v| v.is_finite()).then_some(d)
}

/// Natural continuation from the converged `(x, from)` to `to`: tangent
/// predictor and Newton, the step halved (up to [`MAX_SUBDIVISIONS`] times)
/// when Newton fails. Returns (converged, iterations, residual, x at `to`).
fn advance<P: Problem>(
    problem: &mut P,
    x: &[f64],
    from: f64,
    to: f64,
    settings: &NewtonSettings,
    evaluation: &mut Evaluation,
) -> Result<(bool, usize, f64, Vec<f64>), P::Error> {
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
        let (converged, iterations, residual) =
            newton(problem, &mut guess, target, settings, evaluation)?;
        total += iterations;
        last_residual = residual;
        if converged {
            current = guess;
            omega = target;
        } else {
            halvings += 1;
            if halvings > MAX_SUBDIVISIONS {
                return Ok((false, total, last_residual, guess));
            }
            step = (target - omega) * 0.5;
        }
    }
    Ok((true, total, last_residual, current))
}

/// Solves at each frequency in turn (rad/s), each from the previous
/// converged solution (the first from `start` by plain Newton): natural
/// continuation with a tangent predictor, subdividing a step internally
/// when Newton fails. A point that still does not converge is kept,
/// marked `converged = false`, and the next starts from the last converged one.
pub fn solve_at_frequencies<P: Problem>(
    problem: &mut P,
    start: Vec<f64>,
    omegas: &[f64],
    settings: &NewtonSettings,
    mut observer: impl FnMut(&Point, &Progress),
) -> Branch {
    let mut evaluation = Evaluation::default();
    let mut last: Option<(Vec<f64>, f64)> = None;
    let mut points = Vec::new();
    let mut total = 0;
    for &omega in omegas {
        let outcome = match &last {
            Some((x, from)) => advance(problem, x, *from, omega, settings, &mut evaluation),
            None => {
                let mut x = start.clone();
                newton(problem, &mut x, omega, settings, &mut evaluation)
                    .map(|(c, i, r)| (c, i, r, x))
            }
        };
        match outcome {
            Ok((converged, iterations, residual_norm, x)) => {
                total += iterations;
                let point = Point {
                    omega,
                    unknowns: x.clone(),
                    iterations,
                    residual_norm,
                    converged,
                };
                observer(
                    &point,
                    &Progress {
                        points: points.len() + 1,
                        frequency_hz: hertz(omega),
                        step: 0.0,
                    },
                );
                points.push(point);
                if converged {
                    last = Some((x, omega));
                }
            }
            Err(error) => {
                return Branch {
                    points,
                    stop: StopReason::EvaluationError {
                        frequency_hz: hertz(omega),
                        message: error.to_string(),
                    },
                    total_iterations: total,
                    sweeps: None,
                }
            }
        }
    }
    Branch {
        points,
        stop: StopReason::AllFrequenciesDone,
        total_iterations: total,
        sweeps: None,
    }
}
