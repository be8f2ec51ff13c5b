//! Reading a results folder back: `branch.csv`, `run.json` (typed:
//! [`RunFile`]) and the observed coordinates (`observed_harmonics.csv` or
//! `results.h5`), as `run` writes them; with [`ResultsFolder::read_with_results_file`],
//! everything `results.h5` holds. The one reader of a results folder
//! (issue 41 item 4).

mod run_entry;
pub mod run_file;

pub use run_entry::record_branches_in_run_file;
pub use run_file::{MistuningSummary, RunFile, RunTimings, StabilityTime};

use super::data::ResultsData;
use super::ResultsError;
use crate::case::{BasisChoice, Case};
use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

/// One row of `branch.csv`.
#[derive(Clone, Debug, PartialEq)]
pub struct BranchRecord {
    /// Point index.
    pub point: usize,
    /// Frequency, Hz.
    pub frequency_hz: f64,
    /// Amplitude per reported sector, m.
    pub amplitudes: Vec<f64>,
    /// Newton iterations.
    pub iterations: usize,
    /// Residual norm.
    pub residual_norm: f64,
    /// Whether Newton converged.
    pub converged: bool,
    /// `stable` and `unstable_exponents`, when the stability check ran.
    pub stability: Option<(bool, usize)>,
}

/// `branch.csv`.
#[derive(Clone, Debug, PartialEq)]
pub struct BranchTable {
    /// The reported sectors (1-based), in column order.
    pub sectors: Vec<usize>,
    /// The rows.
    pub rows: Vec<BranchRecord>,
}

/// A results folder as written by `run`.
#[derive(Clone, Debug)]
pub struct ResultsFolder {
    /// The folder.
    pub path: PathBuf,
    /// `branch.csv`.
    pub branch: BranchTable,
    /// The observed dof's coordinates per `(point, sector)` (sector
    /// 1-based): `observed_harmonics.csv`, or `results.h5` without it.
    pub harmonics: BTreeMap<(usize, usize), Vec<f64>>,
    /// `run.json`, as written (for what [`Self::record`] does not type).
    pub run: serde_json::Value,
    /// `run.json`, typed.
    pub record: RunFile,
    /// Everything `results.h5` holds, when read by
    /// [`Self::read_with_results_file`] (`None` from [`Self::read`]).
    pub data: Option<ResultsData>,
}

fn read_text(path: &Path) -> Result<String, ResultsError> {
    std::fs::read_to_string(path).map_err(|e| ResultsError::Read {
        path: path.to_path_buf(),
        message: e.to_string(),
    })
}

/// The text up to its last line break: a run killed while writing a line
/// leaves it unfinished, and every line before it is whole.
fn complete_lines(mut text: String) -> String {
    match text.rfind('\n') {
        Some(end) => text.truncate(end + 1),
        None => text.clear(),
    }
    text
}

fn bad(path: &Path, line: usize, message: impl std::fmt::Display) -> ResultsError {
    ResultsError::Read {
        path: path.to_path_buf(),
        message: format!("line {line}: {message}"),
    }
}

fn number<T: std::str::FromStr>(
    path: &Path,
    line: usize,
    column: &str,
    text: &str,
) -> Result<T, ResultsError> {
    text.trim()
        .parse()
        .map_err(|_| bad(path, line, format!("{column} = {text:?} is not a number")))
}

/// The text of a finished file: refused, naming its last line, when that
/// line is unfinished (no line break at the end: a truncated file, as a run
/// that wrote it to the end always ends its last line).
fn finished_lines(path: &Path, text: String) -> Result<String, ResultsError> {
    if text.is_empty() || text.ends_with('\n') {
        return Ok(text);
    }
    let line = text.lines().count();
    let last = text.lines().last().unwrap_or("");
    let shown: String = last
        .chars()
        .rev()
        .take(24)
        .collect::<Vec<_>>()
        .into_iter()
        .rev()
        .collect();
    Err(bad(
        path,
        line,
        format!(
            "the line is unfinished (it ends with `{shown}` and no line break): the file is \
             truncated; its run finished, so every line it wrote is whole (run again, or copy \
             the folder again)"
        ),
    ))
}

impl BranchTable {
    /// Reads `branch.csv`, without its last line if unfinished (a run
    /// killed while writing it; [`ResultsFolder::read`] refuses it when
    /// the run finished).
    pub fn read(path: &Path) -> Result<Self, ResultsError> {
        Self::parse(path, &complete_lines(read_text(path)?))
    }

    fn parse(path: &Path, text: &str) -> Result<Self, ResultsError> {
        let mut lines = text.lines();
        let mut header: Vec<&str> = lines
            .next()
            .ok_or_else(|| bad(path, 1, "the file is empty"))?
            .split(',')
            .collect();
        let with_stability = header.ends_with(&["stable", "unstable_exponents"]);
        if with_stability {
            header.truncate(header.len() - 2);
        }
        let expected_tail = ["iterations", "residual_norm", "converged"];
        if header.len() < 5
            || header[0] != "point"
            || header[1] != "frequency_hz"
            || header[header.len() - 3..] != expected_tail
        {
            return Err(bad(
                path,
                1,
                "the header is not point,frequency_hz,amplitude_sector_<j>...,iterations,residual_norm,converged",
            ));
        }
        let sectors = header[2..header.len() - 3]
            .iter()
            .map(|h| {
                h.strip_prefix("amplitude_sector_")
                    .and_then(|s| s.parse().ok())
                    .ok_or_else(|| bad(path, 1, format!("unexpected column {h:?}")))
            })
            .collect::<Result<Vec<usize>, _>>()?;
        let mut rows = Vec::new();
        for (index, line) in lines.enumerate() {
            let line_number = index + 2;
            if line.trim().is_empty() {
                continue;
            }
            let mut fields: Vec<&str> = line.split(',').collect();
            let expected = header.len() + if with_stability { 2 } else { 0 };
            if fields.len() != expected {
                return Err(bad(
                    path,
                    line_number,
                    format!("{} fields, the header has {expected}", fields.len()),
                ));
            }
            let stability = if with_stability {
                let unstable = fields[fields.len() - 1].trim();
                let stable = fields[fields.len() - 2].trim();
                let parsed = match (stable, unstable) {
                    ("", "") => None,
                    ("0" | "1", _) => Some((
                        stable == "1",
                        number(path, line_number, "unstable_exponents", unstable)?,
                    )),
                    _ => {
                        return Err(bad(
                            path,
                            line_number,
                            format!("stable = {stable:?} is not 0 or 1"),
                        ))
                    }
                };
                fields.truncate(fields.len() - 2);
                parsed
            } else {
                None
            };
            let k = fields.len();
            rows.push(BranchRecord {
                point: number(path, line_number, "point", fields[0])?,
                frequency_hz: number(path, line_number, "frequency_hz", fields[1])?,
                amplitudes: fields[2..k - 3]
                    .iter()
                    .map(|f| number(path, line_number, "amplitude", f))
                    .collect::<Result<_, _>>()?,
                iterations: number(path, line_number, "iterations", fields[k - 3])?,
                residual_norm: number(path, line_number, "residual_norm", fields[k - 2])?,
                converged: match fields[k - 1].trim() {
                    "true" => true,
                    "false" => false,
                    other => {
                        return Err(bad(
                            path,
                            line_number,
                            format!("converged = {other:?} is not true or false"),
                        ))
                    }
                },
                stability,
            });
        }
        Ok(Self { sectors, rows })
    }

    /// The column of sector `sector` (1-based), if reported.
    pub fn column(&self, sector: usize) -> Option<usize> {
        self.sectors.iter().position(|&s| s == sector)
    }
}

/// Reads `observed_harmonics.csv`: coordinates per `(point, sector)`.
pub fn read_harmonics(path: &Path) -> Result<BTreeMap<(usize, usize), Vec<f64>>, ResultsError> {
    parse_harmonics(path, &complete_lines(read_text(path)?))
}

fn parse_harmonics(
    path: &Path,
    text: &str,
) -> Result<BTreeMap<(usize, usize), Vec<f64>>, ResultsError> {
    let mut lines = text.lines();
    let header: Vec<&str> = lines
        .next()
        .ok_or_else(|| bad(path, 1, "the file is empty"))?
        .split(',')
        .collect();
    if header.len() < 4
        || header[..4] != ["point", "frequency_hz", "sector", "a0"]
        || !header.len().is_multiple_of(2)
    {
        return Err(bad(
            path,
            1,
            "the header is not point,frequency_hz,sector,a0,re_1,im_1,...",
        ));
    }
    let mut out = BTreeMap::new();
    for (index, line) in lines.enumerate() {
        let line_number = index + 2;
        if line.trim().is_empty() {
            continue;
        }
        let fields: Vec<&str> = line.split(',').collect();
        if fields.len() != header.len() {
            return Err(bad(
                path,
                line_number,
                format!("{} fields, the header has {}", fields.len(), header.len()),
            ));
        }
        let point = number(path, line_number, "point", fields[0])?;
        let sector = number(path, line_number, "sector", fields[2])?;
        let coordinates = fields[3..]
            .iter()
            .map(|f| number(path, line_number, "coordinate", f))
            .collect::<Result<Vec<f64>, _>>()?;
        out.insert((point, sector), coordinates);
    }
    Ok(out)
}

/// The observed dof's coordinates per `(point, sector)` of the reported
/// `sectors` from `results.h5`, for a folder without
/// `observed_harmonics.csv` (empty without the file or the feature).
fn harmonics_from_results_file(
    folder: &Path,
    sectors: &[usize],
) -> Result<BTreeMap<(usize, usize), Vec<f64>>, ResultsError> {
    #[cfg(feature = "hdf5")]
    {
        let path = folder.join(super::hdf5::FILE_NAME);
        if path.exists() {
            return Ok(harmonics_from_data(&super::hdf5::read(&path)?, sectors));
        }
    }
    let _ = (folder, sectors);
    Ok(BTreeMap::new())
}

/// The observed dof's coordinates per `(point, sector)` of the reported
/// `sectors` from the content of `results.h5`.
fn harmonics_from_data(
    data: &ResultsData,
    sectors: &[usize],
) -> BTreeMap<(usize, usize), Vec<f64>> {
    let mut out = BTreeMap::new();
    for (point, results) in data.points.iter().enumerate() {
        for &sector in sectors {
            if let Some(c) = results.observed.get(sector.wrapping_sub(1)) {
                out.insert((point, sector), c.clone());
            }
        }
    }
    out
}

/// The case of a results folder's `run.json` (as resolved by its run) and
/// the basis its branch was solved on: what a command needs to rebuild
/// the run's problem.
pub fn read_run_case(folder: &Path) -> Result<(Case, BasisChoice), ResultsError> {
    let path = folder.join("run.json");
    if !path.is_file() {
        return Err(ResultsError::Input(format!(
            "{} has no run.json: give a results folder written by `cyclorub run`",
            folder.display()
        )));
    }
    let record = RunFile::parse(&path, &read_text(&path)?)?;
    same_sectors(folder, &record.case, None)?;
    let basis = record.basis_choice(&path)?;
    Ok((record.case, basis))
}

/// Refuses a `run.json` whose `case.model.sectors` is not the number of
/// sectors `results.h5` holds (`data`, when read; else the file's own
/// attribute, when the folder has one): a `run.json` edited by hand or
/// copied from another run would rebuild another wheel than the one solved.
fn same_sectors(
    folder: &Path,
    case: &Case,
    data: Option<&ResultsData>,
) -> Result<(), ResultsError> {
    #[cfg(feature = "hdf5")]
    {
        let file = folder.join(super::hdf5::FILE_NAME);
        let stored = match data {
            Some(data) => Some(data.sectors),
            None if file.is_file() => super::hdf5::sectors(&file)?,
            None => None,
        };
        if let Some(stored) = stored.filter(|&n| n != case.model.sectors) {
            return Err(ResultsError::Input(format!(
                "{} says case.model.sectors = {}, but {} holds {stored} sectors: the two files \
                 are not of one run (run.json edited by hand, or copied from another run); \
                 restore run.json, or run the case again",
                folder.join("run.json").display(),
                case.model.sectors,
                file.display()
            )));
        }
    }
    let _ = (folder, case, data);
    Ok(())
}

/// Refuses `path` unless it is a folder, saying whether it is missing or a
/// file.
fn check_folder(path: &Path) -> Result<(), ResultsError> {
    if path.is_dir() {
        return Ok(());
    }
    let what = if path.exists() {
        "not a folder: it is a file"
    } else {
        "not a folder: no such folder"
    };
    Err(ResultsError::Read {
        path: path.to_path_buf(),
        message: format!("{what}; give the results folder a run wrote (`cyclorub run`, or Result.save in Python)"),
    })
}

impl ResultsFolder {
    /// Reads a results folder: `run.json`, `branch.csv`, and the observed
    /// coordinates from `observed_harmonics.csv` or, without it,
    /// `results.h5`. Unless `run.json` says the run is still running (or
    /// was killed), a CSV file whose last line is unfinished is truncated:
    /// refused naming the file and the line.
    pub fn read(path: &Path) -> Result<Self, ResultsError> {
        check_folder(path)?;
        Self::read_beside(path, None)
    }

    /// Reads a results folder as [`Self::read`] does, and the whole of its
    /// `results.h5` into [`Self::data`] (the observed coordinates taken
    /// from it when there is no `observed_harmonics.csv`): what Python's
    /// `cyclorub.load` gives. A folder without `results.h5` is refused.
    #[cfg(feature = "hdf5")]
    pub fn read_with_results_file(path: &Path) -> Result<Self, ResultsError> {
        check_folder(path)?;
        let file = path.join(super::hdf5::FILE_NAME);
        if !file.is_file() {
            return Err(ResultsError::Read {
                path: path.to_path_buf(),
                message: format!(
                    "has no {}: give a results folder written by `cyclorub run` (or Result.save in Python)",
                    super::hdf5::FILE_NAME
                ),
            });
        }
        let data = super::hdf5::read(&file)?;
        Self::read_beside(path, Some(data))
    }

    /// The folder `path` (a folder) with `data`, its `results.h5` if read.
    fn read_beside(path: &Path, data: Option<ResultsData>) -> Result<Self, ResultsError> {
        let json_path = path.join("run.json");
        let text = read_text(&json_path)?;
        let run: serde_json::Value =
            serde_json::from_str(&text).map_err(|e| ResultsError::Read {
                path: json_path.clone(),
                message: e.to_string(),
            })?;
        let record = RunFile::parse(&json_path, &text)?;
        same_sectors(path, &record.case, data.as_ref())?;
        // A run still writing (or killed: its status stays "running") may
        // leave its last line unfinished; a finished run's never does.
        let running = record.is_running();
        let text = |file: &Path| -> Result<String, ResultsError> {
            let text = read_text(file)?;
            if running {
                Ok(complete_lines(text))
            } else {
                finished_lines(file, text)
            }
        };
        let branch_path = path.join("branch.csv");
        let branch = BranchTable::parse(&branch_path, &text(&branch_path)?)?;
        let csv = path.join("observed_harmonics.csv");
        let harmonics = if csv.exists() {
            parse_harmonics(&csv, &text(&csv)?)?
        } else if let Some(data) = &data {
            harmonics_from_data(data, &branch.sectors)
        } else {
            harmonics_from_results_file(path, &branch.sectors)?
        };
        Ok(Self {
            path: path.to_path_buf(),
            branch,
            harmonics,
            run,
            record,
            data,
        })
    }

    /// The basis kind recorded in `run.json`.
    pub fn basis_kind(&self) -> String {
        self.record
            .basis
            .as_ref()
            .and_then(|b| b.get("kind"))
            .and_then(|v| v.as_str())
            .unwrap_or("unknown")
            .to_string()
    }
}
