//! Scalar branches `R(x, ω) = 0` (one unknown), for testing continuation
//! apart from harmonic balance: every point can be checked against the
//! curve in closed form. Each test binary uses part of it.
#![allow(dead_code)]

use cyclorub::continuation::{ArcLengthSettings, Evaluation, NewtonSettings, Point, Problem};
use faer::Mat;

/// `R`, `∂R/∂x` and `∂R/∂ω` at `(x, ω)`.
pub type Residual = Box<dyn Fn(f64, f64) -> (f64, f64, f64)>;

/// A branch given by its residual in closed form.
pub struct ScalarBranch {
    residual: Residual,
    smooth: bool,
    pieces: Option<fn(f64) -> u64>,
}

impl ScalarBranch {
    /// A residual continuation may not assume smooth (its default).
    pub fn new(residual: impl Fn(f64, f64) -> (f64, f64, f64) + 'static) -> Self {
        Self {
            residual: Box::new(residual),
            smooth: false,
            pieces: None,
        }
    }

    /// A smooth residual (continuously differentiable).
    pub fn smooth(residual: impl Fn(f64, f64) -> (f64, f64, f64) + 'static) -> Self {
        Self {
            smooth: true,
            ..Self::new(residual)
        }
    }

    /// A piecewise-smooth residual whose pieces are told by `x`.
    pub fn piecewise(
        residual: impl Fn(f64, f64) -> (f64, f64, f64) + 'static,
        pieces: fn(f64) -> u64,
    ) -> Self {
        Self {
            pieces: Some(pieces),
            ..Self::new(residual)
        }
    }
}

/// The error of a closed-form residual, which cannot fail.
#[derive(Debug, thiserror::Error)]
#[error("never")]
pub struct Never;

impl Problem for ScalarBranch {
    type Error = Never;
    fn unknowns(&self) -> usize {
        1
    }
    fn force_scale(&self) -> f64 {
        1.0
    }
    fn is_smooth(&self) -> bool {
        self.smooth
    }
    fn evaluate(
        &mut self,
        x: &[f64],
        omega: f64,
        jacobian: bool,
        out: &mut Evaluation,
    ) -> Result<(), Never> {
        let (r, dx, domega) = (self.residual)(x[0], omega);
        out.residual = vec![r];
        if jacobian {
            out.jacobian = Mat::from_fn(1, 1, |_, _| dx);
            out.derivative_omega = vec![domega];
        }
        Ok(())
    }
    fn piece(&mut self, x: &[f64], _omega: f64) -> Result<Option<u64>, Never> {
        Ok(self.pieces.map(|pieces| pieces(x[0])))
    }
}

/// Settings for a sweep from `start` to `end` on a unit length scale,
/// converged to 1e-12; tests change the fields they are about.
pub fn settings(start: f64, end: f64) -> ArcLengthSettings {
    ArcLengthSettings {
        start,
        end,
        initial_step: 0.01,
        min_step: 1e-12,
        max_step: 0.05,
        length_scale: 1.0,
        newton: NewtonSettings {
            tolerance: 1e-12,
            max_iterations: 20,
        },
        max_points: 100_000,
    }
}

/// Asserts that `x` grows from each point to the next: on a branch that is
/// a graph over `x`, going back means a jump onto a sheet already travelled.
pub fn assert_x_grows(points: &[Point], case: &str) {
    for pair in points.windows(2) {
        assert!(
            pair[1].unknowns[0] > pair[0].unknowns[0],
            "{case}: went back from x = {} to {} (ω = {} to {})",
            pair[0].unknowns[0],
            pair[1].unknowns[0],
            pair[0].omega,
            pair[1].omega
        );
    }
}
