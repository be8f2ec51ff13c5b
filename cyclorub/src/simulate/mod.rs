//! Time integration of the full wheel (`cyclorub simulate`): every sector in
//! physical coordinates, the case's excitation, casing and contact law, no
//! harmonic balance inside. It is the independent check of the periodic
//! solutions and of their stability, and it shows what the wheel does where
//! no periodic solution is stable (transients, modulation, localization).
//!
//! - [`wheel`]: the full wheel's mass, stiffness and damping as
//!   block-circulant operators (sparse in sectors: nothing of size `(N n)²`);
//! - [`circulant`]: solving with them, one `n × n` factorization per nodal
//!   diameter;
//! - [`loading`]: the excitation and the casing's gap per sector and
//!   instant;
//! - [`newmark`]: the implicit scheme for the regularized law of R-HBM
//!   (Newmark average acceleration, Newton with the law's analytic slope on
//!   the contact unknowns, step halving), with sliding friction when the
//!   case has it. It integrates the same law the
//!   harmonic balance solves, so a converged R-HBM point is a periodic
//!   solution of these equations up to the truncation in harmonics and
//!   the time step;
//! - [`lagrange`]: the explicit scheme for the unilateral contact that
//!   DLFT-HBM converges to (`law = "dlft"`): central differences with
//!   forward-increment Lagrange multipliers on a rigid casing (no
//!   penetration at any step, plastic impacts), or the wall of
//!   `wall_stiffness` in series, with sliding friction when the case has
//!   it; [`scheme`] picks the scheme from the law;
//! - [`start`]: the initial state, from rest or from a harmonic balance
//!   point rebuilt on every dof, optionally perturbed;
//! - [`spectrum`]: the amplitude spectra of the last periods per sector;
//! - [`output`]: `simulation.csv`, `simulation.json`, `simulation.h5`
//!   (feature `hdf5`) and the figures (feature `plot`: envelope, time
//!   history, spectrum, waterfall over sectors);
//! - [`run`]: the loop over excitation periods, the per-period envelope,
//!   the Poincaré section and the steady-state detection;
//! - [`attractor`]: what the wheel settled to (periodic, modulated, not
//!   settled), from the per-period maxima.
//!
//! Sectors and dofs are 0-based in the library, 1-based in files and on
//! the command line.

pub mod attractor;
pub mod circulant;
#[cfg(feature = "hdf5")]
pub mod hdf5;
pub mod lagrange;
pub mod loading;
pub mod newmark;
mod newton_system;
pub mod output;
pub mod run;
pub mod scheme;
pub mod setup;
pub mod spectrum;
pub mod start;
pub mod state;
pub mod wheel;

pub use attractor::Attractor;
pub use loading::WheelLoads;
pub use newmark::{Newmark, NewtonSettings};
pub use run::{Ending, History, PeriodRecord, Simulation, SimulationOutcome, SimulationSettings};
pub use setup::WheelSetup;
pub use start::{Perturbation, PerturbationPattern};
pub use state::{Drive, EnergyTally, State};
pub use wheel::{CirculantMatrix, WheelMatrices};

/// Errors of a time integration.
#[derive(Debug, thiserror::Error)]
pub enum SimulateError {
    /// Arguments or settings that do not fit (the message names them).
    #[error("{0}")]
    Input(String),
    /// A dof number beyond the sector's dofs.
    #[error("{key}: dof {dof} is out of range: a sector has dofs 1..={dofs}")]
    DofOutOfRange {
        /// The key or flag.
        key: &'static str,
        /// The dof (1-based).
        dof: usize,
        /// Dofs per sector.
        dofs: usize,
    },
    /// A matrix of the step is not positive definite.
    #[error("the full wheel's matrix of nodal diameter {nodal_diameter} is not positive definite (is the mass matrix positive definite, the stiffness and damping positive semi-definite?)")]
    NotPositiveDefinite {
        /// The nodal diameter.
        nodal_diameter: usize,
    },
    /// The explicit scheme's step is above its stability bound.
    #[error("--steps-per-period: the explicit scheme (law = \"dlft\") is stable below h = 2/ω_max = {bound_s:.3e} s (highest natural frequency {highest_hz:.1} Hz); the step is {step_s:.3e} s")]
    StepTooLong {
        /// The step asked for, s.
        step_s: f64,
        /// The longest step the scheme takes (0.9 of the bound), s.
        largest_s: f64,
        /// `2/ω_max`, s.
        bound_s: f64,
        /// The wheel's highest natural frequency, Hz.
        highest_hz: f64,
    },
    /// The state stopped being finite (nothing of it is written).
    #[error("the integration diverged at t = {time:.6e} s (period {period}): the state is no longer finite; nothing is written. Start closer to the wheel's own amplitudes (a smaller --perturb), or give more --steps-per-period")]
    Diverged {
        /// Time of the first step whose state is not finite, s.
        time: f64,
        /// The period it belongs to (from 1).
        period: usize,
    },
    /// Newton failed even on the smallest step.
    #[error("Newton on the contact forces failed at t = {time:.6e} s after {halvings} halvings of the step: give more --steps-per-period")]
    NewtonFailed {
        /// Time of the failing step, s.
        time: f64,
        /// Halvings tried.
        halvings: usize,
    },
    /// A file could not be written.
    #[error("cannot write {path}: {message}")]
    Write {
        /// The path.
        path: std::path::PathBuf,
        /// Why.
        message: String,
    },
    /// The case is invalid.
    #[error(transparent)]
    Case(#[from] crate::case::CaseError),
    /// The model failed.
    #[error(transparent)]
    Model(#[from] crate::model::ModelError),
    /// The harmonic balance point could not be rebuilt.
    #[error(transparent)]
    Hbm(#[from] crate::hbm::HbmError),
    /// The sizes would not fit in memory (the message names the key or
    /// option, the estimate and what fits).
    #[error(transparent)]
    TooLarge(#[from] crate::memory::TooMuchMemory),
}

impl SimulateError {
    /// Whether the error is in what the user gave.
    pub fn is_input_error(&self) -> bool {
        match self {
            Self::Input(_) | Self::DofOutOfRange { .. } | Self::StepTooLong { .. } => true,
            Self::Model(e) => e.is_input_error(),
            Self::Case(_) | Self::TooLarge(_) => true,
            _ => false,
        }
    }
}
