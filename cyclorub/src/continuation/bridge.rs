//! A fixed-frequency run's bridge (docs/design.md §7): where Newton fails
//! between two frequencies asked for, the branch followed in arc length
//! from the last point reached until it crosses the next one, stopped
//! where it goes too far back, comes back onto the sweep's own path
//! ([`SweptPath`]) or reaches its cap of points.

use super::driver::Continuation;
use super::geometry::Scaling;
use super::newton::NewtonSettings;
use super::settings::ArcLengthSettings;
use super::swept_path::SweptPath;
use super::{hertz, Interrupt, Point, Problem, Settings, StopReason};

/// How far behind the fold a bridge may go, in the width of the
/// frequencies' range.
const BEHIND: f64 = 0.25;

/// The most points a bridge takes (the jump off the default case's
/// plateau takes 64).
const MOST_BRIDGE_POINTS: usize = 200;

/// The corrector's tolerance on a bridge's points for a run's `tolerance`:
/// a hundred times looser, at most 1e-6 (or the run's, when that is looser).
/// They are a path to the frequency asked for, not results: a point on the
/// branch to 1e-6 of the load is on the same branch, and the last Newton
/// iteration of each (a quarter of a bridge's work on the mistuned default
/// case) only adds digits nobody reads. The point reached at the frequency
/// asked for is then solved to the run's tolerance.
pub(super) fn bridge_tolerance(tolerance: f64) -> f64 {
    (100.0 * tolerance).min(1e-6).max(tolerance)
}

/// The branch through the converged `(x, omega)` followed in arc length
/// away from `behind` until it reaches `to` (the continuation's end, solved
/// there exactly), at most [`BEHIND`] of `range`'s width behind the fold
/// and [`MOST_BRIDGE_POINTS`] points: its iterations, its solution at `to`
/// and the points it travelled; `None` when it stops otherwise (gone too
/// far back, come back onto the sweep's `path` round a loop, the step too
/// small, the cap, an interruption or a failed evaluation; said in the
/// log).
pub(super) fn bridge<P: Problem>(
    problem: &mut P,
    (x, omega): (&[f64], f64),
    behind: (Vec<f64>, f64),
    to: f64,
    range: (f64, f64),
    arc_length: ArcLengthSettings,
    (interrupt, path): (Option<&Interrupt>, &SweptPath),
) -> Option<(usize, Vec<f64>, Vec<Point>)> {
    // Behind the fold, a quarter of the frequencies' range (a fold's
    // back-turn can pass the frequencies already solved; a branch that
    // goes further back is not coming back soon), never below half the
    // fold's frequency.
    let (low, high) = (range.0.min(omega), range.1.max(omega));
    let margin = BEHIND * (high - low).max((to - omega).abs());
    let start = if to > omega {
        (omega - margin).max(0.5 * omega)
    } else {
        omega + margin
    };
    let settings = ArcLengthSettings {
        start,
        end: to,
        max_points: arc_length.max_points.min(MOST_BRIDGE_POINTS),
        newton: NewtonSettings {
            tolerance: bridge_tolerance(arc_length.newton.tolerance),
            ..arc_length.newton
        },
        ..arc_length
    };
    let settings: Settings = settings.into();
    // The driver's own scaling, for the path's points.
    let scaling = Scaling::new(&*problem, &settings);
    let mut driver = match Continuation::from_point(problem, x.to_vec(), omega, behind, settings) {
        Ok(driver) => driver.with_meeting(path.meeting(&scaling, (x, omega))),
        Err(error) => {
            tracing::debug!("no arc-length bridge from {:.6} Hz: {error}", hertz(omega));
            return None;
        }
    };
    if let Some(interrupt) = interrupt {
        driver = driver.with_interrupt(interrupt.clone());
    }
    let branch = driver.finish();
    let last = branch.points.last()?;
    #[allow(clippy::float_cmp)] // the end is solved at exactly `to`
    let reached = branch.stop == StopReason::EndReached && last.converged && last.omega == to;
    if reached {
        tracing::info!(
            "{:.4} Hz: Newton did not converge from {:.4} Hz; the branch followed in arc length to it ({} points)",
            hertz(to),
            hertz(omega),
            branch.points.len()
        );
        Some((
            branch.total_iterations,
            last.unknowns.clone(),
            branch.points.clone(),
        ))
    } else if let StopReason::MetOtherSweep {
        frequency_hz,
        point,
    } = branch.stop
    {
        // The driver's stop for a `meeting`, here the sweep's own path
        // (`point` indexes it), said in the bridge's own words.
        tracing::info!(
            "{:.4} Hz: Newton did not converge from {:.4} Hz, and the branch followed in arc length from there came back at {frequency_hz:.4} Hz onto the sweep's own path ({} points; past its point at {:.4} Hz): a loop, which does not reach it",
            hertz(to),
            hertz(omega),
            branch.points.len(),
            path.frequency_hz(point).unwrap_or(f64::NAN),
        );
        None
    } else {
        tracing::info!(
            "{:.4} Hz: Newton did not converge from {:.4} Hz, and the branch followed in arc length from there did not reach it ({} points): {}",
            hertz(to),
            hertz(omega),
            branch.points.len(),
            branch.stop.with_advice()
        );
        None
    }
}
