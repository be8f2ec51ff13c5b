//! Harmonic balance: unknown layout, condensed linear part, AFT-CP and residual.

pub mod aft;
mod friction;
pub mod homotopy;
pub mod layout;
pub mod linear;
pub mod problem;
pub mod recovery;
pub mod residual;
mod sector_products;
pub(crate) mod sector_shifts;
mod wheel_jacobian;

pub use crate::cyclic::HarmonicSet;
pub use homotopy::LoadHomotopy;
pub use problem::{Casing, Forcing, Formulation, ProblemSpec};
pub use residual::{Along, ContactSamples, HarmonicBalance};

/// Errors of the harmonic balance problem.
#[derive(Debug, thiserror::Error)]
pub enum HbmError {
    /// Stopped from outside during an evaluation.
    #[error("the evaluation was interrupted")]
    Interrupted,
    /// The interior dynamic stiffness of a block cannot be inverted.
    #[error("the dynamic stiffness of harmonic {harmonic} ({block}) is singular at {} Hz (an undamped resonance of the dofs off contact, or a stiffness or frequency too large for floating point)", crate::hbm::layout::hertz(*frequency_hz))]
    SingularDynamicStiffness {
        /// Harmonic.
        harmonic: usize,
        /// Which block.
        block: String,
        /// Frequency.
        frequency_hz: f64,
    },
    /// The condensed linear system cannot be solved.
    #[error("the condensed linear system is singular at {frequency_hz:.6} Hz")]
    SingularLinearSystem {
        /// Frequency.
        frequency_hz: f64,
    },
    /// A dof number is beyond the sector's dofs.
    #[error("{key}: dof {} is out of range: a sector has dofs 1..={dofs}", dof + 1)]
    DofOutOfRange {
        /// Case-file key.
        key: &'static str,
        /// The dof (0-based).
        dof: usize,
        /// Dofs per sector.
        dofs: usize,
    },
    /// No contact dof.
    #[error("contact.dofs is empty: at least one contact dof is needed")]
    NoContactDofs,
    /// A contact dof listed twice.
    #[error("contact.dofs lists a dof twice")]
    RepeatedContactDof,
    /// The friction does not fit the contact dofs.
    #[error("{key}: {message}")]
    InvalidFriction {
        /// Case-file key.
        key: &'static str,
        /// What is wrong and what is allowed.
        message: String,
    },
    /// A preload that is not one finite force per sector dof.
    #[error("preload: {values} forces given for a sector of {dofs} dofs; give one finite force (N) per dof")]
    InvalidPreload {
        /// Forces given.
        values: usize,
        /// Dofs of a sector.
        dofs: usize,
    },
    /// Casing lists of the wrong length.
    #[error("casing: {gaps} gaps and {amplitudes} amplitudes given for {contact_dofs} contact dofs (give one value, or one per contact dof)")]
    CasingLength {
        /// Gaps given.
        gaps: usize,
        /// Amplitudes given.
        amplitudes: usize,
        /// Contact dofs.
        contact_dofs: usize,
    },
    /// `N_t < 2 N_h + 1`.
    #[error("harmonic_balance.time_samples = {time_samples} is too small: it must be at least 2 × harmonics + 1 = {}", 2 * harmonics + 1)]
    TooFewTimeSamples {
        /// `N_t`.
        time_samples: usize,
        /// `N_h`.
        harmonics: usize,
    },
    /// The problem would not fit in the memory it may take.
    #[error(
        "{key} = {value}: the problem is too large: {what} would take {gigabytes:.1} GB, above {limit}; \
         lower harmonic_balance.harmonics, harmonic_balance.time_samples, \
         contact.dofs or model.sectors, or choose a smaller basis (basis.kind)"
    )]
    TooLarge {
        /// The key that sizes the largest part.
        key: &'static str,
        /// Its value.
        value: usize,
        /// What takes the memory: unknowns, sector maps, time samples.
        what: String,
        /// The estimate, GB.
        gigabytes: f64,
        /// What it is above: the problem's limit or the memory available.
        limit: String,
    },
    /// The basis was built for another wheel or harmonic count.
    #[error("the basis is for {basis_sectors} sectors and {basis_harmonics} harmonics, the problem has {sectors} and {harmonics}")]
    BasisMismatch {
        /// Basis sectors.
        basis_sectors: usize,
        /// Basis harmonics.
        basis_harmonics: usize,
        /// Problem sectors.
        sectors: usize,
        /// Problem harmonics.
        harmonics: usize,
    },
    /// The basis lacks a pair the loads generate.
    #[error("the {kind} basis lacks the pair (s = {}, k = {}) that the loads generate: its solutions would not be solutions of the full problem", pair.nodal_diameter, pair.harmonic)]
    BasisMissesPair {
        /// The missing pair.
        pair: crate::cyclic::SignedPair,
        /// The basis kind.
        kind: String,
    },
    /// A mistuned wheel on a cyclic basis (issue 44).
    #[error(
        "basis.kind = \"{kind}\" cannot hold a mistuned wheel ([mistuning]): its sectors are no \
         longer alike, so the cyclic classes (nodal diameters) do not decouple and no reduced \
         basis is exact; solve it on the full wheel: basis.kind = \"physical\" (or \
         cyclorub run --basis physical)"
    )]
    MistunedReducedBasis {
        /// The basis asked for.
        kind: String,
    },
    /// The model failed.
    #[error(transparent)]
    Model(#[from] crate::model::ModelError),
    /// The basis failed.
    #[error(transparent)]
    Basis(#[from] crate::basis::BasisError),
    /// The load is invalid.
    #[error(transparent)]
    Load(#[from] crate::cyclic::LoadError),
    /// The residual holds NaN or infinity.
    #[error("the residual is not finite at {frequency_hz:.6} Hz")]
    NotFinite {
        /// Frequency.
        frequency_hz: f64,
    },
}
