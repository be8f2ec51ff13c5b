//! numpy arrays and JSON text of the library's values, shared by the
//! classes.

use numpy::ndarray::Array2;
use numpy::{IntoPyArray, PyArray1, PyArray2};
use pyo3::prelude::*;

/// Natural frequencies: nodal diameters `[d]` and frequencies `[d, mode]`, Hz.
pub type Modes<'py> = (Bound<'py, PyArray1<usize>>, Bound<'py, PyArray2<f64>>);

/// A curve: frequencies `[f]`, Hz, and values `[f, sector]`.
pub type Curve<'py> = (Bound<'py, PyArray1<f64>>, Bound<'py, PyArray2<f64>>);

/// `[f][j]` rows of equal length as an array (NaN-padded when ragged).
pub fn matrix(rows: &[Vec<f64>]) -> Array2<f64> {
    let cols = rows.iter().map(Vec::len).max().unwrap_or(0);
    Array2::from_shape_fn((rows.len(), cols), |(i, j)| {
        rows[i].get(j).copied().unwrap_or(f64::NAN)
    })
}

/// The natural frequencies per nodal diameter as `(diameters, [d, mode])`.
pub fn modes_arrays<'py>(py: Python<'py>, frequencies: &[(usize, Vec<f64>)]) -> Modes<'py> {
    let diameters: Vec<usize> = frequencies.iter().map(|(d, _)| *d).collect();
    let rows: Vec<Vec<f64>> = frequencies.iter().map(|(_, f)| f.clone()).collect();
    (
        PyArray1::from_vec(py, diameters),
        matrix(&rows).into_pyarray(py),
    )
}

/// JSON text of a record.
pub fn json(value: &impl serde::Serialize) -> String {
    serde_json::to_string(value).unwrap_or_else(|e| format!("{{\"error\": \"{e}\"}}"))
}
