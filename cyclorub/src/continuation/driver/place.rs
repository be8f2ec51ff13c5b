//! Placing an accepted step in the branch: its events, the observers, and
//! the stops it may bring (the end frequency, solved there exactly; a
//! closed loop; the other sweep met; the start frequency passed).

use super::super::events::{self, End, Event, EventKind};
use super::super::geometry::distance;
use super::super::guards::revisited_point;
use super::super::observer::State;
use super::super::steps::{Accepted, Via};
use super::super::{hertz, Point, Problem, StopReason};
use super::Continuation;

impl<P: Problem> Continuation<'_, P> {
    /// Places an accepted step in the branch, and stops if it must.
    pub(super) fn accept(&mut self, accepted: Accepted) -> Option<usize> {
        let a = self.settings.arc_length;
        let running = self.running.as_mut()?;
        running.policy.accepted();
        let step = running.control.accepted(accepted.iterations);
        let (x, omega) = self.work.scaling.unscaled(&accepted.candidate);
        let index = self.points.len();
        let mut found = Vec::new();
        if let Via::Kink { omega } = accepted.via {
            running.control.resume_after_kink();
            found.push(Event {
                index,
                frequency_hz: hertz(omega),
                kind: EventKind::Kink,
            });
        }
        if (omega - a.end) * self.direction >= 0.0 {
            return self.end_at(x, accepted, step, found);
        }
        found.extend(events::detect(
            &End {
                z: &running.z,
                tangent: &running.tangent,
                orientation: running.orientation,
            },
            &End {
                z: &accepted.candidate,
                tangent: &accepted.tangent,
                orientation: accepted.orientation,
            },
            index,
            self.work.scaling.factors()[x.len()],
            running.policy.keeps_orientation(),
        ));
        if found.iter().any(|e| e.kind == EventKind::BranchPoint) {
            tracing::info!(
                "the branch's orientation changed at {:.4} Hz (point {index}): a branch point was crossed",
                hertz(omega),
            );
        }
        let point = Point::converged(omega, x, accepted.iterations, accepted.residual_norm);
        let state = State {
            tangent: Some(&accepted.tangent),
            step,
            evaluation: Some(&self.work.evaluation),
            sweep_back: self.observers.sweep_back(),
        };
        self.observers.point(index, &point, &state);
        let closed_loop = &self.settings.guards.closed_loop;
        let revisited =
            revisited_point(&self.points, &point, &self.work.scaling, step, closed_loop);
        self.points.push(point);
        self.record(found);
        if let Some(earlier) = revisited {
            return self.stop_after(StopReason::ClosedLoop {
                frequency_hz: hertz(omega),
                earlier_point: earlier,
            });
        }
        let met = self
            .meeting
            .as_mut()
            .and_then(|meeting| meeting(&accepted.candidate, &accepted.tangent));
        if let Some(point) = met {
            return self.stop_after(StopReason::MetOtherSweep {
                frequency_hz: hertz(omega),
                point,
            });
        }
        // Turned back past the start: the branch leaves the range asked
        // for (and would go on toward ω ≤ 0). The point is kept.
        if (omega - a.start) * self.direction < 0.0 {
            return self.stop_after(StopReason::LeftRange {
                frequency_hz: hertz(omega),
            });
        }
        let running = self.running.as_mut()?;
        running
            .sheets
            .push(distance(&accepted.candidate, &running.z));
        running.trail.push(&accepted.candidate);
        if running.policy.tells_pieces() {
            if let Some(piece) = self.work.piece_at(&accepted.candidate) {
                running.trail.push_piece(piece);
            }
        }
        running.z = accepted.candidate;
        running.tangent = accepted.tangent;
        running.orientation = accepted.orientation;
        Some(index)
    }

    /// The step crossed the end frequency: solves exactly there from the
    /// linear interpolation between the last point and the step's, or, if
    /// that fails, keeps the step's point past the end.
    fn end_at(
        &mut self,
        x: Vec<f64>,
        accepted: Accepted,
        step: f64,
        found: Vec<Event>,
    ) -> Option<usize> {
        let a = self.settings.arc_length;
        let (_, omega) = self.work.scaling.unscaled(&accepted.candidate);
        let index = self.points.len();
        let previous = self.points.last()?;
        let weight = (a.end - previous.omega) / (omega - previous.omega);
        let mut x_end: Vec<f64> = previous
            .unknowns
            .iter()
            .zip(&x)
            .map(|(a, b)| a + weight * (b - a))
            .collect();
        let end = self.work.newton(&mut x_end, a.end, &a.newton);
        let (point, tangent, evaluation) = if let Ok((true, iterations, residual_norm)) = end {
            self.total_iterations += iterations;
            let point = Point::converged(a.end, x_end, iterations, residual_norm);
            (point, None, Some(&self.work.evaluation))
        } else {
            let point = Point::converged(omega, x, accepted.iterations, accepted.residual_norm);
            (point, Some(accepted.tangent.as_slice()), None)
        };
        let state = State {
            tangent,
            step,
            evaluation,
            sweep_back: self.observers.sweep_back(),
        };
        self.observers.point(index, &point, &state);
        self.points.push(point);
        self.record(found);
        self.stop_after(StopReason::EndReached)
    }
}
