//! `cyclorub branches RESULTS [--marker M] [--max-points N] [--case-dir DIR]`:
//! where the wheel goes at the symmetric branch's branch points
//! (docs/design.md §11). For each branch-point marker of a class σ ≠ 0 of `run.json` (or
//! the one asked for), the real crossing is located on the enlarged
//! basis, the bifurcated branch followed on both sides, and written to
//! `RESULTS/branches/` with its sector amplitudes (a CSV per branch and
//! `branches.json`), recorded in `RESULTS/run.json` (`branches`: the
//! summary) and `RESULTS/results.h5` (`/branches`: every point); a marker
//! where no simple real crossing is found (a complex pair, or σ and −σ
//! together) is said so. A branch point switched at again replaces its
//! earlier record in all three.

use super::branches_files::{branch_table, read_sides, this_runs_records};
use super::results_folder::open_point;
use super::{outln, CliError};
use cyclorub::branches::{real_crossings, switch_at, BranchError};
use cyclorub::continuation::{ArcLengthSettings, NewtonSettings, Point, Settings};
use cyclorub::forced_response::length_scale;
use cyclorub::plot::branches::{branches_svg, BranchCurve, CurvePoint, BRANCHES};
use cyclorub::plot::png::write_pngs_beside;
use cyclorub::results::bifurcated::{merge, BifurcatedBranchData, BifurcatedSide, BranchSummary};
use cyclorub::results::folder::{record_branches_in_run_file, RunFile};
use cyclorub::results::hdf5;
use cyclorub::stability::MarkerKind;
use cyclorub::stability::Stability;
use std::f64::consts::PI;
use std::path::{Path, PathBuf};
use std::time::Instant;

/// Arguments of `cyclorub branches`.
#[derive(clap::Args)]
pub struct BranchesArgs {
    /// Results folder written by `cyclorub run` with stability on (its
    /// run.json markers and results.h5 points).
    results: PathBuf,
    /// Switch at this marker only (its position in run.json's
    /// `stability.markers`, from 0); default: every branch-point marker of a class σ ≠ 0.
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
    /// Every branch-point marker of a class σ ≠ 0 of `results`, with the default settings
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

/// The branch-point markers of a run of classes σ ≠ 0 (or the one asked for).
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
        Some(m) if m < markers.len() && markers[m].kind != MarkerKind::BranchPoint => {
            return Err(CliError::usage(format!(
                "--marker {m}: marker {m} is not a branch point ({}, {:.4} Hz): no periodic \
                 branch starts there; give a BranchPoint marker of run.json (stability.markers)",
                kind_name(markers[m].kind),
                markers[m].frequency_hz
            )))
        }
        Some(m) if m < markers.len() && markers[m].nodal_diameter == Some(0) => {
            return Err(CliError::usage(format!(
                "--marker {m}: marker {m} is a branch point of class 0 ({:.4} Hz): two branches of \
                 the wheel's own symmetry class cross there, and switching to the other one is \
                 not done yet; give a branch point of another class",
                markers[m].frequency_hz
            )))
        }
        Some(m) if m < markers.len() => vec![m],
        Some(m) => {
            return Err(CliError::usage(format!(
                "--marker {m}: run.json has {} markers (stability.markers), give 0 to {}",
                markers.len(),
                markers.len().saturating_sub(1)
            )))
        }
        // Class 0's branch points (two branches of the wheel's own class
        // crossing) are not switched at yet.
        None => (0..markers.len())
            .filter(|&i| {
                markers[i].kind == MarkerKind::BranchPoint && markers[i].nodal_diameter != Some(0)
            })
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

/// A marker kind as a sentence names it.
fn kind_name(kind: MarkerKind) -> String {
    match kind {
        MarkerKind::Fold => "a fold".to_string(),
        MarkerKind::RealCrossing => "a real crossing of no class".to_string(),
        MarkerKind::PeriodDoubling => "period doubling".to_string(),
        MarkerKind::NeimarkSacker => "Neimark–Sacker".to_string(),
        MarkerKind::Jump => {
            "a jump of the exponents at a change of contact (no multiplier crosses)".to_string()
        }
        other => format!("{other:?}"),
    }
}

/// Runs `cyclorub branches`.
pub fn execute(args: BranchesArgs) -> Result<(), CliError> {
    if args.max_points < 2 {
        return Err(CliError::usage(format!(
            "--max-points {}: give at least 2",
            args.max_points
        )));
    }
    refuse_an_unfinished_run(&args.results)?;
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
    let layout = prepared.problem.layout();
    if cyclorub::branches::layout_pairs(layout).is_empty() {
        return Err(CliError::usage(format!(
            "{}: the run is on the physical full wheel (basis physical{}), which has no \
             symmetry to break: no bifurcated branch starts from it (its real crossings are the \
             whole wheel's own); switch at the branch points of a tuned run on a cyclic basis \
             (symmetry)",
            args.results.display(),
            if case.mistuning.is_set() {
                ", as a mistuned wheel needs"
            } else {
                ""
            }
        )));
    }
    if let Some(class) = args.class {
        // Checked here, before any arithmetic on it (2σ overflows near
        // the integer limits): −N/2 < σ ≤ N/2.
        let (n, twice) = (layout.sectors as i128, 2 * i128::from(class));
        if twice <= -n || twice > n {
            return Err(CliError::usage(format!(
                "--class {class}: give a class σ with −N/2 < σ ≤ N/2 (N = {n}: {} to {})",
                -((n - 1) / 2),
                n / 2
            )));
        }
    }
    let candidates = match args.class {
        Some(class) => {
            let found = real_crossings(
                &case,
                &prepared.model,
                &mut prepared.problem,
                class,
                &points,
            )?;
            // A sign change of the least eigenvalue is a real crossing unless
            // it passes from one eigenvalue to another of the other sign:
            // locating it tells (tests/pitchfork).
            outln!(
                "class {class}: the enlarged Jacobian's least eigenvalue changes sign {} time{} along the branch (each located below: a real crossing, or refused where it passed from one eigenvalue to another)",
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
    // The records of earlier calls on this run (their CSV names are taken
    // unless replaced); another run's are dropped.
    let earlier = this_runs_records(&args.results, &folder);
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
    let mut records: Vec<BifurcatedBranchData> = Vec::new();
    let mut failures: Vec<String> = Vec::new();
    let mut located: Vec<(i64, f64)> = Vec::new();
    let listed = folder.join("branches.json");
    for candidate in candidates {
        let class = candidate.class;
        let what = match candidate.marker {
            Some(m) => format!("marker {m}"),
            None => format!("crossing after point {}", candidate.index),
        };
        let mut record = BifurcatedBranchData {
            marker: candidate.marker,
            marker_hz: candidate.frequency_hz,
            class,
            parent_point: candidate.index,
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
                // A branch point switched at before is computed again and
                // replaces its earlier record and CSV (said, not silent).
                if let Some(old) = earlier.iter().find(|e| {
                    e.class == class
                        && e.branch_point_hz
                            .is_some_and(|f| (f - hz).abs() <= 1e-9 * hz)
                }) {
                    outln!(
                        "{what} (class {class}): the branch point at {hz:.6} Hz was switched at before ({}); its record is replaced by this one (--max-points {})",
                        old.file.as_deref().unwrap_or("no file"),
                        args.max_points
                    );
                }
                // Two branch points within 1e-4 Hz (8 sectors: 212.702165
                // and 212.702245 Hz) need more digits to keep both CSVs.
                let taken: Vec<&str> = records
                    .iter()
                    .filter_map(|r| r.file.as_deref())
                    .chain(
                        earlier
                            .iter()
                            .filter(|e| {
                                !(e.class == class
                                    && e.branch_point_hz
                                        .is_some_and(|f| (f - hz).abs() <= 1e-9 * hz))
                            })
                            .filter_map(|e| e.file.as_deref()),
                    )
                    .collect();
                let name = [4, 9]
                    .iter()
                    .map(|&digits| format!("class{class}_{hz:.digits$}Hz.csv"))
                    .find(|n| !taken.contains(&format!("branches/{n}").as_str()))
                    .unwrap_or_else(|| format!("class{class}_{hz:.12}Hz.csv"));
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
                let sides = branch
                    .sides_data(observed, case.harmonic_balance.time_samples, &stable)
                    .map_err(|e| CliError::failure(e.to_string()))?;
                let text = branch_table(&sides, branch.problem.layout().sectors);
                write(&folder.join(&name), &text)?;
                outln!(
                    "{what}: class {class} branch point at {hz:.6} Hz (from {:.4} Hz), basis {} unknowns of {} ({:.1} s)",
                    candidate.frequency_hz,
                    branch.unknowns,
                    branch.full_unknowns,
                    clock.elapsed().as_secs_f64()
                );
                for side in sides.iter().map(BifurcatedSide::summary) {
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
                        side.stop_reason
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
    // marker), those of a branch point switched at again replaced: in
    // branches.json, run.json and results.h5 alike.
    let summaries: Vec<BranchSummary> = records.iter().map(|r| r.summary()).collect();
    let path = listed;
    let all = merge(&earlier, &summaries);
    let json = serde_json::to_string_pretty(&all)
        .map_err(|e| CliError::failure(format!("branches.json: {e}")))?;
    write(&path, &json)?;
    record_branches_in_run_file(&args.results, &summaries)
        .map_err(|e| CliError::failure(e.to_string()))?;
    hdf5::replace_branches(
        &args.results.join(hdf5::FILE_NAME),
        &merge(&opened.data.branches, &records),
    )
    .map_err(|e| CliError::failure(e.to_string()))?;
    // The figure holds every branch of the folder, read back from its CSV.
    curves.truncate(1);
    for record in &all {
        let (Some(file), class, Some(hz)) =
            (record.file.as_deref(), record.class, record.branch_point_hz)
        else {
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

/// Refuses a folder whose run did not finish (`run.json` still says
/// `running`: the run is going on, or was killed): its branch is not whole,
/// it has no stability markers, and a run still going would rewrite
/// `run.json` and `results.h5` at its end without the records. A folder
/// without a readable `run.json` is left to [`open_point`] to refuse.
fn refuse_an_unfinished_run(folder: &Path) -> Result<(), CliError> {
    let path = folder.join("run.json");
    let Ok(text) = std::fs::read_to_string(&path) else {
        return Ok(());
    };
    match RunFile::parse(&path, &text) {
        Ok(run) if run.is_running() => Err(CliError::usage(format!(
            "{}: its run did not finish (run.json's status is {:?}: still going, or killed), \
             so its branch is not whole and has no branch-point markers; switch at the branch \
             points of a finished run (allowed: status finished, stopped_early or interrupted)",
            folder.display(),
            run.status
        ))),
        _ => Ok(()),
    }
}

fn write(path: &Path, text: &str) -> Result<(), CliError> {
    std::fs::write(path, text)
        .map_err(|e| CliError::failure(format!("cannot write {}: {e}", path.display())))
}
