//! `cyclorub._native.Case`: a case in memory (the library's `Case`) with
//! the folder its relative paths start from. The Python class
//! `cyclorub.Case` wraps it with attribute-style edits and pickling.

pub use crate::case_type::Case;
use crate::errors::{Error, Result};
use crate::result::RunResult;
use crate::solve::{solve, Request};
use cyclorub::basis::{BasisError, SpectralBasis};
use cyclorub::case::keys::TABLES;
use cyclorub::case::{BasisChoice, Case as LibraryCase};
use cyclorub::cyclic::LoadCase;
use cyclorub::model::ModelKind;
use cyclorub::stability::StabilitySettings;
use cyclorub_app::template::{Example, EXAMPLES};
use numpy::PyArray1;
use pyo3::prelude::*;
use pyo3::types::PyDict;
use serde_json::Value;
use std::path::PathBuf;

/// The value at dotted `key` in `value` (`None`: not there).
fn lookup<'a>(value: &'a Value, key: &str) -> Option<&'a Value> {
    key.split('.')
        .filter(|part| !part.is_empty())
        .try_fold(value, |v, part| v.get(part))
}

/// Whether `key` names a table or a key of the case file.
fn known(key: &str) -> bool {
    TABLES.iter().any(|table| {
        table.name == key
            || table
                .keys
                .iter()
                .any(|k| format!("{}.{}", table.name, k.name) == key)
    })
}

impl Case {
    /// The case as a JSON value.
    fn json(&self) -> Result<Value> {
        serde_json::to_value(&self.inner)
            .map_err(|e| Error::usage(None, format!("the case cannot be serialized: {e}")))
    }

    /// The case with `key` (dotted) set to `new`; not checked beyond types.
    fn with(&self, key: &str, new: Value) -> Result<LibraryCase> {
        if !known(key) {
            return Err(Error::usage(
                Some(key),
                format!(
                    "{key}: no such key in a case file (see docs/case-file.md, or cyclorub.keys())"
                ),
            ));
        }
        let mut value = self.json()?;
        let parts: Vec<&str> = key.split('.').collect();
        let (last, tables) = parts
            .split_last()
            .ok_or_else(|| Error::usage(Some(key), "an empty key"))?;
        let mut slot = &mut value;
        for part in tables {
            let object = slot
                .as_object_mut()
                .ok_or_else(|| Error::usage(Some(key), format!("{key}: not a table")))?;
            slot = object
                .entry(part.to_string())
                .or_insert_with(|| Value::Object(Default::default()));
        }
        let object = slot
            .as_object_mut()
            .ok_or_else(|| Error::usage(Some(key), format!("{key}: not a table")))?;
        if new.is_null() {
            object.remove(*last);
        } else {
            object.insert(last.to_string(), new);
        }
        serde_json::from_value(value)
            .map_err(|e| Error::usage(Some(key), format!("{key}: {e}")).input_case())
    }

    /// The load pairs of the case (what the bases are built from).
    fn load_case(&self) -> Result<LoadCase> {
        let casing = self.inner.casing()?;
        Ok(LoadCase {
            sectors: self.inner.model.sectors(),
            excitation: self.inner.forcing().map(|f| f.pattern),
            casing_order: (casing.order > 0 && casing.amplitudes.iter().any(|&p| p != 0.0))
                .then_some(casing.order),
        })
    }
}

impl Error {
    /// The same error, as an error of the case.
    fn input_case(mut self) -> Self {
        self.kind = "case";
        self
    }
}

/// A rule that builds a basis for a load case and `N_h`.
type Rule = fn(&LoadCase, usize) -> std::result::Result<SpectralBasis, BasisError>;

/// The basis named `name` (`symmetry`, `paper`, `nodal_diameter`, `full`,
/// `physical`).
pub fn basis_choice(name: &str) -> Result<BasisChoice> {
    BasisChoice::parse(name).map_err(|e| Error::usage(Some("basis.kind"), format!("basis: {e}")))
}

#[pymethods]
impl Case {
    /// The paper's default case (academic model, N = 24, traveling wave
    /// h = 1 of 4 N, R-HBM).
    #[staticmethod]
    fn default() -> Self {
        Self {
            inner: LibraryCase::default(),
            case_dir: PathBuf::from("."),
        }
    }

    /// Parses TOML text; `origin` names it in messages, `case_dir` is the
    /// folder relative paths start from. Types and keys are checked here,
    /// values by `validate()` (and before any run).
    #[staticmethod]
    /// With `check = False` only the keys and types are checked.
    #[pyo3(signature = (text, origin = "case.toml".into(), case_dir = PathBuf::from("."), check = true))]
    fn from_toml(text: &str, origin: PathBuf, case_dir: PathBuf, check: bool) -> PyResult<Self> {
        let inner = LibraryCase::from_toml(text, &origin).map_err(Error::from)?;
        if check {
            inner
                .validate()
                .map_err(|e| Error::from(e.located(&origin, text)))?;
        }
        Ok(Self { inner, case_dir })
    }

    /// An independent copy.
    fn copy(&self) -> Self {
        self.clone()
    }

    /// One of the paper's academic studies (`example_names()` lists them).
    #[staticmethod]
    fn example(name: &str) -> PyResult<Self> {
        match Example::find(name) {
            Some(example) => Ok(Self {
                inner: example.case(),
                case_dir: PathBuf::from("."),
            }),
            None => Err(Error::usage(
                None,
                format!(
                    "no example named {name:?}; the examples are: {}",
                    Example::names().join(", ")
                ),
            )
            .into()),
        }
    }

    /// The names of the paper's academic studies.
    #[staticmethod]
    fn example_names() -> Vec<&'static str> {
        EXAMPLES.iter().map(|e| e.name).collect()
    }

    /// The case as TOML text (every key that has a value).
    fn to_toml(&self) -> PyResult<String> {
        toml::to_string(&self.inner).map_err(|e| {
            Error::usage(None, format!("the case cannot be written as TOML: {e}")).into()
        })
    }

    /// The case as JSON text.
    fn to_json(&self) -> PyResult<String> {
        Ok(self.json()?.to_string())
    }

    /// The value at dotted `key` (e.g. `"contact.law"`) as JSON text;
    /// `"null"` for a key that is absent (an automatic rule).
    fn get_json(&self, key: &str) -> PyResult<String> {
        if !known(key) {
            return Err(
                Error::usage(Some(key), format!("{key}: no such key in a case file")).into(),
            );
        }
        Ok(lookup(&self.json()?, key)
            .cloned()
            .unwrap_or(Value::Null)
            .to_string())
    }

    /// Sets dotted `key` to the value given as JSON text (`null`: absent).
    /// The type is checked here, the value by `validate()`.
    fn set_json(&mut self, key: &str, json: &str) -> PyResult<()> {
        let value: Value = serde_json::from_str(json)
            .map_err(|e| Error::usage(Some(key), format!("{key}: not a value: {e}")))?;
        self.inner = self.with(key, value)?;
        Ok(())
    }

    /// Checks every value; raises with the key of the first refused one.
    /// A model written in the case (`kind = "academic"` or `"matrices"`)
    /// is built too, as a run builds it: matrices of unequal sizes, not
    /// symmetric or a stiffness that does not hold the wheel are refused
    /// here, not by the run (a model read from files is checked by the
    /// run, whose reduction may take long).
    fn validate(&self, py: Python<'_>) -> PyResult<()> {
        self.inner.validate().map_err(Error::from)?;
        if matches!(
            self.inner.model.kind,
            ModelKind::Academic | ModelKind::Matrices
        ) {
            let spec = self.inner.model.clone();
            let dir = self.case_dir.clone();
            py.detach(move || spec.build(&dir).map(drop))
                .map_err(Error::from)?;
        }
        Ok(())
    }

    /// The folder the case's relative paths start from.
    #[getter]
    fn get_case_dir(&self) -> PathBuf {
        self.case_dir.clone()
    }

    /// Sets the folder the case's relative paths start from.
    #[setter]
    fn set_case_dir(&mut self, dir: PathBuf) {
        self.case_dir = dir;
    }

    fn __eq__(&self, other: &Self) -> bool {
        self.inner == other.inner && self.case_dir == other.case_dir
    }

    /// What each basis keeps for this case's loads, before running
    /// anything: `{basis: {"unknowns", "full_unknowns", "sampled_sectors",
    /// "reduction_percent", "nodal_diameters": [array per harmonic]}}`,
    /// or `{"error": message}` for a basis that does not apply.
    fn plan<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        self.inner.validate().map_err(Error::from)?;
        let load = self.load_case()?;
        let harmonics = self.inner.harmonic_balance.harmonics;
        let contact = self.inner.contact.dofs.len();
        let out = PyDict::new(py);
        let rules: [(&str, Rule); 4] = [
            ("symmetry", SpectralBasis::symmetry),
            ("paper", SpectralBasis::paper),
            ("nodal_diameter", SpectralBasis::nodal_diameter),
            ("full", |load: &LoadCase, h| {
                SpectralBasis::full(load.sectors, h)
            }),
        ];
        for (name, rule) in rules {
            let entry = PyDict::new(py);
            match rule(&load, harmonics) {
                Ok(basis) => {
                    entry.set_item("unknowns", basis.real_unknowns_per_contact_dof() * contact)?;
                    entry.set_item("full_unknowns", basis.full_size_per_contact_dof() * contact)?;
                    entry.set_item("sampled_sectors", basis.sampled_sectors())?;
                    entry.set_item("reduction_percent", basis.reduction_percent())?;
                    let sets: Vec<Bound<'py, PyArray1<i64>>> = (0..=harmonics)
                        .map(|k| PyArray1::from_slice(py, basis.nodal_diameters(k)))
                        .collect();
                    entry.set_item("nodal_diameters", sets)?;
                }
                Err(error) => entry.set_item("error", error.to_string())?,
            }
            out.set_item(name, entry)?;
        }
        Ok(out)
    }

    /// The deviations `δ_j` of `[mistuning]` (given, or drawn from its
    /// standard deviation and seed as a run draws them), `None` for a tuned
    /// wheel; refused, naming the key, as a run would refuse them.
    fn mistuning_deviations(&self) -> PyResult<Option<Vec<f64>>> {
        Ok(self.inner.mistuning_deviations().map_err(Error::from)?)
    }

    /// Natural frequencies (Hz) of the case's model per nodal diameter:
    /// `(nodal_diameters [d], frequencies_hz [d, mode])`, NaN where a
    /// diameter has fewer modes.
    fn modes<'py>(&self, py: Python<'py>) -> PyResult<crate::arrays::Modes<'py>> {
        let spec = self.inner.model.clone();
        let dir = self.case_dir.clone();
        let frequencies = py
            .detach(move || {
                spec.build(&dir)
                    .and_then(|model| model.natural_frequencies())
            })
            .map_err(Error::from)?;
        Ok(crate::arrays::modes_arrays(py, &frequencies))
    }

    /// Solves the case (see the Python `Case.run`).
    #[pyo3(signature = (basis = None, at_hz = None, stability = None, stability_harmonics = None, progress = None))]
    fn run(
        &self,
        py: Python<'_>,
        basis: Option<&str>,
        at_hz: Option<Vec<f64>>,
        stability: Option<bool>,
        stability_harmonics: Option<usize>,
        progress: Option<Py<PyAny>>,
    ) -> PyResult<RunResult> {
        let basis = match basis {
            Some(name) => basis_choice(name)?,
            None => self.inner.basis.kind,
        };
        if stability_harmonics == Some(0) {
            return Err(Error::usage(
                Some("stability.harmonics"),
                "stability_harmonics = 0: give an integer ≥ 1 (Hill's truncation)",
            )
            .into());
        }
        let settings = match stability {
            Some(false) => None,
            Some(true) => Some(self.inner.stability.settings().unwrap_or_default()),
            None => self.inner.stability.settings(),
        }
        .map(|s| StabilitySettings {
            harmonics: stability_harmonics.or(s.harmonics),
            ..s
        });
        let request = Request {
            case: self.inner.clone(),
            case_dir: self.case_dir.clone(),
            basis,
            at_hz,
            stability: settings,
        };
        let (solution, interrupted) = solve(py, request, progress)?;
        Ok(RunResult::solved(
            solution,
            self.case_dir.clone(),
            interrupted,
        ))
    }
}

/// Every key of a case file: `(table, key, default, unit, allowed, doc)`.
#[pyfunction]
pub fn keys() -> Vec<(
    &'static str,
    &'static str,
    &'static str,
    &'static str,
    &'static str,
    &'static str,
)> {
    TABLES
        .iter()
        .flat_map(|t| {
            t.keys
                .iter()
                .map(move |k| (t.name, k.name, k.default, k.unit, k.allowed, k.doc))
        })
        .collect()
}
