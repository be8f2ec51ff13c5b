//! After `cyclorub run`: the stability check's sizes converged at the
//! branch's fastest growth (or, on a stable branch, its point of largest
//! amplitude): the point re-solved and checked on 2, 4, 8 times the
//! harmonics until its leading real part settles within 5 %, recorded in
//! `run.json` (docs/design.md §10, "sizes").

use super::outln;
use super::results_folder::open_point;
use super::CliError;
use cyclorub::forced_response::{RefinedStability, Refinement};
use cyclorub::plot::figures::redraw_stability;
use cyclorub::results::sizes::{self, ClassSizes, ConvergedSizes};
use cyclorub::stability::{PointStability, Stability, StabilitySettings};
use std::f64::consts::PI;
use std::path::Path;
use std::time::Duration;

/// Prints the converged sizes at the point of fastest growth of the branch
/// in `output` (its largest amplitude when none grows): the point
/// re-solved on 2, 4, 8 times the harmonics and checked with Hill's
/// truncation scaled alike, until the leading real part moves by less than
/// 5 %; adds them to `run.json`. Says why when it cannot (never fails the
/// run).
pub(super) fn print_size_estimate(
    output: &Path,
    case_dir: &Path,
    settings: &StabilitySettings,
) -> Result<(), CliError> {
    match size_estimate(output, case_dir, settings) {
        Ok(Some(line)) => outln!("{line}"),
        Ok(None) => {}
        Err(why) => {
            outln!("sizes: no error estimate ({why})");
            // Kept in run.json too: a skip for time is told from a failure.
            if let Err(error) = sizes::record_reason(output, &why) {
                tracing::warn!("run.json does not say why there are no sizes: {error}");
            }
        }
    }
    Ok(())
}

fn size_estimate(
    output: &Path,
    case_dir: &Path,
    settings: &StabilitySettings,
) -> Result<Option<String>, String> {
    let opened = open_point(output, None, None, case_dir).map_err(|e| e.message)?;
    let Some(stability) = &opened.data.stability else {
        return Ok(None);
    };
    // Among the points solved by Hill's method (and converged): the one
    // whose leading real part is largest; on a branch where nothing grows,
    // the one of largest amplitude (the stiffest contact, where a coarse
    // truncation misses growth first).
    let by_hill: Vec<(usize, f64, f64)> = stability
        .leading_re
        .iter()
        .enumerate()
        .filter(|(i, _)| {
            stability
                .off_contact_bound
                .get(*i)
                .is_some_and(|b| b.is_nan())
                && opened.data.points.get(*i).is_some_and(|p| p.converged)
        })
        .filter_map(|(i, classes)| {
            let re = classes
                .iter()
                .flatten()
                .copied()
                .filter(|r| r.is_finite())
                .fold(f64::NEG_INFINITY, f64::max);
            let amplitude = opened.data.points[i]
                .amplitude
                .iter()
                .copied()
                .fold(0.0, f64::max);
            re.is_finite().then_some((i, re, amplitude))
        })
        .collect();
    let grows = by_hill
        .iter()
        .any(|&(i, ..)| !stability.stable.get(i).copied().unwrap_or(true));
    let chosen = if grows {
        by_hill.iter().max_by(|a, b| a.1.total_cmp(&b.1))
    } else {
        by_hill.iter().max_by(|a, b| a.2.total_cmp(&b.2))
    };
    let Some(&(index, ..)) = chosen else {
        return Ok(None);
    };
    let opened = open_point(output, Some(index), None, case_dir).map_err(|e| e.message)?;
    let (prepared, point) = (&opened.prepared, &opened.data.points[index]);
    let omega = 2.0 * PI * point.frequency_hz;
    let contact_dofs = prepared.case.contact_dofs();
    // Timed like a refinement (which builds its own check).
    let began = std::time::Instant::now();
    let check = Stability::new(&prepared.model, &prepared.problem, &contact_dofs, settings)
        .map_err(|e| e.to_string())?;
    let coarse = check
        .point(&point.unknowns, omega)
        .map_err(|e| e.to_string())?;
    let coarse_time = began.elapsed();
    let refinement = Refinement {
        prepared,
        case_dir,
        basis: opened.basis,
        unknowns: &point.unknowns,
        omega,
        settings,
        full_wheel: false,
    };
    let convergence = refinement
        .converge_within_time(
            &coarse,
            CONVERGED_WITHIN,
            LARGEST_FACTOR,
            (BUDGET, coarse_time),
        )
        .map_err(|e| e.to_string())?;
    let Some(finest) = convergence.last() else {
        return Err(match &convergence.stopped {
            Some(why) => format!(
                "{why}; `cyclorub stability {} --point {index}` refines it without one",
                output.display()
            ),
            None => {
                "Newton did not converge on twice the harmonics at the fastest growth".to_string()
            }
        });
    };
    let Some((_, run_leading)) = coarse.leading() else {
        return Ok(None);
    };
    let stable: Vec<bool> = std::iter::once(coarse.stable())
        .chain(convergence.steps.iter().map(|s| s.stability.stable()))
        .collect();
    let verdict_holds = stable.iter().all(|&s| s == coarse.stable());
    let record = ConvergedSizes {
        point: index,
        frequency_hz: point.frequency_hz,
        chosen_at: if grows {
            "fastest_growth"
        } else {
            "largest_amplitude"
        }
        .to_string(),
        harmonics: std::iter::once(check.harmonics())
            .chain(convergence.steps.iter().map(|s| s.harmonics))
            .collect(),
        leading_re: std::iter::once(Some(run_leading.re))
            .chain(
                convergence
                    .steps
                    .iter()
                    .map(|s| s.stability.leading().map(|(_, e)| e.re)),
            )
            .collect(),
        stable,
        changes: convergence.changes.clone(),
        converged_within: CONVERGED_WITHIN,
        converged: convergence.converged,
        stopped: convergence.stopped.clone(),
        verdict_holds,
        classes: finest
            .stability
            .classes
            .iter()
            .filter_map(|fine| {
                let finest_re = fine.leading()?.re;
                let run_re = coarse
                    .class(fine.nodal_diameter)
                    .and_then(|c| c.leading())
                    .map(|e| e.re);
                Some(ClassSizes {
                    class: fine.nodal_diameter,
                    run_re,
                    finest_re,
                })
            })
            .collect(),
    };
    sizes::record(output, &record).map_err(|e| e.to_string())?;
    // The stability figure again, with each class's converged size.
    let figures = output.join(cyclorub::run::FIGURES_FOLDER);
    if figures.is_dir() {
        let png = cyclorub::plot::figures::png_asked(&opened.data);
        if let Err(e) = redraw_stability(&figures, &opened.data, &record, png) {
            tracing::warn!("the stability figure was not redrawn with the converged sizes: {e}");
        }
    }
    Ok(Some(describe(&record, grows, &coarse, finest, output)))
}

/// The relative change of the leading real part between two refinements
/// below which the run calls its sizes converged (issue 40: "its error
/// estimate under 5 %").
const CONVERGED_WITHIN: f64 = 0.05;

/// The finest refinement the run makes: 8 times its harmonics (on the
/// default branch the fastest point settles there, 1.4 %, in about a
/// second; larger eigenproblems than `largest_eigenproblem` stop it
/// earlier, and it says so).
const LARGEST_FACTOR: usize = 8;

/// The time past which the run starts no refinement, predicted from the
/// last (a mistuned or physical wheel's first refinement can take a
/// minute; the default branch's three take about one second).
const BUDGET: Duration = Duration::from_secs(10);

/// Whether the refinements give the run's verdict: at every truncation;
/// or it changes (the sizes settled on another); or they disagree among
/// themselves while nothing settled (undecided).
fn verdict(record: &ConvergedSizes, coarse: &PointStability, finest: &RefinedStability) -> String {
    if record.verdict_holds {
        return "the verdict holds at every truncation".to_string();
    }
    let at = |stable: bool| {
        record
            .harmonics
            .iter()
            .zip(&record.stable)
            .filter(|(_, s)| **s == stable)
            .map(|(h, _)| h.to_string())
            .collect::<Vec<_>>()
            .join(", ")
    };
    if record.converged {
        format!(
            "the verdict changes ({} growing exponents at H = {}, {} at H = {}): raise \
             stability.harmonics (and harmonic_balance.harmonics)",
            finest.stability.unstable_exponents(),
            finest.harmonics,
            coarse.unstable_exponents(),
            record.harmonics[0]
        )
    } else {
        format!(
            "the verdict is UNDECIDED (growth at H = {}; none at H = {}): raise \
             harmonic_balance.harmonics and stability.harmonics, or check the point with \
             `cyclorub stability --point {} --refinements 4`",
            at(false),
            at(true),
            record.point
        )
    }
}

/// The run's sizes line: the leading real part at each truncation, whether
/// it settled, how far the run's own sizes are there, and the verdict.
fn describe(
    record: &ConvergedSizes,
    grows: bool,
    coarse: &PointStability,
    finest: &RefinedStability,
    output: &Path,
) -> String {
    let which = if grows {
        "the fastest growth"
    } else {
        "the largest amplitude solved by Hill's method"
    };
    let sequence: Vec<String> = record
        .harmonics
        .iter()
        .zip(&record.leading_re)
        .map(|(h, re)| match re {
            Some(re) => format!("{re:+.4e} (H = {h})"),
            None => format!("none (H = {h})"),
        })
        .collect();
    let finest_re = finest.stability.leading().map(|(_, e)| e.re);
    let last_change = record.changes.last().copied().flatten();
    let settled = match (record.converged, last_change, finest_re) {
        (true, Some(c), Some(re)) => format!(
            "settles at {re:+.4e} 1/s within {:.1} % (H = {})",
            100.0 * c,
            finest.harmonics
        ),
        (false, Some(c), Some(re)) => format!(
            "does NOT settle: {re:+.4e} 1/s at H = {}, still moved by {:.1} % by the last refinement{}",
            finest.harmonics,
            100.0 * c,
            record
                .stopped
                .as_ref()
                .map(|s| format!(" (stopped: {s})"))
                .unwrap_or_default()
        ),
        _ => "has no leading exponent on the refined orbit to compare".to_string(),
    };
    // How far the run's truncation is: from the converged value, or only
    // from the finest when nothing settled.
    let off = match (coarse.leading(), finest_re) {
        (Some((_, run)), Some(fine)) if fine.abs() > 0.0 && record.converged => format!(
            "; the run's truncation (H = {}) puts it {:.1} % {}",
            record.harmonics[0],
            100.0 * (run.re - fine).abs() / fine.abs(),
            if run.re < fine { "low" } else { "high" }
        ),
        (Some((_, run)), Some(fine)) if fine.abs() > 0.0 => format!(
            "; the run's truncation (H = {}) is {:.1} % from the finest, itself not settled",
            record.harmonics[0],
            100.0 * (run.re - fine).abs() / fine.abs(),
        ),
        _ => String::new(),
    };
    // Each class's leading real part against the finest, relative to the
    // wheel's (a class near zero would make its own ratio meaningless): the
    // spread a designer reads before trusting a class's size in branch.csv.
    let worst_class = finest_re.filter(|re| re.abs() > 0.0).and_then(|scale| {
        record
            .classes
            .iter()
            .filter_map(|c| Some((c.class, (c.run_re? - c.finest_re).abs() / scale.abs())))
            .max_by(|a, b| a.1.total_cmp(&b.1))
    });
    let by_class = match worst_class {
        Some((class, error)) => format!(
            "; by class the run's leading real parts are off by up to {:.0} % of it (class {class})",
            100.0 * error
        ),
        None => String::new(),
    };
    let verdict = verdict(record, coarse, finest);
    format!(
        "sizes: at {:.4} Hz (point {}, {which}), the leading real part {settled}{off}{by_class}; {verdict}\n  refinements: {} (run.json stability.sizes; `cyclorub stability {} --point P` for any point)",
        record.frequency_hz,
        record.point,
        sequence.join(", "),
        output.display()
    )
}
