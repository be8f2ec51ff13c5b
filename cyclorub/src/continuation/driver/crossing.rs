//! A step that reverses the branch's orientation has crossed a branch
//! point, or jumped onto a close sheet that turns the tangent too little to
//! be seen otherwise. Bisecting the step for where the orientation changes
//! tells them apart: through a branch point the corrected points go on
//! continuously, while a jump leaves a gap as wide as the sheets are apart.
//!
//! The test cannot tell the branch that goes on from one that crosses it
//! (both are continuous), but the step that reversed the orientation was
//! predicted along the tangent and corrected far from the branch point,
//! where the branch ahead is the one that goes on. Creeping up to the
//! branch point with ever shorter steps instead leaves points where the
//! Jacobian is nearly singular along the other branch, and on the full
//! wheel they drifted onto it (the traveling wave's symmetry-breaking
//! branch points on the open fan).

use super::super::corrector::{Constraint, Corrector};
use super::super::geometry::distance;
use super::super::predictor::predict;
use super::super::settings::Settings;
use super::super::workspace::Workspace;
use super::super::Problem;

/// The branch around the step that reversed the orientation.
pub(super) struct Reversal<'r> {
    /// The last point, scaled.
    pub(super) z: &'r [f64],
    /// The unit tangent there.
    pub(super) tangent: &'r [f64],
    /// The orientation there.
    pub(super) orientation: f64,
    /// The step that reversed it.
    pub(super) step: f64,
    /// Its corrected point.
    pub(super) candidate: &'r [f64],
}

/// Whether `reversal` crossed a branch point (see the module's header), and
/// the corrector iterations spent telling.
pub(super) fn crosses_branch_point<P: Problem>(
    work: &mut Workspace<'_, P>,
    corrector: &Corrector,
    settings: &Settings,
    reversal: &Reversal<'_>,
) -> (bool, usize) {
    let Reversal {
        z,
        tangent,
        orientation,
        step,
        candidate,
    } = *reversal;
    let guards = &settings.guards;
    let (mut low, mut high) = (0.0, step);
    let (mut before, mut after) = (z.to_vec(), candidate.to_vec());
    let mut spent = 0;
    for _ in 0..guards.branch_point_bisections {
        let middle = 0.5 * (low + high);
        let predicted = predict(z, tangent, middle);
        let mut point = predicted.clone();
        let plane = Constraint::Plane {
            tangent,
            predicted: &predicted,
        };
        let (converged, iterations) = corrector.correct(work, plane, &mut point);
        spent += iterations;
        let reversed = converged
            .and_then(|(iterations, _)| work.oriented_tangent(tangent, z, &point, iterations))
            .map(|(_, o)| o * orientation < 0.0);
        // Each new bracket is continuous with the one it replaces, so that
        // the whole step is, not only the reversal.
        let continuous = |side: &[f64]| {
            distance(&point, side) <= guards.branch_point_continuity * 0.5 * (high - low)
        };
        match reversed {
            Some(true) if continuous(&after) => (high, after) = (middle, point),
            Some(false) if continuous(&before) => (low, before) = (middle, point),
            // A gap, or a corrector that fails on the way: no evidence of
            // a continuous branch.
            _ => return (false, spent),
        }
    }
    let continuous = distance(&before, &after) <= guards.branch_point_continuity * (high - low);
    // Observers read the last evaluation: the candidate's again, with its
    // Jacobians.
    (
        continuous && work.evaluate_at(candidate, true).is_ok(),
        spent,
    )
}
