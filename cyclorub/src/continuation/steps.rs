//! The step vocabulary shared by the policies, the kink turns and the
//! driver: a step accepted and how it was made, a step refused, and what
//! a way on past a refusal needs. Its own module so that `policy` and
//! `kinks`, which both speak it, do not import each other.

use super::corrector::Corrector;
use super::settings::Settings;

/// How a step was made.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) enum Via {
    /// An ordinary predictor-corrector step.
    Step,
    /// A step past a kink at `omega` (rad/s).
    Kink {
        /// Where the kink was left from.
        omega: f64,
    },
    /// A leap over a small nonsmooth structure.
    Leap,
}

/// A step accepted, not yet placed in the branch.
pub(crate) struct Accepted {
    /// The corrected point, scaled.
    pub(crate) candidate: Vec<f64>,
    /// Corrector iterations.
    pub(crate) iterations: usize,
    /// `‖R‖ / F` there.
    pub(crate) residual_norm: f64,
    /// The unit tangent there.
    pub(crate) tangent: Vec<f64>,
    /// The sign of `det [J D⁻¹ / F; tᵀ]` there.
    pub(crate) orientation: f64,
    /// How it was made.
    pub(crate) via: Via,
}

impl Accepted {
    /// An ordinary step to `candidate`, converged in `(iterations,
    /// residual norm)`, with its tangent and orientation.
    pub(crate) fn new(
        candidate: Vec<f64>,
        (iterations, residual_norm): (usize, f64),
        tangent: Vec<f64>,
        orientation: f64,
    ) -> Self {
        Self {
            candidate,
            iterations,
            residual_norm,
            tangent,
            orientation,
            via: Via::Step,
        }
    }

    /// The same, made another way.
    pub(crate) fn via(self, via: Via) -> Self {
        Self { via, ..self }
    }
}

/// What a way on past a refused step needs to know: the settings, the
/// corrector, and the branch around its last point.
pub(crate) struct Around<'r> {
    /// The settings.
    pub(crate) settings: &'r Settings,
    /// The corrector.
    pub(crate) corrector: &'r Corrector,
    /// The last point, scaled.
    pub(crate) z: &'r [f64],
    /// The unit tangent there.
    pub(crate) tangent: &'r [f64],
    /// The recent points, oldest first.
    pub(crate) trail: &'r [Vec<f64>],
    /// Their pieces (piecewise residuals).
    pub(crate) visited: &'r [u64],
    /// Whether a corrected point lands on a sheet travelled long before.
    pub(crate) lands: &'r dyn Fn(&[f64]) -> bool,
}

/// A step just refused.
pub(crate) struct Refused {
    /// Its length.
    pub(crate) step: f64,
    /// The last step that went through at the first attempt.
    pub(crate) good_step: f64,
    /// How far beyond the admissible turn it went (> 1: too far), if it
    /// converged.
    pub(crate) turn: Option<f64>,
    /// Whether it was refused for turning too far.
    pub(crate) turning_too_fast: bool,
}
