//! Initial states: the wheel at rest, or a harmonic balance point rebuilt
//! on every dof of every sector (the harmonics of any dof come from the
//! contact unknowns, as the recovery of results does), optionally
//! perturbed.

use super::circulant::CirculantFactorization;
use super::loading::WheelLoads;
use super::state::State;
use super::wheel::WheelMatrices;
use super::SimulateError;
use crate::hbm::recovery::dof_coordinates;
use crate::hbm::HarmonicBalance;
use std::f64::consts::PI;

/// The state at `t = 0` (phase 0) of the periodic solution `unknowns` of
/// `problem` at `omega` (rad/s), on every dof of every sector: with
/// `u(τ) = a0 + Σ 2 Re(X_k e^{ikτ})`, `x = a0 + 2 Σ Re X_k` and
/// `v = −2 Σ kω Im X_k`.
pub fn from_harmonic_balance(
    problem: &HarmonicBalance,
    unknowns: &[f64],
    omega: f64,
    wheel: &WheelMatrices,
    contacts: usize,
) -> Result<State, SimulateError> {
    if unknowns.len() != problem.layout().unknowns {
        return Err(SimulateError::Input(format!(
            "the harmonic balance point has {} unknowns, its problem has {}: was it solved on another basis or case?",
            unknowns.len(),
            problem.layout().unknowns
        )));
    }
    let (sectors, dofs) = (wheel.sectors(), wheel.dofs_per_sector());
    if problem.layout().sectors != sectors {
        return Err(SimulateError::Input(format!(
            "the harmonic balance point is for {} sectors, the wheel has {sectors}",
            problem.layout().sectors
        )));
    }
    let all: Vec<usize> = (0..sectors).collect();
    let mut state = State::at_rest(sectors * dofs, contacts);
    for dof in 0..dofs {
        let per_sector = dof_coordinates(problem, unknowns, omega, dof, &all)?;
        for (j, c) in per_sector.iter().enumerate() {
            let (mut x, mut v) = (c[0], 0.0);
            for k in 1..=(c.len() - 1) / 2 {
                x += 2.0 * c[2 * k - 1];
                v -= 2.0 * k as f64 * omega * c[2 * k];
            }
            state.displacement[j * dofs + dof] = x;
            state.velocity[j * dofs + dof] = v;
        }
    }
    Ok(state)
}

/// Where a perturbation acts.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum PerturbationPattern {
    /// Every sector, with a fixed pseudo-random weight in `[−1, 1]` per
    /// sector, so that every nodal diameter is seeded.
    AllSectors,
    /// One sector (0-based).
    Sector(usize),
    /// The nodal diameter `d`: weight `cos(d α j)` on sector `j` (0-based).
    NodalDiameter(usize),
}

/// A perturbation of the initial displacement: the static deflection
/// `K⁻¹ P w` under forces at the contact dofs with weights `w` per sector
/// (the pattern), scaled so that its largest contact displacement is
/// `amplitude` (m). A static shape moves every dof smoothly, unlike a
/// kick of the contact dof alone.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Perturbation {
    /// Largest displacement it adds at a contact dof, m.
    pub amplitude: f64,
    /// Where it acts.
    pub pattern: PerturbationPattern,
}

impl Perturbation {
    /// Parses `AMPLITUDE[:SECTOR|:ND=d]` (sector 1-based) for a wheel of
    /// `sectors` sectors; errors name `--perturb`.
    pub fn parse(text: &str, sectors: usize) -> Result<Self, SimulateError> {
        let bad = |why: String| {
            SimulateError::Input(format!(
                "--perturb {text}: {why} (allowed: AMPLITUDE in m, AMPLITUDE:SECTOR with SECTOR in 1..={sectors}, or AMPLITUDE:ND=d with d in 0..={})",
                sectors / 2
            ))
        };
        let (amplitude, place) = match text.split_once(':') {
            Some((a, p)) => (a, Some(p)),
            None => (text, None),
        };
        let amplitude: f64 = amplitude
            .trim()
            .parse()
            .map_err(|_| bad(format!("{amplitude:?} is not a number")))?;
        if !amplitude.is_finite() {
            return Err(bad("the amplitude must be finite".into()));
        }
        let pattern = match place.map(str::trim) {
            None => PerturbationPattern::AllSectors,
            Some(p) => match p.strip_prefix("ND=").or_else(|| p.strip_prefix("nd=")) {
                Some(d) => {
                    let d: usize = d
                        .parse()
                        .map_err(|_| bad(format!("nodal diameter {d:?} is not an integer")))?;
                    if d > sectors / 2 {
                        return Err(bad(format!("nodal diameter {d} is out of range")));
                    }
                    PerturbationPattern::NodalDiameter(d)
                }
                None => {
                    let j: usize = p
                        .parse()
                        .map_err(|_| bad(format!("sector {p:?} is not an integer")))?;
                    if j == 0 || j > sectors {
                        return Err(bad(format!("sector {j} is out of range")));
                    }
                    PerturbationPattern::Sector(j - 1)
                }
            },
        };
        Ok(Self { amplitude, pattern })
    }

    /// The weight of sector `j` (0-based).
    fn weight(&self, sector: usize, sectors: usize) -> f64 {
        match self.pattern {
            PerturbationPattern::AllSectors => {
                // A fixed linear congruential sequence: reproducible runs.
                let mut seed = (sector as u64 + 1).wrapping_mul(0x9e37_79b9_7f4a_7c15);
                seed ^= seed >> 31;
                seed = seed.wrapping_mul(0xbf58_476d_1ce4_e5b9);
                seed ^= seed >> 29;
                2.0 * (seed >> 11) as f64 / (1u64 << 53) as f64 - 1.0
            }
            PerturbationPattern::Sector(j) => f64::from(u8::from(j == sector)),
            PerturbationPattern::NodalDiameter(d) => {
                (2.0 * PI * (d * sector % sectors) as f64 / sectors as f64).cos()
            }
        }
    }

    /// Adds the perturbation to `state`'s displacement.
    pub fn apply(
        &self,
        state: &mut State,
        wheel: &WheelMatrices,
        loads: &WheelLoads,
    ) -> Result<(), SimulateError> {
        let sectors = wheel.sectors();
        let contacts = loads.contact_dofs().len();
        let mut force = vec![0.0; wheel.size()];
        for j in 0..sectors {
            let w = self.weight(j, sectors);
            for c in 0..contacts {
                force[loads.contact_index(j, c)] = w;
            }
        }
        let mut shape = vec![0.0; wheel.size()];
        CirculantFactorization::new(wheel, 1.0, 0.0, 0.0)
            .map_err(|_| {
                SimulateError::Input(
                    "--perturb: the stiffness of the wheel is singular (a free wheel has no static deflection)"
                        .into(),
                )
            })?
            .solve(&force, &mut shape);
        let largest = (0..sectors)
            .flat_map(|j| (0..contacts).map(move |c| (j, c)))
            .fold(0.0_f64, |m, (j, c)| {
                m.max(shape[loads.contact_index(j, c)].abs())
            });
        if largest == 0.0 {
            return Ok(());
        }
        let scale = self.amplitude / largest;
        for (x, s) in state.displacement.iter_mut().zip(&shape) {
            *x += scale * s;
        }
        Ok(())
    }
}
