//! The library's errors as Python exceptions: `cyclorub.CyclorubError`
//! (defined in `cyclorub/_errors.py`) carrying the key the library names
//! (`.key`, e.g. `"casing.gap"`, or `None`), the whole message
//! (`.message`) and the kind of error (`.kind`). Errors in what the user
//! gave are raised as `cyclorub.InputError`, a subclass that is also a
//! `ValueError`.

use cyclorub::case::CaseError;
use cyclorub::hbm::HbmError;
use cyclorub::model::ModelError;
use cyclorub::results::output_folder::OutputFolderError;
use cyclorub::results::ResultsError;
use cyclorub::run::RunError;
use pyo3::prelude::*;

/// An error of the library, ready to become a Python exception.
#[derive(Debug)]
pub struct Error {
    /// The case-file key the error names, if any.
    pub key: Option<String>,
    /// The library's message, whole.
    pub message: String,
    /// `case`, `model`, `harmonic_balance`, `results`, `run` or `usage`.
    pub kind: &'static str,
    /// Whether the error is in what the user gave.
    pub input: bool,
}

impl Error {
    /// A usage error of the Python API itself (a bad argument).
    pub fn usage(key: Option<&str>, message: impl Into<String>) -> Self {
        Self {
            key: key.map(str::to_string),
            message: message.into(),
            kind: "usage",
            input: true,
        }
    }

    /// A failure of the machinery (a thread that cannot start or died).
    pub fn internal(message: impl Into<String>) -> Self {
        Self {
            key: None,
            message: message.into(),
            kind: "run",
            input: false,
        }
    }
}

/// The key named by a model error, if it names one.
fn model_key(error: &ModelError) -> Option<String> {
    match error {
        ModelError::Invalid { key, .. } => Some(key.to_string()),
        ModelError::NotSquare { what, .. }
        | ModelError::NotSymmetric { what, .. }
        | ModelError::MassNotPositiveDefinite { what, .. }
        | ModelError::SizeMismatch { what, .. }
        | ModelError::NotFinite { what, .. } => Some(what.to_string()),
        ModelError::RepeatedBoundaryDof { at, .. } => Some(at.to_string()),
        ModelError::UnequalBoundaries { left, .. } => Some(left.to_string()),
        ModelError::Io { key, .. } => Some(key.clone()),
        _ => None,
    }
}

impl From<CaseError> for Error {
    fn from(error: CaseError) -> Self {
        let key = match &error {
            CaseError::Invalid { key, .. } => Some(key.clone()),
            CaseError::Parse { key, .. } => key.clone(),
            CaseError::Io { .. } => None,
        };
        Self {
            key,
            message: error.to_string(),
            kind: "case",
            input: true,
        }
    }
}

impl From<ModelError> for Error {
    fn from(error: ModelError) -> Self {
        Self {
            key: model_key(&error),
            input: error.is_input_error(),
            message: error.to_string(),
            kind: "model",
        }
    }
}

impl From<ResultsError> for Error {
    fn from(error: ResultsError) -> Self {
        Self {
            key: None,
            input: error.is_input_error(),
            message: error.to_string(),
            kind: "results",
        }
    }
}

impl From<OutputFolderError> for Error {
    fn from(error: OutputFolderError) -> Self {
        Self {
            key: Some("output.directory".into()),
            input: error.is_input_error(),
            message: error.to_string(),
            kind: "run",
        }
    }
}

impl From<RunError> for Error {
    fn from(error: RunError) -> Self {
        let input = error.is_input_error();
        match error {
            RunError::Case(e) => e.into(),
            RunError::Model(e) => e.into(),
            RunError::Results(e) => e.into(),
            RunError::Hbm(e) => {
                let key = match &e {
                    HbmError::DofOutOfRange { key, .. } => Some(key.to_string()),
                    HbmError::Model(m) => model_key(m),
                    _ => None,
                };
                Self {
                    key,
                    message: e.to_string(),
                    kind: "harmonic_balance",
                    input,
                }
            }
            other => {
                let key = match &other {
                    RunError::OutputFolder { .. } => Some("output.directory"),
                    RunError::NoNaturalFrequency { .. } => Some("continuation.start_hz"),
                    _ => None,
                };
                Self {
                    key: key.map(str::to_string),
                    message: other.to_string(),
                    kind: "run",
                    input,
                }
            }
        }
    }
}

impl From<Error> for PyErr {
    fn from(error: Error) -> Self {
        Python::attach(|py| {
            let class = if error.input {
                "InputError"
            } else {
                "CyclorubError"
            };
            let made = py
                .import("cyclorub._errors")
                .and_then(|module| module.getattr(class))
                .and_then(|class| {
                    class.call1((error.message.clone(), error.key.clone(), error.kind))
                });
            match made {
                Ok(instance) => PyErr::from_value(instance),
                // The package is broken (the module cannot be imported):
                // say the library's message anyway.
                Err(_) => pyo3::exceptions::PyRuntimeError::new_err(error.message),
            }
        })
    }
}

/// The result type of the bindings.
pub type Result<T> = std::result::Result<T, Error>;
