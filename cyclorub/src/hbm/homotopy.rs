//! The harmonic balance problem at a fixed frequency with the external load
//! scaled by a parameter `s`: `R(x, s) = Z x − s F + G̃ F[f]`. Continuation
//! in `s` from 0 (no load: the static contact state alone) to 1 reaches a
//! point of the forced response that Newton cannot reach from the linear
//! response (a blade that touches its casing at rest, say).

use super::residual::{Along, HarmonicBalance};
use super::HbmError;
use crate::contact::Smoothness;
use crate::continuation::{Evaluation, Problem};

/// [`HarmonicBalance`] at frequency `omega` as a problem in the load scale
/// `s` (continuation's parameter, in place of the frequency).
#[derive(Debug)]
pub struct LoadHomotopy<'a> {
    problem: &'a mut HarmonicBalance,
    omega: f64,
}

impl<'a> LoadHomotopy<'a> {
    /// The problem at `omega` (rad/s), its load scaled by the parameter.
    pub fn new(problem: &'a mut HarmonicBalance, omega: f64) -> Self {
        Self { problem, omega }
    }
}

impl Problem for LoadHomotopy<'_> {
    type Error = HbmError;

    fn unknowns(&self) -> usize {
        self.problem.unknowns()
    }

    fn force_scale(&self) -> f64 {
        self.problem.force_scale()
    }

    fn norm_weights(&self) -> Vec<f64> {
        self.problem.norm_weights()
    }

    fn is_smooth(&self) -> bool {
        self.problem.is_smooth()
    }

    /// `R(x, s)` and, with the Jacobian, `∂R/∂s` in place of `∂R/∂ω`.
    fn evaluate(
        &mut self,
        x: &[f64],
        scale: f64,
        jacobian: bool,
        out: &mut Evaluation,
    ) -> Result<(), HbmError> {
        self.problem
            .evaluate_along(x, self.omega, scale, Along::LoadScale, jacobian, out)
    }

    fn piece(&mut self, x: &[f64], scale: f64) -> Result<Option<u64>, HbmError> {
        if self.problem.law().smoothness() != Smoothness::Piecewise {
            return Ok(None);
        }
        let mut scratch = Evaluation::default();
        self.evaluate(x, scale, false, &mut scratch)?;
        Ok(Some(self.problem.last_piece()))
    }

    /// The wrapped problem's: a factorization made on the piece of a
    /// corrected point serves its tangent here as along the frequency.
    fn piece_of_last_evaluation(&self) -> Option<u64> {
        self.problem.piece_of_last_evaluation()
    }
}
