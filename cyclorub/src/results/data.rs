//! Everything a results file holds, as plain values: per point of a branch
//! the observed dof on every sector, the contact state, the cyclic
//! components; the linear response; the natural frequencies; the time
//! histories of one point. Computed from a solved problem here, written
//! and read back by `results::hdf5` (feature `hdf5`).

use super::components::CyclicComponents;
use super::recovery::{
    contact_history, dof_histories, harmonic_amplitudes, linear_dof_peaks,
    linear_static_coordinates, peak, BranchRecovery, ContactSummary, ObservedSummary,
};
use super::ResultsError;
use crate::continuation::Point;
use crate::hbm::HarmonicBalance;
use rayon::prelude::*;
use std::f64::consts::PI;

/// The results of one point of a branch, on all `N` sectors.
///
/// Arrays over sectors are indexed by the 0-based sector; arrays over
/// contact dofs are sector-major (`sector · n_c + contact`).
#[derive(Clone, Debug, PartialEq)]
pub struct PointResults {
    /// Frequency, Hz.
    pub frequency_hz: f64,
    /// Newton iterations.
    pub iterations: usize,
    /// `‖R‖ / force scale`.
    pub residual_norm: f64,
    /// Whether Newton converged.
    pub converged: bool,
    /// The unknowns of the basis solved on (see `run.json`'s basis).
    pub unknowns: Vec<f64>,
    /// The observed dof's displacement coordinates `[a0, Re X1, Im X1, …]`
    /// per sector, m.
    pub observed: Vec<Vec<f64>>,
    /// Largest observed displacement over the period (toward the casing),
    /// per sector, m: `branch.csv`'s amplitude.
    pub amplitude: Vec<f64>,
    /// Largest `|displacement|` of the observed dof, per sector, m.
    pub max_abs: Vec<f64>,
    /// Largest `|velocity|` of the observed dof, per sector, m/s.
    pub velocity_max_abs: Vec<f64>,
    /// Harmonic coordinates of the contact force, per sector and contact
    /// dof, N (the force is `−f` on the blade, `f ≥ 0`).
    pub contact_force: Vec<Vec<f64>>,
    /// Largest contact force over the period, per sector and contact dof, N.
    pub peak_force: Vec<f64>,
    /// Fraction of the period in contact, per sector and contact dof.
    pub contact_fraction: Vec<f64>,
    /// Largest penetration `x − g0`, per sector and contact dof, m.
    pub max_penetration: Vec<f64>,
    /// Number of sectors in contact at some instant of the period.
    pub sectors_in_contact: usize,
    /// Cyclic components of the observed dof.
    pub components: CyclicComponents,
}

impl PointResults {
    /// The results of `point` for sector dof `observed_dof` (0-based),
    /// with time signals sampled at `time_samples` instants. Reads the
    /// problem only; for many points of one problem, [`BranchRecovery`] and
    /// [`Self::from_summary`] share the work that does not depend on the
    /// point.
    pub fn compute(
        problem: &HarmonicBalance,
        point: &Point,
        observed_dof: usize,
        time_samples: usize,
    ) -> Result<Self, ResultsError> {
        let summary = BranchRecovery::new(problem, observed_dof, time_samples)
            .point(&point.unknowns, point.omega)?;
        Self::from_summary(point, summary.observed, summary.contact?)
    }

    /// The results of `point` from its summaries (see
    /// [`BranchRecovery::point`]).
    pub fn from_summary(
        point: &Point,
        observed: ObservedSummary,
        contact: ContactSummary,
    ) -> Result<Self, ResultsError> {
        let components = CyclicComponents::from_sector_coordinates(&observed.coordinates)?;
        Ok(Self {
            frequency_hz: point.omega / (2.0 * PI),
            iterations: point.iterations,
            residual_norm: point.residual_norm,
            converged: point.converged,
            unknowns: point.unknowns.clone(),
            observed: observed.coordinates,
            amplitude: observed.peak,
            max_abs: observed.max_abs,
            velocity_max_abs: observed.velocity_max_abs,
            contact_force: contact.force_coordinates,
            peak_force: contact.peak_force,
            contact_fraction: contact.fraction_in_contact,
            max_penetration: contact.max_penetration,
            sectors_in_contact: contact.sectors_in_contact,
            components,
        })
    }

    /// Amplitude per harmonic of the observed dof on `sector` (0-based), m.
    pub fn harmonic_amplitudes(&self, sector: usize) -> Vec<f64> {
        self.observed
            .get(sector)
            .map_or_else(Vec::new, |c| harmonic_amplitudes(c))
    }
}

/// The linear response (no contact) of the observed dof, per frequency and
/// sector, with the same amplitude definition as the branch.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct LinearResponse {
    /// Frequencies, Hz, increasing.
    pub frequency_hz: Vec<f64>,
    /// `amplitude[f][j]`: largest displacement over the period on sector `j`, m.
    pub amplitude: Vec<Vec<f64>>,
}

impl LinearResponse {
    /// The linear response of sector dof `dof` (0-based) on every sector at
    /// `frequencies_hz` (sorted and deduplicated here), from the linear
    /// part of `problem` (each loaded block solved on its own dofs,
    /// `LinearPart::free_response`, harmonic 0 once; the frequencies in
    /// parallel; the problem is only read).
    pub fn compute(
        problem: &HarmonicBalance,
        dof: usize,
        frequencies_hz: &[f64],
        time_samples: usize,
    ) -> Result<Self, ResultsError> {
        let mut frequencies: Vec<f64> = frequencies_hz
            .iter()
            .cloned()
            .filter(|f| f.is_finite() && *f > 0.0)
            .collect();
        frequencies.sort_by(f64::total_cmp);
        frequencies.dedup_by(|a, b| (*a - *b).abs() <= 1e-12 * b.abs());
        // Harmonic 0 (static loads, preload) once; the others at each
        // frequency, each loaded block solved on its own dofs.
        let static_coordinates = if frequencies.is_empty() {
            Vec::new()
        } else {
            linear_static_coordinates(problem, dof)?
        };
        let amplitude = frequencies
            .par_iter()
            .map(|&f| {
                let omega = 2.0 * PI * f;
                linear_dof_peaks(problem, omega, dof, &static_coordinates, time_samples)
            })
            .collect::<Result<Vec<_>, ResultsError>>()?;
        Ok(Self {
            frequency_hz: frequencies,
            amplitude,
        })
    }
}

/// The time histories of one point on every sector.
#[derive(Clone, Debug, PartialEq)]
pub struct PointHistories {
    /// Index of the point along the branch.
    pub point: usize,
    /// Its frequency, Hz.
    pub frequency_hz: f64,
    /// The instants `t_n = 2π n / (N_t ω)`, s.
    pub time_s: Vec<f64>,
    /// Observed displacement `[sector][n]`, m.
    pub displacement: Vec<Vec<f64>>,
    /// Observed velocity `[sector][n]`, m/s.
    pub velocity: Vec<Vec<f64>>,
    /// Contact force `[sector · n_c + contact][n]`, N.
    pub contact_force: Vec<Vec<f64>>,
    /// Penetration `x − g0` `[sector · n_c + contact][n]`, m.
    pub penetration: Vec<Vec<f64>>,
}

impl PointHistories {
    /// The histories of `point` (its index `index` along the branch) for
    /// sector dof `observed_dof` (0-based).
    pub fn compute(
        problem: &HarmonicBalance,
        point: &Point,
        index: usize,
        observed_dof: usize,
        time_samples: usize,
    ) -> Result<Self, ResultsError> {
        let all: Vec<usize> = (0..problem.layout().sectors).collect();
        let (x, omega) = (&point.unknowns, point.omega);
        let histories = dof_histories(problem, x, omega, observed_dof, &all, time_samples)?;
        let contact = contact_history(problem, x, omega, &all, time_samples)?;
        Ok(Self {
            point: index,
            frequency_hz: omega / (2.0 * PI),
            time_s: (0..time_samples)
                .map(|n| 2.0 * PI * n as f64 / (time_samples as f64 * omega))
                .collect(),
            displacement: histories.iter().map(|h| h.displacement.clone()).collect(),
            velocity: histories.iter().map(|h| h.velocity.clone()).collect(),
            contact_force: contact.signals.iter().map(|s| s.force.clone()).collect(),
            penetration: contact
                .signals
                .iter()
                .map(|s| s.penetration.clone())
                .collect(),
        })
    }
}

/// The name of sector dof `dof` (0-based) of `model` as the user knows it:
/// its node and direction on a finite-element model (`node 420, radial`;
/// `node 420, x` in a Cartesian frame), its mass on a lumped model (`m1`),
/// with `, the blade tip` for the academic model's `m1` (`academic`: the
/// case's model is the paper's academic one).
pub fn observed_name(model: &crate::model::SectorModel, dof: usize, academic: bool) -> String {
    let label = model.dof_label(dof);
    if let Some(rest) = label.strip_prefix("node ") {
        if let Some((node, direction)) = rest.split_once(' ') {
            let direction = match direction {
                "r" => "radial",
                "θ" => "circumferential",
                "z" if model.dof_node(dof).is_some() && label_is_cylindrical(model, dof) => "axial",
                other => other,
            };
            return format!("node {node}, {direction}");
        }
    }
    if academic && dof == crate::model::ACADEMIC_CONTACT_DOF {
        return format!("{label}, the blade tip");
    }
    label
}

/// Whether the node of `dof` has its dofs in a cylindrical frame (a
/// neighbour of the same node is labelled `r` or `θ`).
fn label_is_cylindrical(model: &crate::model::SectorModel, dof: usize) -> bool {
    let node = model.dof_node(dof);
    (dof.saturating_sub(2)..dof + 3)
        .filter(|&d| model.dof_node(d) == node)
        .any(|d| {
            let label = model.dof_label(d);
            label.ends_with(" r") || label.ends_with(" θ")
        })
}

/// The whole content of a results file.
#[derive(Clone, Debug, PartialEq)]
pub struct ResultsData {
    /// The resolved case, as JSON (the `case` of `run.json`).
    pub case_json: String,
    /// The basis record, as JSON (the `basis` of `run.json`).
    pub basis_json: String,
    /// How the branch was followed (stored as `continuation` or
    /// `at_frequencies`).
    pub mode: super::RunMode,
    /// Why the branch stopped, as JSON.
    pub stop_json: String,
    /// Number of sectors `N`.
    pub sectors: usize,
    /// `N_h`.
    pub harmonics: usize,
    /// `N_t` of the time signals.
    pub time_samples: usize,
    /// The observed dof, 1-based.
    pub observed_dof: usize,
    /// The observed dof as the user knows it, for titles and axes: `node
    /// 420, radial` on a finite-element model, `m1, the blade tip` on the
    /// academic one, `dof 17` otherwise ([`observed_name`]).
    pub observed_name: String,
    /// The contact dofs, 1-based.
    pub contact_dofs: Vec<usize>,
    /// The points of the branch.
    pub points: Vec<PointResults>,
    /// The linear response.
    pub linear: LinearResponse,
    /// Natural frequencies (Hz) per nodal diameter `0..=N/2`.
    pub natural_frequencies: Vec<(usize, Vec<f64>)>,
    /// Time histories of one point (the peak of the branch), if any.
    pub histories: Option<PointHistories>,
    /// The last point before a gap in the branch (followed from both ends,
    /// the two sweeps did not meet), if there is one: figures do not join
    /// it to the next.
    pub gap_after: Option<usize>,
    /// The stability of every point, when it was checked.
    pub stability: Option<super::stability::StabilityData>,
    /// A mistuned wheel's deviations and sector peaks (issue 44), `None`
    /// for a tuned wheel.
    pub mistuning: Option<MistuningData>,
    /// The bifurcated branches switched to at the branch points of the
    /// branch (`cyclorub branches`), in the order of `branches.json`;
    /// empty when none was asked for.
    pub branches: Vec<super::bifurcated::BifurcatedBranchData>,
}

/// What a mistuned run (issue 44) stores of its sectors: the deviations
/// and each sector's peak of the observed dof along the curve (the
/// `mistuning` record of `run.json`).
#[derive(Clone, Debug, PartialEq)]
pub struct MistuningData {
    /// `δ_j` of every sector.
    pub deviations: Vec<f64>,
    /// Each sector's largest amplitude of the observed dof, m.
    pub sector_peaks_m: Vec<f64>,
    /// Where each sector peaks, Hz.
    pub sector_peak_frequencies_hz: Vec<f64>,
    /// The sector (1-based) of the largest peak (0: no converged point).
    pub most_responding_sector: usize,
    /// The tuned wheel's peak, m (absent: not computed).
    pub tuned_peak_m: Option<f64>,
    /// Largest sector peak over the tuned peak (absent without it).
    pub amplification_factor: Option<f64>,
    /// What the tuned peak is, or why it is missing.
    pub tuned_reference: String,
    /// Why the amplification factor is not given (`None` when it is, and
    /// in files written before results.h5 stored it).
    pub no_factor_reason: Option<String>,
}

impl ResultsData {
    /// The basis the branch was solved on (`basis_json`'s `kind`); refused
    /// when it is not recorded, rather than guessed.
    pub fn basis_choice(&self) -> Result<crate::case::BasisChoice, ResultsError> {
        let basis: serde_json::Value = serde_json::from_str(&self.basis_json)
            .map_err(|e| ResultsError::Input(format!("run.json's basis: {e}")))?;
        let kind = basis
            .get("kind")
            .and_then(|k| k.as_str())
            .ok_or_else(|| ResultsError::Input("run.json's basis has no kind".into()))?;
        crate::case::BasisChoice::parse(kind).map_err(|e| ResultsError::Input(e.to_string()))
    }

    /// Where the curve of the converged points has a gap (see
    /// [`Self::gap_after`]): the indices, among the converged points, of
    /// those not joined to the one before.
    pub fn converged_breaks(&self) -> Vec<usize> {
        self.gap_after
            .map(|gap| {
                self.points
                    .iter()
                    .take(gap + 1)
                    .filter(|p| p.converged)
                    .count()
            })
            .into_iter()
            .collect()
    }

    /// The point of largest observed amplitude over all sectors (converged
    /// points only), if any.
    pub fn peak_point(&self) -> Option<usize> {
        self.points
            .iter()
            .enumerate()
            .filter(|(_, p)| p.converged)
            .map(|(i, p)| (i, peak(&p.amplitude)))
            .filter(|(_, a)| a.is_finite())
            .max_by(|a, b| a.1.total_cmp(&b.1))
            .map(|(i, _)| i)
    }

    /// The index of the point nearest to `frequency_hz`.
    pub fn nearest_point(&self, frequency_hz: f64) -> Option<usize> {
        self.points
            .iter()
            .enumerate()
            .min_by(|a, b| {
                (a.1.frequency_hz - frequency_hz)
                    .abs()
                    .total_cmp(&(b.1.frequency_hz - frequency_hz).abs())
            })
            .map(|(i, _)| i)
    }

    /// The number of contact dofs per sector.
    pub fn contact_dofs_per_sector(&self) -> usize {
        self.contact_dofs.len()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::model::{Damping, LumpedSector, SectorModel};

    #[test]
    fn the_observed_dof_is_named_as_the_user_knows_it() {
        let academic =
            SectorModel::lumped(4, &LumpedSector::academic(), Damping::None).expect("model");
        assert_eq!(observed_name(&academic, 0, true), "m1, the blade tip");
        assert_eq!(observed_name(&academic, 0, false), "m1");
        assert_eq!(observed_name(&academic, 3, true), "m4");
        let labels = [
            "node 420 r",
            "node 420 θ",
            "node 420 z",
            "node 7 x",
            "mode 1",
        ];
        let meshed = academic
            .with_dof_labels(labels.iter().map(|l| l.to_string()).collect())
            .and_then(|m| m.with_dof_nodes(vec![Some(420), Some(420), Some(420), Some(7), None]))
            .expect("labels");
        let names: Vec<String> = (0..5).map(|d| observed_name(&meshed, d, false)).collect();
        assert_eq!(
            names,
            [
                "node 420, radial",
                "node 420, circumferential",
                "node 420, axial",
                "node 7, x",
                "mode 1"
            ]
        );
    }
}
