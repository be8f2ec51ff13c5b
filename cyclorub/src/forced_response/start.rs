//! Reaching the first point of a branch when Newton from the linear
//! response fails at the start frequency: by continuation in the load
//! (from no excitation), else in the gap (from a casing the linear response
//! does not touch).

use super::build_problem;
use super::RunError;
use crate::case::{Case, PerContactDof};
use crate::continuation::{correct, ArcLengthSettings};
use crate::hbm::homotopy::{solved_by_load_continuation, LoadPath};
use crate::hbm::HarmonicBalance;
use crate::model::SectorModel;

/// The point at `settings.start` reached by continuation in the load scale
/// `s` from 0 to 1 (see [`LoadHomotopy`](crate::hbm::LoadHomotopy)), from
/// the solution without excitation (Newton from rest), with the run's
/// steps ([`solved_by_load_continuation`]); with the number of points of
/// that continuation. `None` when even that fails (the branch then says
/// why Newton failed at the start).
pub(super) fn start_by_load_continuation(
    problem: &mut HarmonicBalance,
    settings: &ArcLengthSettings,
) -> Result<Option<(Vec<f64>, usize)>, RunError> {
    match solved_by_load_continuation(problem, settings.start, settings)? {
        LoadPath::Reached { unknowns, points } => Ok(Some((unknowns, points))),
        LoadPath::NoRest { residual } => {
            tracing::warn!(
                "no solution without excitation either (relative residual {residual:.2e})"
            );
            Ok(None)
        }
        LoadPath::Stopped(stop) => {
            tracing::warn!("the continuation in the load stopped: {}", stop);
            Ok(None)
        }
    }
}

/// Smallest step of the gap continuation, as a fraction of the way.
const GAP_MIN_STEP: f64 = 1e-6;

/// The point at `settings.start` on the case's gaps, reached by
/// continuation in the gap: every gap widened by `Δ` (the casing out of
/// reach of the linear response at the start frequency, so that the
/// linear response solves it), then `Δ` brought to 0 by steps, Newton from
/// the previous point at each, a step halved when Newton fails and grown
/// after a success. Each step builds the problem on its gaps (the casing is
/// part of the problem). With the number of gaps solved; `None` when the
/// step falls below [`GAP_MIN_STEP`] of the way.
pub(super) fn start_by_gap_continuation(
    case: &Case,
    model: &SectorModel,
    problem: &mut HarmonicBalance,
    settings: &ArcLengthSettings,
) -> Result<Option<(Vec<f64>, usize)>, RunError> {
    let omega = settings.start;
    let linear = problem.linear_solution(omega)?;
    // The peak of any contact coordinate is at most twice the sum of the
    // absolute values of its coefficients; the casing's shape adds its
    // amplitude.
    let casing = problem.casing();
    let shape = casing
        .amplitudes
        .iter()
        .fold(0.0_f64, |m, p| m.max(p.abs()));
    let widening = 2.0 * linear.iter().map(|v| v.abs()).sum::<f64>() + shape;
    if !(widening.is_finite() && widening > 0.0) {
        return Ok(None);
    }
    let gaps = casing.gaps.clone();
    let at = |fraction: f64| -> Result<HarmonicBalance, RunError> {
        let mut widened = case.clone();
        widened.casing.gap =
            PerContactDof::Each(gaps.iter().map(|g| g + fraction * widening).collect());
        Ok(build_problem(&widened, model, case.basis.kind)?.0)
    };
    let mut x = at(1.0)?.linear_solution(omega)?;
    let (mut fraction, mut step, mut points) = (1.0_f64, 0.25_f64, 0);
    while fraction > 0.0 {
        let next = (fraction - step).max(0.0);
        let mut trial = x.clone();
        let solved = if next == 0.0 {
            correct(problem, &mut trial, omega, &settings.newton)?
        } else {
            correct(&mut at(next)?, &mut trial, omega, &settings.newton)?
        };
        if solved.0 {
            x = trial;
            fraction = next;
            points += 1;
            step = (1.5 * step).min(0.25);
        } else {
            step *= 0.5;
            if step < GAP_MIN_STEP {
                tracing::warn!(
                    "the continuation in the gap stopped at {:.3e} m above the case's gaps",
                    fraction * widening
                );
                return Ok(None);
            }
        }
    }
    Ok(Some((x, points)))
}
