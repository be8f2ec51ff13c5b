//! How converged a point's sizes are: the orbit and Hill's truncation
//! refined together until the leading real part settles
//! ([`Refinement::converge`]), and its table.

use super::*;

/// The point refined until its sizes converge (each refinement doubling the
/// orbit's harmonics and Hill's truncation, see [`Refinement::converge`]);
/// a refinement where Newton does not converge ends the sequence (said on
/// stderr).
pub(super) fn refine(
    prepared: &cyclorub::forced_response::Prepared,
    basis: cyclorub::case::BasisChoice,
    unknowns: &[f64],
    omega: f64,
    settings: &StabilitySettings,
    coarse: &PointStability,
    args: &StabilityArgs,
) -> Result<Convergence, CliError> {
    let point = Refinement {
        prepared,
        case_dir: &args.case_dir,
        basis,
        unknowns,
        omega,
        settings,
        full_wheel: args.full_wheel,
    };
    let largest = 1usize.checked_shl(args.refinements).unwrap_or(usize::MAX);
    let convergence = point
        .converge(coarse, args.converge_within, largest)
        .map_err(|e| match e {
            RefineError::Stability(e) => stability_error(e, args),
            other => CliError::failure(other.to_string()),
        })?;
    if let Some(reason) = &convergence.stopped {
        eprintln!(
            "warning: not refined to {} times the harmonics: {reason} (--largest-eigenproblem to accept it)",
            2usize << convergence.steps.len().min(60)
        );
    } else if convergence.steps.len() < args.refinements as usize && !convergence.converged {
        eprintln!(
            "warning: Newton did not converge on the refined orbit ({} times the harmonics) at this point: the sizes' estimate stops at the refinements before",
            2usize << convergence.steps.len().min(60)
        );
    }
    Ok(convergence)
}

/// The refinements' leading real parts, then each class's on the finest
/// orbit: the converged sizes.
pub(super) fn print_convergence(
    convergence: &Convergence,
    coarse: &PointStability,
    within: f64,
    whole_wheel: bool,
) -> Result<(), CliError> {
    outln!("sizes: the orbit and Hill's truncation doubled until the leading real part moves by less than {:.1} %:", 100.0 * within);
    let lead = |s: &PointStability| s.leading().map(|(class, e)| (class, e.re));
    if let Some((class, re)) = lead(coarse) {
        outln!(
            "    harmonics {:>4}: {re:+.4e} 1/s (class {class}), the run's orbit",
            coarse_harmonics(convergence)
        );
    }
    for (step, change) in convergence.steps.iter().zip(&convergence.changes) {
        if let Some((class, re)) = lead(&step.stability) {
            let moved = change.map_or("".to_string(), |c| format!(", moved {:.1} %", 100.0 * c));
            outln!(
                "    harmonics {:>4}: {re:+.4e} 1/s (class {class}){moved}",
                step.harmonics
            );
        }
    }
    let Some(last) = convergence.last() else {
        return Ok(());
    };
    match convergence.estimate {
        Some(e) if convergence.converged => outln!(
            "converged: the sizes below are within about {:.1} % (the last refinement's change)",
            100.0 * e
        ),
        Some(e) => outln!(
            "not converged within --refinements: the last refinement still moved the leading real part by {:.1} % (raise --refinements)",
            100.0 * e
        ),
        None => outln!("no growing exponent to measure the sizes by"),
    }
    outln!(
        "    class  leading Re λ (1/s): run's orbit  finest ({} harmonics)",
        last.harmonics
    );
    for class in &last.stability.classes {
        let fine = class.leading();
        let run = coarse.class(class.nodal_diameter).and_then(|c| c.leading());
        if let (Some(a), Some(b)) = (fine, run) {
            outln!(
                "    {:>5}  {:>+24.4e}  {:>+12.4e}",
                class.nodal_diameter,
                b.re,
                a.re
            );
        }
    }
    outln!("finest: {}", verdict(&last.stability, whole_wheel));
    Ok(())
}

/// The run's Hill truncation, from the first refinement's (twice it).
fn coarse_harmonics(convergence: &Convergence) -> usize {
    convergence.steps.first().map_or(0, |s| s.harmonics / 2)
}
