//! `cyclorub._native.Result`: a solved (or loaded) branch with numpy
//! arrays of everything the results files hold. Arrays over points and
//! sectors are `[point, sector, ...]`, indexed from 0 like numpy; the dof
//! and sector *arguments* of methods are numbered from 1, like case files.
//!
//! Only the branch itself is computed by the solve; the per-point
//! recovery (amplitudes on every sector, contact state, cyclic components)
//! runs on first access to an array and is kept, and the linear response
//! and time histories only when asked for (or saved). A loaded result is
//! read by the library's reader of a results folder (see [`crate::loaded`]).

use crate::arrays::{json, matrix, Curve, Modes};
use crate::case_type::Case;
use crate::errors::{Error, Result};
use crate::loaded::LoadedFolder;
use crate::save;
use cyclorub::case::Case as LibraryCase;
use cyclorub::continuation::StopReason;
use cyclorub::forced_response::Solution;
use cyclorub::hbm::HarmonicBalance;
use cyclorub::results::data::{PointResults, ResultsData};
use cyclorub::results::recovery::{dof_histories, BranchRecovery};
use cyclorub::results::stability::StabilityData;
use cyclorub::results::ResultsError;
use numpy::ndarray::{Array1, Array2, Array3, Array4};
use numpy::{IntoPyArray, PyArray1, PyArray2, PyArray3, PyArray4};
use pyo3::prelude::*;
use pyo3::types::PyDict;
use std::path::PathBuf;
use std::sync::OnceLock;

mod access;
mod branches;

/// Where a result comes from.
enum Source {
    /// Solved in this process.
    Solved(Box<Solution>),
    /// Read from a results folder.
    Loaded(Box<LoadedFolder>),
}

/// A branch and what was solved to get it.
#[pyclass(name = "Result", module = "cyclorub._native", frozen)]
pub struct RunResult {
    source: Source,
    /// The case, resolved (frequency range filled in, basis set).
    case: LibraryCase,
    /// The folder the case's relative paths start from.
    case_dir: PathBuf,
    /// Whether Ctrl-C cut the solve short.
    interrupted: bool,
    /// Every point's results on every sector (computed on first use).
    points: OnceLock<Vec<PointResults>>,
    /// Everything `results.h5` holds (computed on first use, or read).
    data: OnceLock<ResultsData>,
    /// The residual of a loaded result and the dofs of a sector, rebuilt
    /// on first use.
    problem: OnceLock<(HarmonicBalance, usize)>,
    /// A mistuned wheel's record as JSON text (`None`: tuned), computed on
    /// first use for a solved result (it solves the tuned reference branch).
    mistuning: OnceLock<Option<String>>,
}

#[pymethods]
impl RunResult {
    /// Whether Ctrl-C cut the solve short (the points found are kept).
    #[getter]
    fn interrupted(&self) -> bool {
        self.interrupted
    }

    /// The case, resolved (frequency range filled in, basis set).
    #[getter]
    fn case(&self) -> Case {
        Case {
            inner: self.case.clone(),
            case_dir: self.case_dir.clone(),
        }
    }

    /// Number of points.
    fn __len__(&self) -> PyResult<usize> {
        Ok(match &self.source {
            Source::Solved(solution) => solution.branch.points.len(),
            Source::Loaded(_) => self.points()?.len(),
        })
    }

    /// Frequency of every point, Hz `[point]`.
    #[getter]
    fn frequency_hz<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyArray1<f64>>> {
        Ok(PyArray1::from_vec(py, self.frequencies()?))
    }

    /// The unknowns of every point `[point, unknown]` (the basis's layout).
    #[getter]
    fn unknowns<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyArray2<f64>>> {
        let rows: Vec<Vec<f64>> = match &self.source {
            Source::Solved(solution) => solution
                .branch
                .points
                .iter()
                .map(|p| p.unknowns.clone())
                .collect(),
            Source::Loaded(_) => self.points()?.iter().map(|p| p.unknowns.clone()).collect(),
        };
        Ok(matrix(&rows).into_pyarray(py))
    }

    /// Largest displacement of the observed dof toward the casing over the
    /// period, m `[point, sector]` (`branch.csv`'s amplitude).
    #[getter]
    fn amplitude<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyArray2<f64>>> {
        self.per_sector(py, |p| &p.amplitude)
    }

    /// Largest |displacement| of the observed dof, m `[point, sector]`.
    #[getter]
    fn max_abs<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyArray2<f64>>> {
        self.per_sector(py, |p| &p.max_abs)
    }

    /// Largest |velocity| of the observed dof, m/s `[point, sector]`.
    #[getter]
    fn velocity_max_abs<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyArray2<f64>>> {
        self.per_sector(py, |p| &p.velocity_max_abs)
    }

    /// The observed dof's harmonic coordinates `[a0, Re X1, Im X1, …]`, m
    /// `[point, sector, 2 N_h + 1]`: `u(t) = a0 + Σ 2 (Re X_k cos kωt − Im X_k sin kωt)`.
    #[getter]
    fn observed<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyArray3<f64>>> {
        let points = self.points()?;
        let size = 2 * self.case.harmonic_balance.harmonics + 1;
        let array = Array3::from_shape_fn((points.len(), self.sectors(), size), |(p, j, i)| {
            points[p]
                .observed
                .get(j)
                .and_then(|c| c.get(i))
                .copied()
                .unwrap_or(f64::NAN)
        });
        Ok(array.into_pyarray(py))
    }

    /// Newton iterations of every point `[point]`.
    #[getter]
    fn iterations(&self, py: Python<'_>) -> PyResult<Py<PyArray1<usize>>> {
        self.per_point(py, |p| p.iterations)
    }

    /// `‖R‖ / f_ex` of every point `[point]`.
    #[getter]
    fn residual_norm(&self, py: Python<'_>) -> PyResult<Py<PyArray1<f64>>> {
        self.per_point(py, |p| p.residual_norm)
    }

    /// Whether Newton converged at every point `[point]`.
    #[getter]
    fn converged(&self, py: Python<'_>) -> PyResult<Py<PyArray1<bool>>> {
        self.per_point(py, |p| p.converged)
    }

    /// Number of sectors in contact at some instant, per point `[point]`.
    #[getter]
    fn sectors_in_contact(&self, py: Python<'_>) -> PyResult<Py<PyArray1<usize>>> {
        self.per_point(py, |p| p.sectors_in_contact)
    }

    /// Fraction of the period in contact `[point, sector, contact dof]`.
    #[getter]
    fn contact_fraction<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyArray3<f64>>> {
        self.per_contact(py, |p| &p.contact_fraction)
    }

    /// Largest contact force over the period, N `[point, sector, contact dof]`.
    #[getter]
    fn peak_force<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyArray3<f64>>> {
        self.per_contact(py, |p| &p.peak_force)
    }

    /// Largest penetration `x − g0`, m `[point, sector, contact dof]`.
    #[getter]
    fn max_penetration<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyArray3<f64>>> {
        self.per_contact(py, |p| &p.max_penetration)
    }

    /// Harmonic coordinates of the contact force, N
    /// `[point, sector, contact dof, 2 N_h + 1]` (the force on the blade is
    /// `−f`, `f ≥ 0`).
    #[getter]
    fn contact_force<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyArray4<f64>>> {
        let points = self.points()?;
        let (sectors, contact) = (self.sectors(), self.case.contact.dofs.len().max(1));
        let size = 2 * self.case.harmonic_balance.harmonics + 1;
        let array =
            Array4::from_shape_fn((points.len(), sectors, contact, size), |(p, j, c, i)| {
                points[p]
                    .contact_force
                    .get(j * contact + c)
                    .and_then(|v| v.get(i))
                    .copied()
                    .unwrap_or(f64::NAN)
            });
        Ok(array.into_pyarray(py))
    }

    /// Forward cyclic components of the observed dof, m
    /// `[point, harmonic 0..=N_h, nodal diameter 0..=N/2]`.
    #[getter]
    fn forward<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyArray3<f64>>> {
        self.components(py, true)
    }

    /// Backward cyclic components, same layout as `forward`.
    #[getter]
    fn backward<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyArray3<f64>>> {
        self.components(py, false)
    }

    /// The stability of every point, when checked: a dict of `stable`
    /// `[point]`, `unstable_exponents` `[point]`, `classes` (their nodal
    /// diameters), `leading_re` / `leading_im` `[point, class, 4]` (1/s,
    /// rad/s), `harmonics`, `markers_json`; `None` when not checked.
    #[getter]
    fn stability<'py>(&self, py: Python<'py>) -> PyResult<Option<Bound<'py, PyDict>>> {
        let Some(data) = self.stability_data()? else {
            return Ok(None);
        };
        let out = PyDict::new(py);
        out.set_item("harmonics", data.harmonics)?;
        out.set_item("classes", PyArray1::from_slice(py, &data.classes))?;
        out.set_item("stable", PyArray1::from_slice(py, &data.stable))?;
        out.set_item(
            "unstable_exponents",
            PyArray1::from_slice(py, &data.unstable_exponents),
        )?;
        let cube = |values: &Vec<Vec<Vec<f64>>>| {
            let classes = values.first().map_or(0, Vec::len);
            let leading = values.first().and_then(|p| p.first()).map_or(0, Vec::len);
            Array3::from_shape_fn((values.len(), classes, leading), |(p, c, i)| {
                values[p]
                    .get(c)
                    .and_then(|v| v.get(i))
                    .copied()
                    .unwrap_or(f64::NAN)
            })
        };
        out.set_item("leading_re", cube(&data.leading_re).into_pyarray(py))?;
        out.set_item("leading_im", cube(&data.leading_im).into_pyarray(py))?;
        out.set_item(
            "off_contact_bound",
            PyArray1::from_slice(py, &data.off_contact_bound),
        )?;
        out.set_item("markers_json", json(&data.markers))?;
        Ok(Some(out))
    }

    /// Why the branch stopped, in words naming the key that governs it.
    #[getter]
    fn stop(&self) -> String {
        match &self.source {
            Source::Solved(solution) => solution.branch.stop.with_advice(),
            // `run.json` holds the stop as data: read back, it says the
            // same words as a solved result.
            Source::Loaded(folder) => folder.record.stop.as_ref().map_or_else(
                || "no stop recorded: the run was still going, or was killed".into(),
                StopReason::with_advice,
            ),
        }
    }

    /// Why the branch stopped, as `run.json` records it (JSON text).
    #[getter]
    fn stop_json(&self) -> String {
        match &self.source {
            Source::Solved(solution) => json(&solution.branch.stop),
            Source::Loaded(folder) => json(&folder.record.stop),
        }
    }

    /// The events along the branch (folds, branch points, kinks, the stop),
    /// as `run.json` records them (JSON text).
    #[getter]
    fn events_json(&self) -> String {
        match &self.source {
            Source::Solved(solution) => json(&solution.branch.events),
            Source::Loaded(folder) => json(&folder.record.events),
        }
    }

    /// The basis solved on (kind, unknowns, sampled sectors, pairs per
    /// harmonic), as `run.json` records it (JSON text).
    #[getter]
    fn basis_json(&self) -> String {
        match &self.source {
            Source::Solved(solution) => json(&solution.basis),
            Source::Loaded(folder) => json(&folder.record.basis),
        }
    }

    /// A mistuned wheel's record, as `run.json`'s `mistuning` holds it
    /// (JSON text: `deviations`, `sector_peaks_m`,
    /// `sector_peak_frequencies_hz`, `most_responding_sector`,
    /// `tuned_peak_m`, `tuned_reference`, `amplification_factor`); `None`
    /// for a tuned wheel. For a solved result the first call solves the
    /// tuned reference branch (the GIL released).
    #[getter]
    fn mistuning_json(&self, py: Python<'_>) -> PyResult<Option<String>> {
        Ok(py.detach(|| self.mistuning_text())?)
    }

    /// The bifurcated branches recorded in a loaded results folder
    /// (`cyclorub branches`), in the order of `branches.json`: per branch
    /// point a dict of `class`, `marker`, `marker_hz`, `parent_point`,
    /// `branch_point_hz`, `basis_unknowns`, `full_unknowns`, `file`,
    /// `not_switched` and `sides` (+v then −v), each a dict of
    /// `direction`, `frequency_hz` `[S]` (Hz), `stable` `[S]` (1, 0, −1:
    /// not checked), `sector_amplitude` `[S, sector]` (m), `stop_json`
    /// and `stop_reason`. Empty for a result solved here (branch
    /// switching is `cyclorub branches`).
    #[getter]
    fn branches<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, pyo3::types::PyList>> {
        match &self.source {
            Source::Solved(_) => Ok(pyo3::types::PyList::empty(py)),
            Source::Loaded(_) => branches::branch_list(py, &self.data()?.branches, self.sectors()),
        }
    }

    /// Set-up, solve and stability times, s (`{}` keys `setup_s`,
    /// `solve_s`, `stability_s`).
    #[getter]
    fn timings<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        let out = PyDict::new(py);
        match &self.source {
            Source::Solved(s) => {
                out.set_item("setup_s", s.setup_s)?;
                out.set_item("solve_s", s.solve_s)?;
                out.set_item("stability_s", s.stability_s)?;
            }
            Source::Loaded(folder) => {
                let record = &folder.record;
                let t = record.timings.as_ref();
                out.set_item("setup_s", t.map(|t| t.setup_s))?;
                out.set_item("solve_s", t.map(|t| t.solve_s))?;
                out.set_item("stability_s", record.stability.as_ref().map(|s| s.time_s))?;
            }
        }
        Ok(out)
    }

    /// The folder a loaded result was read from (`None` when solved here).
    #[getter]
    fn directory(&self) -> Option<PathBuf> {
        match &self.source {
            Source::Solved(_) => None,
            Source::Loaded(folder) => Some(folder.directory.clone()),
        }
    }

    /// The linear response (no contact) of the observed dof over the
    /// branch's range: `(frequency_hz [f], amplitude [f, sector])`.
    fn linear_response<'py>(&self, py: Python<'py>) -> PyResult<Curve<'py>> {
        let data = py.detach(|| self.data())?;
        Ok((
            PyArray1::from_slice(py, &data.linear.frequency_hz),
            matrix(&data.linear.amplitude).into_pyarray(py),
        ))
    }

    /// Natural frequencies per nodal diameter: `(diameters, [d, mode])`, Hz.
    fn natural_frequencies<'py>(&self, py: Python<'py>) -> PyResult<Modes<'py>> {
        let frequencies = match &self.source {
            Source::Solved(s) => s.model.natural_frequencies().map_err(Error::from)?,
            Source::Loaded(_) => self.data()?.natural_frequencies.clone(),
        };
        Ok(crate::arrays::modes_arrays(py, &frequencies))
    }

    /// The motion of sector dof `dof` on sector `sector` (both numbered
    /// from 1) at every point, recovered from the unknowns of any basis:
    /// a dict of `coordinates` `[point, 2 N_h + 1]` (m), `displacement`
    /// and `velocity` `[point, time_samples]` (m, m/s) at the instants
    /// `2π n / (time_samples ω)`, and `peak` `[point]`.
    #[pyo3(signature = (dof, sector = 1, time_samples = None))]
    fn recover<'py>(
        &self,
        py: Python<'py>,
        dof: usize,
        sector: usize,
        time_samples: Option<usize>,
    ) -> PyResult<Bound<'py, PyDict>> {
        let j = self.check_sector(sector)?;
        let harmonics = self.case.harmonic_balance.harmonics;
        let samples = time_samples.unwrap_or(self.case.harmonic_balance.time_samples);
        let frequencies = self.frequencies()?;
        let unknowns: Vec<Vec<f64>> = match &self.source {
            Source::Solved(s) => s.branch.points.iter().map(|p| p.unknowns.clone()).collect(),
            Source::Loaded(_) => self.points()?.iter().map(|p| p.unknowns.clone()).collect(),
        };
        let (problem, dofs) = py.detach(|| self.problem())?;
        if dof == 0 || dof > dofs {
            return Err(Error::usage(
                Some("dof"),
                format!("dof {dof} does not exist: a sector has dofs 1..={dofs} (numbered from 1, like case files)"),
            )
            .into());
        }
        let histories = py.detach(|| {
            frequencies
                .iter()
                .zip(&unknowns)
                .map(|(f, x)| {
                    let omega = 2.0 * std::f64::consts::PI * f;
                    dof_histories(problem, x, omega, dof - 1, &[j], samples)
                        .map(|mut h| h.remove(0))
                })
                .collect::<std::result::Result<Vec<_>, ResultsError>>()
        });
        let histories = histories.map_err(Error::from)?;
        let size = 2 * harmonics + 1;
        let n = histories.len();
        let out = PyDict::new(py);
        let field = |get: fn(&cyclorub::results::recovery::DofHistory) -> &Vec<f64>, cols| {
            Array2::from_shape_fn((n, cols), |(p, i)| {
                get(&histories[p]).get(i).copied().unwrap_or(f64::NAN)
            })
        };
        out.set_item(
            "coordinates",
            field(|h| &h.coordinates, size).into_pyarray(py),
        )?;
        out.set_item(
            "displacement",
            field(|h| &h.displacement, samples).into_pyarray(py),
        )?;
        out.set_item("velocity", field(|h| &h.velocity, samples).into_pyarray(py))?;
        let peaks: Array1<f64> = histories.iter().map(|h| h.peak()).collect();
        out.set_item("peak", peaks.into_pyarray(py))?;
        Ok(out)
    }

    /// Writes the results folder `cyclorub run` writes (`branch.csv`,
    /// `results.h5`, `plots/`, `run.json`; `observed_harmonics.csv` when the case asks) into
    /// `directory`, the GIL released. A folder that holds another run is
    /// refused unless `overwrite` (then that run's files are removed first).
    #[pyo3(signature = (directory, overwrite = false))]
    fn save(&self, py: Python<'_>, directory: PathBuf, overwrite: bool) -> PyResult<()> {
        match &self.source {
            Source::Solved(solution) => {
                py.detach(|| save::write_folder(solution, &directory, overwrite))?;
                Ok(())
            }
            Source::Loaded(folder) => Err(Error::usage(
                None,
                format!(
                    "a loaded result is saved already in {}: copy that folder",
                    folder.directory.display()
                ),
            )
            .into()),
        }
    }
}

/// Reads a results folder written by `cyclorub run` or `Result.save`
/// (`run.json`, `branch.csv`, `results.h5`) through the library's reader;
/// `case_dir` is the folder the case's relative paths start from (for
/// `recover`, which rebuilds the problem).
#[pyfunction]
#[pyo3(signature = (directory, case_dir = None))]
pub fn load(py: Python<'_>, directory: PathBuf, case_dir: Option<PathBuf>) -> PyResult<RunResult> {
    let (folder, data) = py.detach(|| crate::loaded::read(&directory))?;
    let interrupted = matches!(folder.record.stop, Some(StopReason::Interrupted { .. }));
    // The points are taken from `data` on first use, with the contact
    // forces' harmonics recovered when results.h5 did not keep them.
    let stored = OnceLock::new();
    let _ = stored.set(data);
    Ok(RunResult {
        case: folder.record.case.clone(),
        source: Source::Loaded(Box::new(folder)),
        case_dir: case_dir.unwrap_or_else(|| PathBuf::from(".")),
        interrupted,
        points: OnceLock::new(),
        data: stored,
        problem: OnceLock::new(),
        mistuning: OnceLock::new(),
    })
}
