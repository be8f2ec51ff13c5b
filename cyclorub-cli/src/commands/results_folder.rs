//! Reading a results folder back for the commands that work on one of its
//! points (`stability`, `recover`): the case and basis of `run.json`, the
//! points of `results.h5`, the point asked for, the problem rebuilt.

use super::CliError;
use cyclorub::case::{BasisChoice, Case};
use cyclorub::forced_response::{prepare, Prepared};
use cyclorub::results::data::{PointResults, ResultsData};
use cyclorub::results::folder::read_run_case;
use cyclorub::results::hdf5;
use std::path::Path;

/// A point of a results folder, with the run's problem rebuilt.
pub(super) struct OpenedPoint {
    /// The run's case, model and problem, rebuilt from `run.json`.
    pub prepared: Prepared,
    /// The basis the branch was solved on.
    pub basis: BasisChoice,
    /// The points of `results.h5`.
    pub data: ResultsData,
    /// The point's index along the branch.
    pub index: usize,
    /// How it was chosen.
    pub choice: Choice,
}

/// Opens the point of `folder` that `point` or `at_hz` asks for (default:
/// the largest amplitude) and rebuilds the run's problem, its matrix files
/// found from `case_dir`; refuses a bad frequency, folder or matrix file,
/// and warns of a point that did not converge.
pub(super) fn open_point(
    folder: &Path,
    point: Option<usize>,
    at_hz: Option<f64>,
    case_dir: &Path,
) -> Result<OpenedPoint, CliError> {
    if let Some(f) = at_hz {
        if !(f.is_finite() && f > 0.0) {
            return Err(CliError::usage(format!(
                "--at-hz {f}: give a finite frequency > 0 Hz"
            )));
        }
    }
    if !folder.is_dir() {
        return Err(CliError::usage(format!(
            "{}: no such folder; give a results folder written by `cyclorub run`",
            folder.display()
        )));
    }
    let (case, basis) = read_run_case(folder).map_err(|e| CliError::usage(e.to_string()))?;
    let data = read_results(folder)?;
    let (index, choice) = choose_point(&data, point, at_hz)?;
    let point = &data.points[index];
    if !point.converged {
        tracing::warn!(
            "point {index} did not converge (residual {:.2e}): it describes no periodic solution",
            point.residual_norm
        );
    }
    find_matrix_files(&case, case_dir, folder)?;
    let prepared = prepare(&case, case_dir, basis)?;
    same_unknowns(folder, point, &prepared, basis, case_dir)?;
    Ok(OpenedPoint {
        prepared,
        basis,
        data,
        index,
        choice,
    })
}

/// How the point was chosen, for the first line of the table.
pub(super) enum Choice {
    /// `--point`.
    Given,
    /// The nearest to `--at-hz` (asked, Hz), and how far it is from it, Hz.
    Nearest(f64, f64),
    /// The largest amplitude of the branch.
    Peak,
}

impl Choice {
    /// What to add after the point's description.
    pub(super) fn text(&self) -> String {
        match self {
            Choice::Given => String::new(),
            Choice::Nearest(f, 0.0) => format!(" (at --at-hz {f})"),
            Choice::Nearest(f, away) => {
                format!(" (the nearest to --at-hz {f}, {away:.4e} Hz away)")
            }
            Choice::Peak => " (the largest amplitude of the branch)".into(),
        }
    }
}

/// Refuses a case whose matrix files are not found from `case_dir`,
/// naming the key, the file and `--case-dir`.
fn find_matrix_files(case: &Case, case_dir: &Path, folder: &Path) -> Result<(), CliError> {
    let model = &case.model;
    let files = [
        ("model.mass_file", &model.mass_file),
        ("model.stiffness_file", &model.stiffness_file),
        ("model.damping.file", &model.damping.file),
    ];
    for (key, file) in files {
        if let Some(file) = file {
            let path = case_dir.join(file);
            if !path.is_file() {
                return Err(CliError::usage(format!(
                    "{key} = {:?} of {}'s case: no file {}; give --case-dir, the folder of the case file the run was made from",
                    file.display().to_string(),
                    folder.join("run.json").display(),
                    path.display()
                )));
            }
        }
    }
    Ok(())
}

/// The points of `results.h5`.
fn read_results(folder: &Path) -> Result<ResultsData, CliError> {
    let path = folder.join(hdf5::FILE_NAME);
    if !path.is_file() {
        return Err(CliError::usage(format!(
            "{} has no {}: the points' unknowns are read from it \
             (a run by a cyclorub without results.h5 support writes none; run the case again)",
            folder.display(),
            hdf5::FILE_NAME
        )));
    }
    let data = hdf5::read(&path)?;
    if data.points.is_empty() {
        return Err(CliError::usage(format!(
            "{} holds no point",
            path.display()
        )));
    }
    Ok(data)
}

/// The point asked for by `--point` or `--at-hz`, or the peak.
pub(super) fn choose_point(
    data: &ResultsData,
    point: Option<usize>,
    at_hz: Option<f64>,
) -> Result<(usize, Choice), CliError> {
    let count = data.points.len();
    match (point, at_hz) {
        (Some(p), _) if p < count => Ok((p, Choice::Given)),
        (Some(p), _) => Err(CliError::usage(format!(
            "--point {p}: the branch has {count} points, give 0 to {}",
            count - 1
        ))),
        (None, Some(f)) => {
            // A frequency beyond the branch's would silently take its end
            // point: refused with the range instead.
            let (low, high) = data
                .points
                .iter()
                .map(|p| p.frequency_hz)
                .filter(|g| g.is_finite())
                .fold((f64::INFINITY, f64::NEG_INFINITY), |(l, h), g| {
                    (l.min(g), h.max(g))
                });
            if low > high {
                return Err(CliError::usage(format!(
                    "--at-hz {f}: the branch has no point of finite frequency"
                )));
            }
            let slack = 1e-9 * high.abs();
            if f < low - slack || f > high + slack {
                return Err(CliError::usage(format!(
                    "--at-hz {f}: beyond the branch, which spans {low:.6} to {high:.6} Hz ({count} points); give a frequency within it, or --point P (0 to {})",
                    count - 1
                )));
            }
            let p = data
                .nearest_point(f)
                .ok_or_else(|| CliError::usage(format!("--at-hz {f}: the branch has no point")))?;
            let away = (data.points[p].frequency_hz - f).abs();
            Ok((p, Choice::Nearest(f, away)))
        }
        (None, None) => data.peak_point().map(|p| (p, Choice::Peak)).ok_or_else(|| {
            CliError::usage(
                "no converged point of finite amplitude to take by default: give --point P",
            )
        }),
    }
}

/// Refuses a point whose unknowns do not fit the problem rebuilt from the
/// case (matrix files that differ from the run's).
fn same_unknowns(
    folder: &Path,
    point: &PointResults,
    prepared: &Prepared,
    basis: BasisChoice,
    case_dir: &Path,
) -> Result<(), CliError> {
    let unknowns = prepared.problem.layout().unknowns;
    if point.unknowns.len() != unknowns {
        return Err(CliError::usage(format!(
            "{} holds {} unknowns per point, the case of run.json rebuilt on the {} basis has {unknowns}: \
             the case's matrix files differ from those of the run (--case-dir {})",
            folder.join(hdf5::FILE_NAME).display(),
            point.unknowns.len(),
            basis.name(),
            case_dir.display()
        )));
    }
    Ok(())
}
