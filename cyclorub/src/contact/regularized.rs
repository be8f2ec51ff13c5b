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

    /// [`force`](ContactLaw::force)'s arithmetic, the same operations in the
    /// same order (so the same bits), written without branches and compiled
    /// for the machine's vector instructions (chosen at run time): the law
    /// is a sixth of a mistuned full wheel's curve, and scalar `sqrt` and
    /// divisions were most of it. Where `force` takes another way (`γ² = 0`,
    /// `|κp/2| ≥ 1e150`, an input not finite) the signal goes through it.
    fn forces(&self, values: &mut [f64], slope: Option<&mut [f64]>) {
        let (kappa, gamma) = (self.stiffness, self.regularization);
        let arch = pulp::Arch::new();
        // A fold, not `all`: no early exit, so it vectorizes too.
        // `γ² > 0` (not only `γ > 0`: below 1.5e-162 its square is 0) keeps
        // the root at least γ, never 0 where `force` takes its kink's way.
        let ordinary = gamma * gamma > 0.0
            && arch.dispatch(|| {
                values
                    .iter()
                    .fold(true, |ok, q| ok & ((0.5 * kappa * q).abs() < 1e150))
            });
        match (ordinary, slope) {
            (true, Some(slope)) => arch.dispatch(|| {
                for (value, df) in values.iter_mut().zip(slope.iter_mut()) {
                    let (f, s) = smooth_force(kappa, gamma, *value);
                    (*value, *df) = (f, s);
                }
            }),
            (true, None) => arch.dispatch(|| {
                for value in values.iter_mut() {
                    *value = smooth_force(kappa, gamma, *value).0;
                }
            }),
            (false, Some(slope)) => {
                for (value, df) in values.iter_mut().zip(slope.iter_mut()) {
                    (*value, *df) = self.force(*value);
                }
            }
            (false, None) => {
                for value in values.iter_mut() {
                    *value = self.force(*value).0;
                }
            }
        }
    }
}

/// The regularized law's force and slope for `γ > 0` and `|κp/2| < 1e150`
/// (where `force` computes the root directly and it is never zero), both
/// sides of `p = 0` computed and one kept: a select, not a branch.
#[inline(always)]
fn smooth_force(kappa: f64, gamma: f64, penetration: f64) -> (f64, f64) {
    let half = 0.5 * kappa * penetration;
    let root = (half * half + gamma * gamma).sqrt();
    let above = half + root;
    let below = gamma * gamma / (root - half);
    let force = if half >= 0.0 { above } else { below };
    (force, 0.5 * kappa * (1.0 + half / root))
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

    /// Penetrations of every kind the law meets: deep in contact, far
    /// from it, near `p = 0` on both sides, exactly zero, and from a
    /// scrambled sequence (no two neighbours alike, as a vector loop sees).
    fn penetrations() -> Vec<f64> {
        let mut p = vec![
            0.0, -0.0, 1e-30, -1e-30, 2.5e-8, -2.5e-8, 1e-3, -1e-3, 1.0, -1.0,
        ];
        let mut state = 0x2545_f491_4f6c_dd1d_u64;
        for n in 0..4093 {
            state ^= state << 13;
            state ^= state >> 7;
            state ^= state << 17;
            let unit = (state >> 11) as f64 / (1u64 << 53) as f64 - 0.5;
            p.push(unit * 10f64.powi(-(n % 12)));
        }
        p
    }

    #[test]
    fn the_whole_signal_at_once_is_each_instant_bit_for_bit() {
        for (kappa, gamma) in [
            (1e8, 2.5),
            (1e5, 1e-3),
            (3.0, 1e3),
            (1e8, 0.0),
            (1e-170, 1e-170),
        ] {
            let law = RegularizedPenalty::new(kappa, gamma).unwrap();
            let p = penetrations();
            let (mut force, mut slope) = (p.clone(), vec![0.0; p.len()]);
            law.forces(&mut force, Some(&mut slope));
            let mut force_alone = p.clone();
            law.forces(&mut force_alone, None);
            for (n, &q) in p.iter().enumerate() {
                let (f, df) = law.force(q);
                assert_eq!(
                    force[n].to_bits(),
                    f.to_bits(),
                    "κ {kappa}, γ {gamma}, p {q}"
                );
                assert_eq!(
                    slope[n].to_bits(),
                    df.to_bits(),
                    "κ {kappa}, γ {gamma}, p {q}"
                );
                assert_eq!(force_alone[n].to_bits(), f.to_bits());
            }
        }
    }

    #[test]
    fn a_signal_with_a_huge_or_missing_input_is_each_instant_too() {
        let law = RegularizedPenalty::new(1e8, 2.5).unwrap();
        for odd in [1e145, -1e145, f64::NAN, f64::INFINITY] {
            let mut p = penetrations();
            p[17] = odd;
            let (mut force, mut slope) = (p.clone(), vec![0.0; p.len()]);
            law.forces(&mut force, Some(&mut slope));
            for (n, &q) in p.iter().enumerate() {
                let (f, df) = law.force(q);
                assert_eq!(force[n].to_bits(), f.to_bits(), "p {q}");
                assert_eq!(slope[n].to_bits(), df.to_bits(), "p {q}");
            }
        }
    }

    #[test]
    fn bad_parameters_are_refused_with_the_key() {
        let e = RegularizedPenalty::new(-1.0, 2.5).unwrap_err();
        assert!(e.to_string().contains("stiffness = -1"));
        let e = RegularizedPenalty::new(1.0, f64::NAN).unwrap_err();
        assert!(e.to_string().contains("regularization"));
    }
}
