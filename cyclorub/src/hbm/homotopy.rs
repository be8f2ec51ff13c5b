//! The harmonic balance problem at a fixed frequency with the external load
//! scaled by a parameter `s`: `R(x, s) = Z x − s F + G̃ F[f]`. Continuation
//! in `s` from 0 (no load: the static contact state alone) to 1 reaches a
//! point of the forced response that Newton cannot reach from the linear
//! response (a blade that touches its casing at rest, say).

use super::residual::{Along, HarmonicBalance};
use super::HbmError;
use crate::contact::Smoothness;
use crate::continuation::{
    continue_branch, correct, ArcLengthSettings, Evaluation, NewtonSettings, Problem, StopReason,
};

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

/// The point of `problem` at `omega` reached by continuation in the load
/// from no excitation (Newton from rest, then the load scale from 0 to
/// 1), on `length_scale` (m) with `newton`; `None` when either fails.
pub fn solved_by_load_continuation(
    problem: &mut HarmonicBalance,
    omega: f64,
    length_scale: f64,
    newton: &NewtonSettings,
) -> Result<Option<Vec<f64>>, HbmError> {
    let mut rest = vec![0.0; problem.unknowns()];
    let mut homotopy = LoadHomotopy::new(problem, omega);
    let (converged, ..) = correct(&mut homotopy, &mut rest, 0.0, newton)?;
    if !converged {
        return Ok(None);
    }
    let in_load = ArcLengthSettings {
        start: 0.0,
        end: 1.0,
        initial_step: 0.01,
        min_step: 1e-7,
        max_step: 0.1,
        length_scale,
        newton: *newton,
        max_points: LOAD_POINTS,
    };
    let path = continue_branch(&mut homotopy, rest, &in_load, |_, _| {});
    Ok(match (&path.stop, path.points.last()) {
        (StopReason::EndReached, Some(last)) if last.converged => Some(last.unknowns.clone()),
        _ => None,
    })
}

impl HarmonicBalance {
    /// A fresh start at `omega` (its [`Problem::fresh_guess`]): the linear
    /// response (no contact force) where Newton converges from it; else
    /// the point reached by continuation in the load from no excitation,
    /// as a branch's first point is ([`solved_by_load_continuation`]), on
    /// the casing's smallest gap; else the linear response.
    pub fn fresh_start(&mut self, omega: f64) -> Result<Vec<f64>, HbmError> {
        let linear = self.linear_solution(omega)?;
        let newton = NewtonSettings::default();
        let mut x = linear.clone();
        if correct(self, &mut x, omega, &newton)?.0 {
            return Ok(x);
        }
        let gap = self
            .casing()
            .gaps
            .iter()
            .copied()
            .filter(|g| *g > 0.0)
            .fold(f64::INFINITY, f64::min);
        let length_scale = if gap.is_finite() { gap } else { 1e-3 };
        let by_load = solved_by_load_continuation(self, omega, length_scale, &newton)?;
        Ok(by_load.unwrap_or(linear))
    }
}

/// The most points of a continuation in the load for a fresh start.
const LOAD_POINTS: usize = 500;

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
