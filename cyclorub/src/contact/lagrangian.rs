//! The dynamic Lagrangian of DLFT-HBM (Sec. 3.4.3), with the optional
//! flexible wall of Sec. 4.1.
//!
//! Unlike a law, the dynamic Lagrangian is not a function of the
//! penetration alone: its prediction uses the linear residual, so it is
//! evaluated by the residual itself (see `hbm::residual`). This type only
//! holds and checks its parameters.

use super::ContactError;

/// DLFT-HBM parameters: the Lagrangian weight `ε` and, optionally, the
/// stiffness `κ` of a wall between the contact dof and the rigid casing.
///
/// With our signs (force on the structure `−f`, `f ≥ 0`; penetration
/// `p = x − g0`), the prediction is `λ = −(Z x − F) + ε p` and the
/// correction `f = max(0, λ)`, at each sampled instant and sector. The wall
/// is a massless node joined to the contact dof by a spring `κ`; the node
/// touches the rigid casing. Absent, the casing is rigid and touches the
/// contact dof directly.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct DynamicLagrangian {
    epsilon: f64,
    wall_stiffness: Option<f64>,
}

impl DynamicLagrangian {
    /// A dynamic Lagrangian of weight `ε > 0` (N/m) and, if given, a wall
    /// of stiffness `κ > 0` (N/m).
    pub fn new(epsilon: f64, wall_stiffness: Option<f64>) -> Result<Self, ContactError> {
        if !(epsilon.is_finite() && epsilon > 0.0) {
            return Err(ContactError::InvalidParameter {
                key: "epsilon",
                value: epsilon,
                allowed: "the Lagrangian weight ε must be a finite number > 0 (N/m)",
            });
        }
        if let Some(kappa) = wall_stiffness {
            if !(kappa.is_finite() && kappa > 0.0) {
                return Err(ContactError::InvalidParameter {
                    key: "wall_stiffness",
                    value: kappa,
                    allowed: "the wall stiffness κ must be a finite number > 0 (N/m); leave it out for a rigid casing",
                });
            }
        }
        Ok(Self {
            epsilon,
            wall_stiffness,
        })
    }

    /// The Lagrangian weight `ε`, N/m.
    pub fn epsilon(&self) -> f64 {
        self.epsilon
    }

    /// The wall stiffness `κ`, N/m (`None`: rigid casing).
    pub fn wall_stiffness(&self) -> Option<f64> {
        self.wall_stiffness
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn parameters_are_checked_with_their_key() {
        let law = DynamicLagrangian::new(1e9, Some(1e8)).unwrap();
        assert!((law.epsilon() - 1e9).abs() < 1e-6);
        assert!(law.wall_stiffness().is_some_and(|k| (k - 1e8).abs() < 1e-6));
        assert_eq!(
            DynamicLagrangian::new(1e9, None).unwrap().wall_stiffness(),
            None
        );
        let e = DynamicLagrangian::new(0.0, None).unwrap_err();
        assert!(e.to_string().contains("epsilon = 0"), "{e}");
        let e = DynamicLagrangian::new(f64::INFINITY, None).unwrap_err();
        assert!(e.to_string().contains("epsilon"), "{e}");
        let e = DynamicLagrangian::new(1e9, Some(-2.0)).unwrap_err();
        assert!(e.to_string().contains("wall_stiffness = -2"), "{e}");
        let e = DynamicLagrangian::new(1e9, Some(f64::NAN)).unwrap_err();
        assert!(e.to_string().contains("wall_stiffness"), "{e}");
    }
}
