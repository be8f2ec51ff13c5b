//! Sector models: one matrix set per signed nodal diameter, and the full wheel.
//!
//! A sector is described once, as a block-circulant sector (within-sector
//! blocks and coupling to the next sector, e.g. the paper's academic chain,
//! [`LumpedSector`]) or as a finite-element sector (matrices with left and
//! right cyclic boundary dofs, e.g. imported from Matrix Market files). From
//! that one description come, for every signed nodal diameter `s`, Hermitian
//! `M(s)`, `K(s)`, `C(s)` ([`SectorModel::nodal_diameter_matrices`]) and the
//! real matrices of the assembled full wheel ([`SectorModel::full_wheel`]).
//!
//! **Sign convention** (docs/design.md §2): the signed pair `(s, k)` is the wave
//! `exp(i(kωt − sα(j−1)))`, `α = 2π/N`, sectors `j = 1..N`. For the sector
//! pattern `x_j = X·exp(−isα(j−1))`, the full-wheel matrices give on sector 1
//! exactly `K(s) X`. Hence `K(s) = K0 + K1·exp(−iαs) + K1ᵀ·exp(iαs)` for a
//! block-circulant sector and `u_R = exp(−iαs)·u_L` for a finite-element
//! sector. `M(−s) = conj(M(s))`; `K(0)` and `K(N/2)` are real.
//!
//! In the library dofs are 0-based; in case files they are 1-based.

mod academic;
pub mod craig_bampton;
mod damping;
mod eigen;
pub(crate) use eigen::self_adjoint_eigen_by_qr;
mod error;
mod input;
mod matrices;
mod matrix_market;
mod mistuning;
mod sector;
mod spec;
mod validate;
mod wheel_modes;

pub use academic::{
    LumpedSector, Spring, SpringLink, ACADEMIC_CONTACT_DOF, ACADEMIC_MASSES, ACADEMIC_STIFFNESSES,
};
pub use damping::{Damping, ModalDamping};
pub use error::ModelError;
pub use input::{SectorInput, Subject};
pub use matrices::{FullWheelMatrices, NodalDiameterMatrices};
pub use matrix_market::{
    parse_matrix_market, read_matrix_market, read_matrix_market_sparse, MATRIX_MARKET_MAX_ROWS,
};
pub use mistuning::{generate_deviations, DeviationDistribution, Mistuning, ReducedBlade};
pub use sector::{
    Axis, BlockCirculantSector, BoundaryFrame, FiniteElementSector, SectorModel,
    FULL_WHEEL_MAX_DOFS, MAX_SECTORS, SECTOR_MAX_DOFS,
};
pub use spec::{
    DampingKind, DampingSpec, ModelKind, ModelSpec, SpringLinkSpec, SpringSpec, StaticPreload,
};
pub use validate::{DEFAULT_SYMMETRY_TOLERANCE, MAX_SYMMETRY_TOLERANCE};
pub use wheel_modes::WheelMode;
