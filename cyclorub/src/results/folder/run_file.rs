//! `run.json` read back, typed (issue 41 item 4): what a reader of a
//! results folder takes from it. The CLI, the app and Python read a folder
//! through [`super::ResultsFolder`] and this record rather than through
//! `run.json`'s raw JSON.
//!
//! The writer's record (`run::RunRecord`) sits above this module (`run`
//! uses `results`, never the other way: docs/design.md §1), so the parts
//! whose types live up there are read here as plain values: the mistuning
//! summary field for field (`tests/results_folder_run_file.rs` reads a
//! written record back into it), the run's status as its word, the basis
//! and the events as JSON.

use crate::case::{BasisChoice, Case};
use crate::continuation::StopReason;
use crate::results::ResultsError;
use serde::{Deserialize, Deserializer, Serialize};
use std::path::Path;

/// What `run.json` records of a run, as a reader takes it. While the run
/// goes on (or after it was killed) `run.json` holds only its status and
/// case: everything else is then absent.
#[derive(Clone, Debug, Deserialize)]
pub struct RunFile {
    /// `running`, `finished`, `interrupted` or `stopped_early` (the words
    /// of the front door's `RunStatus`); see [`Self::is_running`].
    pub status: String,
    /// The case as its run resolved it (defaults filled, frequency range
    /// set).
    pub case: Case,
    /// The basis record (kind, unknowns, sampled sectors, pairs per
    /// harmonic), as JSON; [`Self::basis_choice`] reads its kind.
    #[serde(default)]
    pub basis: Option<serde_json::Value>,
    /// Why the branch stopped.
    #[serde(default)]
    pub stop: Option<StopReason>,
    /// The events along the branch (folds, branch points, kinks, the stop),
    /// as JSON.
    #[serde(default)]
    pub events: Option<serde_json::Value>,
    /// Set-up, solve and output times.
    #[serde(default)]
    pub timings: Option<RunTimings>,
    /// The time of the stability check.
    #[serde(default)]
    pub stability: Option<StabilityTime>,
    /// A mistuned wheel's deviations, sector peaks and amplification factor
    /// (absent for a tuned wheel).
    #[serde(default)]
    pub mistuning: Option<MistuningSummary>,
    /// The bifurcated branches switched to at the branch's branch points
    /// (`cyclorub branches`; empty when none was asked for).
    #[serde(default)]
    pub branches: Vec<crate::results::bifurcated::BranchSummary>,
}

/// Wall-clock times of a run, s (`run.json`'s `timings`).
#[derive(Clone, Debug, Deserialize, Serialize, PartialEq)]
pub struct RunTimings {
    /// Model, basis and residual set-up.
    pub setup_s: f64,
    /// Continuation.
    pub solve_s: f64,
    /// Recovery and files.
    #[serde(default)]
    pub output_s: f64,
}

/// The time of a run's stability check (`run.json`'s `stability.time_s`).
#[derive(Clone, Debug, Deserialize, PartialEq)]
pub struct StabilityTime {
    /// Time of the check, s.
    #[serde(default)]
    pub time_s: f64,
}

/// A mistuned wheel's record (`run.json`'s `mistuning`, written by
/// `run::mistuning::MistuningRecord`, docs/design.md §12): the same fields,
/// read back. A number the writer could not give (a sector without a
/// converged point) is written as `null` and read as NaN.
#[derive(Clone, Debug, Deserialize, Serialize, PartialEq)]
pub struct MistuningSummary {
    /// `δ_j` of every sector.
    pub deviations: Vec<f64>,
    /// Each sector's largest amplitude of the observed dof along the curve
    /// (toward the casing), m.
    #[serde(deserialize_with = "numbers_or_null")]
    pub sector_peaks_m: Vec<f64>,
    /// Where each sector peaks, Hz.
    #[serde(deserialize_with = "numbers_or_null")]
    pub sector_peak_frequencies_hz: Vec<f64>,
    /// The sector (1-based) of the largest peak.
    pub most_responding_sector: usize,
    /// The tuned wheel's peak of the observed dof, m (absent: its branch
    /// could not be solved, see `tuned_reference`).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub tuned_peak_m: Option<f64>,
    /// What the tuned peak is, or why it is missing.
    pub tuned_reference: String,
    /// Largest sector peak over the tuned peak (absent: see
    /// `no_factor_reason`).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub amplification_factor: Option<f64>,
    /// Why the amplification factor is not given (absent when it is, and
    /// in folders written before it was recorded).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub no_factor_reason: Option<String>,
}

/// Numbers, with `null` (how JSON writes NaN and infinities) read as NaN.
fn numbers_or_null<'de, D: Deserializer<'de>>(deserializer: D) -> Result<Vec<f64>, D::Error> {
    let values: Vec<Option<f64>> = Vec::deserialize(deserializer)?;
    Ok(values.into_iter().map(|v| v.unwrap_or(f64::NAN)).collect())
}

impl RunFile {
    /// Reads `run.json` text (`path` names it in messages).
    pub fn parse(path: &Path, text: &str) -> Result<Self, ResultsError> {
        serde_json::from_str(text).map_err(|e| ResultsError::Read {
            path: path.to_path_buf(),
            message: format!("not a run.json this version reads: {e}"),
        })
    }

    /// Whether the run is still going, or was killed (its status stays
    /// `running`): its files may end with an unfinished line.
    pub fn is_running(&self) -> bool {
        self.status == "running"
    }

    /// The basis the branch was solved on (the basis record's kind);
    /// refused when it is not recorded (a run still going), rather than
    /// guessed.
    pub fn basis_choice(&self, path: &Path) -> Result<BasisChoice, ResultsError> {
        let input = ResultsError::Input;
        let kind = self
            .basis
            .as_ref()
            .and_then(|b| b.get("kind"))
            .and_then(serde_json::Value::as_str)
            .ok_or_else(|| input(format!("{} has no basis.kind", path.display())))?;
        BasisChoice::parse(kind)
            .map_err(|e| input(format!("basis.kind of {}: {e}", path.display())))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_running_run_json_reads_with_its_case_only() {
        let case = serde_json::to_value(Case::default()).expect("case");
        let text = serde_json::json!({"status": "running", "case": case, "output": "x"});
        let file = RunFile::parse(Path::new("run.json"), &text.to_string()).expect("read");
        assert!(file.is_running());
        assert_eq!(file.case, Case::default());
        assert!(file.stop.is_none() && file.mistuning.is_none());
        assert!(file.basis_choice(Path::new("run.json")).is_err());
    }

    #[test]
    fn null_sector_peaks_read_as_nan() {
        let text = r#"{"deviations": [0.0, 0.01], "sector_peaks_m": [1e-3, null],
            "sector_peak_frequencies_hz": [200.0, null], "most_responding_sector": 1,
            "tuned_reference": "not computed: x"}"#;
        let summary: MistuningSummary = serde_json::from_str(text).expect("read");
        assert!(summary.sector_peaks_m[1].is_nan());
        assert_eq!(summary.sector_peaks_m[0].to_bits(), 1e-3f64.to_bits());
        assert_eq!(summary.amplification_factor, None);
    }
}
