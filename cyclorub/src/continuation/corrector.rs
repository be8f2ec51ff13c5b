//! The pseudo-arc-length corrector: Newton on `[R / F; c(z)] = 0` from the
//! prediction, `c` the constraint that closes the system (the hyperplane
//! through the prediction, orthogonal to the tangent), with backtracking on
//! `‖(R / F, c)‖`.

use super::settings::CorrectorSettings;
use super::workspace::Workspace;
use super::{hertz, norm, NewtonSettings, Problem};

/// The equation that closes the corrector's system.
#[derive(Clone, Copy)]
pub(crate) enum Constraint<'a> {
    /// `tᵀ (z − predicted) = 0`: the plane through the prediction.
    Plane {
        /// The plane's normal (the tangent, or the secant predictor's chord).
        tangent: &'a [f64],
        /// The prediction.
        predicted: &'a [f64],
    },
}

impl Constraint<'_> {
    /// Value and gradient.
    fn at(&self, z: &[f64]) -> (f64, Vec<f64>) {
        match *self {
            Constraint::Plane { tangent, predicted } => (
                z.iter()
                    .zip(predicted)
                    .zip(tangent)
                    .map(|((c, p), t)| (c - p) * t)
                    .sum(),
                tangent.to_vec(),
            ),
        }
    }
}

/// The corrector and its settings.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Corrector {
    /// Tolerance and iterations.
    pub(crate) newton: NewtonSettings,
    /// The line search.
    pub(crate) line_search: CorrectorSettings,
}

impl Corrector {
    /// Corrects `candidate` (the prediction, scaled) onto the branch. The
    /// backtracking keeps piecewise-smooth residuals (DLFT) from wandering
    /// to far contact states: the corrector gives up as soon as the Newton
    /// direction stops descending, since a shorter step will do better.
    /// Returns `(iterations, relative residual)` on convergence, and the
    /// iterations spent. On convergence the workspace's evaluation holds
    /// the corrected point's residual and Jacobians, except where the
    /// tangent is taken from the solver's factors (after Newton steps,
    /// when `factors_serve_here`): the Jacobians are then the last
    /// iterate's before it, whose bordered matrix the solver holds
    /// factored.
    pub(crate) fn correct<P: Problem>(
        &self,
        work: &mut Workspace<'_, P>,
        constraint: Constraint<'_>,
        candidate: &mut [f64],
    ) -> (Option<(usize, f64)>, usize) {
        let settings = &self.newton;
        let n = candidate.len() - 1;
        let force = work.force;
        if let Err(error) = work.evaluate_at(candidate, true) {
            // An evaluation failure (e.g. at a singular frequency) is a failed
            // step, not the end: the caller retries with a smaller step.
            tracing::debug!(
                "evaluation failed at {:.4} Hz: {error}",
                hertz(work.scaling.unscaled(candidate).1)
            );
            return (None, 0);
        }
        let mut residual = norm(&work.evaluation.residual) / force;
        let (mut value, mut gradient) = constraint.at(candidate);
        let mut trial = candidate.to_vec();
        for iteration in 0..=settings.max_iterations {
            if !residual.is_finite() || work.interrupted() {
                return (None, iteration);
            }
            if residual <= settings.tolerance {
                return (Some((iteration, residual)), iteration);
            }
            if iteration == settings.max_iterations {
                break;
            }
            let rhs: Vec<f64> = (0..=n)
                .map(|r| {
                    if r == n {
                        -value
                    } else {
                        -work.evaluation.residual[r] / force
                    }
                })
                .collect();
            let delta = work.solve(&gradient, &rhs).y;
            if delta.iter().any(|d| !d.is_finite()) {
                return (None, iteration + 1);
            }
            let merit = residual.hypot(value);
            let mut factor = 1.0;
            let mut improved = false;
            for _ in 0..=self.line_search.max_backtracks {
                for (r, t) in trial.iter_mut().enumerate() {
                    *t = candidate[r] + factor * delta[r];
                }
                // The residual first: the Jacobians only where the next
                // Newton step needs them (not at a refused trial, nor at
                // the converged point, whose tangent comes from the last
                // factorization).
                if work.evaluate_at(&trial, false).is_ok() {
                    let new_residual = norm(&work.evaluation.residual) / force;
                    let (new_value, new_gradient) = constraint.at(&trial);
                    let new_merit = new_residual.hypot(new_value);
                    let converged = new_residual <= settings.tolerance;
                    if new_merit.is_finite()
                        && (new_merit
                            < (1.0 - self.line_search.sufficient_decrease * factor) * merit
                            || converged)
                        && ((converged && work.factors_serve_here())
                            || work.evaluate_at(&trial, true).is_ok())
                    {
                        residual = new_residual;
                        value = new_value;
                        gradient = new_gradient;
                        improved = true;
                        break;
                    }
                }
                factor *= 0.5;
            }
            if !improved {
                return (None, iteration + 1);
            }
            candidate.copy_from_slice(&trial);
        }
        (None, settings.max_iterations)
    }
}
