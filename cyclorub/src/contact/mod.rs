//! Contact laws: time samples of penetration in, forces and derivatives out.
//!
//! The gap at a contact node is `g = g0(t) − x`, `x` the displacement toward
//! the casing; the penetration is `p = −g`. The force on the structure is
//! `−f` along the normal, `f ≥ 0`. A law maps `p` to `(f, df/dp)` at one
//! instant; the AFT never knows which law it runs.

mod lagrangian;
mod regularized;

pub use lagrangian::DynamicLagrangian;
pub use regularized::RegularizedPenalty;

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

/// The contact treatment of a problem: a law evaluated instant by instant
/// inside the AFT (R-HBM), or the dynamic Lagrangian (DLFT-HBM).
#[derive(Clone, Debug)]
pub enum ContactModel {
    /// The regularized penalty law, Eq. (70).
    Regularized(RegularizedPenalty),
    /// The dynamic Lagrangian of DLFT-HBM, with its optional flexible wall.
    Lagrangian(DynamicLagrangian),
}

/// A normal contact law evaluated instant by instant.
pub trait ContactLaw: Send + Sync + std::fmt::Debug {
    /// The contact force `f ≥ 0` and its derivative `df/dp` at penetration `p`.
    fn force(&self, penetration: f64) -> (f64, f64);
    /// Whether the force is continuously differentiable in `p`.
    fn is_smooth(&self) -> bool {
        false
    }
}
