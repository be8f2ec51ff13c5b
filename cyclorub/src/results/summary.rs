//! The summaries of a point on every sector that the result files keep
//! (the observed dof's extremes and coordinates, the contact state), for
//! many points of one problem at once: what they share is formed once, and
//! points are recovered in parallel from a problem read only.

use super::recovery::{
    check_time_samples, check_unknowns, max_abs, peak, velocity_coordinates, with_aft, ContactSetup,
};
#[cfg(doc)]
use super::recovery::{contact_history, dof_histories, ContactSignal};
use super::ResultsError;
use crate::hbm::recovery::dof_coordinates;
use crate::hbm::sector_shifts::{rotate_coordinates, sector_sources};
use crate::hbm::HarmonicBalance;

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
    /// Per sector, whether it touches at some instant.
    pub touching: Vec<bool>,
}

impl ContactSummary {
    /// Appends a sector that repeats sector `source`, `r` samples later.
    fn repeat(&mut self, source: usize, contact_dofs: usize, r: usize, time_samples: usize) {
        for dof in 0..contact_dofs {
            let at = source * contact_dofs + dof;
            let force = rotate_coordinates(&self.force_coordinates[at], r, time_samples);
            self.force_coordinates.push(force);
            self.peak_force.push(self.peak_force[at]);
            self.fraction_in_contact.push(self.fraction_in_contact[at]);
            self.max_penetration.push(self.max_penetration[at]);
        }
        let touching = self.touching[source];
        self.touching.push(touching);
        self.sectors_in_contact += usize::from(touching);
    }
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
/// and contact dof, the same at every point) and which sectors repeat
/// another's signals (`hbm::sector_shifts`: on a reduced basis, the
/// symmetry of the solution). It gives the numbers of [`dof_histories`]
/// and [`contact_history`] reduced to their extremes, with the same
/// transforms, without keeping the time signals; a sector that repeats
/// another gets that sector's extremes (equal to round-off). It reads the
/// problem only: points can be recovered in parallel.
pub struct BranchRecovery<'a> {
    problem: &'a HarmonicBalance,
    observed_dof: usize,
    time_samples: usize,
    /// Gap samples per `sector · n_c + contact`.
    gaps: Vec<Vec<f64>>,
    /// Per sector, the sector it repeats and the rotation in samples.
    sources: Vec<Option<(usize, usize)>>,
}

impl<'a> BranchRecovery<'a> {
    /// Recovery of sector dof `observed_dof` (0-based) and of the contact
    /// state of `problem`, sampled at `time_samples` instants.
    pub fn new(problem: &'a HarmonicBalance, observed_dof: usize, time_samples: usize) -> Self {
        let layout = problem.layout();
        let (n, contact_dofs) = (layout.sectors, problem.normal_dofs());
        let casing = problem.casing();
        let gaps: Vec<Vec<f64>> = (0..n)
            .flat_map(|sector| {
                (0..contact_dofs)
                    .map(move |contact| casing.gap_samples(n, sector, contact, time_samples))
            })
            .collect();
        let sources = sector_sources(layout, time_samples, &gaps);
        Self {
            problem,
            observed_dof,
            time_samples,
            gaps,
            sources,
        }
    }

    /// Computes every sector's signals itself (no sector carried over from
    /// another): the reference the carried-over extremes are tested against.
    pub fn every_sector_computed(mut self) -> Self {
        self.sources.iter_mut().for_each(|s| *s = None);
        self
    }

    /// How many sectors' signals are computed (the others repeat them).
    pub fn computed_sectors(&self) -> usize {
        self.sources.iter().filter(|s| s.is_none()).count()
    }

    /// The summaries of the point `(x, omega)` on every sector. Fails as
    /// [`dof_histories`] does; the contact part fails as
    /// [`contact_history`] does.
    pub fn point(&self, x: &[f64], omega: f64) -> Result<PointSummary, ResultsError> {
        let problem = self.problem;
        let layout = problem.layout();
        let time_samples = self.time_samples;
        let (n, contact_dofs, harmonics) =
            (layout.sectors, problem.normal_dofs(), layout.harmonics());
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
            touching: Vec::with_capacity(n),
        };
        with_aft(harmonics, time_samples, |aft| {
            // One set of buffers per point, reused over sectors and dofs.
            let mut displacement = vec![0.0; time_samples];
            let mut velocity = vec![0.0; time_samples];
            let mut wall = vec![0.0; time_samples];
            let mut reading = vec![0.0; time_samples];
            let mut force = vec![0.0; time_samples];
            for (sector, c) in coordinates.iter().enumerate() {
                if let Some((source, r)) = self.sources[sector] {
                    observed.peak.push(observed.peak[source]);
                    observed.max_abs.push(observed.max_abs[source]);
                    observed
                        .velocity_max_abs
                        .push(observed.velocity_max_abs[source]);
                    if setup.is_ok() {
                        contact.repeat(source, contact_dofs, r, time_samples);
                    }
                    continue;
                }
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
                    let found = law.apply(read, gap, &mut force, None, None);
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
                contact.touching.push(touching);
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

/// Whether two coordinate vectors are bit for bit equal (`==` would take
/// `-0.0` for `0.0`, which can change the sign of a zero sample).
fn same_bits(a: &[f64], b: &[f64]) -> bool {
    a.len() == b.len() && a.iter().zip(b).all(|(x, y)| x.to_bits() == y.to_bits())
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::hbm::aft::Aft;
    use crate::results::recovery::{contact_history, dof_histories};
    use std::f64::consts::PI;

    /// Equal to round-off: within 1e-12 of the largest magnitude.
    fn assert_close(a: &[f64], b: &[f64]) {
        assert_eq!(a.len(), b.len());
        let scale = b.iter().fold(f64::MIN_POSITIVE, |m, v| m.max(v.abs()));
        for (x, y) in a.iter().zip(b) {
            assert!((x - y).abs() <= 1e-12 * scale, "{x} against {y}");
        }
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
            let dof = case.output.observed_index();
            let nt = case.harmonic_balance.time_samples;
            let all: Vec<usize> = (0..problem.layout().sectors).collect();
            let histories = dof_histories(problem, &x, omega, dof, &all, nt).expect("histories");
            let contact = contact_history(problem, &x, omega, &all, nt).expect("contact");
            let summary = BranchRecovery::new(problem, dof, nt)
                .every_sector_computed()
                .point(&x, omega)
                .expect("summary");
            // Sectors carried over from the ones they repeat: the same to
            // round-off, and fewer computed.
            let recovery = BranchRecovery::new(problem, dof, nt);
            assert!(
                recovery.computed_sectors() < problem.layout().sectors,
                "{text}"
            );
            let carried = recovery.point(&x, omega).expect("summary");
            assert_close(&carried.observed.peak, &summary.observed.peak);
            assert_close(&carried.observed.max_abs, &summary.observed.max_abs);
            assert_close(
                &carried.observed.velocity_max_abs,
                &summary.observed.velocity_max_abs,
            );
            let (a, b) = (
                carried.contact.as_ref().expect("contact"),
                summary.contact.as_ref().expect("contact"),
            );
            assert_close(&a.force_coordinates.concat(), &b.force_coordinates.concat());
            assert_close(&a.peak_force, &b.peak_force);
            assert_close(&a.max_penetration, &b.max_penetration);
            assert_eq!(a.fraction_in_contact, b.fraction_in_contact);
            assert_eq!(a.touching, b.touching);
            assert_eq!(a.sectors_in_contact, b.sectors_in_contact);
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
}
