//! The states a run reports, as types (issue 41 item 3): how it ended, how
//! its stability check went and how its branch was followed (the last,
//! [`RunMode`], lives with the results data that store it). Each says
//! itself in the words `run.json` has always held (`Display` and serde
//! alike), so old results still read and callers never compare strings.

pub use crate::results::RunMode;
use serde::{Deserialize, Serialize};
use std::fmt;

/// How a run ended (`run.json`'s `status`).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum RunStatus {
    /// Still going: what `run.json` says until the run ends (or forever, if
    /// it was killed).
    Running,
    /// Everything asked for was done.
    Finished,
    /// Stopped from outside (the branch, or the stability check after it).
    Interrupted,
    /// The branch stopped short, or points did not converge.
    StoppedEarly,
}

impl RunStatus {
    /// The word `run.json` holds.
    pub fn word(self) -> &'static str {
        match self {
            Self::Running => "running",
            Self::Finished => "finished",
            Self::Interrupted => "interrupted",
            Self::StoppedEarly => "stopped_early",
        }
    }
}

impl fmt::Display for RunStatus {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.word())
    }
}

/// How the stability check went (`run.json`'s `stability.status`).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum StabilityStatus {
    /// Every point checked.
    Computed,
    /// Asked for, but not computed (the reason is beside it).
    NotComputed,
    /// Not asked for.
    NotAsked,
}

impl StabilityStatus {
    /// The word `run.json` holds.
    pub fn word(self) -> &'static str {
        match self {
            Self::Computed => "computed",
            Self::NotComputed => "not_computed",
            Self::NotAsked => "not_asked",
        }
    }
}

impl fmt::Display for StabilityStatus {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.word())
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::continuation::StopReason;

    /// The words of run.json written before these types, read back, and
    /// written again the same.
    #[test]
    fn the_words_of_run_json_are_kept_and_read_back() {
        for (status, word) in [
            (RunStatus::Running, "running"),
            (RunStatus::Finished, "finished"),
            (RunStatus::Interrupted, "interrupted"),
            (RunStatus::StoppedEarly, "stopped_early"),
        ] {
            let json = format!("\"{word}\"");
            assert_eq!(serde_json::to_string(&status).expect("json"), json);
            assert_eq!(
                serde_json::from_str::<RunStatus>(&json).expect("read"),
                status
            );
            assert_eq!(status.to_string(), word);
        }
        for (status, word) in [
            (StabilityStatus::Computed, "computed"),
            (StabilityStatus::NotComputed, "not_computed"),
            (StabilityStatus::NotAsked, "not_asked"),
        ] {
            let json = format!("\"{word}\"");
            assert_eq!(serde_json::to_string(&status).expect("json"), json);
            assert_eq!(
                serde_json::from_str::<StabilityStatus>(&json).expect("read"),
                status
            );
            assert_eq!(status.to_string(), word);
        }
        for (mode, word) in [
            (RunMode::Continuation, "continuation"),
            (RunMode::AtFrequencies, "at_frequencies"),
        ] {
            let json = format!("\"{word}\"");
            assert_eq!(serde_json::to_string(&mode).expect("json"), json);
            assert_eq!(serde_json::from_str::<RunMode>(&json).expect("read"), mode);
            assert_eq!(mode.to_string(), word);
        }
        // A stop as run.json holds it, read back into the type.
        let old = r#"{"reason": "step_underflow", "frequency_hz": 127.5, "step": 1e-7}"#;
        let stop: StopReason = serde_json::from_str(old).expect("read");
        assert_eq!(
            stop,
            StopReason::StepUnderflow {
                frequency_hz: 127.5,
                step: 1e-7
            }
        );
        let again: serde_json::Value = serde_json::to_value(&stop).expect("json");
        let old: serde_json::Value = serde_json::from_str(old).expect("json");
        assert_eq!(again, old);
        let end: StopReason = serde_json::from_str(r#"{"reason": "end_reached"}"#).expect("read");
        assert_eq!(end, StopReason::EndReached);
    }
}
