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
use crate::continuation::StopReason;
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
    /// (`branch.csv`'s amplitude: toward the casing), m; NaN (`null` in
    /// run.json) for a sector without a converged point or that never
    /// moves toward the casing (its largest value ≤ 0 is no peak).
    pub sector_peaks_m: Vec<f64>,
    /// Where each sector peaks, Hz (NaN where its peak is).
    pub sector_peak_frequencies_hz: Vec<f64>,
    /// The sector (1-based) of the largest peak (0: no converged point, or
    /// no sector moves toward the casing).
    pub most_responding_sector: usize,
    /// The tuned wheel's peak of the observed dof, m (absent: its branch
    /// could not be solved, see `tuned_reference`, or it never moves
    /// toward the casing: its largest value ≤ 0 is no peak).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub tuned_peak_m: Option<f64>,
    /// What the tuned peak is, or why it is missing.
    pub tuned_reference: String,
    /// Largest sector peak over the tuned peak (absent: see
    /// `no_factor_reason`).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub amplification_factor: Option<f64>,
    /// Why the amplification factor is not given (absent when it is).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub no_factor_reason: Option<String>,
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
            no_factor_reason: self.no_factor_reason.clone(),
        }
    }
}

/// Whether a branch that stopped for `stop` covers its whole frequency
/// range (its peak is then the curve's, not its last point's).
fn covers_range(stop: &StopReason) -> bool {
    matches!(
        stop,
        StopReason::EndReached | StopReason::AllFrequenciesDone | StopReason::MetOtherSweep { .. }
    )
}

/// Whether two frequencies (Hz) are the same one asked for twice (the
/// tuned reference is solved at the mistuned run's frequencies).
fn same_frequency(a: f64, b: f64) -> bool {
    (a - b).abs() <= 1e-9 * a.abs().max(b.abs()).max(1.0)
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
    // Converged points only: a point Newton left is no response.
    let converged: Vec<(f64, &PointSummary)> = solution
        .branch
        .points
        .iter()
        .zip(summaries)
        .filter(|(point, _)| point.converged)
        .map(|(point, summary)| (point.omega / (2.0 * PI), summary))
        .collect();
    let fixed = solution.mode == super::RunMode::AtFrequencies;
    // At fixed frequencies the tuned wheel is solved at the same ones
    // (those where the mistuned wheel converged).
    let at_hz = fixed.then(|| converged.iter().map(|(f, _)| *f).collect::<Vec<f64>>());
    let tuned = if converged.is_empty() {
        Err("no point of the mistuned wheel converged".to_string())
    } else {
        tuned_reference(&solution.case, &solution.case_dir, at_hz).map_err(|error| {
            tracing::warn!("mistuning: the tuned reference branch failed: {error}");
            error.to_string()
        })
    };
    // At fixed frequencies, only those where the tuned wheel converged
    // too are compared.
    let compared: Vec<&(f64, &PointSummary)> = converged
        .iter()
        .filter(|(f, _)| match (&tuned, fixed) {
            (Ok(reference), true) => reference
                .points
                .iter()
                .any(|(g, peak)| peak.is_some() && same_frequency(*f, *g)),
            _ => true,
        })
        .collect();
    let mut peaks = vec![f64::NAN; n];
    let mut at = vec![f64::NAN; n];
    for (frequency, summary) in &compared {
        for (j, &a) in summary.observed.peak.iter().enumerate().take(n) {
            if a.is_finite() && (peaks[j].is_nan() || a > peaks[j]) {
                peaks[j] = a;
                at[j] = *frequency;
            }
        }
    }
    let most = (0..n)
        .filter(|&j| peaks[j].is_finite())
        .max_by(|&a, &b| peaks[a].total_cmp(&peaks[b]));
    let largest = most.map(|j| peaks[j]);
    let tuned_peak_m = tuned.as_ref().ok().and_then(|reference| {
        let same = reference
            .points
            .iter()
            .filter(|(f, _)| !fixed || compared.iter().any(|(g, _)| same_frequency(*f, *g)));
        same.filter_map(|(_, peak)| *peak)
            .fold(None, |m: Option<f64>, a| Some(m.map_or(a, |m| m.max(a))))
    });
    let tuned_reference = match &tuned {
        Ok(reference) => format!(
            "the tuned wheel's nonlinear branch (the case without [mistuning], symmetry basis, \
             {} points)",
            reference.points.len()
        ),
        Err(error) => format!("not computed: {error}"),
    };
    let no_factor_reason = match (&tuned, largest, tuned_peak_m) {
        _ if !covers_range(&solution.branch.stop) => Some(format!(
            "the mistuned curve stopped before the end of its frequency range ({}): its peak may \
             lie beyond its last point",
            solution.branch.stop
        )),
        (Err(error), _, _) => Some(format!("no tuned reference: {error}")),
        (Ok(reference), _, _) if !covers_range(&reference.stop) => Some(format!(
            "the tuned reference stopped before the end of its frequency range ({}): its peak \
             may lie beyond its last point",
            reference.stop
        )),
        (_, None, _) | (_, _, None) if fixed => Some(
            "no frequency at which both the mistuned and the tuned wheel converged".to_string(),
        ),
        (_, None, _) => Some("no converged point of the mistuned wheel".to_string()),
        (_, _, None) => Some("no converged point of the tuned wheel".to_string()),
        // A peak ≤ 0: the observed dof never moves toward the casing (far
        // from resonance, a static offset away from it); no ratio of it.
        (_, Some(m), _) if m <= 0.0 => Some(
            "no sector of the mistuned wheel moves toward the casing at the points compared"
                .to_string(),
        ),
        (_, _, Some(t)) if t <= 0.0 => Some(
            "the tuned wheel does not move toward the casing at the points compared".to_string(),
        ),
        _ => None,
    };
    let amplification_factor = match (no_factor_reason.is_none(), largest, tuned_peak_m) {
        (true, Some(m), Some(t)) => Some(m / t),
        _ => None,
    };
    // A largest value ≤ 0 is no peak: the sector never moves toward the
    // casing (a static offset away from it), so no amplitude is recorded
    // for it (null in run.json, NaN in results.h5), nor a frequency.
    let most = most.filter(|&j| peaks[j] > 0.0);
    let tuned_peak_m = tuned_peak_m.filter(|&t| t > 0.0);
    for (peak, frequency) in peaks.iter_mut().zip(at.iter_mut()) {
        if peak.is_nan() || *peak <= 0.0 {
            *peak = f64::NAN;
            *frequency = f64::NAN;
        }
    }
    Ok(Some(MistuningRecord {
        deviations: mistuning.deviations().to_vec(),
        sector_peaks_m: peaks,
        sector_peak_frequencies_hz: at,
        most_responding_sector: most.map_or(0, |j| j + 1),
        tuned_peak_m,
        tuned_reference,
        amplification_factor,
        no_factor_reason,
    }))
}

/// The tuned wheel's branch as the amplification factor reads it.
#[derive(Clone, Debug)]
pub struct TunedReference {
    /// Each point's frequency (Hz) and largest peak of the observed dof
    /// over the sectors (m, toward the casing; `None`: not converged).
    pub points: Vec<(f64, Option<f64>)>,
    /// Why its branch stopped.
    pub stop: StopReason,
}

/// The tuned wheel's branch: `case` (resolved: frequency range set)
/// without `[mistuning]`, on the symmetry basis, over its frequency range
/// or at the frequencies `at_hz`, its files read from `case_dir`.
pub fn tuned_reference(
    case: &Case,
    case_dir: &std::path::Path,
    at_hz: Option<Vec<f64>>,
) -> Result<TunedReference, RunError> {
    let mut tuned = case.clone();
    tuned.mistuning = MistuningSpec::default();
    let mut request = ForcedResponse::from_case(&tuned)?
        .basis(BasisChoice::Symmetry)
        .case_dir(case_dir);
    if let Some(list) = at_hz {
        request = request.at_frequencies_hz(list);
    }
    let solution = request.build()?.run(&mut [])?;
    let mut points = Vec::with_capacity(solution.branch.points.len());
    for (point, summary) in solution
        .branch
        .points
        .iter()
        .zip(solution.point_summaries())
    {
        let peak = if point.converged {
            Some(
                summary?
                    .observed
                    .peak
                    .iter()
                    .fold(f64::NAN, |m, &a| m.max(a)),
            )
            .filter(|p| p.is_finite())
        } else {
            None
        };
        points.push((point.omega / (2.0 * PI), peak));
    }
    Ok(TunedReference {
        points,
        stop: solution.branch.stop.clone(),
    })
}
