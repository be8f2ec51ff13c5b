//! # cyclorub-app
//!
//! The application over the [`cyclorub`] solver, as the `cyclorub` command
//! uses it: what the solver does not need to solve a case.
//!
//! - [`reproduce`]: the paper's academic studies on every basis, the
//!   reductions checked against the full wheel, and the report;
//! - [`template`]: the commented case files `cyclorub init` prints (the
//!   default case and the paper's examples);
//! - [`plan`]: what each rule keeps, in the shape of the paper's Tables 2,
//!   4 and 5, and mean reductions over ranges of sector counts;
//! - [`compare`]: two results folders of one case, point by point.
#![warn(missing_docs)]
#![deny(clippy::float_cmp)]

pub mod compare;
pub mod plan;
pub mod reproduce;
pub mod template;
