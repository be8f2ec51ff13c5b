//! The harmonic balance problem at a fixed frequency with the external load
//! scaled by a parameter `s`: `R(x, s) = Z x − s F + G̃ F[f]`. Continuation
//! in `s` from 0 (no load: the static contact state alone) to 1 reaches a
//! point of the forced response that Newton cannot reach from the linear
//! response (a blade that touches its casing at rest, say).

use super::residual::{Along, HarmonicBalance};
use super::HbmError;
use crate::contact::Smoothness;
use crate::continuation::{
    correct, ArcLengthSettings, Branch, Continuation, Evaluation, Problem, StopReason,
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

/// How a continuation in the load from no excitation ended.
#[derive(Clone, Debug)]
pub enum LoadPath {
    /// The load scale reached 1: the point, and the continuation's points.
    Reached {
        /// The solution at the full load.
        unknowns: Vec<f64>,
        /// Points of the continuation in the load.
        points: usize,
    },
    /// Newton found no solution without excitation (its relative residual).
    NoRest {
        /// `‖R‖ / force scale` where Newton stopped.
        residual: f64,
    },
    /// The continuation stopped before the full load.
    Stopped(StopReason),
}

/// The point of `problem` at `omega` reached by continuation in the load
/// from no excitation: Newton from rest, then the load scale from 0 to 1
/// with `steps`' Newton settings, steps, length scale and cap of points
/// (its `start` and `end` are replaced), stopped by the interrupt the
/// problem watches. A branch's first point (`forced_response/start.rs`)
/// and a fixed-frequency run's fresh start ([`HarmonicBalance::fresh_start`])
/// both get there this way.
pub fn solved_by_load_continuation(
    problem: &mut HarmonicBalance,
    omega: f64,
    steps: &ArcLengthSettings,
) -> Result<LoadPath, HbmError> {
    let interrupt = problem.interrupt().cloned();
    let mut rest = vec![0.0; problem.unknowns()];
    let mut homotopy = LoadHomotopy::new(problem, omega);
    let (converged, _, residual) = correct(&mut homotopy, &mut rest, 0.0, &steps.newton)?;
    if !converged {
        return Ok(LoadPath::NoRest { residual });
    }
    let in_load = ArcLengthSettings {
        start: 0.0,
        end: 1.0,
        ..*steps
    };
    let path = match Continuation::new(&mut homotopy, rest, in_load.into()) {
        Ok(driver) => match interrupt {
            Some(interrupt) => driver.with_interrupt(interrupt).finish(),
            None => driver.finish(),
        },
        Err(error) => Branch::refused(0.0, &error),
    };
    Ok(match (&path.stop, path.points.last()) {
        (StopReason::EndReached, Some(last)) if last.converged => LoadPath::Reached {
            unknowns: last.unknowns.clone(),
            points: path.points.len(),
        },
        (stop, _) => LoadPath::Stopped(stop.clone()),
    })
}

impl HarmonicBalance {
    /// A fresh start at `omega` (its [`Problem::fresh_guess`]): the linear
    /// response (no contact force) corrected by Newton with `steps.newton`
    /// where that converges; else the point reached by continuation in the
    /// load from no excitation with `steps`, as a branch's first point is
    /// ([`solved_by_load_continuation`]), in at most [`LOAD_POINTS`]
    /// points; `None` when neither gets there (Newton from the linear
    /// response would only fail again).
    pub fn fresh_start(
        &mut self,
        omega: f64,
        steps: &ArcLengthSettings,
    ) -> Result<Option<Vec<f64>>, HbmError> {
        let mut x = self.linear_solution(omega)?;
        if correct(self, &mut x, omega, &steps.newton)?.0 {
            return Ok(Some(x));
        }
        let steps = ArcLengthSettings {
            max_points: steps.max_points.min(LOAD_POINTS),
            ..*steps
        };
        Ok(match solved_by_load_continuation(self, omega, &steps)? {
            LoadPath::Reached { unknowns, .. } => Some(unknowns),
            LoadPath::NoRest { .. } | LoadPath::Stopped(_) => None,
        })
    }
}

/// The most points of a continuation in the load for a fresh start.
pub const LOAD_POINTS: usize = 500;

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
