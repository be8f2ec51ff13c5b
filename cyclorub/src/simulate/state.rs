//! The state of the wheel during a time integration, what drives it, and
//! the energy it exchanges.

use std::f64::consts::PI;

/// The state of the full wheel at one instant (vectors sector-major,
/// `N n` long; contact arrays sector-major, `N n_c` long).
#[derive(Clone, Debug, PartialEq)]
pub struct State {
    /// Time, s.
    pub time: f64,
    /// Displacement of every dof, m.
    pub displacement: Vec<f64>,
    /// Velocity, m/s.
    pub velocity: Vec<f64>,
    /// Acceleration, m/s².
    pub acceleration: Vec<f64>,
    /// Normal contact force `f ≥ 0` of every contact dof, N (on the blade:
    /// `−f`); friction's tangential forces are the integrator's.
    pub contact_force: Vec<f64>,
    /// Penetration `x − g0` of every contact unknown, m (`≤ 0`: open).
    pub penetration: Vec<f64>,
}

impl State {
    /// The wheel at rest at time 0 (`size` dofs, `contacts` contact unknowns).
    pub fn at_rest(size: usize, contacts: usize) -> Self {
        Self {
            time: 0.0,
            displacement: vec![0.0; size],
            velocity: vec![0.0; size],
            acceleration: vec![0.0; size],
            contact_force: vec![0.0; contacts],
            penetration: vec![0.0; contacts],
        }
    }

    /// Whether every displacement, velocity and contact force is finite.
    pub fn is_finite(&self) -> bool {
        self.displacement
            .iter()
            .chain(&self.velocity)
            .chain(&self.contact_force)
            .all(|v| v.is_finite())
    }
}

/// How the excitation's frequency goes with time.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Drive {
    /// A fixed angular frequency `ω` (rad/s): phase `θ = ωt`.
    Fixed {
        /// `ω`, rad/s.
        omega: f64,
    },
    /// A linear sweep `ω(t) = ω0 + ρ t` with continuous phase
    /// `θ = ω0 t + ρ t²/2`, as a rig runs.
    Sweep {
        /// `ω0`, rad/s.
        start_omega: f64,
        /// `ρ`, rad/s² (negative: sweeping down).
        rate: f64,
    },
}

impl Drive {
    /// The phase `θ(t)`, rad.
    pub fn phase(&self, time: f64) -> f64 {
        match *self {
            Drive::Fixed { omega } => omega * time,
            Drive::Sweep { start_omega, rate } => start_omega * time + 0.5 * rate * time * time,
        }
    }

    /// The instantaneous angular frequency `ω(t)`, rad/s.
    pub fn omega(&self, time: f64) -> f64 {
        match *self {
            Drive::Fixed { omega } => omega,
            Drive::Sweep { start_omega, rate } => start_omega + rate * time,
        }
    }

    /// The instantaneous frequency, Hz.
    pub fn frequency_hz(&self, time: f64) -> f64 {
        self.omega(time) / (2.0 * PI)
    }
}

/// Work exchanged by the wheel over some steps (J), summed with the
/// scheme's own quadrature, for which
/// `ΔE = input − damping − contact` holds to round-off
/// (`E = ½ vᵀMv + ½ xᵀKx`; the average acceleration scheme conserves it).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct EnergyTally {
    /// Work of the excitation, `Σ Δxᵀ (F_n + F_{n+1})/2`.
    pub input: f64,
    /// Work dissipated by damping, `Σ Δxᵀ C (v_n + v_{n+1})/2`.
    pub damping: f64,
    /// Work taken by the contact forces, `Σ Δuᵀ (f_n + f_{n+1})/2` (the
    /// casing's rotation and the law's quadrature make it nonzero).
    pub contact: f64,
}
