//! The contact forces of one implicit step on the contact unknowns: the
//! law's normal forces from the penetrations and, with sliding friction,
//! each node's `μ f_N t(w)` at the scheme's end-of-step velocity, with the
//! nonzeros of `∂φ/∂u` that Newton's matrix is built from.

use super::super::loading::WheelLoads;
use super::super::newton_system::Column;
use super::super::state::State;
use crate::contact::{sliding_direction, ContactLaw, RotationSpeed};

/// The sliding friction of the integration: per contact dof (sector-major)
/// its friction node's full-wheel dofs and radius, and the tangential
/// forces at the current state.
#[derive(Debug)]
pub(super) struct Sliding {
    pub(super) coefficient: f64,
    pub(super) speed: RotationSpeed,
    /// `([circumferential, axial] full-wheel indices, ρ)` per contact dof.
    pub(super) nodes: Vec<([usize; 2], f64)>,
    /// `μ f_N t` at the current state: the circumferential forces of every
    /// node, then the axial ones.
    pub(super) forces: Vec<f64>,
}

/// The contact unknowns of `loads` (see [`Newmark`]'s `indices`) and,
/// with friction, its nodes.
pub(super) fn contact_unknowns(loads: &WheelLoads) -> (Vec<usize>, Option<Sliding>) {
    let mut indices: Vec<usize> = contact_indices(loads).collect();
    let Some(friction) = loads.friction() else {
        return (indices, None);
    };
    let per_sector = loads.contact_dofs().len();
    let nodes: Vec<([usize; 2], f64)> = (0..loads.contact_count())
        .filter_map(|k| {
            let at = loads.friction_indices(k / per_sector, k % per_sector)?;
            Some((at, friction.nodes()[k % per_sector].radius))
        })
        .collect();
    indices.extend(nodes.iter().map(|(at, _)| at[0]));
    indices.extend(nodes.iter().map(|(at, _)| at[1]));
    let forces = vec![0.0; 2 * nodes.len()];
    let sliding = Sliding {
        coefficient: friction.coefficient(),
        speed: friction.speed(),
        nodes,
        forces,
    };
    (indices, Some(sliding))
}

/// What the friction forces of a step read: the nodes, the step, `Ω` at
/// its end and the state at its start.
pub(super) struct Slide<'a> {
    pub(super) sliding: &'a Sliding,
    pub(super) step: f64,
    pub(super) speed: f64,
    pub(super) start: &'a State,
}

/// The forces `φ(u)` on the contact unknowns `u` (the law's normal forces
/// from the penetrations `u − g`, then the friction nodes'
/// circumferential and axial forces), the law's slopes, and the nonzeros
/// of each column of `∂φ/∂u`.
pub(super) fn contact_forces(
    law: &dyn ContactLaw,
    gaps: &[f64],
    slide: Option<&Slide<'_>>,
    u: &[f64],
    (force, slope, columns): (&mut [f64], &mut [f64], &mut [Column]),
) {
    let contacts = gaps.len();
    for c in 0..contacts {
        (force[c], slope[c]) = law.force(u[c] - gaps[c]);
        columns[c] = [(c, slope[c]), (c, 0.0), (c, 0.0)];
    }
    let Some(slide) = slide else {
        return;
    };
    let (h, start) = (slide.step, slide.start);
    for (c, &([theta, axial], radius)) in slide.sliding.nodes.iter().enumerate() {
        let (at_theta, at_axial) = (contacts + c, 2 * contacts + c);
        // v₁ = (2/h)(u₁ − u₀) − v₀, the scheme's velocity at the step's end.
        let velocity = |index: usize, value: f64| {
            2.0 / h * (value - start.displacement[index]) - start.velocity[index]
        };
        let w = [
            velocity(theta, u[at_theta]) + radius * slide.speed,
            velocity(axial, u[at_axial]),
        ];
        let (forces, derivatives) =
            sliding_forces(slide.sliding.coefficient, force[c], slope[c], w);
        force[at_theta] = forces[0];
        force[at_axial] = forces[1];
        columns[c][1] = (at_theta, derivatives[0][0]);
        columns[c][2] = (at_axial, derivatives[1][0]);
        for (column, entry) in [(at_theta, 1), (at_axial, 2)] {
            columns[column] = [
                (at_theta, 2.0 / h * derivatives[0][entry]),
                (at_axial, 2.0 / h * derivatives[1][entry]),
                (at_theta, 0.0),
            ];
        }
    }
}

/// The friction forces `μ f_N t(w)` (circumferential, axial) of a node
/// pressed by the normal force `f_N` (of slope `df_N/du`) sliding at `w`,
/// and their derivatives: per force, with respect to `(u_N, w_θ, w_z)`.
pub(super) fn sliding_forces(
    coefficient: f64,
    normal_force: f64,
    normal_slope: f64,
    w: [f64; 2],
) -> ([f64; 2], [[f64; 3]; 2]) {
    let (t, dt) = sliding_direction(w[0], w[1]);
    let force = coefficient * normal_force;
    let row = |r: usize| {
        [
            coefficient * normal_slope * t[r],
            force * dt[r][0],
            force * dt[r][1],
        ]
    };
    ([force * t[0], force * t[1]], [row(0), row(1)])
}

/// The full-wheel index of every contact unknown, sector-major.
pub(super) fn contact_indices(loads: &WheelLoads) -> impl Iterator<Item = usize> + '_ {
    let contacts = loads.contact_dofs().len();
    (0..loads.contact_count()).map(move |k| loads.contact_index(k / contacts, k % contacts))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::contact::RegularizedPenalty;

    /// `∂φ/∂u` from [`contact_forces`]'s column nonzeros against central
    /// differences of `φ`, on two contact dofs with friction nodes, one
    /// pressed into the casing and one barely touching, a fixed speed and
    /// a synchronous one.
    #[test]
    fn the_contact_forces_derivatives_match_central_differences() {
        let law = RegularizedPenalty::new(2e6, 0.5).unwrap();
        let gaps = [1e-3, 1e-3];
        // Two sectors of four dofs: normal 0, circumferential 1, axial 2.
        let mut start = State::at_rest(8, 2);
        start.displacement = vec![9e-4, 1e-5, -2e-5, 0.0, 1.001e-3, -3e-6, 4e-6, 0.0];
        start.velocity = vec![0.1, -0.3, 0.2, 0.0, -0.05, 0.4, -0.1, 0.0];
        for speed in [RotationSpeed::Fixed(30.0), RotationSpeed::Synchronous] {
            let sliding = Sliding {
                coefficient: 0.3,
                speed,
                nodes: vec![([1, 2], 0.4), ([5, 6], 0.4)],
                forces: vec![0.0; 4],
            };
            let slide = Slide {
                sliding: &sliding,
                step: 1e-4,
                speed: speed.at(2.0 * std::f64::consts::PI * 75.0),
                start: &start,
            };
            // Contact unknowns: normal 0, 1; circumferential 0, 1; axial 0, 1.
            let u = [1.04e-3, 1.0005e-3, 1.2e-5, -2.5e-6, -1.9e-5, 4.3e-6];
            let n = u.len();
            let evaluate = |u: &[f64]| {
                let (mut force, mut slope) = (vec![0.0; n], vec![0.0; 2]);
                let mut columns = vec![[(0, 0.0); 3]; n];
                contact_forces(
                    &law,
                    &gaps,
                    Some(&slide),
                    u,
                    (&mut force, &mut slope, &mut columns),
                );
                (force, columns)
            };
            let (force, columns) = evaluate(&u);
            assert!(force[0] > 50.0 && force[1] > 0.0, "in contact: {force:?}");
            for b in 0..n {
                let mut analytic = vec![0.0; n];
                for &(row, value) in &columns[b] {
                    analytic[row] += value;
                }
                let h = 1e-9;
                let (mut plus, mut minus) = (u.to_vec(), u.to_vec());
                plus[b] += h;
                minus[b] -= h;
                let (fp, _) = evaluate(&plus);
                let (fm, _) = evaluate(&minus);
                let scale = analytic.iter().fold(1.0_f64, |m, v| m.max(v.abs()));
                for a in 0..n {
                    let difference = (fp[a] - fm[a]) / (2.0 * h);
                    assert!(
                        (difference - analytic[a]).abs() <= 1e-6 * scale,
                        "{speed:?}: ∂φ_{a}/∂u_{b}: {} against {difference}",
                        analytic[a]
                    );
                }
            }
        }
    }
}
