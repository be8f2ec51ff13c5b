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
    fresh: Option<f64>,
}

impl ScalarBranch {
    /// A residual continuation may not assume smooth (its default).
    pub fn new(residual: impl Fn(f64, f64) -> (f64, f64, f64) + 'static) -> Self {
        Self {
            residual: Box::new(residual),
            smooth: false,
            pieces: None,
            fresh: None,
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

impl ScalarBranch {
    /// The same branch whose [`Problem::fresh_guess`] is `x` at every
    /// frequency.
    pub fn with_fresh_guess(self, x: f64) -> Self {
        Self {
            fresh: Some(x),
            ..self
        }
    }
}

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
    fn fresh_guess(
        &mut self,
        _omega: f64,
        _steps: &ArcLengthSettings,
    ) -> Result<Option<Vec<f64>>, Never> {
        Ok(self.fresh.map(|x| vec![x]))
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
            ..Default::default()
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

/// The S-shaped curve `x³ − x/2 = λ` (`λ = ω − 2`): one solution for
/// `|λ| > 1/(3√6)`, two folds between, `x` growing along it.
pub fn s_curve(x: f64, omega: f64) -> (f64, f64, f64) {
    (x * x * x - 0.5 * x - (omega - 2.0), 3.0 * x * x - 0.5, -1.0)
}

/// The real root of `x³ − x/2 = λ` for `|λ|` large enough to have one.
pub fn s_curve_root(lambda: f64) -> f64 {
    let mut x = lambda.signum();
    for _ in 0..100 {
        x -= (x * x * x - 0.5 * x - lambda) / (3.0 * x * x - 0.5);
    }
    x
}

/// The error of [`Faulty`].
#[derive(Debug, thiserror::Error)]
#[error("fault at x = {0}")]
pub struct Fault(pub f64);

/// A smooth scalar branch whose evaluations fail for `x` in `band` while
/// `active`: a test double for whatever stops a real sweep (a jump onto a
/// travelled sheet, a step underflow).
pub struct Faulty {
    /// The branch.
    pub curve: ScalarBranch,
    /// Where evaluations fail.
    pub band: (f64, f64),
    /// Whether they fail.
    pub active: std::rc::Rc<std::cell::Cell<bool>>,
}

impl Problem for Faulty {
    type Error = Fault;
    fn unknowns(&self) -> usize {
        1
    }
    fn force_scale(&self) -> f64 {
        1.0
    }
    fn is_smooth(&self) -> bool {
        true
    }
    fn evaluate(
        &mut self,
        x: &[f64],
        omega: f64,
        jacobian: bool,
        out: &mut Evaluation,
    ) -> Result<(), Fault> {
        if self.active.get() && x[0] > self.band.0 && x[0] < self.band.1 {
            return Err(Fault(x[0]));
        }
        // A closed-form residual never fails.
        self.curve
            .evaluate(x, omega, jacobian, out)
            .map_err(|_| Fault(x[0]))
    }
}

/// Where each backward interval of the zigzag starts, and its length (in
/// `x`), down to 1e-6: two kinks nearly on top of each other.
pub const ZIGZAG_BACKWARD: [(f64, f64); 4] = [(0.5, 0.05), (1.0, 1e-3), (1.5, 1e-5), (2.0, 1e-6)];

/// The index of the linear piece of the zigzag holding `x`.
pub fn zigzag_piece(x: f64) -> u64 {
    ZIGZAG_BACKWARD
        .iter()
        .map(|&(start, length)| u64::from(x >= start) + u64::from(x >= start + length))
        .sum()
}

/// The zigzag `ω = g(x)`: slope 1, and −1/2 over each backward interval.
pub fn zigzag_frequency(x: f64) -> f64 {
    let backward: f64 = ZIGZAG_BACKWARD
        .iter()
        .map(|&(start, length)| (x - start).clamp(0.0, length))
        .sum();
    2.0 + x - 1.5 * backward
}

/// The zigzag's residual `ω − g(x)`: nonsmooth folds at each backward
/// interval's ends.
pub fn zigzag(x: f64, omega: f64) -> (f64, f64, f64) {
    let slope = if zigzag_piece(x) % 2 == 1 { -0.5 } else { 1.0 };
    (omega - zigzag_frequency(x), -slope, 1.0)
}
