//! What a solution records of how it went: how its first point was
//! reached and what its stability check gave.

use crate::stability::BranchStability;
use serde::Serialize;

/// What the stability check of a branch gave.
#[derive(Clone, Debug)]
pub enum StabilityOutcome {
    /// Not asked for.
    NotAsked,
    /// Asked for, but it could not run (the branch is kept): why.
    NotComputed {
        /// The reason, naming what to change.
        reason: String,
    },
    /// Every point's exponents and the markers.
    Computed(BranchStability),
}

impl StabilityOutcome {
    /// The points' stability, when computed.
    pub fn computed(&self) -> Option<&BranchStability> {
        match self {
            Self::Computed(branch) => Some(branch),
            _ => None,
        }
    }
}

/// How the first point of the branch was reached.
#[derive(Clone, Debug, PartialEq, Serialize)]
#[serde(tag = "method", rename_all = "snake_case")]
pub enum StartRecord {
    /// Newton from the linear response at the start frequency.
    LinearGuess,
    /// Newton from the linear response failed at the start frequency; the
    /// start was reached by continuation in the load scale `s` from 0 (no
    /// excitation: only the static contact state) to 1, at the start
    /// frequency.
    LoadContinuation {
        /// Why Newton from the linear response failed.
        first_attempt: String,
        /// Points of the continuation in the load scale.
        points: usize,
    },
    /// Newton from the linear response and the continuation in the load
    /// both failed; the start was reached by continuation in the gap, from
    /// gaps wide enough that the linear response does not touch the casing
    /// down to the case's gaps, at the start frequency.
    GapContinuation {
        /// Why Newton from the linear response failed.
        first_attempt: String,
        /// Gaps solved on the way (the last is the case's).
        points: usize,
    },
}
