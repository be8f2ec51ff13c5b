//! # cyclorub
//!
//! Nonlinear forced responses of bladed disks rubbing on their casing, by the
//! harmonic balance method condensed on the contact dofs, with the exact
//! cyclic-symmetry reductions of Vadcard, Quaegebeur & Thouverez (2024) and
//! their generalization (the symmetry rule).
//!
//! The modules follow the one-way flow of the method (see `DESIGN.md`):
//! case file → [`model`] → [`basis`] → [`hbm`] residual (with a [`contact`]
//! law) → [`continuation`] → [`results`]; [`reproduce`] runs the paper's
//! studies on every basis and checks the reductions against the full wheel.
#![warn(missing_docs)]
#![deny(clippy::float_cmp)]

pub mod basis;
pub mod case;
pub mod contact;
pub mod continuation;
pub mod cyclic;
pub mod forced_response;
pub mod hbm;
pub mod model;
pub mod plot;
pub mod reproduce;
pub mod results;
pub mod run;
