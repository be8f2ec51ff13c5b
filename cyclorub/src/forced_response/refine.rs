//! A point's orbit refined: the same case with more harmonics, the point's
//! truncated solution as the start, Newton at its frequency. What the
//! stability check needs to say how converged its exponents are (their
//! change from the orbit to the refined one): raising Hill's truncation
//! alone on a truncated orbit does not converge on a stiff contact.

use super::{prepare, Prepared};
use crate::case::BasisChoice;
use crate::continuation::{correct, NewtonSettings};
use crate::run::RunError;
use std::path::Path;

/// A refined orbit: the problem with `factor` times the harmonics (and
/// time samples) and the corrected unknowns.
pub struct RefinedPoint {
    /// The refined case, model and problem.
    pub prepared: Prepared,
    /// The point's unknowns on the refined problem.
    pub unknowns: Vec<f64>,
    /// Newton's iterations.
    pub iterations: usize,
}

/// The point `(unknowns, omega)` of `prepared`'s problem on `factor` times
/// its harmonics (`factor ≥ 2`), corrected by Newton at `omega` from the
/// truncated solution; `None` when Newton does not converge there (the
/// refined orbit is then not this one's). `case_dir` as for [`prepare`].
pub fn refined_point(
    prepared: &Prepared,
    case_dir: &Path,
    basis: BasisChoice,
    unknowns: &[f64],
    omega: f64,
    factor: usize,
) -> Result<Option<RefinedPoint>, RunError> {
    let mut case = prepared.case.clone();
    let factor = factor.max(2);
    case.harmonic_balance.harmonics *= factor;
    case.harmonic_balance.time_samples *= factor;
    let fine = prepare(&case, case_dir, basis)?;
    let Some(mut x) = prepared
        .problem
        .layout()
        .embed(unknowns, fine.problem.layout())
    else {
        return Ok(None);
    };
    let newton = NewtonSettings {
        tolerance: case.continuation.tolerance,
        max_iterations: 4 * case.continuation.max_iterations,
        ..Default::default()
    };
    let mut problem = fine.problem;
    let (converged, iterations, _) = correct(&mut problem, &mut x, omega, &newton)?;
    Ok(converged.then(|| RefinedPoint {
        prepared: Prepared { problem, ..fine },
        unknowns: x,
        iterations,
    }))
}
