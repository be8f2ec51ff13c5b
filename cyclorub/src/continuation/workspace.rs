//! What every part of a continuation step works on: the problem, the
//! scaling, the linear solver (whose factors the predictor reuses after the
//! corrector, where they serve) and the last evaluation, built once per
//! branch.

use super::geometry::Scaling;
use super::interrupt::Interrupt;
use super::linear::{Bordered, LinearSolver, Solution};
use super::newton::{newton_until, NewtonSettings};
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
    /// The last evaluation (see [`super::corrector::Corrector::correct`]).
    pub(crate) evaluation: Evaluation,
    /// Whether the tangent at a corrected point may be taken from the
    /// corrector's last factorization whatever the pieces: on a smooth
    /// residual, or with the secant predictor.
    reuse_factors: bool,
    /// The piece of the evaluation whose Jacobians the solver last
    /// factored (piecewise residuals that keep it).
    factored_piece: Option<u64>,
    /// The scaled point of the problem's last evaluation, when known.
    evaluated: Option<Vec<f64>>,
    /// Raised from outside: Newton and the corrector give up before their
    /// next evaluation.
    interrupt: Option<Interrupt>,
}

impl<'a, P: Problem> Workspace<'a, P> {
    /// A workspace for `problem` with `scaling`, solving with `solver`.
    pub(crate) fn new(
        problem: &'a mut P,
        scaling: Scaling,
        solver: Box<dyn LinearSolver + 'a>,
    ) -> Self {
        let force = problem.force_scale();
        let reuse_factors = problem.is_smooth();
        Self {
            problem,
            scaling,
            force,
            solver,
            evaluation: Evaluation::default(),
            reuse_factors,
            factored_piece: None,
            evaluated: None,
            interrupt: None,
        }
    }

    /// Lets `interrupt` stop Newton and the corrector between evaluations.
    pub(crate) fn set_interrupt(&mut self, interrupt: Interrupt) {
        self.problem.watch_interrupt(&interrupt);
        self.interrupt = Some(interrupt);
    }

    /// Whether the interrupt was raised.
    pub(crate) fn interrupted(&self) -> bool {
        self.interrupt.as_ref().is_some_and(Interrupt::raised)
    }

    /// Lets the tangent at a corrected point come from the corrector's last
    /// factorization whatever the pieces (the secant predictor's).
    pub(crate) fn reuse_factors_across_pieces(&mut self) {
        self.reuse_factors = true;
    }

    /// Evaluates the residual (and its Jacobians if `jacobian`) at the
    /// scaled point `z`, into [`Self::evaluation`].
    pub(crate) fn evaluate_at(&mut self, z: &[f64], jacobian: bool) -> Result<(), P::Error> {
        let (x, omega) = self.scaling.unscaled(z);
        let result = self
            .problem
            .evaluate(&x, omega, jacobian, &mut self.evaluation);
        self.remember_evaluated(z, result.is_ok());
        result
    }

    /// The piece holding the scaled point `z`, if the problem tells pieces:
    /// that of the last evaluation when it was at `z` and the problem
    /// tells it (a corrected point's piece, asked for as it joins the
    /// trail), else from [`Problem::piece`].
    pub(crate) fn piece_at(&mut self, z: &[f64]) -> Option<u64> {
        if self.evaluated.as_deref() == Some(z) {
            if let Some(piece) = self.problem.piece_of_last_evaluation() {
                return Some(piece);
            }
        }
        let (x, omega) = self.scaling.unscaled(z);
        let piece = self.problem.piece(&x, omega).ok().flatten();
        // `piece` need not evaluate: `z` is remembered only when the last
        // evaluation tells this very piece.
        let evaluated_here = piece.is_some() && self.problem.piece_of_last_evaluation() == piece;
        self.remember_evaluated(z, evaluated_here);
        piece
    }

    /// Records that the problem's last evaluation was at `z` (if it
    /// succeeded), or at no known point.
    fn remember_evaluated(&mut self, z: &[f64], succeeded: bool) {
        match (&mut self.evaluated, succeeded) {
            (Some(at), true) => {
                at.clear();
                at.extend_from_slice(z);
            }
            (evaluated, true) => *evaluated = Some(z.to_vec()),
            (evaluated, false) => *evaluated = None,
        }
    }

    /// Forgets where the problem was last evaluated, after it was
    /// evaluated apart from [`Self::evaluate_at`] and [`Self::piece_at`].
    pub(crate) fn forget_evaluated(&mut self) {
        self.evaluated = None;
    }

    /// Plain Newton at fixed `omega` from `x` (updated in place): returns
    /// (converged, iterations, relative residual).
    pub(crate) fn newton(
        &mut self,
        x: &mut [f64],
        omega: f64,
        settings: &NewtonSettings,
    ) -> Result<(bool, usize, f64), P::Error> {
        self.evaluated = None;
        newton_until(
            self.problem,
            x,
            omega,
            settings,
            &mut self.evaluation,
            self.interrupt.as_ref(),
        )
    }

    /// Whether the solver's factors may serve the tangent at the point of
    /// the last evaluation: on a smooth residual, or when they were made
    /// on the same piece (within a piece the Jacobian changes smoothly;
    /// across a kink it jumps, and the null vector can point another way).
    pub(crate) fn factors_serve_here(&self) -> bool {
        self.reuse_factors
            || self
                .factored_piece
                .is_some_and(|piece| self.problem.piece_of_last_evaluation() == Some(piece))
    }

    /// Solves the bordered system of the last evaluation closed by `border`.
    pub(crate) fn solve(&mut self, border: &[f64], rhs: &[f64]) -> Solution {
        self.factored_piece = self.problem.piece_of_last_evaluation();
        let system = Bordered {
            evaluation: &self.evaluation,
            factors: self.scaling.factors(),
            force: self.force,
            border,
        };
        self.solver.solve(&system, rhs)
    }
}

#[cfg(test)]
mod tests {
    use super::super::geometry::Scaling;
    use super::super::linear::DenseLu;
    use super::*;
    use std::cell::Cell;
    use std::rc::Rc;

    /// `x = |ω|` in one unknown, its pieces the sign of ω; `piece` counts
    /// its calls, and, if `keeps`, evaluates and tells the last
    /// evaluation's piece.
    struct Vee {
        keeps: bool,
        last: Option<u64>,
        piece_calls: Rc<Cell<usize>>,
    }

    fn piece_of(omega: f64) -> u64 {
        u64::from(omega >= 0.0)
    }

    impl Problem for Vee {
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
            omega: f64,
            _jacobian: bool,
            out: &mut Evaluation,
        ) -> Result<(), Self::Error> {
            out.residual = vec![x[0] - omega.abs()];
            self.last = Some(piece_of(omega));
            Ok(())
        }
        fn piece(&mut self, x: &[f64], omega: f64) -> Result<Option<u64>, Self::Error> {
            self.piece_calls.set(self.piece_calls.get() + 1);
            if self.keeps {
                let mut scratch = Evaluation::default();
                self.evaluate(x, omega, false, &mut scratch)?;
            }
            Ok(Some(piece_of(omega)))
        }
        fn piece_of_last_evaluation(&self) -> Option<u64> {
            if self.keeps {
                self.last
            } else {
                None
            }
        }
    }

    /// A point's piece comes from its last evaluation when the problem
    /// tells it, without asking again; else (or at another point) from
    /// `piece`, and always the right one.
    #[test]
    fn a_points_piece_is_read_from_its_evaluation_when_the_problem_tells_it() {
        for keeps in [true, false] {
            let calls = Rc::new(Cell::new(0));
            let mut problem = Vee {
                keeps,
                last: None,
                piece_calls: calls.clone(),
            };
            let mut work = Workspace::new(
                &mut problem,
                Scaling::identity(1),
                Box::new(DenseLu::default()),
            );
            let (left, right) = ([1.0, -1.0], [1.0, 1.0]);
            work.evaluate_at(&left, false).unwrap();
            assert_eq!(work.piece_at(&left), Some(0), "keeps {keeps}");
            assert_eq!(calls.get(), usize::from(!keeps), "keeps {keeps}");
            // Another point: asked; then, at it again, read.
            assert_eq!(work.piece_at(&right), Some(1), "keeps {keeps}");
            assert_eq!(work.piece_at(&right), Some(1), "keeps {keeps}");
            assert_eq!(calls.get(), 1 + usize::from(!keeps) * 2, "keeps {keeps}");
            // After an evaluation elsewhere, the earlier point is asked.
            work.evaluate_at(&left, false).unwrap();
            assert_eq!(work.piece_at(&right), Some(1), "keeps {keeps}");
        }
    }
}
