//! Python bindings of the cyclorub solver: the native part
//! (`cyclorub._native`) of the Python package `cyclorub`, whose pure-Python
//! part (`python/cyclorub/`) adds attribute-style case edits, arrays from
//! scipy.sparse, and parameter studies over any executor.
//!
//! Solves run on a worker thread with the GIL released; Ctrl-C stops the
//! branch before its next point and returns what was computed (see
//! [`solve`]). Library errors become `cyclorub.CyclorubError` (or its
//! subclass `cyclorub.InputError`) with the key the library names.
#![warn(missing_docs)]
#![deny(clippy::float_cmp)]

mod arrays;
mod case;
mod case_type;
mod errors;
mod loaded;
mod result;
mod save;
mod solve;
mod stub_types;
mod study;

use pyo3::prelude::*;

/// The native module.
#[pymodule]
fn _native(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_class::<case::Case>()?;
    m.add_class::<result::RunResult>()?;
    m.add_function(wrap_pyfunction!(result::load, m)?)?;
    m.add_function(wrap_pyfunction!(study::whitehead, m)?)?;
    m.add_function(wrap_pyfunction!(study::amplification_figure, m)?)?;
    m.add_function(wrap_pyfunction!(case::keys, m)?)?;
    m.add_function(wrap_pyfunction!(stub_types::key_types, m)?)?;
    m.add("__version__", env!("CARGO_PKG_VERSION"))?;
    Ok(())
}
