//! One attempt from the last point of the branch: predict along the
//! tangent (or the last chord, with the secant predictor), correct on the
//! plane through the prediction, and judge the
//! result against the policy's turn limits and the guards; refused, the
//! policy may find another way on (a kink, a leap).

use super::super::corrector::Constraint;
use super::super::geometry::distance;
use super::super::guards::retraces;
use super::super::predictor::{predict, secant, unit_chord};
use super::super::steps::{Accepted, Around, Refused};
use super::super::{hertz, Problem};
use super::crossing::{crosses_branch_point, Reversal};
use super::Continuation;

impl<P: Problem> Continuation<'_, P> {
    /// One attempt from the last point: an ordinary step, or, refused, the
    /// policy's other way on. `None`: the step must be shortened.
    pub(super) fn attempt(&mut self) -> Option<Accepted> {
        let settings = &self.settings;
        let running = self.running.as_mut()?;
        let work = &mut self.work;
        let step = running.control.step();
        let (z, tangent) = (&running.z, &running.tangent);
        // Along the last chord for a secant predictor (its turn measured
        // to the next chord), else along the tangent.
        let chords = running.policy.predicts_along_chords(settings);
        let secant = chords
            .then(|| secant(running.trail.slices().0, z, tangent, step))
            .flatten();
        let direction = secant.as_deref().unwrap_or(tangent);
        let predicted = predict(z, direction, step);
        let mut candidate = predicted.clone();
        let plane = Constraint::Plane {
            tangent: direction,
            predicted: &predicted,
        };
        let (converged, spent) = self.corrector.correct(work, plane, &mut candidate);
        self.total_iterations += spent;
        // After Newton steps the solver may hold the factors of the last
        // one (see `oriented_tangent`).
        let next = converged.and_then(|(iterations, _)| {
            work.oriented_tangent(direction, z, &candidate, iterations)
        });
        let correction = distance(&candidate, &predicted);
        let limits = running.policy.turn_limits(settings);
        // How far beyond the admissible turn this step went (> 1: too far).
        let chord = secant
            .is_some()
            .then(|| unit_chord(z, &candidate))
            .flatten();
        let turn = next.as_ref().map(|(t, _)| {
            let t = chord.as_deref().unwrap_or(t);
            let cosine: f64 = t.iter().zip(direction).map(|(a, b)| a * b).sum();
            ((1.0 - cosine) / (1.0 - limits.min_tangent_cosine))
                .max(correction / (limits.max_correction_ratio * step))
        });
        let control = &running.control;
        let turning_too_fast = turn.is_some_and(|t| t > 1.0) && !control.at_floor(step);
        // Reversing the orientation went back along the branch or onto a
        // close sheet, unless the step is short enough to cross a branch
        // point. Smooth residuals only: the kinks of a piecewise one keep
        // it by construction, and refusing there stalled DLFT branches.
        let may_flip = step <= settings.guards.branch_point_step * control.good_step()
            || control.at_floor(step);
        let flipped = running.policy.keeps_orientation()
            && next
                .as_ref()
                .is_some_and(|(_, o)| o * running.orientation < 0.0);
        let (trail, visited) = running.trail.slices();
        // Near the tip of a fold, the sheet beyond runs close to and against
        // the one travelled: on a tightly followed branch that is no sign of
        // a jump.
        let back = running.policy.refuses_retrace()
            && next.as_ref().is_some_and(|(t, _)| {
                retraces(&candidate, t, trail, step, &settings.guards.retrace)
            });
        let (sheets, points) = (&running.sheets, &self.points);
        let lands = |candidate: &[f64]| sheets.lands(points, z, candidate);
        // A longer reversing step crosses a branch point if the branch goes
        // on continuously through the reversal (see `crossing`).
        let crossed = flipped
            && !may_flip
            && !turning_too_fast
            && !back
            && converged.is_some()
            && next.is_some()
            && !lands(&candidate)
            && {
                let reversal = Reversal {
                    z,
                    tangent,
                    orientation: running.orientation,
                    step,
                    candidate: &candidate,
                };
                let (crossed, spent) =
                    crosses_branch_point(work, &self.corrector, settings, &reversal);
                self.total_iterations += spent;
                crossed
            };
        let refused_first = turning_too_fast || back || (flipped && !may_flip && !crossed);
        let landed = converged.is_some() && next.is_some() && !refused_first && lands(&candidate);
        if let (Some(converged), Some((next, orientation)), false) =
            (converged, next, refused_first || landed)
        {
            return Some(Accepted::new(candidate, converged, next, orientation));
        }
        // Why steps fail, for `RUST_LOG=debug` when a branch stalls.
        tracing::debug!(
            "step {step:.2e} from {:.6} Hz refused: corrector {}, turn {:.2}, retrace {back}, orientation reversed {flipped}, landed on an old sheet {landed}",
            hertz(work.scaling.unscaled(z).1),
            if converged.is_some() { "converged" } else { "failed" },
            turn.unwrap_or(f64::NAN),
        );
        running.control.failed();
        let around = Around {
            settings,
            corrector: &self.corrector,
            z,
            tangent,
            trail,
            visited,
            lands: &lands,
        };
        let refused = Refused {
            step,
            good_step: running.control.good_step(),
            turn,
            turning_too_fast,
        };
        let (outcome, spent) = running.policy.recover(work, &around, &refused);
        self.total_iterations += spent;
        outcome
    }
}
