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
use crate::stability::FloquetMode;
use faer::c64;
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
    /// Along the Floquet mode of the leading exponent (largest real part)
    /// of symmetry class `σ` at the harmonic balance point the state is
    /// rebuilt from (see [`Perturbation::apply_mode`]): displacement and
    /// velocity of every dof, so that the perturbation grows or decays at
    /// that exponent's rate from the first step.
    Exponent(i64),
}

/// A perturbation of the initial state. For the sector patterns, of the
/// displacement: the static deflection `K⁻¹ P w` under forces at the
/// contact dofs with weights `w` per sector (the pattern), scaled so that
/// its largest contact displacement is `amplitude` (m). A static shape
/// moves every dof smoothly, unlike a kick of the contact dof alone, but it
/// excites many modes at once. Along a Floquet mode
/// ([`PerturbationPattern::Exponent`]), of displacement and velocity, with
/// the same scale: it excites that exponent alone.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Perturbation {
    /// Largest displacement it adds at a contact dof, m.
    pub amplitude: f64,
    /// Where it acts.
    pub pattern: PerturbationPattern,
}

impl Perturbation {
    /// Parses `AMPLITUDE[:SECTOR|:ND=d|:EXPONENT=σ]` (sector 1-based) for a
    /// wheel of `sectors` sectors; errors name `--perturb`. Whether class
    /// `σ` exists is known only with the point's stability check.
    pub fn parse(text: &str, sectors: usize) -> Result<Self, SimulateError> {
        let bad = |why: String| {
            SimulateError::Input(format!(
                "--perturb {text}: {why} (allowed: AMPLITUDE in m, AMPLITUDE:SECTOR with SECTOR in 1..={sectors}, AMPLITUDE:ND=d with d in 0..={}, or AMPLITUDE:EXPONENT=σ with σ a symmetry class of the --from point)",
                sectors / 2
            ))
        };
        let (amplitude, place) = match text.split_once(':') {
            Some((a, p)) => (a, Some(p)),
            None => (text, None),
        };
        let given = amplitude.trim();
        let amplitude: f64 = given
            .parse()
            .map_err(|_| bad(format!("{given:?} is not a number")))?;
        if !amplitude.is_finite() {
            return Err(bad("the amplitude must be finite".into()));
        }
        // The pattern sets the signs; a sign on the amplitude would only
        // flip them (and 0 perturbs nothing).
        if amplitude <= 0.0 {
            return Err(bad(format!("the amplitude {given} m must be > 0")));
        }
        let pattern = match place.map(str::trim) {
            None => PerturbationPattern::AllSectors,
            Some(p) if p.to_ascii_uppercase().starts_with("EXPONENT=") => {
                let sigma = p["EXPONENT=".len()..].trim();
                let sigma: i64 = sigma
                    .parse()
                    .map_err(|_| bad(format!("class {sigma:?} is not an integer")))?;
                PerturbationPattern::Exponent(sigma)
            }
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
            // Not a sector pattern (see `apply_mode`).
            PerturbationPattern::Exponent(_) => 0.0,
        }
    }

    /// Adds the perturbation of a sector pattern to `state`'s
    /// displacement (refused for [`PerturbationPattern::Exponent`], which
    /// needs the point's mode: see [`Self::apply_mode`]).
    pub fn apply(
        &self,
        state: &mut State,
        wheel: &WheelMatrices,
        loads: &WheelLoads,
    ) -> Result<(), SimulateError> {
        if let PerturbationPattern::Exponent(sigma) = self.pattern {
            return Err(SimulateError::Input(format!(
                "--perturb {}:EXPONENT={sigma}: a Floquet mode is one of a harmonic balance point: give --from RESULTS --point P",
                self.amplitude
            )));
        }
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

impl Perturbation {
    /// Adds `Re(e^{iφ} c y(0))` to `state`'s displacement and
    /// `Re(e^{iφ} c ẏ(0))` to its velocity, for the Floquet `mode` of the
    /// point `state` was rebuilt from at `t = 0` and `φ = phase` (rad): the
    /// complex scale `c` makes the mode's largest contact displacement
    /// (in modulus) `amplitude`, real at phase 0, so that the perturbation
    /// of phase 0 has its largest contact displacement `amplitude` (m),
    /// whatever the pattern (a mode that leaves the contact dofs still is
    /// scaled by its largest displacement). The perturbations of phases 0
    /// and `π/2` are the real and imaginary parts of one complex mode (see
    /// [`FloquetMode::real_state`]).
    pub fn apply_mode(
        &self,
        state: &mut State,
        mode: &FloquetMode,
        phase: f64,
        loads: &WheelLoads,
    ) -> Result<(), SimulateError> {
        let size = state.displacement.len();
        if mode.displacement.len() != size || mode.velocity.len() != size {
            return Err(SimulateError::Input(format!(
                "the Floquet mode has {} dofs, the wheel {size}",
                mode.displacement.len()
            )));
        }
        let contacts = loads.contact_dofs().len();
        let sectors = loads.contact_count() / contacts.max(1);
        let largest = |indices: &mut dyn Iterator<Item = usize>| {
            indices
                .map(|i| mode.displacement[i])
                .max_by(|a, b| a.norm_sqr().total_cmp(&b.norm_sqr()))
                .filter(|z| z.norm_sqr() > 0.0)
        };
        let reference = largest(
            &mut (0..sectors)
                .flat_map(|j| (0..contacts).map(move |c| (j, c)))
                .map(|(j, c)| loads.contact_index(j, c)),
        )
        .or_else(|| largest(&mut (0..size)))
        .ok_or_else(|| SimulateError::Input("the Floquet mode vanishes at t = 0".into()))?;
        let scale = c64::cis(phase) * self.amplitude / reference;
        for (x, y) in state.displacement.iter_mut().zip(&mode.displacement) {
            *x += (scale * y).re;
        }
        for (v, y) in state.velocity.iter_mut().zip(&mode.velocity) {
            *v += (scale * y).re;
        }
        Ok(())
    }
}
