//! The explicit scheme for the nonsmooth contact of DLFT-HBM: central
//! differences with forward-increment Lagrange multipliers (Carpenter,
//! Taylor & Katona, 1991), the field's reference for blade–casing rubbing.
//!
//! Each step predicts `x̃ = x + h v_{n−½} + h² M⁻¹ (F − K x − C v_{n−½})`
//! without contact, then finds the multipliers `λ ≥ 0` that put every
//! contact dof back on or inside the casing at the end of the step:
//! `u = ũ − h² W λ ≤ g0`, `λ (g0 − u) = 0`, `W = Pᵀ M⁻¹ P` (a linear
//! complementarity problem, solved by projected Gauss–Seidel; one sweep
//! when the mass is lumped). The contact is rigid and the impact plastic:
//! no penetration at any step. It solves the law DLFT-HBM converges to
//! (unilateral contact, the solution independent of `ε`). With a wall
//! (`wall_stiffness`), the massless wall node in series makes the force
//! `κ max(0, x − g0)`, explicit.
//!
//! With sliding friction (Eqs. 83–84) each contact dof's friction node is
//! pushed along its circumferential and axial dofs by `μ λ t`, `t = w/|w|`
//! the direction of the sliding velocity `w = (v_θ + ρΩ, v_z)` over the
//! step (`v = (x_{n+1} − x_n)/h`, `Ω` at its middle), sliding assumed at all
//! times as in the paper. The multipliers then solve the complementarity
//! problem of `A = W + μ (W_Nθ T_θ + W_Nz T_z)` (`W_N·` the flexibility
//! between the normal and the tangential dofs, `T` the directions), and
//! the directions are found by fixed-point passes from the velocities
//! without contact. With a wall, `μ f t` is explicit, from `v_{n−½}`.
//!
//! The scheme is stable for `h < 2 / ω_max`; the step is checked against
//! the highest natural frequency (power iterations on `M⁻¹ K`).

use super::circulant::CirculantFactorization;
use super::loading::WheelLoads;
use super::state::{Drive, EnergyTally, State};
use super::wheel::WheelMatrices;
use super::SimulateError;
use crate::contact::{sliding_direction, RotationSpeed};
use std::sync::Arc;

/// The fraction of the stability bound `2/ω_max` a step may reach (the
/// bound is estimated by power iterations).
pub const STABLE_FRACTION: f64 = 0.9;

/// Sweeps of projected Gauss–Seidel at most, and its tolerance relative
/// to the largest multiplier.
const SWEEPS: usize = 200;
const SWEEP_TOLERANCE: f64 = 1e-13;

/// Fixed-point passes on the sliding directions at most, and their
/// tolerance (largest change of a direction's component).
const DIRECTION_PASSES: usize = 50;
const DIRECTION_TOLERANCE: f64 = 1e-12;

/// The sliding friction of the explicit scheme.
#[derive(Debug)]
struct Friction {
    coefficient: f64,
    speed: RotationSpeed,
    /// `([circumferential, axial] full-wheel indices, ρ)` per contact dof
    /// (sector-major).
    nodes: Vec<([usize; 2], f64)>,
    /// `W_Nθ` and `W_Nz`: `Pᵀ M⁻¹` between the contact dofs (rows) and
    /// the nodes' circumferential and axial dofs (columns), row-major.
    coupling: [Vec<f64>; 2],
    /// The sliding direction of each node over the step.
    directions: Vec<[f64; 2]>,
}

impl Friction {
    /// `μ λ t` of contact `c` on its node's circumferential and axial dofs.
    fn forces(&self, c: usize, normal: f64) -> [f64; 2] {
        let t = self.directions[c];
        [
            self.coefficient * normal * t[0],
            self.coefficient * normal * t[1],
        ]
    }

    /// The directions of the sliding velocities from `x_n` to `x_{n+1}`
    /// (`Ω = speed`): the largest change.
    fn update_directions(&mut self, from: &[f64], to: &[f64], h: f64, speed: f64) -> f64 {
        let mut change = 0.0_f64;
        for (t, &([theta, axial], radius)) in self.directions.iter_mut().zip(&self.nodes) {
            let (next, _) = sliding_direction(
                (to[theta] - from[theta]) / h + radius * speed,
                (to[axial] - from[axial]) / h,
            );
            change = change
                .max((next[0] - t[0]).abs())
                .max((next[1] - t[1]).abs());
            *t = next;
        }
        change
    }
}

/// The explicit integrator with Lagrange multipliers (rigid casing) or a
/// wall in series.
pub struct CentralDifference {
    wheel: Arc<WheelMatrices>,
    loads: Arc<WheelLoads>,
    drive: Drive,
    step: f64,
    wall_stiffness: Option<f64>,
    mass: CirculantFactorization,
    /// `W = Pᵀ M⁻¹ P`, row-major.
    flexibility: Vec<f64>,
    indices: Vec<usize>,
    state: State,
    steps: u64,
    energy: EnergyTally,
    sweeps: u64,
    force: Vec<f64>,
    predictor: Vec<f64>,
    /// The predictor corrected by the contact forces of one pass.
    corrected: Vec<f64>,
    gaps: Vec<f64>,
    friction: Option<Friction>,
}

impl CentralDifference {
    /// The integrator of `wheel` under `loads`, driven by `drive`, with
    /// steps of `step` s, from `start` (its velocity is taken at `−h/2`).
    pub fn new(
        wheel: Arc<WheelMatrices>,
        loads: Arc<WheelLoads>,
        wall_stiffness: Option<f64>,
        drive: Drive,
        step: f64,
        start: State,
    ) -> Result<Self, SimulateError> {
        let mut mass = CirculantFactorization::new(&wheel, 0.0, 0.0, 1.0)?;
        let indices: Vec<usize> = (0..loads.contact_count())
            .map(|k| {
                let c = loads.contact_dofs().len();
                loads.contact_index(k / c, k % c)
            })
            .collect();
        let (size, contacts) = (wheel.size(), indices.len());
        let mut flexibility = vec![0.0; contacts * contacts];
        let (mut unit, mut column) = (vec![0.0; size], vec![0.0; size]);
        for (b, &i) in indices.iter().enumerate() {
            unit[i] = 1.0;
            mass.solve(&unit, &mut column);
            unit[i] = 0.0;
            for (a, &r) in indices.iter().enumerate() {
                flexibility[a * contacts + b] = column[r];
            }
        }
        let friction = loads.friction().map(|friction| {
            let per_sector = loads.contact_dofs().len();
            let nodes: Vec<([usize; 2], f64)> = (0..contacts)
                .filter_map(|k| {
                    let at = loads.friction_indices(k / per_sector, k % per_sector)?;
                    Some((at, friction.nodes()[k % per_sector].radius))
                })
                .collect();
            let mut coupling = [
                vec![0.0; contacts * contacts],
                vec![0.0; contacts * contacts],
            ];
            for (b, &(at, _)) in nodes.iter().enumerate() {
                for (direction, &j) in at.iter().enumerate() {
                    unit[j] = 1.0;
                    mass.solve(&unit, &mut column);
                    unit[j] = 0.0;
                    for (a, &r) in indices.iter().enumerate() {
                        coupling[direction][a * contacts + b] = column[r];
                    }
                }
            }
            Friction {
                coefficient: friction.coefficient(),
                speed: friction.speed(),
                directions: vec![[0.0; 2]; nodes.len()],
                nodes,
                coupling,
            }
        });
        let highest = highest_frequency(&wheel, &mut mass, &indices, wall_stiffness);
        if step * highest > STABLE_FRACTION * 2.0 {
            return Err(SimulateError::StepTooLong {
                step_s: step,
                largest_s: STABLE_FRACTION * 2.0 / highest,
                bound_s: 2.0 / highest,
                highest_hz: highest / (2.0 * std::f64::consts::PI),
            });
        }
        Ok(Self {
            wheel,
            loads,
            drive,
            step,
            wall_stiffness,
            mass,
            flexibility,
            indices,
            state: start,
            steps: 0,
            energy: EnergyTally::default(),
            sweeps: 0,
            force: vec![0.0; size],
            predictor: vec![0.0; size],
            corrected: vec![0.0; size],
            gaps: vec![0.0; contacts],
            friction,
        })
    }

    /// The state reached (velocity at the last half step).
    pub fn state(&self) -> &State {
        &self.state
    }

    /// The time step, s.
    pub fn step(&self) -> f64 {
        self.step
    }

    /// The wheel.
    pub fn wheel(&self) -> &WheelMatrices {
        &self.wheel
    }

    /// The contact work since the last call (the explicit scheme tallies
    /// no input or damping work: it conserves no energy exactly).
    pub fn take_energy(&mut self) -> EnergyTally {
        std::mem::take(&mut self.energy)
    }

    /// Gauss–Seidel sweeps so far, and 0 halvings.
    pub fn counts(&self) -> (u64, u64) {
        (self.sweeps, 0)
    }

    /// Advances by one step.
    pub fn advance(&mut self) -> Result<(), SimulateError> {
        let h = self.step;
        let time = self.state.time;
        let s = &mut self.state;
        // r = F − K x − C v (− wall forces), then a = M⁻¹ r.
        self.loads.force_at(self.drive.phase(time), &mut self.force);
        self.wheel
            .stiffness
            .apply_add(-1.0, &s.displacement, &mut self.force);
        self.wheel
            .damping
            .apply_add(-1.0, &s.velocity, &mut self.force);
        if let Some(kappa) = self.wall_stiffness {
            self.loads.gaps_at(self.drive.phase(time), &mut self.gaps);
            for (c, &i) in self.indices.iter().enumerate() {
                let f = kappa * (s.displacement[i] - self.gaps[c]).max(0.0);
                s.contact_force[c] = f;
                self.force[i] -= f;
            }
            if let Some(friction) = self.friction.as_mut() {
                let speed = friction.speed.at(self.drive.omega(time));
                for (t, &([theta, axial], radius)) in
                    friction.directions.iter_mut().zip(&friction.nodes)
                {
                    *t = sliding_direction(s.velocity[theta] + radius * speed, s.velocity[axial]).0;
                }
                for (c, &([theta, axial], _)) in friction.nodes.iter().enumerate() {
                    let [f_theta, f_axial] = friction.forces(c, s.contact_force[c]);
                    self.force[theta] -= f_theta;
                    self.force[axial] -= f_axial;
                }
            }
        }
        self.mass.solve(&self.force, &mut s.acceleration);
        for i in 0..s.displacement.len() {
            self.predictor[i] = s.displacement[i] + h * s.velocity[i] + h * h * s.acceleration[i];
        }
        self.loads
            .gaps_at(self.drive.phase(time + h), &mut self.gaps);
        if self.wall_stiffness.is_none() {
            self.multipliers(time);
        }
        let s = &mut self.state;
        let mut contact = 0.0;
        for (c, &i) in self.indices.iter().enumerate() {
            contact += (self.predictor[i] - s.displacement[i]) * s.contact_force[c];
            s.penetration[c] = self.predictor[i] - self.gaps[c];
        }
        if let Some(friction) = &self.friction {
            for (c, &([theta, axial], _)) in friction.nodes.iter().enumerate() {
                let [f_theta, f_axial] = friction.forces(c, s.contact_force[c]);
                contact += (self.predictor[theta] - s.displacement[theta]) * f_theta
                    + (self.predictor[axial] - s.displacement[axial]) * f_axial;
            }
        }
        for i in 0..s.displacement.len() {
            let v = (self.predictor[i] - s.displacement[i]) / h;
            s.acceleration[i] = (v - s.velocity[i]) / h;
            s.velocity[i] = v;
            s.displacement[i] = self.predictor[i];
        }
        if s.displacement.iter().any(|x| !x.is_finite()) {
            return Err(SimulateError::Input(
                "the explicit scheme diverged: give more --steps-per-period".into(),
            ));
        }
        self.energy.contact += contact;
        self.steps += 1;
        s.time = self.steps as f64 * h;
        Ok(())
    }

    /// The multipliers of the end of the step on a rigid casing (into
    /// `state.contact_force`), and the predictor corrected by them (and by
    /// the friction they press). Without penetration at the end of the
    /// free step there is no contact force.
    fn multipliers(&mut self, time: f64) {
        let h = self.step;
        let contacts = self.indices.len();
        let lambda = &mut self.state.contact_force;
        lambda.iter_mut().for_each(|l| *l = 0.0);
        let violated = self
            .indices
            .iter()
            .zip(&self.gaps)
            .any(|(&i, g)| self.predictor[i] > *g);
        if !violated {
            return;
        }
        let speed = self.friction.as_ref().map_or(0.0, |friction| {
            friction.speed.at(self.drive.omega(time + 0.5 * h))
        });
        let from = &self.state.displacement;
        if let Some(friction) = self.friction.as_mut() {
            friction.update_directions(from, &self.predictor, h, speed);
        }
        // A = W + μ (W_Nθ T_θ + W_Nz T_z).
        let mut matrix = self.flexibility.clone();
        for pass in 0..DIRECTION_PASSES {
            if let Some(friction) = &self.friction {
                for a in 0..contacts {
                    for (b, t) in friction.directions.iter().enumerate() {
                        let at = a * contacts + b;
                        matrix[at] = self.flexibility[at]
                            + friction.coefficient
                                * (friction.coupling[0][at] * t[0]
                                    + friction.coupling[1][at] * t[1]);
                    }
                }
            }
            for _ in 0..SWEEPS {
                self.sweeps += 1;
                let mut change = 0.0_f64;
                let mut largest = 0.0_f64;
                for a in 0..contacts {
                    let coupled: f64 = (0..contacts)
                        .map(|b| matrix[a * contacts + b] * lambda[b])
                        .sum();
                    let u = self.predictor[self.indices[a]] - h * h * coupled;
                    let next = (lambda[a]
                        + (u - self.gaps[a]) / (h * h * matrix[a * contacts + a]))
                        .max(0.0);
                    change = change.max((next - lambda[a]).abs());
                    lambda[a] = next;
                    largest = largest.max(next);
                }
                if change <= SWEEP_TOLERANCE * largest {
                    break;
                }
            }
            // x = x̃ − h² M⁻¹ (P λ + P_θ μλt_θ + P_z μλt_z).
            self.force.iter_mut().for_each(|f| *f = 0.0);
            for (c, &i) in self.indices.iter().enumerate() {
                self.force[i] = lambda[c];
            }
            if let Some(friction) = &self.friction {
                for (c, &([theta, axial], _)) in friction.nodes.iter().enumerate() {
                    let [f_theta, f_axial] = friction.forces(c, lambda[c]);
                    self.force[theta] += f_theta;
                    self.force[axial] += f_axial;
                }
            }
            self.mass.solve(&self.force, &mut self.state.acceleration);
            for ((x, p), a) in self
                .corrected
                .iter_mut()
                .zip(&self.predictor)
                .zip(&self.state.acceleration)
            {
                *x = p - h * h * a;
            }
            let Some(friction) = self.friction.as_mut() else {
                break;
            };
            let change = friction.update_directions(from, &self.corrected, h, speed);
            if change <= DIRECTION_TOLERANCE || pass + 1 == DIRECTION_PASSES {
                break;
            }
        }
        std::mem::swap(&mut self.predictor, &mut self.corrected);
    }
}

/// `ω_max`, rad/s: power iterations on `M⁻¹ (K + κ P Pᵀ)`, 5 % added for
/// their underestimate.
fn highest_frequency(
    wheel: &WheelMatrices,
    mass: &mut CirculantFactorization,
    indices: &[usize],
    wall: Option<f64>,
) -> f64 {
    let size = wheel.size();
    let mut x: Vec<f64> = (0..size)
        .map(|i| 1.0 + ((i * 7919) % 13) as f64 / 13.0)
        .collect();
    let (mut y, mut r) = (vec![0.0; size], vec![0.0; size]);
    let mut value = 0.0;
    for _ in 0..60 {
        r.iter_mut().for_each(|v| *v = 0.0);
        wheel.stiffness.apply_add(1.0, &x, &mut r);
        if let Some(kappa) = wall {
            for &i in indices {
                r[i] += kappa * x[i];
            }
        }
        mass.solve(&r, &mut y);
        let norm = y.iter().map(|v| v * v).sum::<f64>().sqrt();
        let previous = x.iter().map(|v| v * v).sum::<f64>().sqrt();
        value = norm / previous.max(f64::MIN_POSITIVE);
        x.iter_mut()
            .zip(&y)
            .for_each(|(a, b)| *a = b / norm.max(f64::MIN_POSITIVE));
    }
    1.05 * value.sqrt()
}
