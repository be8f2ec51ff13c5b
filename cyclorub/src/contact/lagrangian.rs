//! The dynamic Lagrangian of DLFT-HBM (Sec. 3.4.3), with the optional
//! flexible wall of Sec. 4.1.

use super::{ContactError, ContactLaw, LawInput, Smoothness, TimeScheme};

/// DLFT-HBM: the Lagrangian weight `ε` and, optionally, the stiffness `κ`
/// of a wall between the contact dof and the rigid casing.
///
/// With our signs (force on the structure `−f`, `f ≥ 0`; penetration
/// `p = x − g0`; linear residual `r = Z x − F`), the prediction is
/// `λ = −r + ε p` and the correction `f = max(0, λ)`, at each sampled
/// instant and sector. In the paper's signs (force `f_nl = −f ≤ 0`, gap
/// `g = −p`) this is `f_nl^p = (Z x − F) + ε g` and `f_nl = min(0, f_nl^p)`:
/// the paper's Eq. (71) prints `−ε ĝ`, which would push a penetrating node
/// further in. At convergence `λ = f + ε p` up to the harmonic truncation of
/// `f`, so contact (`λ > 0`) gives `p ≈ 0` and separation `p ≤ 0`; the
/// solution does not depend on `ε`.
///
/// The wall is a massless node joined to the contact dof by a spring `κ`;
/// the node touches the rigid casing (the linear part condenses it, see
/// `hbm::linear`). Absent, the casing is rigid and touches the contact dof
/// directly.
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

impl ContactLaw for DynamicLagrangian {
    /// The prediction `λ = ε p − ρ`.
    fn input(&self) -> LawInput {
        LawInput {
            penetration: self.epsilon,
            residual: -1.0,
        }
    }

    /// The correction `max(0, λ)`, of slope 1 in contact and 0 apart.
    fn force(&self, lambda: f64) -> (f64, f64) {
        if lambda > 0.0 {
            (lambda, 1.0)
        } else {
            (0.0, 0.0)
        }
    }

    /// Unilateral contact, held exactly by Lagrange multipliers in time.
    fn time_scheme(&self) -> TimeScheme {
        TimeScheme::ExplicitLagrange
    }

    /// Affine within a contact state: the residual tells its pieces.
    fn smoothness(&self) -> Smoothness {
        Smoothness::Piecewise
    }

    fn wall_stiffness(&self) -> Option<f64> {
        DynamicLagrangian::wall_stiffness(self)
    }

    /// In contact the casing holds the contact dof (through the wall of
    /// stiffness `κ` when there is one): a perturbation meets the spring
    /// `κ`, or, on a rigid casing, the constraint, which the penalty `ε`
    /// stands for (the constraint's exponents are its limit as `ε` grows).
    /// Apart, nothing.
    fn linearized_stiffness(&self, slope: f64) -> f64 {
        self.wall_stiffness.unwrap_or(self.epsilon) * slope
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

    #[test]
    fn the_correction_keeps_positive_multipliers_only() {
        let law = DynamicLagrangian::new(1e9, None).unwrap();
        assert_eq!(law.force(2.5), (2.5, 1.0));
        assert_eq!(law.force(-2.5), (0.0, 0.0));
        assert_eq!(law.force(0.0), (0.0, 0.0));
    }
}
