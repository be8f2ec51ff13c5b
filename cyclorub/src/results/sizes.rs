//! The stability check's sizes converged at one point of a run (its
//! fastest growth, or on a stable branch its largest amplitude solved by
//! Hill's method): the point re-solved and checked on 2, 4, 8 times the
//! harmonics until its leading real part settles (docs/design.md §10,
//! "sizes"). `cyclorub run` computes them after the branch and keeps them
//! in `run.json` as `stability.sizes`; the stability figure draws them
//! beside the run's own truncation.

use super::ResultsError;
use serde::{Deserialize, Serialize};
use std::path::Path;

/// What `run.json`'s `stability.sizes` holds.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct ConvergedSizes {
    /// The point's index along the branch.
    pub point: usize,
    /// Its frequency, Hz.
    pub frequency_hz: f64,
    /// Why this point: `fastest_growth` or `largest_amplitude`.
    pub chosen_at: String,
    /// Hill's harmonics of each check, the run's truncation first, then
    /// each refinement (the orbit's harmonics scaled alike).
    pub harmonics: Vec<usize>,
    /// The wheel's leading real part at each (1/s; `None`: no exponent in
    /// the region).
    pub leading_re: Vec<Option<f64>>,
    /// Whether each check found no growing exponent (the run's first).
    #[serde(default)]
    pub stable: Vec<bool>,
    /// Each refinement's change of the leading real part from the one
    /// before, relative to its own.
    pub changes: Vec<Option<f64>>,
    /// The change below which the sizes count as converged.
    pub converged_within: f64,
    /// Whether the last change fell below it.
    pub converged: bool,
    /// Why the refinements stopped short, if they did.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub stopped: Option<String>,
    /// Whether every check gives the run's verdict.
    pub verdict_holds: bool,
    /// Each class's leading real part at the run's truncation and at the
    /// finest.
    pub classes: Vec<ClassSizes>,
}

/// One class's leading real part, 1/s.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct ClassSizes {
    /// The class (nodal diameter σ).
    pub class: i64,
    /// At the run's truncation (`None`: no exponent in its region).
    pub run_re: Option<f64>,
    /// At the finest refinement.
    pub finest_re: f64,
}

impl ConvergedSizes {
    /// Hill's harmonics of the finest check.
    pub fn finest_harmonics(&self) -> usize {
        self.harmonics.last().copied().unwrap_or(0)
    }
}

/// The sizes `run.json` in `folder` holds, if any (an older run, a run
/// without stability or whose refinement failed has none).
pub fn read(folder: &Path) -> Option<ConvergedSizes> {
    let text = std::fs::read_to_string(folder.join("run.json")).ok()?;
    let json: serde_json::Value = serde_json::from_str(&text).ok()?;
    serde_json::from_value(json.get("stability")?.get("sizes")?.clone()).ok()
}

/// Why `run.json` in `folder` has no sizes (`stability.sizes_reason`), if
/// the run said.
pub fn read_reason(folder: &Path) -> Option<String> {
    let text = std::fs::read_to_string(folder.join("run.json")).ok()?;
    let json: serde_json::Value = serde_json::from_str(&text).ok()?;
    Some(
        json.get("stability")?
            .get("sizes_reason")?
            .as_str()?
            .to_string(),
    )
}

/// Adds `sizes` to `run.json`'s `stability` in `folder` (read and written
/// whole; the rest unchanged).
pub fn record(folder: &Path, sizes: &ConvergedSizes) -> Result<(), ResultsError> {
    record_entry(
        folder,
        "sizes",
        serde_json::to_value(sizes).map_err(|e| ResultsError::Read {
            path: folder.join("run.json"),
            message: e.to_string(),
        })?,
    )
}

/// Adds why the run has no sizes (`reason`) to `run.json`'s `stability`
/// in `folder` as `sizes_reason` (a refinement predicted past the budget,
/// Newton failing on twice the harmonics…).
pub fn record_reason(folder: &Path, reason: &str) -> Result<(), ResultsError> {
    record_entry(folder, "sizes_reason", serde_json::Value::from(reason))
}

/// Sets `stability.<key>` in `folder`'s `run.json` to `value`.
fn record_entry(folder: &Path, key: &str, value: serde_json::Value) -> Result<(), ResultsError> {
    let path = folder.join("run.json");
    let unreadable = |message: String| ResultsError::Read {
        path: path.clone(),
        message,
    };
    let text = std::fs::read_to_string(&path).map_err(|e| unreadable(e.to_string()))?;
    let mut json: serde_json::Value =
        serde_json::from_str(&text).map_err(|e| unreadable(e.to_string()))?;
    let Some(stability) = json.get_mut("stability").and_then(|s| s.as_object_mut()) else {
        return Err(unreadable("no stability section".into()));
    };
    stability.insert(key.to_string(), value);
    super::write_json(folder, "run.json", &json).map(|_| ())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn why_there_are_no_sizes_is_read_back() {
        let folder = std::env::temp_dir().join(format!("sizes-reason-{}", std::process::id()));
        std::fs::create_dir_all(&folder).unwrap();
        std::fs::write(
            folder.join("run.json"),
            r#"{"status": "finished", "stability": {"status": "computed"}}"#,
        )
        .unwrap();
        assert_eq!(read_reason(&folder), None);
        record_reason(&folder, "past the budget").unwrap();
        assert_eq!(read_reason(&folder).as_deref(), Some("past the budget"));
        assert_eq!(read(&folder), None);
        // The rest of run.json kept as it was.
        let text = std::fs::read_to_string(folder.join("run.json")).unwrap();
        let json: serde_json::Value = serde_json::from_str(&text).unwrap();
        assert_eq!(json["status"], "finished");
        assert_eq!(json["stability"]["status"], "computed");
        std::fs::remove_dir_all(&folder).unwrap();
    }

    #[test]
    fn sizes_recorded_in_run_json_are_read_back_and_the_rest_kept() {
        let folder = std::env::temp_dir().join(format!("sizes-{}", std::process::id()));
        std::fs::create_dir_all(&folder).unwrap();
        std::fs::write(
            folder.join("run.json"),
            r#"{"status": "finished", "stability": {"status": "computed", "markers": []}}"#,
        )
        .unwrap();
        assert_eq!(read(&folder), None);
        let sizes = ConvergedSizes {
            point: 43,
            frequency_hz: 127.5,
            chosen_at: "fastest_growth".into(),
            harmonics: vec![10, 20],
            leading_re: vec![Some(201.0), Some(241.6)],
            stable: vec![false, false],
            changes: vec![Some(0.168)],
            converged_within: 0.05,
            converged: false,
            stopped: Some("budget".into()),
            verdict_holds: true,
            classes: vec![ClassSizes {
                class: 2,
                run_re: None,
                finest_re: 241.6,
            }],
        };
        record(&folder, &sizes).unwrap();
        assert_eq!(read(&folder), Some(sizes));
        let json: serde_json::Value =
            serde_json::from_str(&std::fs::read_to_string(folder.join("run.json")).unwrap())
                .unwrap();
        assert_eq!(json["status"], "finished");
        assert_eq!(json["stability"]["status"], "computed");
        // A folder whose run.json has no stability section is refused.
        std::fs::write(folder.join("run.json"), r#"{"status": "finished"}"#).unwrap();
        assert!(record(&folder, &read_back_nothing()).is_err());
        std::fs::remove_dir_all(&folder).unwrap();
    }

    fn read_back_nothing() -> ConvergedSizes {
        ConvergedSizes {
            point: 0,
            frequency_hz: 1.0,
            chosen_at: "largest_amplitude".into(),
            harmonics: vec![3],
            leading_re: vec![None],
            stable: vec![true],
            changes: Vec::new(),
            converged_within: 0.05,
            converged: false,
            stopped: None,
            verdict_holds: true,
            classes: Vec::new(),
        }
    }
}
