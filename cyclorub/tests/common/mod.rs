//! Helpers shared by the integration tests.

pub mod blade;
pub mod scalar_branch;
pub mod spectra;
