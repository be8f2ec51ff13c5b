//! What a mistuning study needs of the library (issue 44 item 5): the
//! figure of its amplification factors, drawn by the library's plotters
//! SVG backend like every other figure of a run (no plotting package
//! needed in Python), and Whitehead's bound.

use crate::errors::Error;
use cyclorub::plot::mistuning_study::{whitehead_bound, write_amplification_distribution};
use pyo3::prelude::*;
use std::path::PathBuf;

/// Whitehead's bound `(1 + √N)/2` on the amplification factor of a wheel
/// of `sectors` sectors.
#[pyfunction]
pub fn whitehead(sectors: usize) -> f64 {
    whitehead_bound(sectors)
}

/// Draws the distribution of the amplification factors `factors` (NaN
/// left out) of a wheel of `sectors` sectors into the SVG file `path`
/// (its PNG beside when `png`): histogram and empirical cumulative
/// distribution, the tuned wheel's 1 and Whitehead's bound marked. Returns
/// the files written.
#[pyfunction]
#[pyo3(signature = (factors, sectors, path, png = false))]
pub fn amplification_figure(
    py: Python<'_>,
    factors: Vec<f64>,
    sectors: usize,
    path: PathBuf,
    png: bool,
) -> PyResult<Vec<PathBuf>> {
    if sectors == 0 {
        return Err(Error::usage(
            Some("sectors"),
            "sectors = 0: a wheel has at least one sector",
        )
        .into());
    }
    let written = py
        .detach(|| write_amplification_distribution(&path, &factors, sectors, png))
        .map_err(|e| {
            let input = e.is_input_error() || matches!(e, cyclorub::plot::PlotError::Empty { .. });
            let mut error = Error::usage(None, e.to_string());
            error.kind = "results";
            error.input = input;
            error
        })?;
    Ok(written)
}
