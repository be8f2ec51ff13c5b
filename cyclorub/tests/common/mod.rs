//! Helpers shared by the integration tests.

pub mod scalar_branch;
