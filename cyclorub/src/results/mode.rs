//! How a branch was followed (`run.json`'s and `results.h5`'s `mode`), as
//! a type (issue 41 item 3). It lives with the results data that store it,
//! below the front door that sets it.

use serde::{Deserialize, Serialize};
use std::fmt;

/// How the branch was followed (`run.json`'s `mode`).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum RunMode {
    /// Arc-length continuation over the frequency range.
    Continuation,
    /// A solve at each frequency asked for, each from the last.
    AtFrequencies,
}

impl RunMode {
    /// The word `run.json` holds.
    pub fn word(self) -> &'static str {
        match self {
            Self::Continuation => "continuation",
            Self::AtFrequencies => "at_frequencies",
        }
    }
}

impl fmt::Display for RunMode {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.word())
    }
}

impl std::str::FromStr for RunMode {
    type Err = String;

    /// Reads the word `run.json` and `results.h5` hold; the error names the
    /// words allowed.
    fn from_str(word: &str) -> Result<Self, Self::Err> {
        [Self::Continuation, Self::AtFrequencies]
            .into_iter()
            .find(|mode| mode.word() == word)
            .ok_or_else(|| {
                format!("mode {word:?} is neither \"continuation\" nor \"at_frequencies\"")
            })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The words of the files are read back into the type; another word is
    /// refused by name.
    #[test]
    fn a_mode_is_read_from_its_word() {
        for mode in [RunMode::Continuation, RunMode::AtFrequencies] {
            assert_eq!(mode.word().parse::<RunMode>(), Ok(mode));
        }
        let refused = "sweep".parse::<RunMode>().expect_err("not a mode");
        assert!(refused.contains("\"sweep\""), "{refused}");
    }
}
