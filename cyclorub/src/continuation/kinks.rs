//! Turning the kinks of a nonsmooth branch, and leaping over small
//! nonsmooth structures: the ways on that the policies for nonsmooth
//! residuals try when ordinary steps fail (see `policy`).
//!
//! Past a kink the tangent turns by a fixed angle however short the step,
//! up to a reversal of the frequency (a nonsmooth fold), so that halving
//! the step only creeps toward it. The kink is passed instead: located by
//! bisection when the residual tells its pieces, and left along the null
//! vector of the Jacobian beyond it.

use super::corrector::Constraint;
use super::geometry::{along, distance, dot};
use super::guards::retraces;
use super::settings::Settings;
use super::steps::{Accepted, Around, Via};
use super::workspace::Workspace;
use super::{hertz, norm, Problem};

/// Where the piece of the branch through `z` ends along a direction: the
/// last point found on it (`corner`), the first one past it (`past`, on the
/// piece `beyond`), and their distance.
pub(crate) struct Kink {
    corner: Vec<f64>,
    past: Vec<f64>,
    width: f64,
    beyond: u64,
}

/// Bisects the ray `z + s · tangent`, `0 ≤ s ≤ reach`, for the first change
/// of piece, to `resolution · reach`.
fn locate_kink<P: Problem>(
    work: &mut Workspace<'_, P>,
    z: &[f64],
    tangent: &[f64],
    reach: f64,
    resolution: f64,
) -> Option<Kink> {
    let here = work.piece_at(z)?;
    let far = work.piece_at(&along(z, tangent, reach))?;
    if far == here {
        return None;
    }
    let (mut lo, mut hi, mut beyond) = (0.0, reach, far);
    while hi - lo > resolution * reach {
        let middle = 0.5 * (lo + hi);
        let piece = work.piece_at(&along(z, tangent, middle))?;
        if piece == here {
            lo = middle;
        } else {
            (hi, beyond) = (middle, piece);
        }
    }
    Some(Kink {
        corner: along(z, tangent, lo),
        past: along(z, tangent, hi),
        width: hi - lo,
        beyond,
    })
}

/// The way on past a located kink, reached along `tangent`: the null vector
/// of the Jacobian on the next piece, oriented so as to keep the branch's
/// `orientation` (the way into that piece, exact, and blind to further
/// kinks close by, which can mislead a look at the pieces); without it,
/// the side of the kink that lies in the next piece, and failing that, the
/// side where the residual stays small. Returns the direction and whether
/// it was told exactly.
fn way_past<P: Problem>(
    work: &mut Workspace<'_, P>,
    settings: &Settings,
    kink: &Kink,
    (tangent, orientation): (&[f64], Option<f64>),
) -> Option<(Vec<f64>, bool)> {
    work.evaluate_at(&kink.past, true).ok()?;
    let (beyond, beyond_orientation) = work.null_vector(tangent)?;
    let signed = |sign: f64| -> Vec<f64> { beyond.iter().map(|v| sign * v).collect() };
    if let Some(orientation) = orientation {
        return Some((signed(orientation * beyond_orientation), true));
    }
    for scale in settings.kinks.side_scales {
        let length = scale * kink.width;
        let sides = [1.0, -1.0].map(|sign| {
            work.piece_at(&along(&kink.corner, &beyond, sign * length)) == Some(kink.beyond)
        });
        if sides[0] != sides[1] {
            return Some((signed(if sides[0] { 1.0 } else { -1.0 }), true));
        }
    }
    let sign = residual_side(
        work,
        settings,
        &kink.corner,
        &beyond,
        settings.kinks.test_distance * kink.width,
        tangent,
    );
    Some((signed(sign), false))
}

/// Which way along `beyond` from `origin` the branch goes on: the residual
/// at `distance` on either side (on the wrong side it grows at first
/// order); if neither side stands out, the way `tangent` was going.
fn residual_side<P: Problem>(
    work: &mut Workspace<'_, P>,
    settings: &Settings,
    origin: &[f64],
    beyond: &[f64],
    distance: f64,
    tangent: &[f64],
) -> f64 {
    let mut side = |sign: f64| -> f64 {
        match work.evaluate_at(&along(origin, beyond, sign * distance), false) {
            Ok(()) => norm(&work.evaluation.residual),
            Err(_) => f64::INFINITY,
        }
    };
    let (plus, minus) = (side(1.0), side(-1.0));
    let ratio = settings.kinks.side_ratio;
    if plus < ratio * minus {
        1.0
    } else if minus < ratio * plus {
        -1.0
    } else {
        dot(beyond, tangent).signum()
    }
}

/// Where to leave from past the kink ahead of `around.z` (within `probe`)
/// on a residual that tells its pieces: the kink located by bisection and
/// the way past it (again at once if the next piece ends right away, as
/// when several instants switch together). Returns the point to leave
/// from, the direction, and whether the pieces told it exactly.
pub(crate) fn piecewise_way<P: Problem>(
    work: &mut Workspace<'_, P>,
    around: &Around<'_>,
    probe: f64,
    steps: &[f64],
) -> Option<(Vec<f64>, Vec<f64>, bool)> {
    let (settings, kinks) = (around.settings, &around.settings.kinks);
    // No change of piece within the step: an ordinary failure.
    let mut kink = locate_kink(work, around.z, around.tangent, probe, kinks.resolution)?;
    // The orientation of the branch where it comes from: the way on past
    // the kinks keeps it.
    let orientation = match work.evaluate_at(around.z, true) {
        Ok(()) => work.null_vector(around.tangent).map(|(_, o)| o),
        Err(_) => None,
    };
    let mut incoming = around.tangent.to_vec();
    let mut way = None;
    for _ in 0..kinks.max_pivots {
        let (direction, told) = way_past(work, settings, &kink, (&incoming, orientation))?;
        // Does the next piece end at once?
        let reach = kinks.near * steps.iter().cloned().fold(0.0, f64::max);
        let next = locate_kink(work, &kink.past, &direction, reach, kinks.resolution);
        way = Some((kink.past.clone(), direction.clone(), told));
        match next {
            Some(next) => {
                kink = next;
                incoming = direction;
            }
            None => break,
        }
    }
    way
}

/// Where to leave from past a kink within `probe` of `around.z` on a
/// residual that does not tell its pieces: from `z`, along the null vector
/// of the Jacobian at `z + probe · tangent`, toward the side where the
/// residual stays small (never told exactly).
pub(crate) fn nonsmooth_way<P: Problem>(
    work: &mut Workspace<'_, P>,
    around: &Around<'_>,
    probe: f64,
) -> Option<(Vec<f64>, Vec<f64>, bool)> {
    let (z, tangent, settings) = (around.z, around.tangent, around.settings);
    work.evaluate_at(&along(z, tangent, probe), true).ok()?;
    let (beyond, _) = work.null_vector(tangent)?;
    let distance = settings.kinks.test_distance * probe;
    let sign = residual_side(work, settings, z, &beyond, distance, tangent);
    let beyond = beyond.iter().map(|v| sign * v).collect();
    Some((z.to_vec(), beyond, false))
}

/// Leaves `origin` (a kink at `kink_omega`, rad/s) along `beyond`:
/// plane-corrected steps of each length in `steps` in turn. A step must not
/// turn too far (the lax limits), stray from its prediction, go back the
/// way we came (the trail, and, when the way was `told`, pieces already
/// visited: going back beside the branch onto *new* pieces is a cusp of
/// the piecewise-smooth curve) or land on a sheet travelled long before.
/// When the pieces told the way, the other way is tried only if the told
/// one landed on an old sheet; a way straight back is never tried.
pub(crate) fn turn<P: Problem>(
    work: &mut Workspace<'_, P>,
    around: &Around<'_>,
    (origin, beyond, told): (Vec<f64>, Vec<f64>, bool),
    steps: &[f64],
) -> (Option<Accepted>, usize) {
    let (settings, corrector) = (around.settings, around.corrector);
    let limits = &settings.guards.lax;
    let forward = dot(&beyond, around.tangent);
    tracing::debug!(
        "kink at {:.6} Hz: way on told exactly {told}, cosine with the way in {forward:.3}, frequency component {:.3e}",
        hertz(work.scaling.unscaled(&origin).1),
        beyond[beyond.len() - 1],
    );
    let kink_omega = work.scaling.unscaled(&origin).1;
    let mut spent = 0;
    let mut landed = false;
    for sign in [1.0, -1.0] {
        if sign < 0.0 && told && !landed {
            break;
        }
        if sign * forward < -settings.kinks.max_reversal && !(told && sign > 0.0) {
            // Straight back the way we came: not a way on.
            continue;
        }
        let beyond: Vec<f64> = beyond.iter().map(|v| sign * v).collect();
        for &step in steps {
            let predicted = along(&origin, &beyond, step);
            let mut candidate = predicted.clone();
            let plane = Constraint::Plane {
                tangent: &beyond,
                predicted: &predicted,
            };
            let (accepted, used) = corrector.correct(work, plane, &mut candidate);
            spent += used;
            let Some((iterations, residual_norm)) = accepted else {
                continue;
            };
            let Some((next, orientation)) =
                work.oriented_tangent(&beyond, &origin, &candidate, iterations)
            else {
                continue;
            };
            let correction = distance(&candidate, &predicted);
            let cosine = dot(&next, &beyond);
            let back = retraces(
                &candidate,
                &next,
                around.trail,
                step,
                &settings.guards.retrace,
            ) && (!told
                || work
                    .piece_at(&candidate)
                    .is_some_and(|piece| around.visited.contains(&piece)));
            tracing::debug!(
                "kink step {step:.2e} (side {sign}) to {:.6} Hz: turn cosine {cosine:.3}, correction {:.2e}, back {back}",
                hertz(work.scaling.unscaled(&candidate).1),
                correction / step,
            );
            if cosine < limits.min_tangent_cosine
                || correction > limits.max_correction_ratio * step
                || back
            {
                continue;
            }
            if (around.lands)(&candidate) {
                tracing::debug!(
                    "kink step {step:.2e} (side {sign}) landed on a sheet travelled before"
                );
                landed = true;
                continue;
            }
            let via = Via::Kink { omega: kink_omega };
            let accepted = Accepted::new(candidate, (iterations, residual_norm), next, orientation);
            return (Some(accepted.via(via)), spent);
        }
    }
    (None, spent)
}

/// A last resort when the step has shrunk far below the last easy one: a
/// plane-corrected step from `z` along the tangent of each length in
/// `steps` (long ones), accepted if it converges, does not stray further
/// from its prediction than its length, does not go back the way we came
/// and does not land on an old sheet. Small nonsmooth structures (an
/// instant grazing the casing and leaving it again) are passed over rather
/// than resolved.
pub(crate) fn leap<P: Problem>(
    work: &mut Workspace<'_, P>,
    around: &Around<'_>,
    steps: &[f64],
) -> (Option<Accepted>, usize) {
    let (z, tangent) = (around.z, around.tangent);
    let (settings, corrector) = (around.settings, around.corrector);
    let mut spent = 0;
    for &step in steps {
        let predicted = along(z, tangent, step);
        let mut candidate = predicted.clone();
        let plane = Constraint::Plane {
            tangent,
            predicted: &predicted,
        };
        let (accepted, used) = corrector.correct(work, plane, &mut candidate);
        spent += used;
        let Some(converged) = accepted else {
            continue;
        };
        let Some((next, orientation)) = work.oriented_tangent(tangent, z, &candidate, converged.0)
        else {
            continue;
        };
        let retrace = &settings.guards.retrace;
        if distance(&candidate, &predicted) > step
            || retraces(&candidate, &next, around.trail, step, retrace)
            || (around.lands)(&candidate)
        {
            continue;
        }
        let accepted = Accepted::new(candidate, converged, next, orientation);
        return (Some(accepted.via(Via::Leap)), spent);
    }
    (None, spent)
}
