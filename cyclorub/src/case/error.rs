//! Errors of a case file: a file that cannot be read, TOML that does not
//! parse, a value refused with its key (and, located, its line).

use std::path::{Path, PathBuf};

/// Errors reading or checking a case file.
#[derive(Debug, thiserror::Error)]
pub enum CaseError {
    /// The file cannot be read.
    #[error("cannot read the case file {path}: {source}")]
    Io {
        /// The file.
        path: PathBuf,
        /// Why.
        source: std::io::Error,
    },
    /// The TOML is malformed or holds an unknown key.
    #[error("{path}: {message}")]
    Parse {
        /// The file.
        path: PathBuf,
        /// The dotted key the parser stopped at (`contact.law`), when the
        /// error is at a key or its value ([`parse_key`]).
        key: Option<String>,
        /// The parser's message (line, key, allowed keys).
        message: String,
    },
    /// A value is not allowed.
    #[error("{key} = {value}: {allowed}")]
    Invalid {
        /// The key, e.g. `casing.gap`.
        key: String,
        /// The value given.
        value: String,
        /// What is allowed.
        allowed: String,
    },
}

pub(crate) fn invalid(
    key: &str,
    value: impl std::fmt::Display,
    allowed: impl Into<String>,
) -> CaseError {
    CaseError::Invalid {
        key: key.into(),
        value: value.to_string(),
        allowed: allowed.into(),
    }
}

/// A contact parameter refused by its law, named by its key.
pub(crate) fn contact_error(error: crate::contact::ContactError) -> CaseError {
    let crate::contact::ContactError::InvalidParameter {
        key,
        value,
        allowed,
    } = error;
    // The rotation speed is the one parameter of a contact law's input
    // that has its own table.
    let table = if key == "speed" {
        "rotation"
    } else {
        "contact"
    };
    invalid(&format!("{table}.{key}"), number_text(value), allowed)
}

/// A number as a message shows it: `1e300` rather than its 301 digits,
/// `2.5e-9` rather than its zeros; plain between 1e-3 and 1e6.
pub(crate) fn number_text(x: f64) -> String {
    if x.is_finite() && x != 0.0 && !(1e-3..1e6).contains(&x.abs()) {
        format!("{x:e}")
    } else {
        format!("{x}")
    }
}

/// The line (1-based) of `key` (`table.leaf`, e.g. `casing.gap` or
/// `model.damping.ratio`) in TOML `text`: the first `leaf = …` line under the
/// `[table]` header. `None` when the key is not written (a default).
pub fn key_line(text: &str, key: &str) -> Option<usize> {
    let (table, leaf) = key.rsplit_once('.').unwrap_or(("", key));
    let mut current = String::new();
    for (index, line) in text.lines().enumerate() {
        let line = line.trim();
        if let Some(header) = line.strip_prefix('[') {
            current = header
                .trim_end_matches(']')
                .trim()
                .trim_end_matches(']')
                .to_string();
            continue;
        }
        if current == table {
            if let Some(rest) = line.strip_prefix(leaf) {
                if rest.trim_start().starts_with('=') {
                    return Some(index + 1);
                }
            }
        }
    }
    None
}

impl CaseError {
    /// A refused value with where it is written: `path:line` appended to
    /// what is allowed (unchanged when the key is not in `text`).
    pub fn located(self, path: &Path, text: &str) -> Self {
        match self {
            CaseError::Invalid {
                key,
                value,
                allowed,
            } => {
                let allowed = match key_line(text, &key) {
                    Some(line) => format!("{allowed} (at {}:{line})", path.display()),
                    None => allowed,
                };
                CaseError::Invalid {
                    key,
                    value,
                    allowed,
                }
            }
            other => other,
        }
    }
}

/// The dotted key (`contact.law`, `model.damping.ratio`) whose line holds
/// byte `at` of TOML `text`, or the nearest `key =` line above it within
/// its table (a value spread over lines); `None` outside any `key = …`
/// (a table header, a malformed line).
pub fn parse_key(text: &str, at: usize) -> Option<String> {
    let line = text.get(..at)?.matches('\n').count();
    let lines: Vec<&str> = text.lines().take(line + 1).collect();
    let mut leaf = None;
    for line in lines.iter().rev() {
        let line = line.split('#').next().unwrap_or("").trim();
        if let Some(header) = line.strip_prefix('[') {
            let table = header.trim_start_matches('[').trim_end_matches(']').trim();
            return leaf.map(|l: &str| {
                if table.is_empty() {
                    l.to_string()
                } else {
                    format!("{table}.{l}")
                }
            });
        }
        if leaf.is_none() {
            if let Some((name, _)) = line.split_once('=') {
                let name = name.trim().trim_matches('"');
                let bare = |c: char| c.is_ascii_alphanumeric() || c == '_' || c == '-' || c == '.';
                if !name.is_empty() && name.chars().all(bare) {
                    leaf = Some(name);
                }
            }
        }
    }
    leaf.map(str::to_string)
}
