//! What a point of a branch means physically, on any sector and from any
//! basis (reduced ones included): the displacement and velocity of any dof
//! as time series and per-harmonic amplitudes, the contact force history,
//! and which sectors touch the casing and for how long (Sec. 5.4).
//!
//! Sectors and dofs are 0-based here (sector `j` is the paper's `j + 1`).
//! Time samples are at `τ_n = ω t_n = 2π n / N_t`, `n = 0..N_t`.

use super::ResultsError;
use crate::contact::apply_law;
use crate::hbm::aft::Aft;
use crate::hbm::recovery::{dof_coordinates, wall_coordinates};
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

fn check_time_samples(problem: &HarmonicBalance, time_samples: usize) -> Result<(), ResultsError> {
    let harmonics = problem.layout().harmonics;
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
    Ok(with_aft(problem.layout().harmonics, time_samples, |aft| {
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
    }))
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
    Ok(with_aft(problem.layout().harmonics, time_samples, |aft| {
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
    }))
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

fn check_unknowns(problem: &HarmonicBalance, x: &[f64]) -> Result<(), ResultsError> {
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
    let (n, contact_dofs, harmonics) = (layout.sectors, layout.contact_dofs, layout.harmonics);
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
                apply_law(problem.law(), read, &gap, &mut force, None, None);
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

/// The observed dof on every sector at one point, reduced to what the
/// result files keep (see [`BranchRecovery::point`]).
#[derive(Clone, Debug, PartialEq)]
pub struct ObservedSummary {
    /// Displacement harmonic coordinates `[a0, Re X1, Im X1, …]` per sector, m.
    pub coordinates: Vec<Vec<f64>>,
    /// Largest displacement over the period (toward the casing) per sector, m.
    pub peak: Vec<f64>,
    /// Largest `|displacement|` per sector, m.
    pub max_abs: Vec<f64>,
    /// Largest `|velocity|` per sector, m/s.
    pub velocity_max_abs: Vec<f64>,
}

/// The contact state on every sector at one point, reduced to what the
/// result files keep; arrays are sector-major (`sector · n_c + contact`).
#[derive(Clone, Debug, PartialEq)]
pub struct ContactSummary {
    /// Harmonic coordinates of the contact force, N.
    pub force_coordinates: Vec<Vec<f64>>,
    /// Largest contact force over the period, N ([`ContactSignal::peak_force`]).
    pub peak_force: Vec<f64>,
    /// Fraction of the period in contact ([`ContactSignal::fraction_in_contact`]).
    pub fraction_in_contact: Vec<f64>,
    /// Largest penetration, m ([`ContactSignal::max_penetration`]).
    pub max_penetration: Vec<f64>,
    /// Number of sectors in contact at some instant.
    pub sectors_in_contact: usize,
}

/// One point's summaries. The contact part fails apart from the observed
/// dof's, so a run can still write `branch.csv` when it does.
#[derive(Debug)]
pub struct PointSummary {
    /// The observed dof.
    pub observed: ObservedSummary,
    /// The contact state, or why it could not be recovered.
    pub contact: Result<ContactSummary, ResultsError>,
}

/// The recovery of many points of one problem on every sector, with what
/// they share formed once: the gap samples (a cosine per instant, sector
/// and contact dof, the same at every point). It gives the same numbers
/// as [`dof_histories`] and [`contact_history`] reduced to their
/// extremes, with the same transforms, without keeping the time signals.
/// It reads the problem only: points can be recovered in parallel.
pub struct BranchRecovery<'a> {
    problem: &'a HarmonicBalance,
    observed_dof: usize,
    time_samples: usize,
    /// Gap samples per `sector · n_c + contact`.
    gaps: Vec<Vec<f64>>,
}

impl<'a> BranchRecovery<'a> {
    /// Recovery of sector dof `observed_dof` (0-based) and of the contact
    /// state of `problem`, sampled at `time_samples` instants.
    pub fn new(problem: &'a HarmonicBalance, observed_dof: usize, time_samples: usize) -> Self {
        let layout = problem.layout();
        let (n, contact_dofs) = (layout.sectors, layout.contact_dofs);
        let casing = problem.casing();
        let gaps = (0..n)
            .flat_map(|sector| {
                (0..contact_dofs)
                    .map(move |contact| casing.gap_samples(n, sector, contact, time_samples))
            })
            .collect();
        Self {
            problem,
            observed_dof,
            time_samples,
            gaps,
        }
    }

    /// The summaries of the point `(x, omega)` on every sector. Fails as
    /// [`dof_histories`] does; the contact part fails as
    /// [`contact_history`] does.
    pub fn point(&self, x: &[f64], omega: f64) -> Result<PointSummary, ResultsError> {
        let problem = self.problem;
        let layout = problem.layout();
        let time_samples = self.time_samples;
        let (n, contact_dofs, harmonics) = (layout.sectors, layout.contact_dofs, layout.harmonics);
        let all: Vec<usize> = (0..n).collect();
        check_time_samples(problem, time_samples)?;
        check_unknowns(problem, x)?;
        let coordinates = dof_coordinates(problem, x, omega, self.observed_dof, &all)?;
        let setup = ContactSetup::new(problem, x, omega, &all);
        let size = layout.coordinates();
        let law = problem.law();
        let mut observed = ObservedSummary {
            coordinates: Vec::new(),
            peak: Vec::with_capacity(n),
            max_abs: Vec::with_capacity(n),
            velocity_max_abs: Vec::with_capacity(n),
        };
        let mut contact = ContactSummary {
            force_coordinates: Vec::with_capacity(n * contact_dofs),
            peak_force: Vec::with_capacity(n * contact_dofs),
            fraction_in_contact: Vec::with_capacity(n * contact_dofs),
            max_penetration: Vec::with_capacity(n * contact_dofs),
            sectors_in_contact: 0,
        };
        with_aft(harmonics, time_samples, |aft| {
            // One set of buffers per point, reused over sectors and dofs.
            let mut displacement = vec![0.0; time_samples];
            let mut velocity = vec![0.0; time_samples];
            let mut wall = vec![0.0; time_samples];
            let mut reading = vec![0.0; time_samples];
            let mut force = vec![0.0; time_samples];
            for (sector, c) in coordinates.iter().enumerate() {
                aft.to_time(c, &mut displacement);
                observed.peak.push(peak(&displacement));
                observed.max_abs.push(max_abs(&displacement));
                aft.to_time(&velocity_coordinates(c, omega), &mut velocity);
                observed.velocity_max_abs.push(max_abs(&velocity));
                let Ok(setup) = &setup else {
                    continue;
                };
                let mut touching = false;
                for dof in 0..contact_dofs {
                    let wall_coordinates = &setup.per_contact[dof][sector];
                    // The observed dof is often the contact dof itself (no
                    // wall): the same coordinates give the same samples.
                    let samples: &[f64] = if same_bits(wall_coordinates, c) {
                        &displacement
                    } else {
                        aft.to_time(wall_coordinates, &mut wall);
                        &wall
                    };
                    let gap = &self.gaps[sector * contact_dofs + dof];
                    let max_penetration = samples
                        .iter()
                        .zip(gap)
                        .fold(f64::NEG_INFINITY, |m, (x, g)| m.max(x - g));
                    let read: &[f64] = match &setup.per_contact_variable {
                        Some(variable) => {
                            aft.to_time(&variable[dof][sector], &mut reading);
                            &reading
                        }
                        None => samples,
                    };
                    let found = apply_law(law, read, gap, &mut force, None, None);
                    let mut force_coordinates = vec![0.0; size];
                    aft.to_frequency(&force, &mut force_coordinates);
                    contact.force_coordinates.push(force_coordinates);
                    contact.peak_force.push(max_abs(&force));
                    contact
                        .fraction_in_contact
                        .push(found.instants_in_contact as f64 / time_samples as f64);
                    contact.max_penetration.push(max_penetration);
                    touching |= found.instants_in_contact > 0;
                }
                contact.sectors_in_contact += usize::from(touching);
            }
        });
        observed.coordinates = coordinates;
        Ok(PointSummary {
            observed,
            contact: setup.map(|_| contact),
        })
    }
}

/// The contact unknowns' coordinates `[contact][sector]` of a point and,
/// for a law that reads the linear residual, of what it reads
/// (`v = a x + b r`, see [`crate::contact`]).
struct ContactSetup {
    per_contact: Vec<Vec<Vec<f64>>>,
    per_contact_variable: Option<Vec<Vec<Vec<f64>>>>,
}

impl ContactSetup {
    fn new(
        problem: &HarmonicBalance,
        x: &[f64],
        omega: f64,
        sectors: &[usize],
    ) -> Result<Self, ResultsError> {
        check_sectors(problem, sectors)?;
        check_unknowns(problem, x)?;
        let contact_dofs = problem.layout().contact_dofs;
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

/// Whether two coordinate vectors are bit for bit equal (`==` would take
/// `-0.0` for `0.0`, which can change the sign of a zero sample).
fn same_bits(a: &[f64], b: &[f64]) -> bool {
    a.len() == b.len() && a.iter().zip(b).all(|(x, y)| x.to_bits() == y.to_bits())
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

    /// Bits of a list of numbers, for exact comparisons.
    fn bits(values: impl IntoIterator<Item = f64>) -> Vec<u64> {
        values.into_iter().map(f64::to_bits).collect()
    }

    #[test]
    fn branch_recovery_equals_the_full_histories_bit_for_bit() {
        use crate::case::{BasisChoice, Case};
        use std::path::Path;
        let base = "[model]\nsectors = 6\n[casing]\norder = 2\namplitude = 5e-5\n\
                    [harmonic_balance]\nharmonics = 3\ntime_samples = 66\n";
        let cases = [
            format!("{base}[output]\nobserved_dof = 1\n"),
            format!("{base}[output]\nobserved_dof = 2\n"),
            format!("{base}[contact]\nlaw = \"dlft\"\nwall_stiffness = 1e8\n"),
        ];
        for text in &cases {
            let case = Case::from_toml(text, Path::new("test.toml")).expect("case");
            let mut prepared =
                crate::run::prepare(&case, Path::new("."), BasisChoice::Symmetry).expect("prepare");
            let problem = &mut prepared.problem;
            let omega = 2.0 * PI * 210.0;
            // Far above the gap: every sector touches the casing.
            let x: Vec<f64> = problem
                .linear_solution(omega)
                .expect("linear")
                .iter()
                .map(|v| 50.0 * v)
                .collect();
            let dof = case.output.observed_dof - 1;
            let nt = case.harmonic_balance.time_samples;
            let all: Vec<usize> = (0..problem.layout().sectors).collect();
            let histories = dof_histories(problem, &x, omega, dof, &all, nt).expect("histories");
            let contact = contact_history(problem, &x, omega, &all, nt).expect("contact");
            let summary = BranchRecovery::new(problem, dof, nt)
                .point(&x, omega)
                .expect("summary");
            let observed = &summary.observed;
            let summary_contact = summary.contact.as_ref().expect("contact summary");
            assert!(!contact.sectors_in_contact().is_empty(), "{text}");
            assert_eq!(
                bits(observed.coordinates.concat()),
                bits(histories.iter().flat_map(|h| h.coordinates.clone()))
            );
            assert_eq!(
                bits(observed.peak.clone()),
                bits(histories.iter().map(|h| h.peak()))
            );
            assert_eq!(
                bits(observed.max_abs.clone()),
                bits(histories.iter().map(|h| h.max_abs()))
            );
            assert_eq!(
                bits(observed.velocity_max_abs.clone()),
                bits(histories.iter().map(|h| h.velocity_max_abs()))
            );
            let mut aft = Aft::new(case.harmonic_balance.harmonics, nt);
            let forces = contact.signals.iter().flat_map(|s| {
                let mut c = vec![0.0; aft.coordinates()];
                aft.to_frequency(&s.force, &mut c);
                c
            });
            assert_eq!(
                bits(summary_contact.force_coordinates.concat()),
                bits(forces)
            );
            let signals = &contact.signals;
            assert_eq!(
                bits(summary_contact.peak_force.clone()),
                bits(signals.iter().map(|s| s.peak_force()))
            );
            assert_eq!(
                bits(summary_contact.fraction_in_contact.clone()),
                bits(signals.iter().map(|s| s.fraction_in_contact()))
            );
            assert_eq!(
                bits(summary_contact.max_penetration.clone()),
                bits(signals.iter().map(|s| s.max_penetration()))
            );
            assert_eq!(
                summary_contact.sectors_in_contact,
                contact.sectors_in_contact().len()
            );
        }
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
