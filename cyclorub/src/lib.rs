//! # cyclorub
//!
//! Nonlinear forced responses of bladed disks rubbing on their casing, by the
//! harmonic balance method condensed on the contact dofs, with the exact
//! cyclic-symmetry reductions of Vadcard, Quaegebeur & Thouverez (2024) and
//! their generalization (the symmetry rule).
//!
//! The modules follow the one-way flow of the method (see `docs/design.md`):
//! case file → [`model`] → [`basis`] → [`hbm`] residual (with a [`contact`]
//! law) → [`continuation`] → [`results`]. [`forced_response`] is the front
//! door (a case in, a branch in memory out); [`run::write`] writes a results
//! folder. [`mesh`] only writes model files (the open fan sector); the
//! solver never depends on it.
//!
//! Cargo features, both on by default: `plot` (the `plot` module: SVG
//! figures, `plots/` in a results folder) and `hdf5` (`results::hdf5`:
//! `results.h5`). Without them (`--no-default-features`) the solver builds
//! without plotters or an HDF5 library and a results folder holds the CSV
//! files and `run.json`. The application (the paper's reproduction, the
//! commented case templates, the plan tables, comparing results folders)
//! is the `cyclorub-app` crate, used by the command line.
#![warn(missing_docs)]
#![deny(clippy::float_cmp)]

pub mod basis;
pub mod branches;
pub mod case;
pub mod contact;
pub mod continuation;
pub mod cyclic;
pub mod forced_response;
pub mod hbm;
pub mod memory;
pub mod mesh;
pub mod model;
#[cfg(feature = "plot")]
pub mod plot;
pub mod results;
pub mod run;
pub mod simulate;
pub mod stability;
