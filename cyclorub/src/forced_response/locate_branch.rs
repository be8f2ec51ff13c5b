//! A branch's markers located on it with the case's Newton settings, said
//! in the log (docs/design.md §10, "Located"): the front door's call of
//! [`locate_markers`].

use super::chord::ChordMetric;
use super::locate_markers::{locate_markers, Located, BRACKET_HZ};
use super::prepare::{frequency_range, length_scale};
use crate::case::Case;
use crate::continuation::{NewtonSettings, Point, Problem};
use crate::hbm::HarmonicBalance;
use crate::stability::{BranchStability, Stability, StabilityError, StabilitySettings};
use std::f64::consts::PI;
use std::time::Instant;

/// [`locate_markers`] on a branch's stability, Newton with the case's
/// `[continuation]` tolerance and iterations; what it did is said in the
/// log (markers located, trial points solved, time).
pub fn locate_branch_markers(
    check: &Stability<'_>,
    problem: &HarmonicBalance,
    points: &[Point],
    stability: &mut BranchStability,
    case: &Case,
) -> Located {
    let clock = Instant::now();
    let newton = NewtonSettings {
        tolerance: case.continuation.tolerance,
        max_iterations: case.continuation.max_iterations,
        ..NewtonSettings::default()
    };
    // The continuation's metric: the case's gap and frequency range (the
    // points' span where the case gives no range); a case without a gap
    // (refused before any branch) measures in metres.
    let length = case
        .casing()
        .ok()
        .zip(points.first())
        .and_then(|(casing, first)| length_scale(&casing, &first.unknowns).ok())
        .unwrap_or(1.0);
    let range = frequency_range(case)
        .map(|(start, end)| (2.0 * PI * start, 2.0 * PI * end))
        .unwrap_or_else(|_| {
            points
                .iter()
                .fold((f64::INFINITY, f64::NEG_INFINITY), |(l, h), p| {
                    (l.min(p.omega), h.max(p.omega))
                })
        });
    let metrics = ChordMetric::in_order(
        ChordMetric::continuation(length, range),
        problem.is_smooth(),
    );
    let report = locate_markers(
        check,
        problem,
        points,
        &mut stability.markers,
        &newton,
        metrics,
    );
    let mut index = 0;
    stability.markers.retain(|_| {
        index += 1;
        !report.unmatched.iter().any(|(i, _)| *i == index - 1)
    });
    if !stability.markers.is_empty() {
        let unmatched = match report.unmatched.len() {
            0 => String::new(),
            n => format!(", {n} removed as not crossings (the tracking paired two exponents)"),
        };
        tracing::info!(
            "stability: {} of {} events located to {BRACKET_HZ:.0e} Hz, {} left where interpolation placed them{unmatched} ({} markers in all; {} branch points solved, {:.2} s)",
            report.located,
            report.events - report.unmatched.len(),
            report.failed.len(),
            stability.markers.len(),
            report.solves,
            clock.elapsed().as_secs_f64()
        );
    }
    report
}

impl super::Solution {
    /// `stability`'s markers located on this solution's branch (checked
    /// with `settings`, as the run checked it): [`locate_branch_markers`].
    pub fn locate_markers(
        &self,
        settings: &StabilitySettings,
        stability: &mut BranchStability,
    ) -> Result<Located, StabilityError> {
        let check = self.stability_check(settings)?;
        Ok(locate_branch_markers(
            &check,
            &self.problem,
            &self.branch.points,
            stability,
            &self.case,
        ))
    }
}
