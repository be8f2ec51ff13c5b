//! The bifurcated branches of a loaded result (`cyclorub branches`, or
//! `cyclorub run --branches`), as `results.h5`'s `/branches` group holds
//! them: one dict per branch point, numpy arrays per side.

use crate::arrays::{json, matrix};
use cyclorub::results::bifurcated::{BifurcatedBranchData, BifurcatedSide};
use numpy::{IntoPyArray, PyArray1};
use pyo3::prelude::*;
use pyo3::types::{PyDict, PyList};

/// `branches` as a list of dicts, in the order of `branches.json`.
pub fn branch_list<'py>(
    py: Python<'py>,
    branches: &[BifurcatedBranchData],
    sectors: usize,
) -> PyResult<Bound<'py, PyList>> {
    let list = PyList::empty(py);
    for branch in branches {
        let out = PyDict::new(py);
        out.set_item("class", branch.class)?;
        out.set_item("marker", branch.marker)?;
        out.set_item("marker_hz", branch.marker_hz)?;
        out.set_item("parent_point", branch.parent_point)?;
        out.set_item("branch_point_hz", branch.branch_point_hz)?;
        out.set_item("basis_unknowns", branch.basis_unknowns)?;
        out.set_item("full_unknowns", branch.full_unknowns)?;
        out.set_item("file", branch.file.as_deref())?;
        out.set_item("not_switched", branch.not_switched.as_deref())?;
        let sides = PyList::empty(py);
        for side in &branch.sides {
            sides.append(side_dict(py, side, sectors)?)?;
        }
        out.set_item("sides", sides)?;
        list.append(out)?;
    }
    Ok(list)
}

/// One side: `direction`, `frequency_hz` `[S]` (Hz), `stable` `[S]` (1
/// stable, 0 unstable, −1 not checked, as `results.h5`), `sector_amplitude`
/// `[S, sector]` (m), `stop_json` and `stop_reason`.
fn side_dict<'py>(
    py: Python<'py>,
    side: &BifurcatedSide,
    sectors: usize,
) -> PyResult<Bound<'py, PyDict>> {
    let out = PyDict::new(py);
    out.set_item("direction", side.direction)?;
    out.set_item("frequency_hz", PyArray1::from_slice(py, &side.frequency_hz))?;
    let stable: Vec<i8> = side.stable.iter().map(|s| s.map_or(-1, i8::from)).collect();
    out.set_item("stable", PyArray1::from_vec(py, stable))?;
    // A side without points is still `[0, sector]`.
    let mut amplitude = matrix(&side.sector_amplitudes_m);
    if side.sector_amplitudes_m.is_empty() {
        amplitude = numpy::ndarray::Array2::zeros((0, sectors));
    }
    out.set_item("sector_amplitude", amplitude.into_pyarray(py))?;
    out.set_item("stop_json", json(&side.stop))?;
    out.set_item("stop_reason", side.stop_reason.as_str())?;
    Ok(out)
}
