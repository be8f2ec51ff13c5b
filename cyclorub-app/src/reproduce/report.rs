//! The reproduction report: `report.md` (a person reads it), `report.json`
//! (a program reads it) and the figures of each study in `figures/`.

use super::stability::HillMethod;
use super::{
    Comparison, Report, ReproduceError, ReproduceMode, RunSummary, Study, CURVE_TOLERANCE,
    ENERGY_TOLERANCE, TOLERANCE,
};
use cyclorub::case::BasisChoice;
use cyclorub::plot::components::cyclic_components;
use cyclorub::plot::forced_response::{forced_response, Captions, SectorCurves};
use cyclorub::results::{write_json, ResultsError};
use cyclorub::run::RunOutcome;
use cyclorub::run::StabilityStatus;
use std::fmt::Write as _;
use std::path::{Path, PathBuf};

/// The folder of the figures, inside the report's folder.
pub const FIGURES: &str = "figures";

/// `(Hz, amplitude of sector j)` along a run.
fn sector_curve(outcome: &RunOutcome, sector: usize) -> Vec<(f64, f64)> {
    outcome
        .data
        .points
        .iter()
        .filter(|p| p.converged)
        .filter_map(|p| Some((p.frequency_hz, *p.amplitude.get(sector)?)))
        .collect()
}

/// The sectors worth drawing (0-based): sector 1, and those of largest and
/// smallest peak when their curves differ from the ones already kept by
/// more than 1 % of the largest amplitude.
fn sectors_to_draw(outcome: &RunOutcome) -> Vec<usize> {
    let points = &outcome.data.points;
    let n = points.first().map_or(0, |p| p.amplitude.len());
    if n == 0 {
        return vec![0];
    }
    let peak = |j: usize| {
        points
            .iter()
            .map(|p| p.amplitude[j])
            .fold(f64::MIN, f64::max)
    };
    let scale = (0..n).map(peak).fold(0.0_f64, f64::max);
    let largest = (0..n)
        .max_by(|a, b| peak(*a).total_cmp(&peak(*b)))
        .unwrap_or(0);
    let smallest = (0..n)
        .min_by(|a, b| peak(*a).total_cmp(&peak(*b)))
        .unwrap_or(0);
    let mut kept = vec![0];
    for j in [largest, smallest] {
        let differs = kept.iter().all(|&k| {
            points
                .iter()
                .map(|p| (p.amplitude[j] - p.amplitude[k]).abs())
                .fold(0.0_f64, f64::max)
                > 0.01 * scale
        });
        if differs {
            kept.push(j);
        }
    }
    kept
}

/// Draws the figures of a study: the forced response (symmetry basis
/// solid, paper's basis solid when it differs, full wheel dashed, linear
/// dotted) and the cyclic components of the full solution at its
/// resonance. `outcomes` are the runs in the order of the study's runs (a
/// run not made is `None`). Returns the files, relative to `output`.
pub fn figures(
    output: &Path,
    study: &Study,
    outcomes: &[Option<RunOutcome>],
) -> Result<Vec<PathBuf>, ReproduceError> {
    let mut files = Vec::new();
    let folder = output.join(FIGURES);
    std::fs::create_dir_all(&folder).map_err(|source| ResultsError::Io {
        path: folder.clone(),
        source,
    })?;
    let stem = format!("{}-{}", study.case, study.law.name());
    let reduced = outcomes.first().and_then(Option::as_ref);
    let paper = outcomes.get(1).and_then(Option::as_ref);
    let full = outcomes.get(2).and_then(Option::as_ref);
    let Some(main) = reduced.or(full) else {
        return Ok(files);
    };
    let mut curves: Vec<SectorCurves> = sectors_to_draw(full.unwrap_or(main))
        .into_iter()
        .map(|j| SectorCurves {
            label: format!("sector {}", j + 1),
            nonlinear: reduced.map(|r| sector_curve(r, j)).unwrap_or_default(),
            breaks: reduced
                .map(|r| r.data.converged_breaks())
                .unwrap_or_default(),
            linear: main
                .data
                .linear
                .frequency_hz
                .iter()
                .zip(&main.data.linear.amplitude)
                .filter_map(|(f, a)| Some((*f, *a.get(j)?)))
                .collect(),
            reference: full.map(|f| sector_curve(f, j)).unwrap_or_default(),
            ..SectorCurves::default()
        })
        .collect();
    if let Some(paper) = paper {
        curves.push(SectorCurves {
            label: "sector 1, paper's basis".into(),
            nonlinear: sector_curve(paper, 0),
            ..SectorCurves::default()
        });
    }
    let title = format!(
        "{} — {} (N = {}, N_h = {}, N_t = {}): solid symmetry basis, dashed full wheel",
        study.case,
        law_title(study),
        study.sectors,
        study.harmonics,
        study.time_samples
    );
    let file = PathBuf::from(FIGURES).join(format!("{stem}-forced-response.svg"));
    forced_response(
        &output.join(&file),
        &Captions {
            title,
            amplitude_axis: "amplitude (m)".into(),
            reference: "full wheel (physical)".into(),
        },
        &curves,
    )?;
    files.push(file);
    if let Some(full) = full {
        if let Some(peak) = full.data.peak_point() {
            let point = &full.data.points[peak];
            let file = PathBuf::from(FIGURES).join(format!("{stem}-components.svg"));
            let title = format!(
                "{} — {}: cyclic components of the full wheel at {:.3} Hz",
                study.case,
                law_title(study),
                point.frequency_hz
            );
            cyclic_components(&output.join(&file), &point.components, &title, 1e-14)?;
            files.push(file);
        }
    }
    Ok(files)
}

fn law_title(study: &Study) -> &'static str {
    study.law.method()
}

/// A number in a table: scientific with 2 digits, or `—`.
fn e(value: Option<f64>) -> String {
    value.map_or_else(|| "—".into(), |v| format!("{v:.1e}"))
}

fn stop_text(run: &RunSummary) -> String {
    if let Some(error) = &run.error {
        return format!("failed: {error}");
    }
    if let Some(other) = &run.same_as {
        return format!("same basis as {other}, not run again");
    }
    // The library's words: the stop, or, when the branch was followed from
    // both ends, how each sweep stopped and whether they were joined.
    match (&run.stop, &run.sweeps) {
        (Some(_), Some(sweeps)) => sweeps.summary(),
        (Some(stop), None) => stop.to_string(),
        (None, _) => "not run".into(),
    }
}

fn verdict(c: &Comparison) -> String {
    if !c.exact() {
        return "**differs**".into();
    }
    let leaves = c.energy_outside.as_ref().and_then(|e| e.leaves_at_hz);
    match (c.complete(), leaves, c.same_curve()) {
        (true, None, true) => "exact".into(),
        (_, Some(hz), _) => format!(
            "exact; **the full branch leaves this basis at {hz:.3} Hz** (symmetry breaking)"
        ),
        (false, None, _) => "exact; **the full resonance is outside this basis**".into(),
        (true, None, false) => "exact; the full branch took another path".into(),
    }
}

/// The Markdown of a report.
pub fn markdown(report: &Report) -> String {
    let mut md = String::new();
    let exact = report.studies.iter().filter(|s| s.exact()).count();
    let _ = writeln!(
        md,
        "# Reproduction of Vadcard, Quaegebeur & Thouverez (2024), Sec. 4 and Appendix C\n"
    );
    let _ = writeln!(
        md,
        "Made by `cyclorub reproduce {}{}` in {:.1} s ({} mode). \
         **{exact} of {} studies exact.**\n",
        report.folder.display(),
        if report.mode == ReproduceMode::Quick {
            " --quick"
        } else {
            ""
        },
        report.wall_s,
        report.mode,
        report.studies.len()
    );
    let _ = writeln!(
        md,
        "Each case is solved with each contact law on the symmetry basis (docs/design.md §3), \
         on the paper's basis and on the full wheel assembled in physical coordinates \
         (the reference), each by its own pseudo-arc-length continuation. A reduction \
         is **exact** when every point of its branch, carried over to the full wheel, \
         is a full solution: Newton on the full problem at the same frequency moves \
         it by at most {TOLERANCE:.0e} relative (unknowns and the observed dof on every \
         sector), both being first brought to a residual three decades below the \
         continuation's tolerance. The full branch is also checked against each basis: \
         at its resonance it should have at most {ENERGY_TOLERANCE:.0e} of its energy \
         (every dof of the sector) outside; where it has more, it has left the \
         symmetric solutions (a symmetry-breaking bifurcation the reduced model cannot \
         follow, docs/design.md §3, or the full continuation jumping onto another branch), \
         and the report says where. The curve distance \
         is the largest distance from a point of the full branch to the reduced one \
         (frequency over the range, amplitude over the largest amplitude); above \
         {CURVE_TOLERANCE:.0e} the two continuations went different ways. `N_t` is \
         the nearest multiple of `N` to the case file's, so that time-sampling \
         aliases stay in the basis.\n"
    );
    let _ = writeln!(
        md,
        "The **stability** column is the Floquet exponents of every converged point \
         (Hill's method, `cyclorub::stability`) of the symmetry-basis run, class by \
         class: class σ = 0 is the reduced problem's own stability, the others the \
         perturbations of other nodal diameters that no reduced run sees; together \
         they are the full wheel's spectrum. A point is unstable when an exponent \
         has a real part above 1e-8 ω; the column gives the stretches of consecutive \
         unstable points along the branch (first and last frequency) and their \
         growing classes. The paper's basis has the same solutions and is not \
         checked again; the full wheel is checked without symmetry only when its \
         eigenproblem has at most {} unknowns (otherwise: not computed, with the \
         reason). Each study's section lists the markers where stability changes.\n",
        super::stability::FULL_WHEEL_EIGENPROBLEM
    );
    let _ = writeln!(
        md,
        "| case | law | basis | unknowns | reduction | sectors sampled | points | solve (s) | full / reduced time | largest difference to full | full residual of reduced points | curve distance | energy outside basis | verdict | stability |"
    );
    let _ = writeln!(
        md,
        "|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|"
    );
    for study in &report.studies {
        for run in &study.runs {
            let comparison = study.comparisons.iter().find(|c| c.basis == run.basis);
            let difference = comparison.and_then(|c| {
                c.point_by_point.as_ref().map(|p| {
                    p.largest_unknowns_difference
                        .max(p.largest_displacement_difference)
                })
            });
            let residual =
                comparison.and_then(|c| c.point_by_point.as_ref().map(|p| p.largest_full_residual));
            let row_verdict = match (comparison, run.error.as_ref(), run.same_as.as_ref()) {
                (_, Some(_), _) => "run failed".to_string(),
                (_, _, Some(other)) => format!("as {other}"),
                (Some(c), _, _) => verdict(c).to_string(),
                (None, _, _) if run.basis == BasisChoice::Physical => "reference".into(),
                (None, _, _) => "not compared".into(),
            };
            let stability = match (&run.stability, run.same_as.as_ref()) {
                (_, Some(other)) => format!("as {other}"),
                (Some(s), None) => s.cell(),
                (None, None) => "—".into(),
            };
            let _ = writeln!(
                md,
                "| {} | {} | {} | {} | {:.1} % | {} | {} | {} | {} | {} | {} | {} | {} | {} | {} |",
                study.case,
                law_title(study),
                run.basis,
                run.unknowns,
                run.reduction_percent,
                run.sampled_sectors,
                run.points,
                run.timings
                    .as_ref()
                    .filter(|_| run.same_as.is_none())
                    .map_or_else(|| "—".into(), |t| format!("{:.2}", t.solve_s)),
                comparison
                    .and_then(|c| c.time_ratio)
                    .filter(|_| run.same_as.is_none())
                    .map_or_else(|| "—".into(), |r| format!("{r:.1}×")),
                e(difference),
                e(residual),
                e(comparison.and_then(|c| c.curve_distance)),
                e(comparison.and_then(|c| c.energy_outside.as_ref().map(|e| e.at_resonance))),
                row_verdict,
                stability
            );
        }
    }
    for study in &report.studies {
        let _ = writeln!(md, "\n## {} — {}\n", study.case, law_title(study));
        if !study.description.is_empty() {
            let _ = writeln!(md, "{}\n", study.description);
        }
        let _ = writeln!(
            md,
            "N = {}, N_h = {}, N_t = {} (case file: {}), {:.3} to {:.3} Hz{}.\n",
            study.sectors,
            study.harmonics,
            study.time_samples,
            study.time_samples_in_file,
            study.start_hz,
            study.end_hz,
            study.resonance_hz.map_or_else(String::new, |f| format!(
                "; full-wheel resonance at {f:.3} Hz"
            ))
        );
        for run in &study.runs {
            let _ = writeln!(
                md,
                "- **{}**: {} unknowns of {} ({:.1} %), {} sampled sectors; {} points, {} Newton iterations; {}{}",
                run.basis,
                run.unknowns,
                run.full_unknowns,
                run.reduction_percent,
                run.sampled_sectors,
                run.points,
                run.iterations,
                stop_text(run),
                run.folder
                    .as_ref()
                    .map_or_else(String::new, |f| format!(" — results in `{}`", f.display()))
            );
            if !run.harmonics.is_empty() && run.same_as.is_none() {
                let sets: Vec<String> = run
                    .harmonics
                    .iter()
                    .map(|h| {
                        format!(
                            "{{{}}}",
                            h.signed_nodal_diameters
                                .iter()
                                .map(i64::to_string)
                                .collect::<Vec<_>>()
                                .join(", ")
                        )
                    })
                    .collect();
                let _ = writeln!(
                    md,
                    "  - pairs per harmonic 0..{}: {}",
                    run.harmonics.len() - 1,
                    sets.join(" ")
                );
            }
        }
        for c in &study.comparisons {
            if let Some(p) = &c.point_by_point {
                let energy = c.energy_outside.clone().unwrap_or_default();
                let _ = writeln!(
                    md,
                    "- {} against the full wheel: {} points brought to ‖R‖/f_ex ≤ {:.0e} (or their round-off floor, at most {:.1e}); largest full residual of a reduced point {:.1e}; largest correction by Newton on the full wheel {:.1e} (unknowns), {:.1e} (observed dof); {} not converged; curve distance {}; energy of the full branch outside the basis: {:.1e} at its resonance, {:.1e} at most{}: {}",
                    c.basis,
                    p.points,
                    p.tight_tolerance,
                    p.largest_round_off_floor,
                    p.largest_full_residual,
                    p.largest_unknowns_difference,
                    p.largest_displacement_difference,
                    p.not_converged,
                    e(c.curve_distance),
                    energy.at_resonance,
                    energy.largest,
                    energy
                        .leaves_at_hz
                        .map_or_else(String::new, |hz| format!(", from {hz:.3} Hz on")),
                    verdict(c)
                );
            }
        }
        stability_lines(&mut md, study);
        for figure in &study.figures {
            let _ = writeln!(md, "\n![{}]({})", figure.display(), figure.display());
        }
    }
    md
}

/// The stability of a study's runs, for its section: each checked run's
/// verdict, its unstable stretches and its markers; why the others were
/// not checked.
fn stability_lines(md: &mut String, study: &Study) {
    /// Markers listed per run; report.json has them all.
    const SHOWN: usize = 12;
    for run in study.runs.iter().filter(|r| r.same_as.is_none()) {
        let Some(s) = &run.stability else {
            continue;
        };
        match s.status {
            StabilityStatus::Computed => {
                let method = match s.method {
                    HillMethod::FullWheel => "on the whole wheel, without symmetry",
                    HillMethod::SymmetryClasses | HillMethod::None => "per symmetry class",
                };
                let _ = writeln!(
                    md,
                    "- stability, {} (Hill's method {method}, H = {}, {:.1} s): {} of {} points unstable ({} solved by Hill's method, the others off contact); {}",
                    run.basis,
                    s.harmonics.unwrap_or(0),
                    s.time_s,
                    s.unstable_points,
                    s.points,
                    s.points_by_hill,
                    s.marker_counts()
                );
                for stretch in &s.unstable {
                    let classes = if stretch.classes.is_empty() {
                        String::new()
                    } else {
                        format!(
                            ", growing in class{} σ = {}",
                            if stretch.classes.len() > 1 { "es" } else { "" },
                            stretch
                                .classes
                                .iter()
                                .map(i64::to_string)
                                .collect::<Vec<_>>()
                                .join(", ")
                        )
                    };
                    let _ = writeln!(
                        md,
                        "  - unstable from point {} ({:.4} Hz) to point {} ({:.4} Hz), spanning {:.4}–{:.4} Hz, {} points{classes}, largest real part {:.3e} 1/s",
                        stretch.first_point,
                        stretch.from_hz,
                        stretch.last_point,
                        stretch.to_hz,
                        stretch.low_hz,
                        stretch.high_hz,
                        stretch.points,
                        stretch.largest_growth
                    );
                }
                for line in s.marker_lines(SHOWN) {
                    let _ = writeln!(md, "  - {line}");
                }
            }
            StabilityStatus::NotComputed => {
                let _ = writeln!(
                    md,
                    "- stability, {}: not computed: {}",
                    run.basis,
                    s.reason.as_deref().unwrap_or("")
                );
            }
            StabilityStatus::NotAsked => {
                let _ = writeln!(
                    md,
                    "- stability, {}: {}",
                    run.basis,
                    s.reason.as_deref().unwrap_or("not asked")
                );
            }
        }
    }
}

/// Writes `report.md` and `report.json` into `output`.
pub fn write(output: &Path, report: &Report) -> Result<(), ResultsError> {
    let path = output.join("report.md");
    std::fs::write(&path, markdown(report)).map_err(|source| ResultsError::Io { path, source })?;
    write_json(output, "report.json", report).map(|_| ())
}
