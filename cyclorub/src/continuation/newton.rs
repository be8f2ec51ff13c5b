//! Newton's method at fixed frequency: the first point of a branch, the
//! point at its end frequency, and every point of a fixed-frequency run.

use super::{norm, Evaluation, Problem};
use faer::linalg::solvers::Solve;
use faer::Mat;

/// Halvings of a Newton step tried when the full step does not lower the
/// residual (the last one is taken anyway): 6, down to 1/64 of the step.
const MAX_HALVINGS: usize = 6;
/// Sufficient decrease (Armijo) of the residual norm, per unit step.
const SUFFICIENT_DECREASE: f64 = 1e-4;

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
        // Backtrack if the full step makes things worse.
        let mut factor = 1.0;
        let mut accepted = false;
        for _ in 0..=MAX_HALVINGS {
            for r in 0..n {
                trial[r] = x[r] + factor * step[(r, 0)];
            }
            problem.evaluate(&trial, omega, true, evaluation)?;
            let new_residual = norm(&evaluation.residual) / scale;
            if new_residual.is_finite()
                && new_residual < residual * (1.0 - SUFFICIENT_DECREASE * factor)
            {
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
