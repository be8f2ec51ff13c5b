//! The loop over excitation periods: per-period envelope per sector, the
//! Poincaré section, the energy balance, the time histories of the last
//! periods, and the steady-state detection.

use super::loading::WheelLoads;
use super::newmark::NewtonSettings;
use super::scheme::Scheme;
use super::state::{Drive, EnergyTally, State};
use super::wheel::{dispersion_ratio, WheelMatrices};
use super::SimulateError;
use crate::contact::ContactLaw;
use std::collections::VecDeque;
use std::f64::consts::PI;
use std::sync::Arc;
use std::time::Instant;

/// Settings of a time integration.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SimulationSettings {
    /// Time steps per excitation period (at the highest frequency of a
    /// sweep).
    pub steps_per_period: usize,
    /// Excitation periods to integrate at most (fixed frequency).
    pub periods: usize,
    /// Stop when the state at the end of each of the last
    /// [`STEADY_PERIODS`] periods is within this distance of the one a
    /// period before, relative to its size (`None`: never stop early).
    pub steady_tolerance: Option<f64>,
    /// Newton and step halving.
    pub newton: NewtonSettings,
    /// The observed sector dof (0-based) of the envelope.
    pub observed_dof: usize,
    /// Periods at the end whose every step is kept in the histories.
    pub history_periods: usize,
    /// At a fixed frequency, integrate the implicit scheme on the wheel
    /// whose discrete response at the excitation frequency is the exact one
    /// ([`super::wheel::dispersion_ratio`]); off, the steady amplitude near
    /// a resonance is off by the scheme's period error.
    pub dispersion_correction: bool,
}

impl Default for SimulationSettings {
    fn default() -> Self {
        Self {
            steps_per_period: 256,
            periods: 200,
            steady_tolerance: Some(1e-6),
            newton: NewtonSettings::default(),
            observed_dof: 0,
            history_periods: 5,
            dispersion_correction: true,
        }
    }
}

/// Periods in a row that must repeat for a steady state.
pub const STEADY_PERIODS: usize = 3;

/// What one excitation period did.
#[derive(Clone, Debug, PartialEq)]
pub struct PeriodRecord {
    /// The period's number, from 1.
    pub period: usize,
    /// Time at its end, s.
    pub end_time: f64,
    /// Instantaneous excitation frequency at its end, Hz.
    pub frequency_hz: f64,
    /// Largest displacement of the observed dof (toward the casing) over
    /// the period's steps, per sector, m.
    pub maxima: Vec<f64>,
    /// Largest contact force over the period's steps, per sector (any of
    /// its contact dofs), N.
    pub peak_force: Vec<f64>,
    /// Poincaré section: the observed dof's displacement at the period's
    /// end, per sector, m.
    pub section_displacement: Vec<f64>,
    /// Poincaré section: the observed dof's velocity, per sector, m/s.
    pub section_velocity: Vec<f64>,
    /// `‖z_p − z_{p−1}‖ / ‖z_p‖` of the whole state `z = (x, v/ω)` at the
    /// ends of this period and the one before (infinite for the first).
    pub poincare_distance: f64,
    /// Work exchanged over the period.
    pub energy: EnergyTally,
    /// Change of `½vᵀMv + ½xᵀKx` over the period, J.
    pub energy_change: f64,
}

impl PeriodRecord {
    /// `input − damping − contact − ΔE`, relative to the input: round-off
    /// for the average acceleration scheme.
    pub fn energy_error(&self) -> f64 {
        let e = &self.energy;
        (e.input - e.damping - e.contact - self.energy_change)
            / e.input.abs().max(f64::MIN_POSITIVE)
    }
}

/// Every step of the last periods (sector-major arrays per step).
#[derive(Clone, Debug, Default, PartialEq)]
pub struct History {
    /// Time, s.
    pub time: Vec<f64>,
    /// Observed dof's displacement, `[step · N + sector]`, m.
    pub observed_displacement: Vec<f64>,
    /// Observed dof's velocity, `[step · N + sector]`, m/s.
    pub observed_velocity: Vec<f64>,
    /// Contact dofs' displacement, `[step · N n_c + sector · n_c + contact]`, m.
    pub contact_displacement: Vec<f64>,
    /// Contact dofs' velocity, same layout, m/s.
    pub contact_velocity: Vec<f64>,
    /// Contact forces, same layout, N.
    pub contact_force: Vec<f64>,
}

impl History {
    fn push(&mut self, state: &State, observed: impl Iterator<Item = usize>, contacts: &[usize]) {
        self.time.push(state.time);
        for i in observed {
            self.observed_displacement.push(state.displacement[i]);
            self.observed_velocity.push(state.velocity[i]);
        }
        for (&i, f) in contacts.iter().zip(&state.contact_force) {
            self.contact_displacement.push(state.displacement[i]);
            self.contact_velocity.push(state.velocity[i]);
            self.contact_force.push(*f);
        }
    }
}

/// Why the integration stopped.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Ending {
    /// The last periods repeat to the tolerance: a steady state.
    Steady {
        /// The period it was detected at.
        period: usize,
    },
    /// All the periods asked for were integrated.
    PeriodsDone,
    /// The sweep reached its end frequency.
    SweepDone,
}

impl Ending {
    /// A sentence for people.
    pub fn describe(&self, tolerance: Option<f64>) -> String {
        match self {
            Ending::Steady { period } => format!(
                "steady state after {period} periods: the last {STEADY_PERIODS} periods repeat to {:.1e}",
                tolerance.unwrap_or(0.0)
            ),
            Ending::PeriodsDone => "all periods integrated, no steady state detected".into(),
            Ending::SweepDone => "the sweep reached its end frequency".into(),
        }
    }
}

/// What a time integration produced.
#[derive(Clone, Debug)]
pub struct SimulationOutcome {
    /// One record per excitation period.
    pub periods: Vec<PeriodRecord>,
    /// Every step of the last periods.
    pub history: History,
    /// The state reached.
    pub last_state: State,
    /// Why it stopped.
    pub ending: Ending,
    /// Time step, s.
    pub step: f64,
    /// Steps taken (before halving).
    pub steps: u64,
    /// Newton iterations.
    pub newton_iterations: u64,
    /// Step halvings.
    pub halvings: u64,
    /// Factorizations of Newton's matrix (implicit scheme; 0 for the
    /// explicit one): fewer than the iterations when it is kept.
    pub factorizations: u64,
    /// Wall-clock time of the integration, s.
    pub wall_seconds: f64,
}

impl SimulationOutcome {
    /// Steps per second of wall-clock time.
    pub fn steps_per_second(&self) -> f64 {
        self.steps as f64 / self.wall_seconds.max(f64::MIN_POSITIVE)
    }

    /// The modulation of the envelope over the last `periods` periods:
    /// `(across sectors, over periods)`, each `(max − min) / max` of the
    /// per-period maxima (0 for a traveling wave at steady state); over
    /// periods `None` when fewer than two were integrated (one period has
    /// nothing to be compared with).
    pub fn modulation(&self, periods: usize) -> (f64, Option<f64>) {
        let last = &self.periods[self.periods.len().saturating_sub(periods)..];
        let relative = |values: &mut dyn Iterator<Item = f64>| {
            let (low, high) = values.fold((f64::INFINITY, f64::NEG_INFINITY), |(l, h), v| {
                (l.min(v), h.max(v))
            });
            if high.abs() > 0.0 {
                (high - low) / high.abs()
            } else {
                0.0
            }
        };
        let across = last
            .iter()
            .map(|p| relative(&mut p.maxima.iter().copied()))
            .fold(0.0, f64::max);
        let sectors = last.first().map_or(0, |p| p.maxima.len());
        let over = (last.len() >= 2).then(|| {
            (0..sectors)
                .map(|j| relative(&mut last.iter().map(|p| p.maxima[j])))
                .fold(0.0, f64::max)
        });
        (across, over)
    }
}

/// A time integration of the full wheel, ready to run.
pub struct Simulation {
    integrator: Scheme,
    loads: Arc<WheelLoads>,
    drive: Drive,
    settings: SimulationSettings,
    stop_time: Option<f64>,
    /// The steps per period asked for, when the explicit scheme needed more.
    raised_from: Option<usize>,
}

impl Simulation {
    /// The integration of `wheel` under `loads` with `law`, driven by
    /// `drive`, from `start`. A sweep stops at `stop_time` (s); a fixed
    /// frequency after `settings.periods` periods or at a steady state.
    pub fn new(
        wheel: Arc<WheelMatrices>,
        loads: Arc<WheelLoads>,
        law: Arc<dyn ContactLaw>,
        drive: Drive,
        settings: SimulationSettings,
        start: State,
        stop_time: Option<f64>,
    ) -> Result<Self, SimulateError> {
        if settings.steps_per_period < 4 {
            return Err(SimulateError::Input(format!(
                "--steps-per-period {}: give at least 4",
                settings.steps_per_period
            )));
        }
        if settings.observed_dof >= wheel.dofs_per_sector() {
            return Err(SimulateError::DofOutOfRange {
                key: "output.observed_dof",
                dof: settings.observed_dof + 1,
                dofs: wheel.dofs_per_sector(),
            });
        }
        let highest = match drive {
            Drive::Fixed { omega } => omega,
            Drive::Sweep { .. } => {
                let end = stop_time.map_or(drive.omega(0.0), |t| drive.omega(t));
                drive.omega(0.0).max(end)
            }
        };
        if !(highest.is_finite() && highest > 0.0 && drive.omega(0.0) > 0.0) {
            return Err(SimulateError::Input(format!(
                "the excitation frequency must be > 0 Hz (got {:.6} Hz)",
                highest / (2.0 * PI)
            )));
        }
        // Periods a sweep goes through: its duration at the highest frequency.
        let periods = match stop_time {
            Some(t) => (t.abs() * highest / (2.0 * PI)).ceil().min(u64::MAX as f64) as u64 + 1,
            None => settings.periods as u64,
        };
        let mut settings = settings;
        let mut raised_from = None;
        loop {
            crate::memory::SimulationSizes {
                periods,
                steps_per_period: settings.steps_per_period as u64,
                history_periods: settings.history_periods as u64,
                sweep: stop_time.is_some(),
                ..crate::memory::SimulationSizes::of_wheel(
                    wheel.sectors(),
                    wheel.dofs_per_sector(),
                    // With friction each contact dof brings its node's two tangential dofs.
                    loads.contact_dofs().len() * if loads.friction().is_some() { 3 } else { 1 },
                )
            }
            .check_run()?;
            let step = 2.0 * PI / highest / settings.steps_per_period as f64;
            let dispersion = match drive {
                Drive::Fixed { omega } if settings.dispersion_correction => {
                    Some(dispersion_ratio(omega, step))
                }
                _ => None,
            };
            let built = Scheme::for_law(
                wheel.clone(),
                loads.clone(),
                law.clone(),
                drive,
                step,
                settings.newton,
                start.clone(),
                dispersion,
            );
            match built {
                Ok(integrator) => {
                    return Ok(Self {
                        integrator,
                        loads,
                        drive,
                        settings,
                        stop_time,
                        raised_from,
                    })
                }
                // The explicit scheme's bound is known: take the steps it
                // needs (a multiple of the sectors, so that a traveling
                // wave's time grid keeps its symmetry), once.
                Err(SimulateError::StepTooLong { largest_s, .. }) if raised_from.is_none() => {
                    let needed = (2.0 * PI / highest / largest_s).ceil() as usize;
                    let sectors = wheel.sectors().max(1);
                    let needed = needed.div_ceil(sectors) * sectors;
                    tracing::warn!(
                        "the explicit scheme (law = \"dlft\") is stable below a step of {largest_s:.3e} s: \
                         integrating with {needed} steps a period instead of {}",
                        settings.steps_per_period
                    );
                    raised_from = Some(settings.steps_per_period);
                    settings.steps_per_period = needed;
                }
                Err(error) => return Err(error),
            }
        }
    }

    /// The steps per excitation period integrated (the settings', or the
    /// explicit scheme's stable count when those were too few).
    pub fn steps_per_period(&self) -> usize {
        self.settings.steps_per_period
    }

    /// The steps per period asked for, when the explicit scheme needed more
    /// (see [`Self::steps_per_period`]).
    pub fn steps_raised_from(&self) -> Option<usize> {
        self.raised_from
    }

    /// The dispersion correction applied (`Ω/Ω_w`, see
    /// [`super::wheel::dispersion_ratio`]), if any: at a fixed frequency
    /// with the implicit scheme.
    pub fn dispersion_ratio(&self) -> Option<f64> {
        self.integrator.dispersion_ratio()
    }

    /// The scheme's name.
    pub fn scheme(&self) -> &'static str {
        self.integrator.name()
    }

    /// Runs, calling `progress` after each period.
    pub fn run(
        mut self,
        mut progress: impl FnMut(&PeriodRecord),
    ) -> Result<SimulationOutcome, SimulateError> {
        let clock = Instant::now();
        let wheel_sectors = self.integrator.wheel().sectors();
        let dofs = self.integrator.wheel().dofs_per_sector();
        let observed = self.settings.observed_dof;
        let contacts = self.loads.contact_dofs().len();
        let contact_indices: Vec<usize> = (0..wheel_sectors * contacts)
            .map(|k| self.loads.contact_index(k / contacts, k % contacts))
            .collect();
        let observed_indices = move || (0..wheel_sectors).map(move |j| j * dofs + observed);
        let mut periods: Vec<PeriodRecord> = Vec::new();
        let mut recent: VecDeque<History> = VecDeque::new();
        let mut previous_section = self.section();
        let mut energy_before = self.mechanical_energy();
        let mut steps: u64 = 0;
        let ending = loop {
            let mut maxima = vec![f64::NEG_INFINITY; wheel_sectors];
            let mut peak_force = vec![0.0_f64; wheel_sectors];
            let mut history = History::default();
            let keep = self.settings.history_periods > 0;
            let period_index = periods.len();
            let target_phase = 2.0 * PI * (period_index + 1) as f64;
            let mut sweep_done = false;
            loop {
                self.integrator.advance()?;
                steps += 1;
                let state = self.integrator.state();
                if !state.is_finite() {
                    return Err(SimulateError::Diverged {
                        time: state.time,
                        period: period_index + 1,
                    });
                }
                for (j, i) in observed_indices().enumerate() {
                    maxima[j] = maxima[j].max(state.displacement[i]);
                }
                for (k, f) in state.contact_force.iter().enumerate() {
                    peak_force[k / contacts] = peak_force[k / contacts].max(*f);
                }
                if keep {
                    history.push(state, observed_indices(), &contact_indices);
                }
                let period_done = match self.drive {
                    Drive::Fixed { .. } => {
                        steps.is_multiple_of(self.settings.steps_per_period as u64)
                    }
                    Drive::Sweep { .. } => self.drive.phase(state.time) >= target_phase,
                };
                if let Some(stop) = self.stop_time {
                    if state.time >= stop {
                        sweep_done = true;
                        break;
                    }
                }
                if period_done {
                    break;
                }
            }
            let time = self.integrator.time();
            let section = self.section();
            let distance = relative_distance(&section, &previous_section);
            previous_section = section;
            let energy_now = self.mechanical_energy();
            let state = self.integrator.state();
            let record = PeriodRecord {
                period: period_index + 1,
                end_time: time,
                // A sweep's last step ends past its stop time: its frequency
                // is the end frequency, not one extrapolated beyond it.
                frequency_hz: self
                    .drive
                    .frequency_hz(self.stop_time.map_or(time, |stop| time.min(stop))),
                maxima,
                peak_force,
                section_displacement: observed_indices().map(|i| state.displacement[i]).collect(),
                section_velocity: observed_indices().map(|i| state.velocity[i]).collect(),
                poincare_distance: if period_index == 0 {
                    f64::INFINITY
                } else {
                    distance
                },
                energy: self.integrator.take_energy(),
                energy_change: energy_now - energy_before,
            };
            energy_before = energy_now;
            progress(&record);
            periods.push(record);
            if keep {
                recent.push_back(history);
                if recent.len() > self.settings.history_periods {
                    recent.pop_front();
                }
            }
            if sweep_done {
                break Ending::SweepDone;
            }
            if let (Drive::Fixed { .. }, Some(tolerance)) =
                (self.drive, self.settings.steady_tolerance)
            {
                let repeated = periods.len() > STEADY_PERIODS
                    && periods[periods.len() - STEADY_PERIODS..]
                        .iter()
                        .all(|p| p.poincare_distance <= tolerance);
                if repeated {
                    break Ending::Steady {
                        period: periods.len(),
                    };
                }
            }
            if self.stop_time.is_none() && periods.len() >= self.settings.periods {
                break Ending::PeriodsDone;
            }
        };
        let mut history = History::default();
        for h in recent {
            history.time.extend(h.time);
            history
                .observed_displacement
                .extend(h.observed_displacement);
            history.observed_velocity.extend(h.observed_velocity);
            history.contact_displacement.extend(h.contact_displacement);
            history.contact_velocity.extend(h.contact_velocity);
            history.contact_force.extend(h.contact_force);
        }
        let (newton_iterations, halvings) = self.integrator.counts();
        Ok(SimulationOutcome {
            periods,
            history,
            last_state: self.integrator.state().clone(),
            ending,
            step: self.integrator.step(),
            steps,
            newton_iterations,
            halvings,
            factorizations: self.integrator.factorizations(),
            wall_seconds: clock.elapsed().as_secs_f64(),
        })
    }

    /// The whole state `(x, v/ω)`.
    fn section(&self) -> Vec<f64> {
        let state = self.integrator.state();
        let omega = self.drive.omega(state.time);
        state
            .displacement
            .iter()
            .copied()
            .chain(state.velocity.iter().map(|v| v / omega))
            .collect()
    }

    /// `½vᵀMv + ½xᵀKx`, J.
    fn mechanical_energy(&self) -> f64 {
        let state = self.integrator.state();
        let wheel = self.integrator.wheel();
        let mut work = vec![0.0; wheel.size()];
        0.5 * wheel
            .mass
            .quadratic(&state.velocity, &state.velocity, &mut work)
            + 0.5
                * wheel
                    .stiffness
                    .quadratic(&state.displacement, &state.displacement, &mut work)
    }
}

/// `‖a − b‖ / ‖a‖`.
fn relative_distance(a: &[f64], b: &[f64]) -> f64 {
    let difference: f64 = a.iter().zip(b).map(|(x, y)| (x - y) * (x - y)).sum();
    let size: f64 = a.iter().map(|x| x * x).sum();
    (difference / size.max(f64::MIN_POSITIVE)).sqrt()
}
