//! After `cyclorub run`: how converged the stability check's sizes are, at
//! the branch's fastest growth (or, on a stable branch, its point of
//! largest amplitude) (docs/design.md §10, "sizes").

use super::outln;
use super::results_folder::open_point;
use super::CliError;
use cyclorub::forced_response::refined_stability;
use cyclorub::stability::{Stability, StabilitySettings};
use std::f64::consts::PI;
use std::path::Path;

/// Prints the error estimate of the exponents' sizes at the point of
/// fastest growth of the branch in `output` (its largest amplitude when
/// none grows): the point re-solved on twice
/// the harmonics and checked with twice Hill's truncation, and the change
/// of the leading real part. Says why when it cannot (never fails the run).
pub(super) fn print_size_estimate(
    output: &Path,
    case_dir: &Path,
    settings: &StabilitySettings,
) -> Result<(), CliError> {
    match size_estimate(output, case_dir, settings) {
        Ok(Some(line)) => outln!("{line}"),
        Ok(None) => {}
        Err(why) => outln!("sizes: no error estimate ({why})"),
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
    let check = Stability::new(&prepared.model, &prepared.problem, &contact_dofs, settings)
        .map_err(|e| e.to_string())?;
    let coarse = check
        .point(&point.unknowns, omega)
        .map_err(|e| e.to_string())?;
    let refined = refined_stability(
        prepared,
        case_dir,
        opened.basis,
        &point.unknowns,
        omega,
        settings,
        false,
    )
    .map_err(|e| e.to_string())?
    .ok_or("Newton did not converge on twice the harmonics at the fastest growth")?;
    let Some(change) = refined.leading_change(&coarse) else {
        return Ok(None);
    };
    let verdict = if refined.stability.stable() == coarse.stable() {
        "the verdict holds".to_string()
    } else {
        format!(
            "the verdict changes ({} growing exponents at H = {}, {} at H = {}): raise \
             stability.harmonics (and harmonic_balance.harmonics)",
            refined.stability.unstable_exponents(),
            refined.harmonics,
            coarse.unstable_exponents(),
            check.harmonics()
        )
    };
    let which = if grows {
        "the fastest growth"
    } else {
        "the largest amplitude solved by Hill's method"
    };
    Ok(Some(format!(
        "sizes: at {:.4} Hz (point {index}, {which}), twice the harmonics (H = {}) move the leading real part by {:.1} %; {verdict} (`cyclorub stability {} --point P` for any point)",
        point.frequency_hz,
        refined.harmonics,
        100.0 * change,
        output.display()
    )))
}
