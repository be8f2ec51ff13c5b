//! Contact laws: what a law reads at each sampled instant, the force it
//! gives and its derivative; and the casing that sets the gap.
//!
//! The gap at a contact node is `g = g0(t) − x`, `x` the displacement toward
//! the casing; the penetration is `p = −g`. The force on the structure is
//! `−f` along the normal, `f ≥ 0`.
//!
//! Every law reads, at each sampled instant, one number
//! `q = a p + b ρ` (its [`LawInput`]): `p` the penetration and `ρ` the
//! sample of the linear residual `r = Z x − F` (the force that equilibrium
//! asks of the contact is `−r`). A law maps `q` to `(f, df/dq)` and is in
//! contact when `q > 0`:
//! - the regularized penalty law (R-HBM) reads the penetration (`a = 1`,
//!   `b = 0`);
//! - the dynamic Lagrangian (DLFT-HBM) reads its prediction
//!   `λ = ε p − ρ` (`a = ε`, `b = −1`) and corrects it to `max(0, λ)`.
//!
//! With `q` formed in the unknowns' space as `v = a x + b r` and sampled as
//! `q(τ) = v(τ) − a g0(τ)`, the residual `R = r + G̃ F[f(q)]` has one
//! Jacobian for every law (`T = F diag(df/dq) F⁻¹`, `Ḡ`, `G̃` the maps to
//! and from the sampled sectors): `∂R/∂x = Z + G̃ T Ḡ (a I + b Z)` and
//! `∂R/∂ω = ∂r/∂ω + b G̃ T Ḡ ∂r/∂ω`. The harmonic balance residual and the
//! recovery of results call the same [`ContactLaw::apply`]: a new law is one file
//! implementing [`ContactLaw`].

mod casing;
mod friction;
mod lagrangian;
mod regularized;

pub use casing::Casing;
pub use friction::{sliding_direction, FrictionNode, RotationSpeed, SlidingFriction};
pub use lagrangian::DynamicLagrangian;
pub use regularized::RegularizedPenalty;

use std::sync::Arc;

/// Errors in the contact parameters.
#[derive(Debug, thiserror::Error, PartialEq)]
pub enum ContactError {
    /// A parameter is negative or not finite.
    #[error("[contact] {key} = {value}: {allowed}")]
    InvalidParameter {
        /// The case-file key.
        key: &'static str,
        /// The value given.
        value: f64,
        /// What is allowed.
        allowed: &'static str,
    },
}

/// The weights of what a law reads at each instant, `q = a p + b ρ` (see
/// the module documentation).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct LawInput {
    /// `a`, the weight of the penetration.
    pub penetration: f64,
    /// `b`, the weight of the linear residual `Z x − F` (0 for a law of the
    /// penetration alone).
    pub residual: f64,
}

impl LawInput {
    /// A law of the penetration alone (`a = 1`, `b = 0`).
    pub const PENETRATION: Self = Self {
        penetration: 1.0,
        residual: 0.0,
    };

    /// Whether the law reads the linear residual (then the input of a point
    /// needs `Z(ω)`, not only the unknowns).
    pub fn reads_residual(&self) -> bool {
        self.residual != 0.0
    }

    /// The input `q = v − a g0` at one instant from the sample `v` of
    /// `a x + b r` and the gap `g0`; the law is in contact when `q > 0`.
    pub fn at(&self, v: f64, gap: f64) -> f64 {
        v - self.penetration * gap
    }
}

/// How smooth the residual of a law is, which decides how continuation
/// goes past its corners.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Smoothness {
    /// Continuously differentiable: every turn of a branch resolves with a
    /// short enough step.
    Smooth,
    /// Affine in the unknowns within one contact state (the set of sampled
    /// instants in contact), which names the smooth piece a point is on
    /// (DLFT-HBM).
    Piecewise,
    /// Kinks that the law does not name (the plain penalty law, `γ = 0`).
    Nonsmooth,
}

/// The time integration a law needs (`cyclorub simulate`): each law says
/// which, so that a new law is never integrated by a scheme meant for
/// another (what it reads is not what decides).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum TimeScheme {
    /// An implicit scheme (Newmark average acceleration) with Newton on the
    /// contact unknowns at each step: for a law that gives a force and its
    /// derivative from the penetration, smooth enough for Newton (the
    /// regularized penalty law).
    Implicit,
    /// An explicit scheme (central differences) with forward-increment
    /// Lagrange multipliers: for a law that holds the contact dof on the
    /// casing exactly (unilateral contact, the dynamic Lagrangian), whose
    /// force is a multiplier rather than a function of the penetration.
    ExplicitLagrange,
}

impl std::fmt::Display for TimeScheme {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(match self {
            Self::Implicit => "the implicit scheme (Newmark average acceleration with Newton)",
            Self::ExplicitLagrange => {
                "the explicit scheme (central differences with Lagrange multipliers)"
            }
        })
    }
}

/// A normal contact law evaluated instant by instant (see the module
/// documentation for what it reads).
pub trait ContactLaw: Send + Sync + std::fmt::Debug {
    /// What the law reads at each instant.
    fn input(&self) -> LawInput;
    /// The time integration the law needs (no default: a new law says).
    fn time_scheme(&self) -> TimeScheme;
    /// The contact force `f ≥ 0` and its derivative `df/dq` for the input `q`.
    fn force(&self, input: f64) -> (f64, f64);
    /// [`force`](Self::force) at every instant of a signal: each `values[n]`
    /// (an input `q`) replaced by its force, and `slope[n] = df/dq` when
    /// given (as long as `values`). A law overrides it where a loop over
    /// the whole signal computes faster, with the same bits.
    fn forces(&self, values: &mut [f64], slope: Option<&mut [f64]>) {
        match slope {
            Some(slope) => {
                for (value, df) in values.iter_mut().zip(slope.iter_mut()) {
                    (*value, *df) = self.force(*value);
                }
            }
            None => {
                for value in values.iter_mut() {
                    *value = self.force(*value).0;
                }
            }
        }
    }
    /// How smooth the residual is.
    fn smoothness(&self) -> Smoothness;
    /// The stiffness of a wall in series between the contact dof and the
    /// casing, N/m (`None`: the contact dof touches the casing).
    fn wall_stiffness(&self) -> Option<f64> {
        None
    }
    /// The stiffness the law adds to its contact dof for a small
    /// perturbation of the structure at an instant where the law's slope is
    /// `slope = df/dq` (stability, [`crate::stability`]): `∂f/∂p = a ·
    /// df/dq` with the linear residual held, by default.
    fn linearized_stiffness(&self, slope: f64) -> f64 {
        self.input().penetration * slope
    }

    /// The law at every instant of one signal: with `reading[n] = v(τ_n)`
    /// (the samples of `v = a x + b r`, see the module documentation) and the
    /// gap `gap[n] = g0(τ_n)`, the input is `q = v − a g0`; fills
    /// `force[n] = f(q)` and, if given, `slope[n] = df/dq`; continues the
    /// contact state's hash `hash` (start from [`EMPTY_STATE`]) when given.
    /// Provided, so compiled for each law: a call through `dyn ContactLaw`
    /// costs one dispatch per signal, not one per instant. The residual and
    /// the recovery both call it.
    fn apply(
        &self,
        reading: &[f64],
        gap: &[f64],
        force: &mut [f64],
        slope: Option<&mut [f64]>,
        hash: Option<u64>,
    ) -> SignalContact {
        let input = self.input();
        let mut state = hash.unwrap_or(EMPTY_STATE);
        let mut instants_in_contact = 0;
        // The inputs first (with the contact state), then the law over the
        // whole signal: a loop with no state carried from one instant to
        // the next, which [`forces`](Self::forces) may vectorize.
        // The shortest of the signals given, as zipping them all would.
        let instants = reading
            .len()
            .min(gap.len())
            .min(force.len())
            .min(slope.as_ref().map_or(usize::MAX, |s| s.len()));
        let force = &mut force[..instants];
        for ((v, g), f) in reading.iter().zip(gap).zip(force.iter_mut()) {
            let q = input.at(*v, *g);
            instants_in_contact += usize::from(q > 0.0);
            *f = q;
        }
        // The hash chains instant to instant: a loop of its own, only
        // when asked (the piecewise laws' contact states).
        if hash.is_some() {
            for q in force.iter() {
                state = (state ^ u64::from(*q > 0.0)).wrapping_mul(0x0100_0000_01b3);
            }
        }
        match slope {
            Some(slope) => self.forces(force, Some(&mut slope[..instants])),
            None => self.forces(force, None),
        }
        SignalContact {
            instants_in_contact,
            state,
        }
    }
}

/// The contact treatments a case file can name.
#[derive(Clone, Debug)]
pub enum ContactModel {
    /// The regularized penalty law, Eq. (70).
    Regularized(RegularizedPenalty),
    /// The dynamic Lagrangian of DLFT-HBM, with its optional flexible wall.
    Lagrangian(DynamicLagrangian),
}

impl ContactModel {
    /// The law, for the residual and the recovery.
    pub fn law(&self) -> Arc<dyn ContactLaw> {
        match self {
            ContactModel::Regularized(law) => Arc::new(*law),
            ContactModel::Lagrangian(law) => Arc::new(*law),
        }
    }
}

/// What [`ContactLaw::apply`] found on one signal.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct SignalContact {
    /// Instants in contact (`q > 0`).
    pub instants_in_contact: usize,
    /// An FNV-1a hash of which instants are in contact (only when asked).
    pub state: u64,
}

/// The FNV-1a offset basis: the state hash of no instant.
pub const EMPTY_STATE: u64 = 0xcbf2_9ce4_8422_2325;

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn each_law_names_the_time_scheme_it_needs() {
        let regularized = RegularizedPenalty::new(1e8, 2.5).expect("law");
        let lagrangian = DynamicLagrangian::new(1e9, None).expect("law");
        assert_eq!(regularized.time_scheme(), TimeScheme::Implicit);
        assert_eq!(lagrangian.time_scheme(), TimeScheme::ExplicitLagrange);
        // Through the case file's contact models, as simulate receives them.
        let model = ContactModel::Lagrangian(lagrangian);
        assert_eq!(model.law().time_scheme(), TimeScheme::ExplicitLagrange);
        assert!(TimeScheme::ExplicitLagrange
            .to_string()
            .contains("Lagrange multipliers"));
    }

    #[test]
    fn the_penetration_law_reads_v_minus_the_gap() {
        let law = RegularizedPenalty::new(2.0, 0.0).unwrap();
        let mut force = [0.0; 3];
        let mut slope = [0.0; 3];
        let found = law.apply(
            &[1.0, 3.0, 0.5],
            &[2.0, 2.0, 0.5],
            &mut force,
            Some(&mut slope),
            None,
        );
        // Exact: a plain penalty law of stiffness 2 on penetrations 0, 1, 0.
        assert_eq!(force.map(f64::to_bits), [0.0, 2.0, 0.0].map(f64::to_bits));
        assert_eq!(slope[1].to_bits(), 2.0_f64.to_bits());
        assert_eq!(found.instants_in_contact, 1);
        assert_eq!(found.state, EMPTY_STATE, "no hash asked");
    }

    #[test]
    fn the_lagrangian_reads_its_prediction_minus_epsilon_gaps() {
        let law = DynamicLagrangian::new(10.0, None).unwrap();
        let mut force = [0.0; 2];
        // q = v − ε g: 5 − 10·0.2 = 3 in contact; 1 − 10·0.2 = −1 separated.
        let found = law.apply(&[5.0, 1.0], &[0.2, 0.2], &mut force, None, Some(0));
        assert_eq!(force.map(f64::to_bits), [3.0, 0.0].map(f64::to_bits));
        assert_eq!(found.instants_in_contact, 1);
        let other = law.apply(&[1.0, 5.0], &[0.2, 0.2], &mut force, None, Some(0));
        assert_ne!(found.state, other.state, "the hash tells which instants");
    }
}
