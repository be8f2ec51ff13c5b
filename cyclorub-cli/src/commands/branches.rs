//! `cyclorub branches RESULTS [--marker M] [--max-points N] [--case-dir DIR]`:
//! where the wheel goes at the symmetric branch's branch points
//! (docs/design.md §11). For each branch-point marker of `run.json` (or
//! the one asked for), the real crossing is located on the enlarged
//! basis, the bifurcated branch followed on both sides, and written to
//! `RESULTS/branches/` with its sector amplitudes (a CSV per branch and
//! `branches.json`); a marker where no simple real crossing is found (a
//! complex pair, or σ and −σ together) is said so.

use super::results_folder::open_point;
use super::{outln, CliError};
use cyclorub::branches::{
    real_crossings, sector_amplitudes, switch_at, BifurcatedBranch, BranchError, SideStop,
};
use cyclorub::continuation::{ArcLengthSettings, NewtonSettings, Point, Settings};
use cyclorub::forced_response::length_scale;
use cyclorub::plot::branches::{branches_svg, BranchCurve, CurvePoint, BRANCHES};
use cyclorub::plot::png::write_pngs_beside;
use cyclorub::stability::MarkerKind;
use cyclorub::stability::Stability;
use serde::Serialize;
use std::f64::consts::PI;
use std::fmt::Write as _;
use std::path::{Path, PathBuf};
use std::time::Instant;

/// Arguments of `cyclorub branches`.
#[derive(clap::Args)]
pub struct BranchesArgs {
    /// Results folder written by `cyclorub run` with stability on (its
    /// run.json markers and results.h5 points).
    results: PathBuf,
    /// Switch at this marker only (its position in run.json's
    /// `stability.markers`, from 0); default: every branch-point marker.
    #[arg(long)]
    marker: Option<usize>,
    /// Check the stability of every point of the bifurcated branches, in
    /// the enlarged basis's own classes (Hill's method, the case's
    /// `[stability]` settings): costly where the enlarged basis is the full
    /// wheel (one class of every pair: about 0.13 s a point on 8 sectors in release).
    #[arg(long)]
    stability: bool,
    /// Find the real crossings of class σ along the branch by the enlarged
    /// Jacobian itself, without Hill's markers (for a run without
    /// stability, such as the open fan's), and switch at each.
    #[arg(long, conflicts_with = "marker")]
    class: Option<i64>,
    /// Most points on each side of a bifurcated branch.
    #[arg(long, default_value_t = 500)]
    max_points: usize,
    /// Folder the case's relative paths (matrix files) start from.
    #[arg(long, default_value = ".")]
    case_dir: PathBuf,
}

impl BranchesArgs {
    /// Every branch-point marker of `results`, with the default settings
    /// (what `cyclorub run --branches` does after its run).
    pub fn every_marker(results: PathBuf, case_dir: PathBuf) -> Self {
        Self {
            results,
            marker: None,
            class: None,
            stability: false,
            max_points: 500,
            case_dir,
        }
    }
}

/// A place to switch at: between points `index` and `index + 1`.
struct Candidate {
    marker: Option<usize>,
    index: usize,
    class: i64,
    frequency_hz: f64,
}

/// The branch-point markers of a run (or the one asked for).
fn marker_candidates(
    stability: Option<&cyclorub::results::stability::StabilityData>,
    marker: Option<usize>,
    results: &Path,
) -> Result<Vec<Candidate>, CliError> {
    let Some(stability) = stability else {
        return Err(CliError::usage(format!(
            "{} holds no stability: run the case with stability on (no --no-stability, [stability] enabled = true), or give --class σ to find the crossings of one class without it",
            results.display()
        )));
    };
    let markers = &stability.markers;
    let chosen: Vec<usize> = match marker {
        Some(m) if m < markers.len() => vec![m],
        Some(m) => {
            return Err(CliError::usage(format!(
                "--marker {m}: run.json has {} markers (stability.markers), give 0 to {}",
                markers.len(),
                markers.len().saturating_sub(1)
            )))
        }
        None => (0..markers.len())
            .filter(|&i| markers[i].kind == MarkerKind::BranchPoint)
            .collect(),
    };
    Ok(chosen
        .into_iter()
        .map(|m| Candidate {
            marker: Some(m),
            index: markers[m].index,
            class: markers[m].nodal_diameter.unwrap_or(0),
            frequency_hz: markers[m].frequency_hz,
        })
        .collect())
}

/// One side of a bifurcated branch in `branches.json`.
#[derive(Serialize)]
struct SideRecord {
    direction: f64,
    points: usize,
    /// Points where an exponent grows (`None`: stability not checked).
    unstable_points: Option<usize>,
    stop: SideStop,
    from_hz: Option<f64>,
    to_hz: Option<f64>,
    /// The largest sector amplitude along the side and where.
    peak_amplitude_m: Option<f64>,
    peak_sector: Option<usize>,
    peak_hz: Option<f64>,
}

/// One branch point in `branches.json`: switched, or why not.
#[derive(Serialize)]
struct BranchRecord {
    /// Its position in run.json's `stability.markers` (`None`: found by
    /// `--class`).
    marker: Option<usize>,
    marker_hz: f64,
    class: i64,
    #[serde(skip_serializing_if = "Option::is_none")]
    branch_point_hz: Option<f64>,
    #[serde(skip_serializing_if = "Option::is_none")]
    basis_unknowns: Option<usize>,
    #[serde(skip_serializing_if = "Option::is_none")]
    full_unknowns: Option<usize>,
    #[serde(skip_serializing_if = "Vec::is_empty")]
    sides: Vec<SideRecord>,
    #[serde(skip_serializing_if = "Option::is_none")]
    file: Option<String>,
    #[serde(skip_serializing_if = "Option::is_none")]
    not_switched: Option<String>,
}

/// Runs `cyclorub branches`.
pub fn execute(args: BranchesArgs) -> Result<(), CliError> {
    if args.max_points < 2 {
        return Err(CliError::usage(format!(
            "--max-points {}: give at least 2",
            args.max_points
        )));
    }
    let opened = open_point(&args.results, Some(0), None, &args.case_dir)?;
    let symmetric_stability = opened.data.stability.clone();
    let mut prepared = opened.prepared;
    let points: Vec<Point> = opened
        .data
        .points
        .iter()
        .map(|p| Point {
            omega: 2.0 * PI * p.frequency_hz,
            unknowns: p.unknowns.clone(),
            iterations: p.iterations,
            residual_norm: p.residual_norm,
            converged: p.converged,
        })
        .collect();
    let case = prepared.case.clone();
    let candidates = match args.class {
        Some(class) => {
            let found = real_crossings(
                &case,
                &prepared.model,
                &mut prepared.problem,
                class,
                &points,
            )?;
            outln!(
                "class {class}: {} real crossing{} found along the branch by the enlarged Jacobian",
                found.len(),
                if found.len() == 1 { "" } else { "s" }
            );
            found
                .into_iter()
                .map(|index| Candidate {
                    marker: None,
                    index,
                    class,
                    frequency_hz: points[index].omega / (2.0 * PI),
                })
                .collect()
        }
        None => marker_candidates(symmetric_stability.as_ref(), args.marker, &args.results)?,
    };
    if candidates.is_empty() {
        outln!(
            "no branch point in {}: nothing to switch to",
            args.results.display()
        );
        return Ok(());
    }
    let k = &case.continuation;
    let (start, end) = match (k.start_hz, k.end_hz) {
        (Some(a), Some(b)) => (2.0 * PI * a.min(b), 2.0 * PI * a.max(b)),
        _ => return Err(CliError::failure("run.json's case has no frequency range")),
    };
    let settings = Settings::from(ArcLengthSettings {
        start,
        end,
        initial_step: k.initial_step,
        min_step: k.min_step,
        max_step: k.max_step,
        length_scale: length_scale(
            &case.casing().map_err(|e| CliError::usage(e.to_string()))?,
            &points[0].unknowns,
        )?,
        newton: NewtonSettings {
            tolerance: k.tolerance,
            max_iterations: k.max_iterations,
            ..Default::default()
        },
        max_points: args.max_points,
    });
    let observed = case.output.observed_dof.saturating_sub(1);
    let folder = args.results.join("branches");
    std::fs::create_dir_all(&folder)
        .map_err(|e| CliError::failure(format!("cannot create {}: {e}", folder.display())))?;
    let stability_settings = if args.stability {
        case.stability.settings()
    } else {
        None
    };
    let mut curves = vec![BranchCurve {
        label: "symmetric branch".into(),
        points: opened
            .data
            .points
            .iter()
            .enumerate()
            .filter(|(_, p)| p.converged)
            .map(|(i, p)| CurvePoint {
                frequency_hz: p.frequency_hz,
                largest_m: p.amplitude.iter().cloned().fold(f64::NAN, f64::max),
                smallest_m: p.amplitude.iter().cloned().fold(f64::NAN, f64::min),
                stable: symmetric_stability
                    .as_ref()
                    .and_then(|s| s.stable.get(i).copied()),
            })
            .collect(),
        spread: false,
    }];
    let mut records: Vec<BranchRecord> = Vec::new();
    let mut failures: Vec<String> = Vec::new();
    let mut located: Vec<(i64, f64)> = Vec::new();
    for candidate in candidates {
        let class = candidate.class;
        let what = match candidate.marker {
            Some(m) => format!("marker {m}"),
            None => format!("crossing after point {}", candidate.index),
        };
        let mut record = BranchRecord {
            marker: candidate.marker,
            marker_hz: candidate.frequency_hz,
            class,
            branch_point_hz: None,
            basis_unknowns: None,
            full_unknowns: None,
            sides: Vec::new(),
            file: None,
            not_switched: None,
        };
        let (Some(a), Some(b)) = (points.get(candidate.index), points.get(candidate.index + 1))
        else {
            record.not_switched = Some("its points are not in results.h5".into());
            records.push(record);
            continue;
        };
        let clock = Instant::now();
        let switched = switch_at(
            &case,
            &prepared.model,
            &mut prepared.problem,
            class,
            (&a.unknowns, a.omega),
            (&b.unknowns, b.omega),
            &settings,
        );
        match switched {
            Err(error) => {
                outln!(
                    "{what} (class {class}, {:.4} Hz): not switched: {error}",
                    candidate.frequency_hz
                );
                record.not_switched = Some(error.to_string());
                // A failure of the computation (not a crossing that starts no
                // branch) is kept and reported once the branches found so far
                // are written.
                if !matches!(
                    error,
                    BranchError::NoSignChange { .. }
                        | BranchError::NotReal { .. }
                        | BranchError::ClassInBasis { .. }
                        | BranchError::Bracket { .. }
                ) {
                    failures.push(format!("{what}: {error}"));
                }
            }
            Ok(branch) => {
                let hz = branch.branch_point.omega / (2.0 * PI);
                if located
                    .iter()
                    .any(|&(c, f)| c == class && (f - hz).abs() <= 1e-9 * hz)
                {
                    outln!("{what} (class {class}): the branch point at {hz:.6} Hz, switched at already");
                    record.not_switched = Some(format!(
                        "the same branch point as an earlier marker ({hz:.6} Hz)"
                    ));
                    records.push(record);
                    continue;
                }
                located.push((class, hz));
                let name = format!("class{class}_{hz:.4}Hz.csv");
                // Each point's stability in the enlarged basis's own classes.
                let stable: Vec<Vec<Option<bool>>> = match &stability_settings {
                    Some(settings) => {
                        let check = Stability::new(
                            &prepared.model,
                            &branch.problem,
                            &case.contact_dofs(),
                            settings,
                        )
                        .map_err(|e| CliError::failure(e.to_string()))?;
                        let mut out = Vec::new();
                        for side in &branch.sides {
                            let verdicts = check
                                .branch(&side.points)
                                .map_err(|e| CliError::failure(e.to_string()))?;
                            out.push(verdicts.points.iter().map(|p| Some(p.stable())).collect());
                        }
                        out
                    }
                    None => branch
                        .sides
                        .iter()
                        .map(|s| vec![None; s.points.len()])
                        .collect(),
                };
                let (text, sides) = branch_table(
                    &branch,
                    observed,
                    case.harmonic_balance.time_samples,
                    &stable,
                )?;
                write(&folder.join(&name), &text)?;
                outln!(
                    "{what}: class {class} branch point at {hz:.6} Hz (from {:.4} Hz), basis {} unknowns of {} ({:.1} s)",
                    candidate.frequency_hz,
                    branch.unknowns,
                    branch.full_unknowns,
                    clock.elapsed().as_secs_f64()
                );
                for side in &sides {
                    outln!(
                        "  side {:+}: {} points ({}), {:.4} to {:.4} Hz, largest sector amplitude {:.4e} m (sector {}, {:.4} Hz); {}",
                        side.direction,
                        side.points,
                        side.unstable_points.map_or_else(
                            || "stability not checked".to_string(),
                            |n| format!("{n} unstable")
                        ),
                        side.from_hz.unwrap_or(f64::NAN),
                        side.to_hz.unwrap_or(f64::NAN),
                        side.peak_amplitude_m.unwrap_or(f64::NAN),
                        side.peak_sector.unwrap_or(0),
                        side.peak_hz.unwrap_or(f64::NAN),
                        describe(&side.stop)
                    );
                }
                record.branch_point_hz = Some(hz);
                record.basis_unknowns = Some(branch.unknowns);
                record.full_unknowns = Some(branch.full_unknowns);
                record.sides = sides;
                record.file = Some(format!("branches/{name}"));
            }
        }
        records.push(record);
    }
    // The records of earlier calls are kept (another class, another
    // marker), those of a branch point switched at again replaced.
    let path = folder.join("branches.json");
    let mut all: Vec<serde_json::Value> = Vec::new();
    if let Ok(text) = std::fs::read_to_string(&path) {
        if let Ok(earlier) = serde_json::from_str::<Vec<serde_json::Value>>(&text) {
            let same = |old: &serde_json::Value| {
                records.iter().any(|r| {
                    let close = |a: Option<f64>, b: Option<f64>| match (a, b) {
                        (Some(a), Some(b)) => (a - b).abs() <= 1e-9 * a.abs(),
                        _ => false,
                    };
                    old["class"].as_i64() == Some(r.class)
                        && match r.branch_point_hz {
                            Some(hz) => close(old["branch_point_hz"].as_f64(), Some(hz)),
                            None => close(old["marker_hz"].as_f64(), Some(r.marker_hz)),
                        }
                })
            };
            all.extend(earlier.into_iter().filter(|old| !same(old)));
        }
    }
    for record in &records {
        all.push(
            serde_json::to_value(record)
                .map_err(|e| CliError::failure(format!("branches.json: {e}")))?,
        );
    }
    let json = serde_json::to_string_pretty(&all)
        .map_err(|e| CliError::failure(format!("branches.json: {e}")))?;
    write(&path, &json)?;
    // The figure holds every branch of the folder, read back from its CSV.
    curves.truncate(1);
    for record in &all {
        let (Some(file), Some(class), Some(hz)) = (
            record["file"].as_str(),
            record["class"].as_i64(),
            record["branch_point_hz"].as_f64(),
        ) else {
            continue;
        };
        let text = std::fs::read_to_string(args.results.join(file)).unwrap_or_default();
        for (direction, points) in read_sides(&text) {
            let checked = points.iter().all(|p| p.stable.is_some());
            curves.push(BranchCurve {
                label: format!(
                    "class {class} at {hz:.4} Hz, side {direction:+}{}",
                    if checked {
                        ""
                    } else {
                        " (stability not checked)"
                    }
                ),
                points,
                spread: true,
            });
        }
    }
    if curves.len() > 1 {
        let title = format!(
            "Symmetric and bifurcated branches (N = {})",
            prepared.problem.layout().sectors
        );
        let svg = branches_svg(&curves, &title, &opened.data.observed_name)?;
        let path = folder.join(BRANCHES);
        write(&path, &svg)?;
        write_pngs_beside(&[path])?;
    }
    outln!("wrote {}", folder.display());
    if failures.is_empty() {
        Ok(())
    } else {
        Err(CliError::failure(format!(
            "{} branch point(s) could not be switched at (the others are written): {}",
            failures.len(),
            failures.join("; ")
        )))
    }
}

/// The sides of a branch CSV written by [`branch_table`]: each side's
/// direction and points (rows that do not parse are skipped).
fn read_sides(text: &str) -> Vec<(f64, Vec<CurvePoint>)> {
    let mut sides: Vec<(f64, Vec<CurvePoint>)> = Vec::new();
    for line in text.lines().skip(1) {
        let cells: Vec<&str> = line.split(',').collect();
        let number = |i: usize| cells.get(i).and_then(|c| c.parse::<f64>().ok());
        let (Some(direction), Some(frequency_hz), Some(largest_m), Some(smallest_m)) =
            (number(0), number(2), number(4), number(5))
        else {
            continue;
        };
        let stable = match cells.get(3) {
            Some(&"stable") => Some(true),
            Some(&"unstable") => Some(false),
            _ => None,
        };
        let point = CurvePoint {
            frequency_hz,
            largest_m,
            smallest_m,
            stable,
        };
        match sides.last_mut() {
            Some((d, points)) if *d == direction => points.push(point),
            _ => sides.push((direction, vec![point])),
        }
    }
    sides
}

/// A bifurcated branch's CSV text and its sides' summaries.
type BranchTable = (String, Vec<SideRecord>);

/// The CSV of a bifurcated branch (one row per point of each side, the
/// observed dof's amplitude on every sector) and its sides' summaries.
fn branch_table(
    branch: &BifurcatedBranch,
    dof: usize,
    time_samples: usize,
    stable: &[Vec<Option<bool>>],
) -> Result<BranchTable, CliError> {
    let sectors = branch.problem.layout().sectors;
    let mut text = String::from("side,point,frequency_hz,stable,largest_sector_amplitude_m,smallest_sector_amplitude_m,most_responding_sector");
    for j in 1..=sectors {
        let _ = write!(text, ",sector_{j}_m");
    }
    text.push('\n');
    let mut sides = Vec::new();
    for (s, side) in branch.sides.iter().enumerate() {
        let mut peak: Option<(f64, usize, f64)> = None;
        for (i, p) in side.points.iter().enumerate() {
            let verdict = stable.get(s).and_then(|v| v.get(i)).copied().flatten();
            let amplitudes = sector_amplitudes(&branch.problem, p, dof, time_samples)?;
            let (most, largest) =
                amplitudes
                    .iter()
                    .enumerate()
                    .fold(
                        (0, f64::MIN),
                        |(b, m), (j, a)| if *a > m { (j, *a) } else { (b, m) },
                    );
            let smallest = amplitudes.iter().cloned().fold(f64::MAX, f64::min);
            let hz = p.omega / (2.0 * PI);
            if peak.is_none_or(|(a, _, _)| largest > a) {
                peak = Some((largest, most + 1, hz));
            }
            let word = match verdict {
                Some(true) => "stable",
                Some(false) => "unstable",
                None => "",
            };
            let _ = write!(
                text,
                "{},{i},{hz:.10},{word},{largest:.10e},{smallest:.10e},{}",
                side.direction,
                most + 1
            );
            for a in &amplitudes {
                let _ = write!(text, ",{a:.10e}");
            }
            text.push('\n');
        }
        let verdicts = stable.get(s);
        sides.push(SideRecord {
            direction: side.direction,
            points: side.points.len(),
            unstable_points: verdicts
                .filter(|v| v.iter().all(Option::is_some))
                .map(|v| v.iter().filter(|x| **x == Some(false)).count()),
            stop: side.stop.clone(),
            from_hz: side.points.first().map(|p| p.omega / (2.0 * PI)),
            to_hz: side.points.last().map(|p| p.omega / (2.0 * PI)),
            peak_amplitude_m: peak.map(|p| p.0),
            peak_sector: peak.map(|p| p.1),
            peak_hz: peak.map(|p| p.2),
        });
    }
    Ok((text, sides))
}

/// Why a side stopped, in words.
fn describe(stop: &SideStop) -> String {
    match stop {
        SideStop::Continuation { stop } => stop.to_string(),
        SideStop::Rejoined { frequency_hz } => {
            format!(
                "rejoined the symmetric branch near {frequency_hz:.4} Hz (another branch point)"
            )
        }
        SideStop::NoFirstPoint { distance } => {
            format!("no first point off the branch point (down to {distance:.1e} of arc length)")
        }
    }
}

fn write(path: &Path, text: &str) -> Result<(), CliError> {
    std::fs::write(path, text)
        .map_err(|e| CliError::failure(format!("cannot write {}: {e}", path.display())))
}
