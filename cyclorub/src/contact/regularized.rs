//! The regularized penalty law of R-HBM, Eq. (70).

use super::{ContactError, ContactLaw, LawInput, Smoothness, TimeScheme};

/// `f = κp/2 + sqrt((κp/2)² + γ²)` with penetration `p`; `γ = 0` is the plain
/// penalty law `κ max(p, 0)` (the unilateral spring of other HBM tools).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct RegularizedPenalty {
    stiffness: f64,
    regularization: f64,
}

impl RegularizedPenalty {
    /// A law of contact stiffness `κ > 0` (N/m) and regularization `γ ≥ 0` (N).
    pub fn new(stiffness: f64, regularization: f64) -> Result<Self, ContactError> {
        if !(stiffness.is_finite() && stiffness > 0.0) {
            return Err(ContactError::InvalidParameter {
                key: "stiffness",
                value: stiffness,
                allowed: "the contact stiffness κ must be a finite number > 0 (N/m)",
            });
        }
        // γ is the force at zero penetration and γ² enters the law: beyond
        // LARGEST_REGULARIZATION it overflows (a hostile run's 1e300 gave a
        // residual "not finite" at the first point, naming nothing).
        if !(regularization.is_finite() && (0.0..=LARGEST_REGULARIZATION).contains(&regularization))
        {
            return Err(ContactError::InvalidParameter {
                key: "regularization",
                value: regularization,
                allowed: "the regularization γ (the contact force at zero penetration) must be a \
                          finite number from 0 to 1e150 N (its square enters the law)",
            });
        }
        Ok(Self {
            stiffness,
            regularization,
        })
    }

    /// Contact stiffness κ, N/m.
    pub fn stiffness(&self) -> f64 {
        self.stiffness
    }

    /// Regularization γ, N.
    pub fn regularization(&self) -> f64 {
        self.regularization
    }
}

/// The largest regularization `γ` (N): `γ²` stays finite with room.
pub const LARGEST_REGULARIZATION: f64 = 1e150;

impl ContactLaw for RegularizedPenalty {
    /// The penetration alone.
    fn input(&self) -> LawInput {
        LawInput::PENETRATION
    }

    /// A force of the penetration: Newton at each implicit step.
    fn time_scheme(&self) -> TimeScheme {
        TimeScheme::Implicit
    }

    /// Smooth for `γ > 0`; the plain penalty law has a kink at `p = 0`.
    fn smoothness(&self) -> Smoothness {
        if self.regularization > 0.0 {
            Smoothness::Smooth
        } else {
            Smoothness::Nonsmooth
        }
    }

    fn force(&self, penetration: f64) -> (f64, f64) {
        let half = 0.5 * self.stiffness * penetration;
        // sqrt(a² + b²) directly: `hypot` guards against overflow that
        // cannot happen below |κp/2| ~ 1e150, and costs a quarter of a
        // curve's time in the contact loop.
        let root = if half.abs() < 1e150 {
            (half * half + self.regularization * self.regularization).sqrt()
        } else {
            half.hypot(self.regularization)
        };
        if root == 0.0 {
            // γ = 0 at p = 0: the kink of the penalty law; take the mean slope.
            return (0.0, 0.5 * self.stiffness);
        }
        // Written to avoid cancellation when p ≪ 0: f = γ² / (root − half).
        let force = if half >= 0.0 {
            half + root
        } else {
            self.regularization * self.regularization / (root - half)
        };
        let slope = 0.5 * self.stiffness * (1.0 + half / root);
        (force, slope)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_regularization_whose_square_overflows_is_refused_by_name() {
        let error = RegularizedPenalty::new(1e8, 1e300).unwrap_err().to_string();
        assert!(
            error.contains("regularization") && error.contains("1e150"),
            "{error}"
        );
        // The largest allowed gives finite forces across the penetrations.
        let law = RegularizedPenalty::new(1e8, LARGEST_REGULARIZATION).unwrap();
        for p in [-1e3, -1e-3, 0.0, 1e-3, 1e3] {
            let (force, slope) = law.force(p);
            assert!(
                force.is_finite() && slope.is_finite(),
                "{p}: {force} {slope}"
            );
        }
    }

    #[test]
    fn derivative_matches_central_differences() {
        let law = RegularizedPenalty::new(1e8, 2.5).unwrap();
        for &p in &[-1e-3, -1e-7, -2e-8, 0.0, 3e-8, 1e-6, 1e-3] {
            let h = 1e-12_f64.max(1e-6 * f64::abs(p));
            let (fp, _) = law.force(p + h);
            let (fm, _) = law.force(p - h);
            let (_, d) = law.force(p);
            let fd = (fp - fm) / (2.0 * h);
            assert!(
                (fd - d).abs() <= 1e-6 * d.abs().max(1.0),
                "p={p} fd={fd} d={d}"
            );
        }
    }

    #[test]
    fn zero_regularization_is_the_penalty_law() {
        let law = RegularizedPenalty::new(2.0, 0.0).unwrap();
        assert!(law.force(-1.0).0.abs() < f64::MIN_POSITIVE);
        assert!((law.force(3.0).0 - 6.0).abs() < 1e-15);
    }

    #[test]
    fn far_from_contact_the_force_is_tiny_and_positive() {
        let law = RegularizedPenalty::new(1e8, 2.5).unwrap();
        let (f, _) = law.force(-1e-3);
        let expected = 2.5 * 2.5 / 1e5; // γ²/(κ|p|) to first order
        assert!(f > 0.0 && (f - expected).abs() < 1e-6 * expected);
    }

    #[test]
    fn bad_parameters_are_refused_with_the_key() {
        let e = RegularizedPenalty::new(-1.0, 2.5).unwrap_err();
        assert!(e.to_string().contains("stiffness = -1"));
        let e = RegularizedPenalty::new(1.0, f64::NAN).unwrap_err();
        assert!(e.to_string().contains("regularization"));
    }
}
