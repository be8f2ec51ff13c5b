//! Helpers shared by the integration tests.

pub mod blade;
#[cfg(feature = "hdf5")]
pub mod h5py;
pub mod scalar_branch;
pub mod spectra;
