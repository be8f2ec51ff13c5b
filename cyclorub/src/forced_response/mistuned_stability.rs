//! Whether a mistuned wheel's points are checked (issue 44): a mistuned
//! wheel has one symmetry class, the whole wheel, so its Hill problem is
//! `N` times a tuned class's on every contact dof and harmonic; where that
//! is beyond the stability check's largest eigenproblem (finite-element
//! sectors, many contact dofs) the check is left out with a reason that
//! says what it would cost.

use super::Prepared;
use crate::model::FULL_WHEEL_MAX_DOFS;
use crate::stability::{HillSolver, StabilitySettings};

/// CPU seconds per point of the condensed check of the default mistuned
/// case (N = 24, one contact dof, 2H + 1 = 21: a contact resolvent of
/// size 504), release build (docs/stability.md; 5.8–6.6 s for
/// `cyclorub stability --point` at 126, 128, 130 Hz, 0.3 s of it the
/// process): what the estimate of a larger wheel's cost scales from.
const SECONDS_AT_REFERENCE: f64 = 5.5;

/// The contact resolvent's size that [`SECONDS_AT_REFERENCE`] was measured at.
const REFERENCE_SIZE: f64 = 504.0;

/// A continuation's points are checked only where a point's check is
/// estimated below this many CPU seconds: a mistuned branch has thousands
/// of points (docs/mistuning.md, "A long branch").
const CONTINUATION_SECONDS: f64 = 0.5;

/// Why the points of `prepared`'s mistuned wheel are not checked with
/// `settings`, or `None` when they are (a tuned wheel always is);
/// `continuation` when the points come from continuation (not fixed
/// frequencies).
pub(crate) fn mistuned_stability_refusal(
    prepared: &Prepared,
    settings: &StabilitySettings,
    continuation: bool,
) -> Option<String> {
    if !prepared.model.is_mistuned() {
        return None;
    }
    let layout = prepared.problem.layout();
    let sectors = layout.sectors;
    let dofs = prepared.model.dofs_per_sector();
    let contact = layout.contact_dofs;
    let harmonics = 2 * settings.harmonics.unwrap_or(layout.harmonics()) + 1;
    let wheel_dofs = sectors.saturating_mul(dofs);
    if wheel_dofs > FULL_WHEEL_MAX_DOFS {
        return Some(format!(
            "not checked on this mistuned wheel: its one symmetry class is the whole wheel, whose \
             {wheel_dofs} dofs ({sectors} sectors × {dofs}) are above the {FULL_WHEEL_MAX_DOFS} \
             the stability check assembles densely"
        ));
    }
    // What `Stability::full_wheel` refuses: the condensed solver's
    // `2 · contact dofs · N · (2H + 1)`, the dense ones' `2 · dofs · …`.
    let per_sector = match settings.solver {
        HillSolver::Condensed => contact,
        _ => dofs,
    };
    let size = 2usize
        .saturating_mul(per_sector)
        .saturating_mul(sectors)
        .saturating_mul(harmonics);
    let resolvent = contact.saturating_mul(sectors).saturating_mul(harmonics);
    let seconds = SECONDS_AT_REFERENCE * (resolvent as f64 / REFERENCE_SIZE).powi(3);
    if size <= settings.largest_eigenproblem {
        if continuation && seconds > CONTINUATION_SECONDS {
            return Some(format!(
                "not checked along this mistuned branch: its one symmetry class is the whole \
                 wheel, about {seconds:.1} s of CPU a point (a contact resolvent of size \
                 {resolvent}), and a mistuned branch has thousands of points; `cyclorub run \
                 --at-hz …` checks the points at fixed frequencies, `cyclorub stability RESULTS \
                 --point I` one point of this run"
            ));
        }
        return None;
    }
    Some(format!(
        "not checked on this mistuned wheel: its one symmetry class is the whole wheel, a Hill \
         problem of size {size} (2 × {per_sector} dofs × {sectors} sectors × {harmonics} \
         harmonics), above the largest eigenproblem {limit}; its condensed check factors a \
         contact resolvent of size {resolvent} ({contact} contact dofs × {sectors} × {harmonics}) \
         at each of the contour's nodes, about {seconds:.0} s of CPU a point (cubic in the size, from \
         {SECONDS_AT_REFERENCE} s at size 504); `cyclorub stability RESULTS --point I \
         --largest-eigenproblem {size}` checks one point",
        limit = settings.largest_eigenproblem,
    ))
}
