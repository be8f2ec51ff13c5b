//! The `Case` class's value (a library case and the folder its relative
//! paths start from), in a module of its own: a result hands back its
//! case (`result`) without depending on the methods that edit and run
//! one (`case`, which returns results).

use cyclorub::case::Case as LibraryCase;
use pyo3::prelude::*;
use std::path::PathBuf;

/// A case: every input of a run (see docs/case-file.md), and the
/// folder its relative paths (Matrix Market files) start from.
#[pyclass(name = "Case", module = "cyclorub._native")]
#[derive(Clone)]
pub struct Case {
    /// The case.
    pub inner: LibraryCase,
    /// The folder relative paths start from.
    pub case_dir: PathBuf,
}
