//! The implicit scheme for the regularized law: Newmark's average
//! acceleration (trapezoidal rule, `β = 1/4`, `γ = 1/2`: A-stable, no
//! numerical damping, second order), with Newton iterations on the contact
//! unknowns alone.
//!
//! The linear part is constant, so the step is condensed on the contact
//! unknowns: with `S = K + (2/h) C + (4/h²) M` (factorized once per step
//! size, see [`super::circulant`]), the predictor `y = S⁻¹ r` of the
//! linear dynamics and the flexibility `G = Pᵀ S⁻¹ P` of the contact
//! unknowns `u = Pᵀ x`, each step solves `u = Pᵀ y − G f(u − g0)` by Newton
//! with the law's analytic slope (`J = I + G diag(df/dp)`, of size `N n_c`;
//! with friction `J = I + G ∂φ/∂u` on `3 N n_c` unknowns, see below)
//! and then `x = y − S⁻¹ P f`. Nothing is refactorized when the contact
//! state changes; a step whose Newton fails is halved (each level of
//! halving factorizes its own `S` once, on first use).
//!
//! With sliding friction (Eqs. 83–84, [`crate::contact::SlidingFriction`]) the contact
//! unknowns also hold each friction node's circumferential and axial
//! dofs, pushed by `μ f_N t`, `t = w/|w|` the direction of the sliding
//! velocity `w = (v_θ + ρΩ, v_z)` at the end of the step (the scheme's
//! `v₁ = (2/h)(u₁ − u₀) − v₀`): Newton's Jacobian gains the force's
//! derivatives through the normal force and through `w` (`2/h ∂t/∂w`),
//! the same function of each node's own state as the harmonic balance's.
//! Sliding is assumed at all times, as in the paper: `∂t/∂w` grows like
//! `1/|w|`, so a wheel turning slowly (`ρΩ` near the nodes' own velocities
//! or below) may need short steps.

use super::circulant::CirculantFactorization;
use super::loading::WheelLoads;
use super::newton_system::{ActiveSystem, Column};
use super::state::{Drive, EnergyTally, State};
use super::wheel::{dot, WheelMatrices};
use super::SimulateError;
use crate::contact::{ContactLaw, TimeScheme};
use contact::{contact_forces, contact_indices, contact_unknowns, sliding_forces, Slide, Sliding};
use std::sync::Arc;

mod contact;

/// Settings of the Newton iterations and of step halving.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct NewtonSettings {
    /// Tolerance on the contact displacement's correction, relative to the
    /// length scale (the largest gap), dimensionless.
    pub tolerance: f64,
    /// Iterations before the step is halved.
    pub max_iterations: usize,
    /// Halvings of one step before the integration gives up.
    pub max_halvings: usize,
    /// Keep Newton's factorized matrix between iterations and steps while
    /// the residual contracts by [`CONTRACTION`] an iteration and the
    /// active set is the same (a chord iteration); `false`: factorize at
    /// every iteration (plain Newton). The same tolerance either way.
    pub keep_jacobian: bool,
}

/// A kept Newton matrix serves while each iteration divides the residual
/// by at least 1/`CONTRACTION`; else it is factorized afresh.
pub const CONTRACTION: f64 = 0.25;

impl Default for NewtonSettings {
    fn default() -> Self {
        Self {
            tolerance: 1e-10,
            max_iterations: 30,
            max_halvings: 12,
            keep_jacobian: true,
        }
    }
}

/// One step size: `S` factorized, the contact flexibility `G` and the
/// kept Newton matrix.
#[derive(Debug)]
struct Level {
    step: f64,
    factorization: CirculantFactorization,
    /// `G = Pᵀ S⁻¹ P`, row-major, square of the contact unknowns.
    flexibility: Vec<f64>,
    /// `G` column-major (the same up to round-off: `G` is symmetric).
    flexibility_columns: Vec<f64>,
    system: ActiveSystem,
}

/// Work vectors of one step (allocated once).
#[derive(Debug)]
struct Work {
    rhs: Vec<f64>,
    combination: Vec<f64>,
    predictor: Vec<f64>,
    correction: Vec<f64>,
    next: State,
    gaps: Vec<f64>,
    linear_contact: Vec<f64>,
    contact: Vec<f64>,
    force: Vec<f64>,
    slope: Vec<f64>,
    columns: Vec<Column>,
    residual: Vec<f64>,
    /// The contact unknowns before the last correction.
    last_contact: Vec<f64>,
    previous_force: Vec<f64>,
    next_force: Vec<f64>,
}

/// The implicit integrator of the full wheel with a law of the
/// penetration (the regularized penalty law of R-HBM).
pub struct Newmark {
    wheel: Arc<WheelMatrices>,
    loads: Arc<WheelLoads>,
    law: Arc<dyn ContactLaw>,
    drive: Drive,
    step: f64,
    settings: NewtonSettings,
    tolerance: f64,
    levels: Vec<Option<Level>>,
    /// The full-wheel index of each contact unknown: the contact dofs
    /// (sector-major), then with friction the circumferential and the
    /// axial dofs of their nodes.
    indices: Vec<usize>,
    sliding: Option<Sliding>,
    state: State,
    macro_steps: u64,
    sub_time: f64,
    work: Work,
    energy: EnergyTally,
    /// Newton iterations, halvings and factorizations of Newton's matrix
    /// so far.
    iterations: u64,
    halvings: u64,
    factorizations: u64,
}

impl Newmark {
    /// An integrator of `wheel` under `loads` with `law`, driven by
    /// `drive`, with steps of `step` seconds, from `start` (its acceleration
    /// is recomputed from the equations of motion at its time).
    pub fn new(
        wheel: Arc<WheelMatrices>,
        loads: Arc<WheelLoads>,
        law: Arc<dyn ContactLaw>,
        drive: Drive,
        step: f64,
        settings: NewtonSettings,
        start: State,
    ) -> Result<Self, SimulateError> {
        if law.time_scheme() != TimeScheme::Implicit {
            return Err(SimulateError::Input(format!(
                "contact.law: this law needs {}, not the implicit scheme ({law:?})",
                law.time_scheme()
            )));
        }
        if !(step.is_finite() && step > 0.0) {
            return Err(SimulateError::Input(format!(
                "time step {step} s: it must be a finite number > 0"
            )));
        }
        let size = wheel.size();
        if start.displacement.len() != size || start.velocity.len() != size {
            return Err(SimulateError::Input(format!(
                "the initial state has {} displacements and {} velocities; the wheel has {size} dofs",
                start.displacement.len(),
                start.velocity.len()
            )));
        }
        let contacts = loads.contact_count();
        let tolerance = settings.tolerance * length_scale(loads.casing());
        let (indices, sliding) = contact_unknowns(&loads);
        let unknowns = indices.len();
        let work = Work {
            rhs: vec![0.0; size],
            combination: vec![0.0; size],
            predictor: vec![0.0; size],
            correction: vec![0.0; size],
            next: State::at_rest(size, contacts),
            gaps: vec![0.0; contacts],
            linear_contact: vec![0.0; unknowns],
            contact: vec![0.0; unknowns],
            force: vec![0.0; unknowns],
            slope: vec![0.0; contacts],
            columns: vec![[(0, 0.0); 3]; unknowns],
            residual: vec![0.0; unknowns],
            last_contact: vec![0.0; unknowns],
            previous_force: vec![0.0; size],
            next_force: vec![0.0; size],
        };
        let mut integrator = Self {
            wheel,
            loads,
            law,
            drive,
            step,
            settings,
            tolerance,
            levels: Vec::new(),
            indices,
            sliding,
            state: start,
            macro_steps: 0,
            sub_time: 0.0,
            work,
            energy: EnergyTally::default(),
            iterations: 0,
            halvings: 0,
            factorizations: 0,
        };
        integrator.initial_acceleration()?;
        Ok(integrator)
    }

    /// The state reached.
    pub fn state(&self) -> &State {
        &self.state
    }

    /// The time step, s.
    pub fn step(&self) -> f64 {
        self.step
    }

    /// The time reached, s.
    pub fn time(&self) -> f64 {
        self.state.time
    }

    /// The energy exchanged since the last [`Self::take_energy`].
    pub fn take_energy(&mut self) -> EnergyTally {
        std::mem::take(&mut self.energy)
    }

    /// Newton iterations and step halvings so far.
    pub fn counts(&self) -> (u64, u64) {
        (self.iterations, self.halvings)
    }

    /// Factorizations of Newton's matrix so far (as many as the iterations
    /// without [`NewtonSettings::keep_jacobian`]).
    pub fn factorizations(&self) -> u64 {
        self.factorizations
    }

    /// The wheel's matrices.
    pub fn wheel(&self) -> &WheelMatrices {
        &self.wheel
    }

    /// `a = M⁻¹ (F − C v − K x − P f)` at the state's time.
    fn initial_acceleration(&mut self) -> Result<(), SimulateError> {
        let mut mass = CirculantFactorization::new(&self.wheel, 0.0, 0.0, 1.0)?;
        let phase = self.drive.phase(self.state.time);
        let w = &mut self.work;
        self.loads.force_at(phase, &mut w.rhs);
        w.previous_force.copy_from_slice(&w.rhs);
        self.wheel
            .damping
            .apply_add(-1.0, &self.state.velocity, &mut w.rhs);
        self.wheel
            .stiffness
            .apply_add(-1.0, &self.state.displacement, &mut w.rhs);
        self.loads.gaps_at(phase, &mut w.gaps);
        for (c, index) in contact_indices(&self.loads).enumerate() {
            let penetration = self.state.displacement[index] - w.gaps[c];
            let (f, _) = self.law.force(penetration);
            self.state.contact_force[c] = f;
            self.state.penetration[c] = penetration;
            w.rhs[index] -= f;
        }
        if let Some(sliding) = self.sliding.as_mut() {
            let omega = self.drive.omega(self.state.time);
            let count = sliding.nodes.len();
            for (c, &([theta, axial], radius)) in sliding.nodes.iter().enumerate() {
                let w_now = [
                    self.state.velocity[theta] + radius * sliding.speed.at(omega),
                    self.state.velocity[axial],
                ];
                let (forces, _) =
                    sliding_forces(sliding.coefficient, self.state.contact_force[c], 0.0, w_now);
                sliding.forces[c] = forces[0];
                sliding.forces[count + c] = forces[1];
                w.rhs[theta] -= forces[0];
                w.rhs[axial] -= forces[1];
            }
        }
        mass.solve(&w.rhs, &mut self.state.acceleration);
        Ok(())
    }

    /// Advances by one step (halved as often as Newton needs).
    pub fn advance(&mut self) -> Result<(), SimulateError> {
        self.advance_level(0)?;
        self.macro_steps += 1;
        self.sub_time = 0.0;
        self.state.time = self.macro_steps as f64 * self.step;
        Ok(())
    }

    fn advance_level(&mut self, level: usize) -> Result<(), SimulateError> {
        if self.try_step(level)? {
            return Ok(());
        }
        if level >= self.settings.max_halvings {
            return Err(SimulateError::NewtonFailed {
                time: self.state.time,
                halvings: level,
            });
        }
        self.halvings += 1;
        self.advance_level(level + 1)?;
        self.advance_level(level + 1)
    }

    fn level(&mut self, level: usize) -> Result<&Level, SimulateError> {
        if self.levels.len() <= level {
            self.levels.resize_with(level + 1, || None);
        }
        if self.levels[level].is_none() {
            let h = self.step / f64::powi(2.0, level as i32);
            let mut factorization =
                CirculantFactorization::new(&self.wheel, 1.0, 2.0 / h, 4.0 / (h * h))?;
            let contacts = self.indices.len();
            let size = self.wheel.size();
            let indices = &self.indices;
            let mut flexibility = vec![0.0; contacts * contacts];
            let mut flexibility_columns = vec![0.0; contacts * contacts];
            let mut unit = vec![0.0; size];
            let mut column = vec![0.0; size];
            for (b, &index) in indices.iter().enumerate() {
                unit[index] = 1.0;
                factorization.solve(&unit, &mut column);
                unit[index] = 0.0;
                for (a, &row) in indices.iter().enumerate() {
                    flexibility[a * contacts + b] = column[row];
                    flexibility_columns[b * contacts + a] = column[row];
                }
            }
            self.levels[level] = Some(Level {
                step: h,
                factorization,
                flexibility,
                flexibility_columns,
                system: ActiveSystem::default(),
            });
        }
        self.levels[level].as_ref().ok_or(SimulateError::Input(
            "unreachable: level built above".into(),
        ))
    }

    /// One step at halving level `level`; `false` when Newton fails (the
    /// state is then unchanged).
    fn try_step(&mut self, level: usize) -> Result<bool, SimulateError> {
        self.level(level)?;
        let Some(level) = self.levels[level].as_mut() else {
            return Ok(false);
        };
        let h = level.step;
        let time = self.macro_steps as f64 * self.step + self.sub_time + h;
        let phase = self.drive.phase(time);
        let w = &mut self.work;
        let s = &self.state;
        // r = F1 + M (4/h² x + 4/h v + a) + C (2/h x + v).
        self.loads.force_at(phase, &mut w.next_force);
        w.rhs.copy_from_slice(&w.next_force);
        for ((c, x), (v, a)) in w
            .combination
            .iter_mut()
            .zip(&s.displacement)
            .zip(s.velocity.iter().zip(&s.acceleration))
        {
            *c = 4.0 / (h * h) * x + 4.0 / h * v + a;
        }
        self.wheel.mass.apply_add(1.0, &w.combination, &mut w.rhs);
        for ((c, x), v) in w
            .combination
            .iter_mut()
            .zip(&s.displacement)
            .zip(&s.velocity)
        {
            *c = 2.0 / h * x + v;
        }
        self.wheel
            .damping
            .apply_add(1.0, &w.combination, &mut w.rhs);
        level.factorization.solve(&w.rhs, &mut w.predictor);
        // Newton on the contact unknowns.
        self.loads.gaps_at(phase, &mut w.gaps);
        let contacts = w.gaps.len();
        let unknowns = self.indices.len();
        let g = &level.flexibility;
        let sliding = self.sliding.as_ref().map(|sliding| Slide {
            sliding,
            step: h,
            speed: sliding.speed.at(self.drive.omega(time)),
            start: s,
        });
        for (c, &index) in self.indices.iter().enumerate() {
            w.linear_contact[c] = w.predictor[index];
        }
        // The forces at the start of the step (the first guess).
        w.force[..contacts].copy_from_slice(&s.contact_force);
        if let Some(sliding) = &self.sliding {
            w.force[contacts..].copy_from_slice(&sliding.forces);
        }
        for a in 0..unknowns {
            let row = &g[a * unknowns..][..unknowns];
            w.contact[a] = w.linear_contact[a] - dot(row, &w.force);
        }
        // Newton, or chord iterations on a kept matrix while they contract.
        // An iteration on a kept matrix that did not contract is undone if
        // it made things worse, not counted, and the rest of the step is
        // plain Newton: the iteration budget stays Newton's.
        let system = &mut level.system;
        let mut converged = false;
        let mut previous = f64::INFINITY;
        let (mut kept, mut may_keep) = (false, self.settings.keep_jacobian);
        let mut iteration = 0;
        loop {
            contact_forces(
                self.law.as_ref(),
                &w.gaps,
                sliding.as_ref(),
                &w.contact,
                (&mut w.force, &mut w.slope, &mut w.columns),
            );
            let mut largest = newton_residual(g, w);
            // (Written so that a residual that is not a number counts as
            // neither contracted nor improved.)
            let (contracted, improved) = (largest <= CONTRACTION * previous, largest < previous);
            if kept && !contracted {
                system.forget();
                may_keep = false;
                iteration -= 1;
                if !improved {
                    w.contact.copy_from_slice(&w.last_contact);
                    contact_forces(
                        self.law.as_ref(),
                        &w.gaps,
                        sliding.as_ref(),
                        &w.contact,
                        (&mut w.force, &mut w.slope, &mut w.columns),
                    );
                    largest = newton_residual(g, w);
                }
            }
            if !largest.is_finite() {
                break;
            }
            if largest <= self.tolerance {
                converged = true;
                break;
            }
            if iteration == self.settings.max_iterations {
                break;
            }
            iteration += 1;
            self.iterations += 1;
            kept = may_keep && system.kept_for(&w.columns);
            if !kept {
                self.factorizations += 1;
                if !system.factorize(&level.flexibility_columns, &w.columns) {
                    break;
                }
            }
            if !system.solve(&mut w.residual) {
                break;
            }
            previous = largest;
            w.last_contact.copy_from_slice(&w.contact);
            for (u, d) in w.contact.iter_mut().zip(&w.residual) {
                *u -= d;
            }
        }
        if !converged {
            return Ok(false);
        }
        // x1 = y − S⁻¹ P φ.
        w.rhs.iter_mut().for_each(|v| *v = 0.0);
        for (c, &index) in self.indices.iter().enumerate() {
            w.rhs[index] += w.force[c];
        }
        level.factorization.solve(&w.rhs, &mut w.correction);
        let next = &mut w.next;
        let mut input = 0.0;
        for i in 0..next.displacement.len() {
            let x1 = w.predictor[i] - w.correction[i];
            let dx = x1 - s.displacement[i];
            let v1 = 2.0 / h * dx - s.velocity[i];
            let a1 = 4.0 / (h * h) * (dx - h * s.velocity[i]) - s.acceleration[i];
            input += dx * 0.5 * (w.next_force[i] + w.previous_force[i]);
            next.displacement[i] = x1;
            next.velocity[i] = v1;
            next.acceleration[i] = a1;
        }
        let mut contact_work = 0.0;
        for (c, &index) in self.indices.iter().enumerate() {
            let du = next.displacement[index] - s.displacement[index];
            let before = match (&self.sliding, c.checked_sub(contacts)) {
                (Some(sliding), Some(t)) => sliding.forces[t],
                _ => s.contact_force[c],
            };
            contact_work += du * 0.5 * (w.force[c] + before);
        }
        for c in 0..contacts {
            next.contact_force[c] = w.force[c];
            next.penetration[c] = w.contact[c] - w.gaps[c];
        }
        if let Some(sliding) = self.sliding.as_mut() {
            sliding.forces.copy_from_slice(&w.force[contacts..]);
        }
        // Damping work: Δxᵀ C v_mid, with Δx = h v_mid.
        for ((c, v0), v1) in w
            .combination
            .iter_mut()
            .zip(&s.velocity)
            .zip(&next.velocity)
        {
            *c = 0.5 * (v0 + v1);
        }
        let damping =
            h * self
                .wheel
                .damping
                .quadratic(&w.combination, &w.combination, &mut w.correction);
        self.energy.input += input;
        self.energy.damping += damping;
        self.energy.contact += contact_work;
        next.time = time;
        std::mem::swap(&mut w.previous_force, &mut w.next_force);
        std::mem::swap(&mut self.state, &mut w.next);
        self.sub_time += h;
        Ok(true)
    }
}

/// Newton's residual `u − Pᵀ y + G φ(u)` into `w.residual` (`G`
/// row-major): its largest magnitude.
fn newton_residual(g: &[f64], w: &mut Work) -> f64 {
    let unknowns = w.residual.len();
    let mut largest = 0.0_f64;
    for (a, r) in w.residual.iter_mut().enumerate() {
        let row = &g[a * unknowns..][..unknowns];
        *r = w.contact[a] - w.linear_contact[a] + dot(row, &w.force);
        largest = largest.max(r.abs());
    }
    largest
}

/// The length the Newton tolerance is relative to: the largest mean gap or
/// casing amplitude; 1 µm when the blades touch a circular casing at rest.
pub(crate) fn length_scale(casing: &crate::contact::Casing) -> f64 {
    let largest = casing
        .gaps
        .iter()
        .chain(&casing.amplitudes)
        .fold(0.0_f64, |m, v| m.max(v.abs()));
    if largest > 0.0 {
        largest
    } else {
        1e-6
    }
}
