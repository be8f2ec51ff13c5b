//! Helpers shared by the integration tests.

pub mod blade;
pub mod branches;
#[cfg(feature = "hdf5")]
pub mod h5py;
pub mod periods;
pub mod scalar_branch;
pub mod spectra;
