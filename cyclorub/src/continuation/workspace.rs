//! What every part of a continuation step works on: the problem, the
//! scaling, the linear solver and the last evaluation (whose Jacobians the
//! predictor reuses after the corrector), built once per branch.

use super::geometry::Scaling;
use super::linear::{Bordered, LinearSolver, Solution};
use super::newton::{newton, NewtonSettings};
use super::{Evaluation, Problem};

/// The problem and the buffers of one branch.
pub(crate) struct Workspace<'a, P: Problem> {
    /// The residual.
    pub(crate) problem: &'a mut P,
    /// Scaled unknowns.
    pub(crate) scaling: Scaling,
    /// The problem's force scale: residuals are divided by it.
    pub(crate) force: f64,
    /// Solves the bordered systems.
    pub(crate) solver: Box<dyn LinearSolver + 'a>,
    /// The last evaluation: after a converged correction, at the corrected
    /// point, with its Jacobians.
    pub(crate) evaluation: Evaluation,
}

impl<'a, P: Problem> Workspace<'a, P> {
    /// A workspace for `problem` with `scaling`, solving with `solver`.
    pub(crate) fn new(
        problem: &'a mut P,
        scaling: Scaling,
        solver: Box<dyn LinearSolver + 'a>,
    ) -> Self {
        let force = problem.force_scale();
        Self {
            problem,
            scaling,
            force,
            solver,
            evaluation: Evaluation::default(),
        }
    }

    /// Evaluates the residual (and its Jacobians if `jacobian`) at the
    /// scaled point `z`, into [`Self::evaluation`].
    pub(crate) fn evaluate_at(&mut self, z: &[f64], jacobian: bool) -> Result<(), P::Error> {
        let (x, omega) = self.scaling.unscaled(z);
        self.problem
            .evaluate(&x, omega, jacobian, &mut self.evaluation)
    }

    /// The piece holding the scaled point `z`, if the problem tells pieces.
    pub(crate) fn piece_at(&mut self, z: &[f64]) -> Option<u64> {
        let (x, omega) = self.scaling.unscaled(z);
        self.problem.piece(&x, omega).ok().flatten()
    }

    /// Plain Newton at fixed `omega` from `x` (updated in place): returns
    /// (converged, iterations, relative residual).
    pub(crate) fn newton(
        &mut self,
        x: &mut [f64],
        omega: f64,
        settings: &NewtonSettings,
    ) -> Result<(bool, usize, f64), P::Error> {
        newton(self.problem, x, omega, settings, &mut self.evaluation)
    }

    /// Solves the bordered system of the last evaluation closed by `border`.
    pub(crate) fn solve(&mut self, border: &[f64], rhs: &[f64]) -> Solution {
        let system = Bordered {
            evaluation: &self.evaluation,
            factors: self.scaling.factors(),
            force: self.force,
            border,
        };
        self.solver.solve(&system, rhs)
    }
}
