//! The integrator a law calls for ([`ContactLaw::time_scheme`]): the
//! implicit scheme for a law of the penetration (the regularized law), the
//! explicit scheme with Lagrange multipliers for the dynamic Lagrangian's
//! unilateral contact.

use super::lagrange::CentralDifference;
use super::loading::WheelLoads;
use super::newmark::{Newmark, NewtonSettings};
use super::state::{Drive, EnergyTally, State};
use super::wheel::WheelMatrices;
use super::SimulateError;
use crate::contact::{ContactLaw, TimeScheme};
use std::sync::Arc;

/// One of the two schemes.
pub enum Scheme {
    /// Newmark average acceleration with Newton (regularized law), and the
    /// dispersion correction its wheel was built with (`Ω/Ω_w`).
    Implicit(Box<Newmark>, Option<f64>),
    /// Central differences with Lagrange multipliers (`law = "dlft"`).
    Explicit(Box<CentralDifference>),
}

impl Scheme {
    /// The scheme for `law`, with steps of `step` s, from `start`; the
    /// implicit scheme on the wheel warped by `dispersion` (`Ω/Ω_w`, see
    /// [`WheelMatrices::time_warped`]) when given; the explicit one ignores
    /// it (its steps are far shorter, bound by stability).
    #[allow(clippy::too_many_arguments)]
    pub fn for_law(
        wheel: Arc<WheelMatrices>,
        loads: Arc<WheelLoads>,
        law: Arc<dyn ContactLaw>,
        drive: Drive,
        step: f64,
        newton: NewtonSettings,
        start: State,
        dispersion: Option<f64>,
    ) -> Result<Self, SimulateError> {
        match law.time_scheme() {
            TimeScheme::ExplicitLagrange => {
                let wall = law.wall_stiffness();
                Ok(Self::Explicit(Box::new(CentralDifference::new(
                    wheel, loads, wall, drive, step, start,
                )?)))
            }
            TimeScheme::Implicit => {
                let wheel = match dispersion {
                    Some(ratio) => Arc::new(wheel.time_warped(ratio)),
                    None => wheel,
                };
                Ok(Self::Implicit(
                    Box::new(Newmark::new(wheel, loads, law, drive, step, newton, start)?),
                    dispersion,
                ))
            }
        }
    }

    /// The dispersion correction the implicit scheme applies (`Ω/Ω_w`).
    pub fn dispersion_ratio(&self) -> Option<f64> {
        match self {
            Self::Implicit(_, ratio) => *ratio,
            Self::Explicit(_) => None,
        }
    }

    /// A name for people.
    pub fn name(&self) -> &'static str {
        match self {
            Self::Implicit(..) => {
                "Newmark average acceleration, Newton on the contact unknowns (regularized law)"
            }
            Self::Explicit(_) => {
                "central differences, forward-increment Lagrange multipliers (unilateral contact)"
            }
        }
    }

    /// Advances by one step.
    pub fn advance(&mut self) -> Result<(), SimulateError> {
        match self {
            Self::Implicit(s, _) => s.advance(),
            Self::Explicit(s) => s.advance(),
        }
    }

    /// The state reached.
    pub fn state(&self) -> &State {
        match self {
            Self::Implicit(s, _) => s.state(),
            Self::Explicit(s) => s.state(),
        }
    }

    /// The time reached, s.
    pub fn time(&self) -> f64 {
        self.state().time
    }

    /// The time step, s.
    pub fn step(&self) -> f64 {
        match self {
            Self::Implicit(s, _) => s.step(),
            Self::Explicit(s) => s.step(),
        }
    }

    /// The work exchanged since the last call.
    pub fn take_energy(&mut self) -> EnergyTally {
        match self {
            Self::Implicit(s, _) => s.take_energy(),
            Self::Explicit(s) => s.take_energy(),
        }
    }

    /// Iterations (Newton, or Gauss–Seidel sweeps) and halvings.
    pub fn counts(&self) -> (u64, u64) {
        match self {
            Self::Implicit(s, _) => s.counts(),
            Self::Explicit(s) => s.counts(),
        }
    }

    /// Factorizations of Newton's matrix (0 for the explicit scheme).
    pub fn factorizations(&self) -> u64 {
        match self {
            Self::Implicit(s, _) => s.factorizations(),
            Self::Explicit(_) => 0,
        }
    }

    /// The wheel.
    pub fn wheel(&self) -> &WheelMatrices {
        match self {
            Self::Implicit(s, _) => s.wheel(),
            Self::Explicit(s) => s.wheel(),
        }
    }
}
