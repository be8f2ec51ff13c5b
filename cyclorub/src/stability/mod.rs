//! Stability of the periodic solutions by Hill's method, per symmetry class
//! (docs/design.md §10).
//!
//! A point of a branch is an exact periodic solution of the full wheel; a
//! small perturbation `y(t) = e^{λt} Σ_k q_k e^{ikωt}` of every dof of every
//! sector grows when an exponent `λ` has `Re λ > 0`. The contact force is
//! linearized at the point, instant by instant and sector by sector, as
//! the stiffness its law adds to the contact dof
//! ([`ContactLaw::linearized_stiffness`](crate::contact::ContactLaw)):
//! - the regularized penalty law (R-HBM): its slope `df/dp`;
//! - the dynamic Lagrangian (DLFT-HBM): in contact the casing holds the
//!   contact dof, through the wall `κ` when there is one (the stiffness is
//!   then `κ`); on a rigid casing the constraint is stood for by the
//!   penalty `ε` (its exponents tend to the constrained ones as `ε` grows,
//!   so choose `ε` well above the structure's stiffness, as the paper's
//!   `1e9` is); apart, nothing.
//!
//! Sliding friction adds, at each friction node, the linearization of
//! `μ f_N t(w)` ([`ContactTerm`]): `μ k_N t` from the normal dof onto the
//! tangential ones, and the damping `μ f_N ∂t/∂w` between the tangential
//! velocities. The condensed solver holds them; the targeted solver and
//! the weak-contact shortcut hold the normal stiffness alone (with
//! friction the targeted solver gives way to the dense one, and only a
//! point with no contact takes the linear wheel's exponents); a wall in
//! series with friction is refused.
//!
//! The dynamics are not condensed on the contact dofs (that would make the
//! eigenproblem nonlinear in `λ`): each class's Hill matrix holds every dof
//! of a sector for each of its pairs. The classes are the cosets of the
//! solution's pair subgroup ([`classes`]): block `σ = 0` is the reduced
//! problem's own stability (its real crossings are the folds of the
//! branch); the others are the perturbations that break the symmetry,
//! which no reduced run sees. Their union is the full wheel's spectrum,
//! which [`Stability::full_wheel`] computes without symmetry as the
//! reference.

mod analysis;
mod classes;
pub mod condensed;
mod contact_stiffness;
mod hill;
mod markers;
mod modes;
mod off_contact;
mod settings;
mod small_lu;
mod spectrum;
mod targeted;
mod validated;
mod vectors;

pub use analysis::Stability;
pub use classes::{pairs_per_class, symmetry_classes, SymmetryClass};
pub use condensed::Following;
pub use contact_stiffness::{
    ContactStiffness, ContactTerm, SpaceTimeTable, StiffnessSpectrum, TermKind,
};
pub use markers::{
    crossing_kind, frequency_turns, group_events, markers, multiplier_angle, nodal_diameters,
    BranchStability, Location, Marker, MarkerKind, EVENT_GROUPING, REAL_ANGLE,
};
pub use modes::FloquetMode;
pub use settings::{HillSolver, StabilitySettings};
pub use spectrum::{ClassSpectrum, Exponent, PointStability};

/// Errors of the stability check.
#[derive(Debug, thiserror::Error)]
pub enum StabilityError {
    /// A setting out of range.
    #[error("{key} = {value}: {allowed}")]
    Setting {
        /// The key or argument.
        key: &'static str,
        /// The value given.
        value: String,
        /// What is allowed.
        allowed: &'static str,
    },
    /// No symmetry class of that nodal diameter.
    #[error("there is no symmetry class {class}: the classes are {available}")]
    NoClass {
        /// The class asked for.
        class: i64,
        /// The classes there are.
        available: String,
    },
    /// Friction with a wall in series: the wall's tangential springs are
    /// not in Hill's matrices (a defensive check: the harmonic balance
    /// refuses that problem first).
    #[error("stability with friction (contact.friction) and a wall (contact.wall_stiffness) is not available: Hill's matrices hold the friction of a node on a rigid casing or with the regularized law; set [stability] enabled = false or run with --no-stability")]
    Friction,
    /// The model and the problem do not describe the same wheel.
    #[error("the stability check was given {message}")]
    Mismatch {
        /// What differs.
        message: String,
    },
    /// A mass matrix is not positive definite (Hill's method needs `M⁻¹`).
    #[error("the mass matrix of {what} is not positive definite: every dof needs mass for the stability check")]
    SingularMass {
        /// Which matrices.
        what: String,
    },
    /// One class's eigenproblem is larger than allowed.
    #[error("the stability eigenproblem of one class has size {size}, above the limit {limit}: lower [stability] harmonics (now {harmonics}), or solve on a cyclic basis (the symmetry rule), whose classes are smaller")]
    TooLarge {
        /// `2 · dofs · pairs`.
        size: usize,
        /// The limit.
        limit: usize,
        /// Hill's harmonics.
        harmonics: usize,
    },
    /// The eigenvalue solver failed.
    #[error("the eigenvalue solver of the stability check failed: {message}")]
    Eigen {
        /// What it said.
        message: String,
    },
    /// NaN or infinity where a number was expected.
    #[error("{what} is not finite at {frequency_hz:.6} Hz")]
    NotFinite {
        /// What.
        what: &'static str,
        /// Frequency.
        frequency_hz: f64,
    },
    /// Stopped from outside before every point was checked.
    #[error("the stability check was interrupted")]
    Interrupted,
    /// The residual failed.
    #[error(transparent)]
    Hbm(#[from] crate::hbm::HbmError),
    /// The model failed.
    #[error(transparent)]
    Model(#[from] crate::model::ModelError),
    /// The basis failed.
    #[error(transparent)]
    Basis(#[from] crate::basis::BasisError),
}
