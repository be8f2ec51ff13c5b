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
//! with the law's analytic slope (`J = I + G diag(df/dp)`, of size `N n_c`)
//! and then `x = y − S⁻¹ P f`. Nothing is refactorized when the contact
//! state changes; a step whose Newton fails is halved (each level of
//! halving factorizes its own `S` once, on first use).

use super::circulant::{solve_dense, CirculantFactorization};
use super::loading::WheelLoads;
use super::state::{Drive, EnergyTally, State};
use super::wheel::WheelMatrices;
use super::SimulateError;
use crate::contact::ContactLaw;
use std::sync::Arc;

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
}

impl Default for NewtonSettings {
    fn default() -> Self {
        Self {
            tolerance: 1e-10,
            max_iterations: 30,
            max_halvings: 12,
        }
    }
}

/// One step size: `S` factorized and the contact flexibility `G`.
#[derive(Debug)]
struct Level {
    step: f64,
    factorization: CirculantFactorization,
    /// `G = Pᵀ S⁻¹ P`, row-major, `N n_c` square.
    flexibility: Vec<f64>,
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
    residual: Vec<f64>,
    jacobian: Vec<f64>,
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
    state: State,
    macro_steps: u64,
    sub_time: f64,
    work: Work,
    energy: EnergyTally,
    /// Newton iterations and halvings so far.
    iterations: u64,
    halvings: u64,
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
        if law.input().reads_residual() {
            return Err(SimulateError::Input(
                "contact.law = \"dlft\": the implicit scheme solves the regularized law; \
                 the dynamic Lagrangian needs the explicit scheme with Lagrange multipliers"
                    .into(),
            ));
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
        let work = Work {
            rhs: vec![0.0; size],
            combination: vec![0.0; size],
            predictor: vec![0.0; size],
            correction: vec![0.0; size],
            next: State::at_rest(size, contacts),
            gaps: vec![0.0; contacts],
            linear_contact: vec![0.0; contacts],
            contact: vec![0.0; contacts],
            force: vec![0.0; contacts],
            slope: vec![0.0; contacts],
            residual: vec![0.0; contacts],
            jacobian: vec![0.0; contacts * contacts],
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
            state: start,
            macro_steps: 0,
            sub_time: 0.0,
            work,
            energy: EnergyTally::default(),
            iterations: 0,
            halvings: 0,
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
            let contacts = self.loads.contact_count();
            let size = self.wheel.size();
            let indices: Vec<usize> = contact_indices(&self.loads).collect();
            let mut flexibility = vec![0.0; contacts * contacts];
            let mut unit = vec![0.0; size];
            let mut column = vec![0.0; size];
            for (b, &index) in indices.iter().enumerate() {
                unit[index] = 1.0;
                factorization.solve(&unit, &mut column);
                unit[index] = 0.0;
                for (a, &row) in indices.iter().enumerate() {
                    flexibility[a * contacts + b] = column[row];
                }
            }
            self.levels[level] = Some(Level {
                step: h,
                factorization,
                flexibility,
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
        let g = &level.flexibility;
        for (c, index) in contact_indices(&self.loads).enumerate() {
            w.linear_contact[c] = w.predictor[index];
        }
        for a in 0..contacts {
            let row = &g[a * contacts..][..contacts];
            let push: f64 = row.iter().zip(&s.contact_force).map(|(g, f)| g * f).sum();
            w.contact[a] = w.linear_contact[a] - push;
        }
        let mut converged = false;
        for iteration in 0..=self.settings.max_iterations {
            for c in 0..contacts {
                (w.force[c], w.slope[c]) = self.law.force(w.contact[c] - w.gaps[c]);
            }
            let mut largest = 0.0_f64;
            for a in 0..contacts {
                let row = &g[a * contacts..][..contacts];
                let push: f64 = row.iter().zip(&w.force).map(|(g, f)| g * f).sum();
                w.residual[a] = w.contact[a] - w.linear_contact[a] + push;
                largest = largest.max(w.residual[a].abs());
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
            self.iterations += 1;
            for a in 0..contacts {
                for b in 0..contacts {
                    w.jacobian[a * contacts + b] =
                        g[a * contacts + b] * w.slope[b] + if a == b { 1.0 } else { 0.0 };
                }
            }
            if !solve_dense(&mut w.jacobian, &mut w.residual, contacts) {
                break;
            }
            for (u, d) in w.contact.iter_mut().zip(&w.residual) {
                *u -= d;
            }
        }
        if !converged {
            return Ok(false);
        }
        // x1 = y − S⁻¹ P f.
        w.rhs.iter_mut().for_each(|v| *v = 0.0);
        for (c, index) in contact_indices(&self.loads).enumerate() {
            w.rhs[index] = w.force[c];
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
        for (c, index) in contact_indices(&self.loads).enumerate() {
            let du = next.displacement[index] - s.displacement[index];
            contact_work += du * 0.5 * (w.force[c] + s.contact_force[c]);
            next.contact_force[c] = w.force[c];
            next.penetration[c] = w.contact[c] - w.gaps[c];
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

/// The full-wheel index of every contact unknown, sector-major.
fn contact_indices(loads: &WheelLoads) -> impl Iterator<Item = usize> + '_ {
    let contacts = loads.contact_dofs().len();
    (0..loads.contact_count()).map(move |k| loads.contact_index(k / contacts, k % contacts))
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
