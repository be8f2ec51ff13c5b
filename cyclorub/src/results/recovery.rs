//! What a point of a branch means physically, on any sector and from any
//! basis (reduced ones included): the displacement and velocity of any dof
//! as time series and per-harmonic amplitudes, the contact force history,
//! and which sectors touch the casing and for how long (Sec. 5.4).
//!
//! Sectors and dofs are 0-based here (sector `j` is the paper's `j + 1`).
//! Time samples are at `τ_n = ω t_n = 2π n / N_t`, `n = 0..N_t`.

pub use super::summary::{BranchRecovery, ContactSummary, ObservedSummary, PointSummary};
use super::ResultsError;
use crate::hbm::aft::Aft;
use crate::hbm::recovery::{dof_coordinates, linear_dof_coordinates, wall_coordinates};
use crate::hbm::HarmonicBalance;
use std::cell::RefCell;
use std::f64::consts::PI;

thread_local! {
    /// The last transform planned on this thread: recovery runs point after
    /// point with the same `(N_h, N_t)`, and planning costs more than a
    /// transform.
    static AFT: RefCell<Option<Aft>> = const { RefCell::new(None) };
}

/// Runs `f` with an [`Aft`] for `(harmonics, time_samples)`, planned once
/// per thread and size.
pub(crate) fn with_aft<R>(
    harmonics: usize,
    time_samples: usize,
    f: impl FnOnce(&mut Aft) -> R,
) -> R {
    AFT.with(|cell| {
        let mut slot = cell.borrow_mut();
        let fits = slot
            .as_ref()
            .is_some_and(|a| a.harmonics() == harmonics && a.time_samples() == time_samples);
        if !fits {
            *slot = Some(Aft::new(harmonics, time_samples));
        }
        match slot.as_mut() {
            Some(aft) => f(aft),
            None => f(&mut Aft::new(harmonics, time_samples)),
        }
    })
}

/// The real harmonic coordinates of the velocity of a signal whose
/// displacement coordinates are `coordinates` (see [`crate::hbm::aft`]):
/// `d/dt` multiplies `X_k` by `i k ω`.
pub fn velocity_coordinates(coordinates: &[f64], omega: f64) -> Vec<f64> {
    let mut out = vec![0.0; coordinates.len()];
    for k in 1..=(coordinates.len().saturating_sub(1)) / 2 {
        let factor = k as f64 * omega;
        out[2 * k - 1] = -factor * coordinates[2 * k];
        out[2 * k] = factor * coordinates[2 * k - 1];
    }
    out
}

/// The amplitude of each harmonic, `[|a0|, 2|X_1|, …, 2|X_Nh|]`: the
/// amplitude of the cosine `2|X_k| cos(kωt + φ_k)` each harmonic adds.
pub fn harmonic_amplitudes(coordinates: &[f64]) -> Vec<f64> {
    let harmonics = coordinates.len().saturating_sub(1) / 2;
    let mut out = Vec::with_capacity(harmonics + 1);
    out.push(coordinates.first().map_or(0.0, |a| a.abs()));
    for k in 1..=harmonics {
        out.push(2.0 * coordinates[2 * k - 1].hypot(coordinates[2 * k]));
    }
    out
}

/// The largest sample (the displacement toward the casing, as `branch.csv`
/// reports it).
pub fn peak(samples: &[f64]) -> f64 {
    samples.iter().cloned().fold(f64::NEG_INFINITY, f64::max)
}

/// The largest absolute sample.
pub fn max_abs(samples: &[f64]) -> f64 {
    samples.iter().fold(0.0_f64, |m, v| m.max(v.abs()))
}

/// The motion of one dof on one sector over one period.
#[derive(Clone, Debug, PartialEq)]
pub struct DofHistory {
    /// The sector (0-based).
    pub sector: usize,
    /// Displacement harmonic coordinates `[a0, Re X1, Im X1, …]`, m.
    pub coordinates: Vec<f64>,
    /// Velocity harmonic coordinates, m/s.
    pub velocity_coordinates: Vec<f64>,
    /// Displacement at `τ_n`, m.
    pub displacement: Vec<f64>,
    /// Velocity at `τ_n`, m/s.
    pub velocity: Vec<f64>,
}

impl DofHistory {
    /// Amplitude per harmonic of the displacement, m (see [`harmonic_amplitudes`]).
    pub fn harmonic_amplitudes(&self) -> Vec<f64> {
        harmonic_amplitudes(&self.coordinates)
    }

    /// The largest displacement over the period (toward the casing), m.
    pub fn peak(&self) -> f64 {
        peak(&self.displacement)
    }

    /// The largest `|displacement|` over the period, m.
    pub fn max_abs(&self) -> f64 {
        max_abs(&self.displacement)
    }

    /// The largest `|velocity|` over the period, m/s.
    pub fn velocity_max_abs(&self) -> f64 {
        max_abs(&self.velocity)
    }
}

fn check_sectors(problem: &HarmonicBalance, sectors: &[usize]) -> Result<(), ResultsError> {
    let n = problem.layout().sectors;
    match sectors.iter().find(|&&j| j >= n) {
        Some(&j) => Err(ResultsError::Input(format!(
            "sector {} does not exist: the wheel has sectors 1..={n}",
            j + 1
        ))),
        None => Ok(()),
    }
}

pub(super) fn check_time_samples(
    problem: &HarmonicBalance,
    time_samples: usize,
) -> Result<(), ResultsError> {
    let harmonics = problem.layout().harmonics();
    if time_samples < 2 * harmonics + 1 {
        return Err(ResultsError::Input(format!(
            "{time_samples} time samples cannot hold {harmonics} harmonics: give at least {}",
            2 * harmonics + 1
        )));
    }
    Ok(())
}

/// The displacement and velocity of sector dof `dof` (0-based) on each
/// sector of `sectors` (0-based) at the point `(x, omega)`, recovered from
/// the unknowns of any basis, sampled at `time_samples` instants.
pub fn dof_histories(
    problem: &HarmonicBalance,
    x: &[f64],
    omega: f64,
    dof: usize,
    sectors: &[usize],
    time_samples: usize,
) -> Result<Vec<DofHistory>, ResultsError> {
    check_sectors(problem, sectors)?;
    check_time_samples(problem, time_samples)?;
    if x.len() != problem.layout().unknowns {
        return Err(ResultsError::Input(format!(
            "{} unknowns given, the problem has {}",
            x.len(),
            problem.layout().unknowns
        )));
    }
    let coordinates = dof_coordinates(problem, x, omega, dof, sectors)?;
    Ok(with_aft(
        problem.layout().harmonics(),
        time_samples,
        |aft| {
            sectors
                .iter()
                .zip(coordinates)
                .map(|(&sector, coordinates)| {
                    let velocity_coordinates = velocity_coordinates(&coordinates, omega);
                    let mut displacement = vec![0.0; time_samples];
                    let mut velocity = vec![0.0; time_samples];
                    aft.to_time(&coordinates, &mut displacement);
                    aft.to_time(&velocity_coordinates, &mut velocity);
                    DofHistory {
                        sector,
                        coordinates,
                        velocity_coordinates,
                        displacement,
                        velocity,
                    }
                })
                .collect()
        },
    ))
}

/// The largest displacement over the period (toward the casing) of sector
/// dof `dof` (0-based) on each sector of `sectors` (0-based): the amplitude
/// of `branch.csv`, without the rest of [`dof_histories`].
pub fn dof_peaks(
    problem: &HarmonicBalance,
    x: &[f64],
    omega: f64,
    dof: usize,
    sectors: &[usize],
    time_samples: usize,
) -> Result<Vec<f64>, ResultsError> {
    check_sectors(problem, sectors)?;
    check_time_samples(problem, time_samples)?;
    let coordinates = dof_coordinates(problem, x, omega, dof, sectors)?;
    Ok(coordinate_peaks(problem, &coordinates, time_samples))
}

/// The linear response's [`dof_peaks`] at `omega` on every sector, its
/// harmonic 0 given (`static_coordinates`, the same at every frequency:
/// [`linear_static_coordinates`]), the rest solved on each loaded block's
/// dofs ([`crate::hbm::recovery::linear_dof_coordinates`]).
pub fn linear_dof_peaks(
    problem: &HarmonicBalance,
    omega: f64,
    dof: usize,
    static_coordinates: &[Vec<f64>],
    time_samples: usize,
) -> Result<Vec<f64>, ResultsError> {
    check_time_samples(problem, time_samples)?;
    let all: Vec<usize> = (0..problem.layout().sectors).collect();
    let mut coordinates = linear_dof_coordinates(problem, omega, dof, &all, |k| k > 0)?;
    for (c, s) in coordinates.iter_mut().zip(static_coordinates) {
        c[0] += s[0];
    }
    Ok(coordinate_peaks(problem, &coordinates, time_samples))
}

/// Harmonic 0 of the linear response of sector dof `dof` on every sector
/// (the static and preload loads), for [`linear_dof_peaks`].
pub fn linear_static_coordinates(
    problem: &HarmonicBalance,
    dof: usize,
) -> Result<Vec<Vec<f64>>, ResultsError> {
    let all: Vec<usize> = (0..problem.layout().sectors).collect();
    Ok(linear_dof_coordinates(problem, 0.0, dof, &all, |k| k == 0)?)
}

/// The largest of `time_samples` samples of each sector's coordinates (or
/// the first harmonic's crest nearest to a sample, when nothing is above
/// it).
fn coordinate_peaks(
    problem: &HarmonicBalance,
    coordinates: &[Vec<f64>],
    time_samples: usize,
) -> Vec<f64> {
    with_aft(problem.layout().harmonics(), time_samples, |aft| {
        let mut samples = vec![0.0; time_samples];
        coordinates
            .iter()
            .map(|c| {
                sampled_peak_of_first_harmonic(c, time_samples).unwrap_or_else(|| {
                    aft.to_time(c, &mut samples);
                    peak(&samples)
                })
            })
            .collect()
    })
}

/// The largest of the `N_t` samples of `a0 + 2|X1| cos(τ + φ)` without
/// sampling, when the coordinates hold nothing above harmonic 1 (a linear
/// response); `None` otherwise.
fn sampled_peak_of_first_harmonic(coordinates: &[f64], time_samples: usize) -> Option<f64> {
    if coordinates.len() < 3 || coordinates[3..].iter().any(|&v| v != 0.0) {
        return None;
    }
    let amplitude = 2.0 * coordinates[1].hypot(coordinates[2]);
    let phase = coordinates[2].atan2(coordinates[1]);
    // The sample nearest to the crest τ = −φ.
    let step = 2.0 * PI / time_samples as f64;
    let offset = (-phase).rem_euclid(step);
    let distance = offset.min(step - offset);
    Some(coordinates[0] + amplitude * distance.cos())
}

/// The contact state of one contact dof on one sector over one period.
#[derive(Clone, Debug, PartialEq)]
pub struct ContactSignal {
    /// The sector (0-based).
    pub sector: usize,
    /// The contact dof's position in the case's contact dof list (0-based).
    pub contact: usize,
    /// Penetration `p = x − g0` at `τ_n`, m (`p ≤ 0`: open gap). With a
    /// flexible wall (DLFT-HBM), `x` is the wall node's displacement.
    pub penetration: Vec<f64>,
    /// Contact force `f ≥ 0` at `τ_n`, N (acting as `−f` on the blade).
    pub force: Vec<f64>,
    /// Whether the dof touches the casing at `τ_n`: `p > 0` for a law
    /// (the regularized law's force then exceeds its value `γ` at `p = 0`),
    /// `f > 0` for DLFT-HBM.
    pub in_contact: Vec<bool>,
}

impl ContactSignal {
    /// The fraction of the period spent in contact, in `[0, 1]`.
    pub fn fraction_in_contact(&self) -> f64 {
        if self.in_contact.is_empty() {
            return 0.0;
        }
        self.in_contact.iter().filter(|&&c| c).count() as f64 / self.in_contact.len() as f64
    }

    /// The largest contact force over the period, N.
    pub fn peak_force(&self) -> f64 {
        max_abs(&self.force)
    }

    /// The largest penetration over the period, m.
    pub fn max_penetration(&self) -> f64 {
        peak(&self.penetration)
    }
}

/// The contact histories of a point: one signal per sector asked for and
/// contact dof (sector-major).
#[derive(Clone, Debug, PartialEq)]
pub struct ContactHistory {
    /// Contact dofs per sector.
    pub contact_dofs: usize,
    /// The signals, sector-major.
    pub signals: Vec<ContactSignal>,
}

impl ContactHistory {
    /// The signal of `sector` and contact dof `contact` (both 0-based).
    pub fn signal(&self, sector: usize, contact: usize) -> Option<&ContactSignal> {
        self.signals
            .iter()
            .find(|s| s.sector == sector && s.contact == contact)
    }

    /// The sectors (0-based) where some contact dof touches the casing at
    /// some instant.
    pub fn sectors_in_contact(&self) -> Vec<usize> {
        let mut sectors: Vec<usize> = self
            .signals
            .iter()
            .filter(|s| s.in_contact.iter().any(|&c| c))
            .map(|s| s.sector)
            .collect();
        sectors.dedup();
        sectors
    }

    /// The fraction of the period each sector spends in contact (any of
    /// its contact dofs), in the order of the sectors asked for.
    pub fn fraction_per_sector(&self) -> Vec<(usize, f64)> {
        let mut out: Vec<(usize, f64)> = Vec::new();
        let mut index = 0;
        while index < self.signals.len() {
            let sector = self.signals[index].sector;
            let group: Vec<&ContactSignal> = self.signals[index..]
                .iter()
                .take_while(|s| s.sector == sector)
                .collect();
            let samples = group.first().map_or(0, |s| s.in_contact.len());
            let touching = (0..samples)
                .filter(|&n| group.iter().any(|s| s.in_contact[n]))
                .count();
            out.push((sector, touching as f64 / samples.max(1) as f64));
            index += group.len();
        }
        out
    }
}

pub(super) fn check_unknowns(problem: &HarmonicBalance, x: &[f64]) -> Result<(), ResultsError> {
    let unknowns = problem.layout().unknowns;
    if x.len() != unknowns {
        return Err(ResultsError::Input(format!(
            "{} unknowns given, the problem has {unknowns}",
            x.len()
        )));
    }
    Ok(())
}

/// The contact force history of every contact dof on each sector of
/// `sectors` (0-based) at the point `(x, omega)`: the problem's contact law
/// applied to what it reads there (see [`crate::contact`]), formed from the
/// unknowns as the residual forms it. Exact on every sector, sampled or
/// not, for any basis.
pub fn contact_history(
    problem: &HarmonicBalance,
    x: &[f64],
    omega: f64,
    sectors: &[usize],
    time_samples: usize,
) -> Result<ContactHistory, ResultsError> {
    check_time_samples(problem, time_samples)?;
    let setup = ContactSetup::new(problem, x, omega, sectors)?;
    let layout = problem.layout();
    let (n, contact_dofs, harmonics) = (layout.sectors, problem.normal_dofs(), layout.harmonics());
    let casing = problem.casing();
    let mut displacement = vec![0.0; time_samples];
    let mut reading = vec![0.0; time_samples];
    let signals = with_aft(harmonics, time_samples, |aft| {
        let mut signals = Vec::with_capacity(sectors.len() * contact_dofs);
        for (index, &sector) in sectors.iter().enumerate() {
            for contact in 0..contact_dofs {
                let gap = casing.gap_samples(n, sector, contact, time_samples);
                aft.to_time(&setup.per_contact[contact][index], &mut displacement);
                let penetration: Vec<f64> =
                    displacement.iter().zip(&gap).map(|(x, g)| x - g).collect();
                let read = match &setup.per_contact_variable {
                    Some(variable) => {
                        aft.to_time(&variable[contact][index], &mut reading);
                        &reading
                    }
                    None => &displacement,
                };
                let mut force = vec![0.0; time_samples];
                problem.law().apply(read, &gap, &mut force, None, None);
                let input = problem.law().input();
                let in_contact = read
                    .iter()
                    .zip(&gap)
                    .map(|(v, g)| input.at(*v, *g) > 0.0)
                    .collect();
                signals.push(ContactSignal {
                    sector,
                    contact,
                    penetration,
                    force,
                    in_contact,
                });
            }
        }
        signals
    });
    Ok(ContactHistory {
        contact_dofs,
        signals,
    })
}

/// The contact unknowns' coordinates `[contact][sector]` of a point and,
/// for a law that reads the linear residual, of what it reads
/// (`v = a x + b r`, see [`crate::contact`]).
pub(super) struct ContactSetup {
    pub(super) per_contact: Vec<Vec<Vec<f64>>>,
    pub(super) per_contact_variable: Option<Vec<Vec<Vec<f64>>>>,
}

impl ContactSetup {
    pub(super) fn new(
        problem: &HarmonicBalance,
        x: &[f64],
        omega: f64,
        sectors: &[usize],
    ) -> Result<Self, ResultsError> {
        check_sectors(problem, sectors)?;
        check_unknowns(problem, x)?;
        let contact_dofs = problem.normal_dofs();
        let per_contact = (0..contact_dofs)
            .map(|c| wall_coordinates(problem, x, c, sectors))
            .collect();
        let per_contact_variable = if problem.law().input().reads_residual() {
            let v = problem.law_variable(x, omega)?;
            Some(
                (0..contact_dofs)
                    .map(|c| wall_coordinates(problem, &v, c, sectors))
                    .collect(),
            )
        } else {
            None
        };
        Ok(Self {
            per_contact,
            per_contact_variable,
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_first_harmonic_peak_equals_the_sampled_maximum() {
        let mut aft = Aft::new(3, 37);
        let mut samples = vec![0.0; 37];
        for (re, im) in [(0.3, -0.7), (-1.0, 0.2), (0.0, 1.0), (-0.5, -0.5)] {
            let c = [0.1, re, im, 0.0, 0.0, 0.0, 0.0];
            aft.to_time(&c, &mut samples);
            let closed = sampled_peak_of_first_harmonic(&c, 37).unwrap();
            assert!(
                (closed - peak(&samples)).abs() < 1e-14,
                "{closed} vs {}",
                peak(&samples)
            );
        }
        assert!(sampled_peak_of_first_harmonic(&[0.0, 1.0, 0.0, 0.1, 0.0], 37).is_none());
    }

    #[test]
    fn velocity_of_a_cosine_is_minus_omega_sine() {
        // u = 2 Re(X1 e^{iωt}) with X1 = 0.5: u = cos ωt, v = −ω sin ωt.
        let omega = 3.0;
        let coordinates = [0.2, 0.5, 0.0];
        let v = velocity_coordinates(&coordinates, omega);
        let mut aft = Aft::new(1, 16);
        let mut samples = vec![0.0; 16];
        aft.to_time(&v, &mut samples);
        for (n, s) in samples.iter().enumerate() {
            let tau = 2.0 * PI * n as f64 / 16.0;
            assert!((s + omega * tau.sin()).abs() < 1e-14);
        }
        assert_eq!(harmonic_amplitudes(&coordinates), vec![0.2, 1.0]);
    }
}
