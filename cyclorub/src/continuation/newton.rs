//! Newton's method at fixed frequency: the first point of a branch, the
//! point at its end frequency, and every point of a fixed-frequency run.

use super::interrupt::Interrupt;
use super::structured::solve_structured;
use super::{norm, Evaluation, Problem};
use faer::linalg::solvers::Solve;
use faer::Mat;

/// Newton settings at fixed frequency: convergence, and the backtracking
/// line search on the residual norm.
///
/// ```
/// # use cyclorub::continuation::NewtonSettings;
/// let newton = NewtonSettings { tolerance: 1e-10, ..Default::default() };
/// assert_eq!(newton.max_halvings, 6);
/// ```
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct NewtonSettings {
    /// Convergence: `‖R‖ / force scale ≤ tolerance`. Default 1e-8, the case
    /// file's `continuation.tolerance`.
    pub tolerance: f64,
    /// Iterations before giving up. Default 15, the case file's
    /// `continuation.max_iterations`.
    pub max_iterations: usize,
    /// Halvings of a Newton step tried when the full step does not lower
    /// the residual enough; the last one is taken anyway. Default 6, down
    /// to 1/64 of the step: a start far from the solution (the linear
    /// guess of a contacting blade) needs short steps to enter the contact
    /// state, and more halvings only cost evaluations on a step that points
    /// away.
    pub max_halvings: usize,
    /// Sufficient decrease (Armijo): a step scaled by `f` must lower the
    /// residual norm by the fraction `sufficient_decrease · f`. Default
    /// 1e-4, the usual choice: almost any decrease is taken.
    pub sufficient_decrease: f64,
}

impl Default for NewtonSettings {
    fn default() -> Self {
        Self {
            tolerance: 1e-8,
            max_iterations: 15,
            max_halvings: 6,
            sufficient_decrease: 1e-4,
        }
    }
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
    newton_until(problem, x, omega, settings, evaluation, None)
}

/// [`newton`], given up (not converged) before the next iteration or
/// trial step once `interrupt` is raised: a point whose every evaluation
/// is long (many harmonics) stops within one of them.
pub(crate) fn newton_until<P: Problem>(
    problem: &mut P,
    x: &mut [f64],
    omega: f64,
    settings: &NewtonSettings,
    evaluation: &mut Evaluation,
    interrupt: Option<&Interrupt>,
) -> Result<(bool, usize, f64), P::Error> {
    let raised = || interrupt.is_some_and(Interrupt::raised);
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
        if raised() {
            return Ok((false, iteration, residual));
        }
        let negative: Vec<f64> = evaluation.residual.iter().map(|r| -r).collect();
        let step = match solve_structured(evaluation, &negative) {
            Some(step) => step,
            None => {
                let rhs = Mat::from_fn(n, 1, |r, _| negative[r]);
                let step = evaluation.jacobian.partial_piv_lu().solve(&rhs);
                (0..n).map(|r| step[(r, 0)]).collect()
            }
        };
        if step.iter().any(|s| !s.is_finite()) {
            return Ok((false, iteration, residual));
        }
        // Backtrack if the full step makes things worse.
        let mut factor = 1.0;
        let mut accepted = false;
        for _ in 0..=settings.max_halvings {
            if raised() {
                return Ok((false, iteration, residual));
            }
            for r in 0..n {
                trial[r] = x[r] + factor * step[r];
            }
            problem.evaluate(&trial, omega, true, evaluation)?;
            let new_residual = norm(&evaluation.residual) / scale;
            if new_residual.is_finite()
                && new_residual < residual * (1.0 - settings.sufficient_decrease * factor)
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

/// [`correct`], given up (not converged) before its next evaluation once
/// `interrupt` is raised.
pub fn correct_until<P: Problem>(
    problem: &mut P,
    x: &mut [f64],
    omega: f64,
    settings: &NewtonSettings,
    interrupt: &Interrupt,
) -> Result<(bool, usize, f64), P::Error> {
    newton_until(
        problem,
        x,
        omega,
        settings,
        &mut Evaluation::default(),
        Some(interrupt),
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    /// `R(x) = atan(x)`: a full Newton step from |x| > 1.392 overshoots
    /// further each time, so only the line search brings it to 0.
    struct Arctangent;

    impl Problem for Arctangent {
        type Error = std::convert::Infallible;

        fn unknowns(&self) -> usize {
            1
        }

        fn force_scale(&self) -> f64 {
            1.0
        }

        fn evaluate(
            &mut self,
            x: &[f64],
            _omega: f64,
            jacobian: bool,
            out: &mut Evaluation,
        ) -> Result<(), Self::Error> {
            out.residual = vec![x[0].atan()];
            if jacobian {
                out.jacobian = Mat::from_fn(1, 1, |_, _| 1.0 / (1.0 + x[0] * x[0]));
                out.derivative_omega = vec![0.0];
            }
            Ok(())
        }
    }

    #[test]
    fn the_line_search_settings_steer_newton() {
        let settings = NewtonSettings {
            tolerance: 1e-12,
            max_iterations: 30,
            ..Default::default()
        };
        let mut x = [3.0];
        let (converged, _, residual) = correct(&mut Arctangent, &mut x, 1.0, &settings).unwrap();
        assert!(converged && x[0].abs() < 1e-12, "{x:?}, {residual:e}");
        // Without halvings, every full step is taken and diverges.
        let plain = NewtonSettings {
            max_halvings: 0,
            ..settings
        };
        let mut x = [3.0];
        let (converged, _, _) = correct(&mut Arctangent, &mut x, 1.0, &plain).unwrap();
        // Away from the root (or no longer finite).
        assert!(!converged && (x[0].is_nan() || x[0].abs() >= 3.0), "{x:?}");
    }
}
