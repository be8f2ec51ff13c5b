//! What `run.json` records of a mistuned wheel (issue 44, docs/design.md
//! §12): the deviations, each sector's peak along the curve, the most
//! responding sector and the amplification factor.
//!
//! The amplification factor is the largest sector peak over the **tuned
//! wheel's nonlinear peak**: the same case without `[mistuning]`, solved on
//! the symmetry basis over the same frequency range (exact for the tuned
//! wheel, and cheap: 0.1–1 s on the academic cases). A linear tuned peak
//! would mix two effects, as contact caps the mistuned peak near the gap
//! while the linear tuned one is not capped.

use super::RunError;
use crate::case::{BasisChoice, Case, MistuningSpec};
use crate::forced_response::{ForcedResponse, Solution};
use crate::results::data::MistuningData;
use crate::results::recovery::PointSummary;
use serde::Serialize;
use std::f64::consts::PI;

/// The mistuning part of `run.json`.
#[derive(Clone, Debug, Serialize, PartialEq)]
pub struct MistuningRecord {
    /// `δ_j` of every sector (given, or drawn from the case's generator).
    pub deviations: Vec<f64>,
    /// Each sector's largest amplitude of the observed dof along the curve
    /// (`branch.csv`'s amplitude: toward the casing), m.
    pub sector_peaks_m: Vec<f64>,
    /// Where each sector peaks, Hz.
    pub sector_peak_frequencies_hz: Vec<f64>,
    /// The sector (1-based) of the largest peak.
    pub most_responding_sector: usize,
    /// The tuned wheel's peak of the observed dof, m (absent: its branch
    /// could not be solved; see `tuned_reference`).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub tuned_peak_m: Option<f64>,
    /// What the tuned peak is, or why it is missing.
    pub tuned_reference: String,
    /// Largest sector peak over the tuned peak (absent without it).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub amplification_factor: Option<f64>,
}

impl MistuningRecord {
    /// What `results.h5` stores of it (its `/mistuning` group).
    pub fn data(&self) -> MistuningData {
        MistuningData {
            deviations: self.deviations.clone(),
            sector_peaks_m: self.sector_peaks_m.clone(),
            sector_peak_frequencies_hz: self.sector_peak_frequencies_hz.clone(),
            most_responding_sector: self.most_responding_sector,
            tuned_peak_m: self.tuned_peak_m,
            amplification_factor: self.amplification_factor,
            tuned_reference: self.tuned_reference.clone(),
        }
    }
}

/// The record of `solution` when its wheel is mistuned (`None` otherwise),
/// from its points' summaries (branch order, every sector); solves the
/// tuned reference branch.
pub fn record(
    solution: &Solution,
    summaries: &[PointSummary],
) -> Result<Option<MistuningRecord>, RunError> {
    let Some(mistuning) = solution.model.mistuning() else {
        return Ok(None);
    };
    let n = solution.model.sectors();
    let mut peaks = vec![f64::NEG_INFINITY; n];
    let mut at = vec![f64::NAN; n];
    for (point, summary) in solution.branch.points.iter().zip(summaries) {
        if !point.converged {
            continue;
        }
        for (j, &a) in summary.observed.peak.iter().enumerate().take(n) {
            if a > peaks[j] {
                peaks[j] = a;
                at[j] = point.omega / (2.0 * PI);
            }
        }
    }
    let most = (0..n)
        .max_by(|&a, &b| peaks[a].total_cmp(&peaks[b]))
        .unwrap_or(0);
    // At fixed frequencies the tuned wheel is solved at the same ones.
    let at_hz = (solution.mode == super::RunMode::AtFrequencies).then(|| {
        solution
            .branch
            .points
            .iter()
            .map(|p| p.omega / (2.0 * PI))
            .collect()
    });
    let (tuned_peak_m, tuned_reference) =
        match tuned_peak(&solution.case, &solution.case_dir, at_hz) {
            Ok((peak, points)) => (
                Some(peak),
                format!(
                    "the tuned wheel's nonlinear branch (the case without [mistuning], symmetry \
                 basis, {points} points)"
                ),
            ),
            Err(error) => {
                tracing::warn!("mistuning: the tuned reference branch failed: {error}");
                (None, format!("not computed: {error}"))
            }
        };
    let amplification_factor = tuned_peak_m.filter(|t| *t > 0.0).map(|t| peaks[most] / t);
    Ok(Some(MistuningRecord {
        deviations: mistuning.deviations().to_vec(),
        sector_peaks_m: peaks,
        sector_peak_frequencies_hz: at,
        most_responding_sector: most + 1,
        tuned_peak_m,
        tuned_reference,
        amplification_factor,
    }))
}

/// The tuned wheel's peak (m, the observed dof toward the casing, largest
/// over sectors and converged points) and its number of points: `case`
/// (resolved: frequency range set) without `[mistuning]`, on the symmetry
/// basis, over its frequency range or at the frequencies `at_hz`, its
/// files read from `case_dir`.
pub fn tuned_peak(
    case: &Case,
    case_dir: &std::path::Path,
    at_hz: Option<Vec<f64>>,
) -> Result<(f64, usize), RunError> {
    let mut tuned = case.clone();
    tuned.mistuning = MistuningSpec::default();
    let mut request = ForcedResponse::from_case(&tuned)?
        .basis(BasisChoice::Symmetry)
        .case_dir(case_dir);
    if let Some(list) = at_hz {
        request = request.at_frequencies_hz(list);
    }
    let solution = request.build()?.run(&mut [])?;
    let mut peak = f64::NEG_INFINITY;
    for (point, summary) in solution
        .branch
        .points
        .iter()
        .zip(solution.point_summaries())
    {
        if point.converged {
            peak = summary?.observed.peak.iter().fold(peak, |m, &a| m.max(a));
        }
    }
    Ok((peak, solution.branch.points.len()))
}
