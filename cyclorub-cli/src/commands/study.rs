//! `cyclorub study FOLDER [--output DIR] [--at-hz F1,F2,...]`: every case
//! file of a folder solved in turn (issue 44 item 5), one row each in
//! `DIR/study.csv` (the columns of Python's `cyclorub.study`, a mistuned
//! case's amplification factor among them), and the distribution of the
//! amplification factors in `DIR/amplification_factors.svg` when a case is
//! mistuned. No results folder is written per case. A case that does not
//! finish (refused, failed, stopped early, a point not converged) keeps its
//! row, is counted on the last line, and makes the exit code
//! [`INCOMPLETE_EXIT_CODE`].

use super::{outln, CliError};
use cyclorub::case::Case;
use cyclorub::continuation::StopReason;
use cyclorub::forced_response::{ForcedResponse, Solution};
use cyclorub::plot::mistuning_study::write_amplification_distribution;
use cyclorub::run::mistuning::MistuningRecord;
use std::path::{Path, PathBuf};

/// Arguments of `cyclorub study`.
#[derive(clap::Args)]
pub struct StudyArgs {
    /// Folder of case files (`*.toml`), solved in name order.
    folder: PathBuf,
    /// Where `study.csv` and the figure go (default: FOLDER/study).
    #[arg(long)]
    output: Option<PathBuf>,
    /// Solve every case at exactly these frequencies (Hz, comma-separated):
    /// every peak, and a mistuned case's tuned reference, read on one grid.
    #[arg(long, value_delimiter = ',')]
    at_hz: Option<Vec<f64>>,
}

/// The columns of `study.csv`.
const HEADER: &str = "label,sectors,basis,points,stop,finished,peak_amplitude_m,\
peak_frequency_hz,solve_s,seed,standard_deviation,amplification_factor,\
largest_sector_peak_m,most_responding_sector,tuned_peak_m,deviations,error,\
no_factor_reason";

/// The index of the `finished` column.
const FINISHED_COLUMN: usize = 5;

/// The index of the `error` column.
const ERROR_COLUMN: usize = 16;

/// The exit code of a study with an unfinished row (a case refused or
/// failed, stopped before the end of its range, or with a point that did
/// not converge): study.csv is written, but the study is incomplete. Not 1
/// (a failure to do the work) nor 2 (bad input to the command), so that a
/// script can tell them apart.
pub const INCOMPLETE_EXIT_CODE: u8 = 3;

/// A CSV cell of text: quoted, its quotes doubled.
fn quoted(text: &str) -> String {
    format!("\"{}\"", text.replace('"', "\"\""))
}

/// A number, empty when absent or not finite.
fn cell(value: Option<f64>) -> String {
    value
        .filter(|v| v.is_finite())
        .map_or_else(String::new, |v| format!("{v:e}"))
}

/// The case files of `folder`, in name order.
fn case_files(folder: &Path) -> Result<Vec<PathBuf>, CliError> {
    let entries = std::fs::read_dir(folder).map_err(|e| {
        CliError::usage(format!(
            "{}: {e}; give a folder of case files (*.toml)",
            folder.display()
        ))
    })?;
    let mut files: Vec<PathBuf> = entries
        .filter_map(|entry| entry.ok().map(|e| e.path()))
        .filter(|p| p.is_file() && p.extension().is_some_and(|e| e == "toml"))
        .collect();
    files.sort();
    if files.is_empty() {
        return Err(CliError::usage(format!(
            "{} has no case files (*.toml): give a folder of case files",
            folder.display()
        )));
    }
    Ok(files)
}

/// Solves the case file `path`: its solution and, when its wheel is
/// mistuned, its mistuning record (the tuned reference solved too).
fn solve(
    path: &Path,
    folder: &Path,
    at_hz: Option<&Vec<f64>>,
) -> Result<(Case, Solution, Option<MistuningRecord>), String> {
    let case = Case::from_file_checked(path).map_err(|e| e.to_string())?;
    let mut request = ForcedResponse::from_case(&case)
        .map_err(|e| e.to_string())?
        .case_dir(folder);
    if let Some(list) = at_hz {
        request = request.at_frequencies_hz(list.clone());
    }
    let solution = request
        .build()
        .and_then(|solver| solver.run(&mut []))
        .map_err(|e| e.to_string())?;
    let summaries = solution
        .point_summaries()
        .into_iter()
        .collect::<Result<Vec<_>, _>>()
        .map_err(|e| e.to_string())?;
    let mistuning =
        cyclorub::run::mistuning::record(&solution, &summaries).map_err(|e| e.to_string())?;
    Ok((case, solution, mistuning))
}

/// Whether `solution` finished: the whole range (or every frequency)
/// solved, every point converged, as `cyclorub run` says.
fn finished(solution: &Solution) -> bool {
    matches!(
        solution.branch.stop,
        StopReason::EndReached | StopReason::AllFrequenciesDone
    ) && solution.branch.points.iter().all(|p| p.converged)
}

/// Why a solved case is unfinished, for the last line.
fn unfinished_why(solution: &Solution) -> String {
    let points = &solution.branch.points;
    let failed = points.iter().filter(|p| !p.converged).count();
    let total = points.len();
    match solution.branch.stop {
        StopReason::EndReached | StopReason::AllFrequenciesDone => {
            format!("{failed} of {total} points not converged")
        }
        ref stop if failed > 0 => format!("{stop}; {failed} of {total} points not converged"),
        ref stop => stop.to_string(),
    }
}

/// The row of a solved case.
fn row(
    label: &str,
    case: &Case,
    solution: &Solution,
    mistuning: Option<&MistuningRecord>,
) -> String {
    let peaks: Vec<(f64, f64)> = solution
        .point_summaries()
        .into_iter()
        .zip(&solution.branch.points)
        .filter(|(_, point)| point.converged)
        .filter_map(|(summary, point)| {
            let peak = summary
                .ok()?
                .observed
                .peak
                .iter()
                .cloned()
                .fold(f64::NAN, f64::max);
            Some((point.omega / (2.0 * std::f64::consts::PI), peak))
        })
        .collect();
    let best = peaks
        .iter()
        .filter(|(_, a)| a.is_finite())
        .max_by(|a, b| a.1.total_cmp(&b.1));
    let stop = serde_json::to_value(&solution.branch.stop)
        .ok()
        .and_then(|v| v.get("reason").and_then(|r| r.as_str().map(str::to_string)))
        .unwrap_or_default();
    let m = mistuning;
    let largest = m.map(|m| m.sector_peaks_m.iter().cloned().fold(f64::NAN, f64::max));
    let deviations = m.map_or_else(String::new, |m| {
        m.deviations
            .iter()
            .map(|d| format!("{d:e}"))
            .collect::<Vec<_>>()
            .join(" ")
    });
    [
        quoted(label),
        case.model.sectors().to_string(),
        solution.basis.kind.clone(),
        solution.branch.points.len().to_string(),
        stop,
        finished(solution).to_string(),
        cell(best.map(|b| b.1)),
        cell(best.map(|b| b.0)),
        cell(Some(solution.solve_s)),
        m.and(case.mistuning.seed)
            .map_or_else(String::new, |s| s.to_string()),
        cell(m.and(case.mistuning.standard_deviation)),
        cell(m.and_then(|m| m.amplification_factor)),
        cell(largest),
        m.map_or_else(String::new, |m| m.most_responding_sector.to_string()),
        cell(m.and_then(|m| m.tuned_peak_m)),
        deviations,
        String::new(),
        m.and_then(|m| m.no_factor_reason.as_deref())
            .map_or_else(String::new, quoted),
    ]
    .join(",")
}

/// Runs `cyclorub study`.
pub fn execute(args: StudyArgs) -> Result<(), CliError> {
    if let Some(list) = &args.at_hz {
        if list.is_empty() {
            return Err(CliError::usage("--at-hz: give at least one frequency (Hz)"));
        }
    }
    let files = case_files(&args.folder)?;
    let output = args
        .output
        .clone()
        .unwrap_or_else(|| args.folder.join("study"));
    std::fs::create_dir_all(&output)
        .map_err(|e| CliError::usage(format!("--output {}: {e}", output.display())))?;
    let mut lines = vec![HEADER.to_string()];
    let mut factors = Vec::new();
    let mut sectors = Vec::new();
    // Each unfinished case's label and why, for the last line.
    let mut unfinished: Vec<String> = Vec::new();
    for (k, path) in files.iter().enumerate() {
        let label = path
            .file_stem()
            .map_or_else(String::new, |s| s.to_string_lossy().into_owned());
        eprintln!("cyclorub study: case {}/{}: {label}", k + 1, files.len());
        match solve(path, &args.folder, args.at_hz.as_ref()) {
            Ok((case, solution, mistuning)) => {
                if let Some(m) = &mistuning {
                    factors.push(m.amplification_factor.unwrap_or(f64::NAN));
                    sectors.push(case.model.sectors());
                }
                let factor = match &mistuning {
                    Some(m) => match (m.amplification_factor, &m.no_factor_reason) {
                        (Some(f), _) => format!(", amplification factor {f:.4}"),
                        (None, Some(why)) => format!(", no amplification factor: {why}"),
                        (None, None) => String::new(),
                    },
                    None => String::new(),
                };
                outln!("{label}: {} points{factor}", solution.branch.points.len());
                if !finished(&solution) {
                    unfinished.push(format!("{label} ({})", unfinished_why(&solution)));
                }
                lines.push(row(&label, &case, &solution, mistuning.as_ref()));
            }
            Err(message) => {
                outln!("{label}: refused: {message}");
                let mut cells = vec![String::new(); HEADER.split(',').count()];
                cells[0] = quoted(&label);
                cells[FINISHED_COLUMN] = false.to_string();
                unfinished.push(format!("{label} (refused)"));
                if let Some(error) = cells.get_mut(ERROR_COLUMN) {
                    *error = quoted(&message);
                }
                lines.push(cells.join(","));
            }
        }
    }
    let table = output.join("study.csv");
    std::fs::write(&table, lines.join("\n") + "\n")
        .map_err(|e| CliError::failure(format!("cannot write {}: {e}", table.display())))?;
    outln!("wrote {}", table.display());
    if !factors.is_empty() && factors.iter().all(|f| !f.is_finite()) {
        outln!("no amplification figure: no mistuned case has an amplification factor (study.csv, no_factor_reason)");
    } else if !factors.is_empty() {
        sectors.sort_unstable();
        sectors.dedup();
        if let [n] = sectors[..] {
            let figure = output.join("amplification_factors.svg");
            write_amplification_distribution(&figure, &factors, n, false)?;
            outln!("wrote {}", figure.display());
        } else {
            outln!("no amplification figure: the mistuned cases have different numbers of sectors ({sectors:?})");
        }
    }
    let total = files.len();
    if unfinished.is_empty() {
        outln!("{total} of {total} cases finished");
        return Ok(());
    }
    let count = unfinished.len();
    outln!(
        "{count} of {total} cases unfinished (finished = false in study.csv): {}",
        unfinished.join(", ")
    );
    Err(CliError {
        message: format!(
            "the study is incomplete: {count} of {total} cases unfinished (exit code {INCOMPLETE_EXIT_CODE})"
        ),
        exit_code: INCOMPLETE_EXIT_CODE,
    })
}
