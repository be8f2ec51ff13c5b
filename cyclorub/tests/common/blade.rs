//! A small wheel with three-direction contact nodes and sliding friction,
//! shared by the tests of friction in the time integration and in the
//! stability check.
#![allow(dead_code)]

use cyclorub::case::{BasisChoice, Case};
use cyclorub::forced_response::{ForcedResponse, Solution};
use std::path::Path;

/// A wheel of 6 sectors of four dofs: the contact node's normal (toward
/// the casing), circumferential and axial dofs, and a blade dof that holds
/// them and takes the traveling load; coupled to the next sector through
/// the normal and blade dofs. The casing turns at 30 rad/s past nodes at
/// 0.4 m: a sliding speed of 12 m/s, of the order of the nodes' own
/// velocities, so that the direction of sliding swings over the period.
pub const BLADE: &str = r#"
[model]
kind = "matrices"
sectors = 6
mass = [
    [0.3, 0.0, 0.0, 0.05],
    [0.0, 0.25, 0.0, 0.0],
    [0.0, 0.0, 0.28, 0.0],
    [0.05, 0.0, 0.0, 1.0],
]
stiffness = [
    [3.0e5, -2.0e4, 1.0e4, -1.0e5],
    [-2.0e4, 2.0e5, -3.0e4, -6.0e4],
    [1.0e4, -3.0e4, 2.5e5, -5.0e4],
    [-1.0e5, -6.0e4, -5.0e4, 4.0e5],
]
stiffness_coupling = [
    [-1.0e4, 0.0, 0.0, 0.0],
    [0.0, 0.0, 0.0, 0.0],
    [0.0, 0.0, 0.0, 0.0],
    [0.0, 0.0, 0.0, -5.0e4],
]
[model.damping]
kind = "rayleigh"
alpha = 2.0
beta = 1e-6
[excitation]
kind = "traveling"
engine_order = 1
amplitude = 30.0
dofs = [4]
[casing]
gap = 1e-3
[contact]
law = "regularized"
dofs = [1]
stiffness = 2e6
regularization = 0.5
friction = 0.3
circumferential_dofs = [2]
axial_dofs = [3]
radius = 0.4
[rotation]
speed = 30.0
[harmonic_balance]
harmonics = 12
time_samples = 1536
"#;

/// The harmonic balance point with friction past first contact, below the
/// resonance of nodal diameter 1.
pub fn contact_point(case: &Case) -> (Solution, usize) {
    contact_point_on(case, case.basis.kind)
}

/// [`contact_point`] solved on `basis`.
pub fn contact_point_on(case: &Case, basis: BasisChoice) -> (Solution, usize) {
    let model = case.model.build(Path::new(".")).unwrap();
    let first = model.natural_frequencies().unwrap()[1].1[0];
    let frequencies: Vec<f64> = [0.9, 0.94, 0.96, 0.97, 0.975, 0.98, 0.983, 0.986]
        .iter()
        .map(|f| f * first)
        .collect();
    let solution = ForcedResponse::from_case(case)
        .unwrap()
        .basis(basis)
        .at_frequencies_hz(frequencies)
        .build()
        .unwrap()
        .run(&mut [])
        .unwrap();
    let last = solution.branch.points.len() - 1;
    assert!(solution.branch.points.iter().all(|p| p.converged));
    (solution, last)
}
