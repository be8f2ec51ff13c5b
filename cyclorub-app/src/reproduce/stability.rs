//! The stability of a study's runs as the report gives it: how many points
//! grow, over which stretches of the branch and in which symmetry classes,
//! and the markers where stability changes (see `cyclorub::stability`).
//!
//! The reduced run on the symmetry basis is checked class by class (its
//! classes together are the full wheel's spectrum); the full wheel in
//! physical coordinates is checked by Hill's method without symmetry only
//! when its eigenproblem is small ([`FULL_WHEEL_EIGENPROBLEM`]), and is
//! otherwise reported as not computed, with the reason.

use cyclorub::case::BasisChoice;
use cyclorub::run::{further_crossings, group_markers, MarkerRecord, RunOutcome, StabilityStatus};
use cyclorub::stability::{MarkerKind, StabilitySettings};
use serde::Serialize;
use std::f64::consts::PI;

/// The largest eigenproblem (`2 · dofs · N · (2H + 1)`) of the full wheel's
/// check without symmetry in a reproduction. A dense eigenproblem of that
/// size takes about a second, and the full branch has hundreds of points;
/// above it (every paper case: 5040 for N = 24 with `N_h = 10`) the
/// physical run's stability is reported as not computed.
pub const FULL_WHEEL_EIGENPROBLEM: usize = 1000;

/// The check of the symmetry-basis run: the library's defaults.
pub fn symmetry_settings() -> StabilitySettings {
    StabilitySettings::default()
}

/// The check of the full wheel's run: refused above
/// [`FULL_WHEEL_EIGENPROBLEM`].
pub fn full_wheel_settings() -> StabilitySettings {
    StabilitySettings {
        largest_eigenproblem: FULL_WHEEL_EIGENPROBLEM,
        ..StabilitySettings::default()
    }
}

/// A stretch of consecutive unstable points along the branch.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct UnstableStretch {
    /// First point of the stretch (index along the branch).
    pub first_point: usize,
    /// Last point of the stretch.
    pub last_point: usize,
    /// Frequency of the first point, Hz.
    pub from_hz: f64,
    /// Frequency of the last point, Hz.
    pub to_hz: f64,
    /// Lowest frequency in the stretch, Hz (the branch may fold inside it).
    pub low_hz: f64,
    /// Highest frequency in the stretch, Hz.
    pub high_hz: f64,
    /// Unstable points in the stretch.
    pub points: usize,
    /// The classes (`σ ≥ 0`, the nodal diameter of the perturbation; its
    /// conjugate class `−σ` grows with it) with a growing exponent
    /// somewhere in the stretch; empty on the whole wheel solved without
    /// classes.
    pub classes: Vec<i64>,
    /// Largest real part of an exponent in the stretch, 1/s.
    pub largest_growth: f64,
}

/// How Hill's method was applied to a run (`report.json`'s
/// `stability.method`, in the words it has always held).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
pub enum HillMethod {
    /// Per symmetry class of the run's basis.
    #[serde(rename = "symmetry_classes")]
    SymmetryClasses,
    /// On the whole wheel, without symmetry (the physical basis).
    #[serde(rename = "full_wheel")]
    FullWheel,
    /// Not applied (the check was not computed).
    #[serde(rename = "")]
    None,
}

/// What a run's stability check gave, for the report.
#[derive(Clone, Debug, Serialize)]
pub struct StabilitySummary {
    /// Computed, not computed (asked but refused or failed: see `reason`)
    /// or not asked; report.json holds the library's words.
    pub status: StabilityStatus,
    /// Why it was not computed or not asked.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub reason: Option<String>,
    /// How Hill's method was applied (absent, `""` in report.json, when
    /// not computed).
    pub method: HillMethod,
    /// Harmonics of Hill's truncation.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub harmonics: Option<usize>,
    /// Converged points checked.
    pub points: usize,
    /// Converged points with a growing exponent.
    pub unstable_points: usize,
    /// Points solved by Hill's method (the others were off contact and
    /// took the linear wheel's exponents).
    pub points_by_hill: usize,
    /// The unstable stretches along the branch.
    pub unstable: Vec<UnstableStretch>,
    /// Where stability changes (see `cyclorub::stability::Marker`), with
    /// the amplitude there.
    pub markers: Vec<MarkerRecord>,
    /// Time of the check, s.
    pub time_s: f64,
}

impl StabilitySummary {
    /// Not asked for, and why.
    pub fn not_asked(reason: &str) -> Self {
        Self {
            status: StabilityStatus::NotAsked,
            reason: Some(reason.into()),
            method: HillMethod::None,
            harmonics: None,
            points: 0,
            unstable_points: 0,
            points_by_hill: 0,
            unstable: Vec::new(),
            markers: Vec::new(),
            time_s: 0.0,
        }
    }

    /// The summary of a run's check; `tolerance` is the settings' (a real
    /// part above `tolerance · ω` grows).
    pub fn from_outcome(outcome: &RunOutcome, basis: BasisChoice, tolerance: f64) -> Self {
        let record = &outcome.record.stability;
        let method = match basis {
            BasisChoice::Physical => HillMethod::FullWheel,
            _ => HillMethod::SymmetryClasses,
        };
        let mut summary = Self {
            status: record.status,
            reason: record.reason.clone(),
            method,
            harmonics: record.harmonics,
            points: 0,
            unstable_points: 0,
            points_by_hill: record.points_by_hill,
            unstable: Vec::new(),
            markers: record.markers.clone(),
            time_s: record.time_s,
        };
        let Some(data) = &outcome.data.stability else {
            return summary;
        };
        let by_class = method == HillMethod::SymmetryClasses;
        let mut current: Option<UnstableStretch> = None;
        for (index, point) in outcome.data.points.iter().enumerate() {
            if !point.converged {
                continue;
            }
            let Some(&stable) = data.stable.get(index) else {
                continue;
            };
            summary.points += 1;
            if stable {
                summary.unstable.extend(current.take());
                continue;
            }
            summary.unstable_points += 1;
            let omega = 2.0 * PI * point.frequency_hz;
            let mut growth = f64::NEG_INFINITY;
            let mut classes = Vec::new();
            if let Some(row) = data.leading_re.get(index) {
                for (&sigma, leading) in data.classes.iter().zip(row) {
                    let re = leading.first().copied().unwrap_or(f64::NAN);
                    if re > growth {
                        growth = re;
                    }
                    if by_class && sigma >= 0 && re > tolerance * omega {
                        classes.push(sigma);
                    }
                }
            }
            let stretch = current.get_or_insert_with(|| UnstableStretch {
                first_point: index,
                last_point: index,
                from_hz: point.frequency_hz,
                to_hz: point.frequency_hz,
                low_hz: point.frequency_hz,
                high_hz: point.frequency_hz,
                points: 0,
                classes: Vec::new(),
                largest_growth: f64::NEG_INFINITY,
            });
            stretch.last_point = index;
            stretch.to_hz = point.frequency_hz;
            stretch.low_hz = stretch.low_hz.min(point.frequency_hz);
            stretch.high_hz = stretch.high_hz.max(point.frequency_hz);
            stretch.points += 1;
            stretch.largest_growth = stretch.largest_growth.max(growth);
            stretch.classes.extend(classes);
            stretch.classes.sort_unstable();
            stretch.classes.dedup();
        }
        summary.unstable.extend(current);
        summary
    }

    /// The whole branch is stable (computed, no point grows).
    pub fn stable(&self) -> bool {
        self.status == StabilityStatus::Computed && self.unstable_points == 0
    }

    /// One short cell of the report's table.
    pub fn cell(&self) -> String {
        match self.status {
            StabilityStatus::Computed if self.unstable_points == 0 => {
                format!("stable ({} points)", self.points)
            }
            StabilityStatus::Computed => {
                const SHOWN: usize = 3;
                let mut stretches: Vec<String> = self
                    .unstable
                    .iter()
                    .take(SHOWN)
                    .map(|s| {
                        format!(
                            "{}{}",
                            hz_range(s.low_hz, s.high_hz),
                            classes_text(&s.classes, " (σ = ", ")")
                        )
                    })
                    .collect();
                if self.unstable.len() > SHOWN {
                    stretches.push(format!("{} more stretches", self.unstable.len() - SHOWN));
                }
                format!(
                    "**unstable** at {} of {} points: {}",
                    self.unstable_points,
                    self.points,
                    stretches.join("; ")
                )
            }
            StabilityStatus::NotComputed => "not computed (see below)".into(),
            StabilityStatus::NotAsked => "—".into(),
        }
    }

    /// The markers, those of one kind and direction within 1e-4 in
    /// frequency of each other (a set of diameters crossing at first
    /// contact) on one line each; at most `shown` lines.
    pub fn marker_lines(&self, shown: usize) -> Vec<String> {
        let groups = group_markers(&self.markers);
        let mut lines: Vec<String> = groups
            .iter()
            .take(shown)
            .map(|group| {
                let (first, m) = (group.first(), &group.first().marker);
                let classes = group.nodal_diameters();
                let exponent = group
                    .exponent()
                    .map(|e| format!(", exponent {:.3} {:+.3}i 1/s", e.re, e.im))
                    .unwrap_or_default();
                format!(
                    "{}{} at {:.4} Hz, amplitude {:.3e} m{exponent}: stability {}",
                    kind_text(m.kind),
                    classes_text(&classes, ", class σ = ", ""),
                    m.frequency_hz,
                    first.amplitude_m,
                    match (m.loses_stability, m.class_changes) {
                        (true, true) => "lost",
                        (false, true) => "regained",
                        (true, false) => "lost by one more exponent (the class was unstable)",
                        (false, false) => "still lost (one growing exponent fewer)",
                    }
                )
            })
            .collect();
        if groups.len() > shown {
            lines.push(format!(
                "… {} more markers in report.json",
                groups[shown..]
                    .iter()
                    .map(|g| g.records.len())
                    .sum::<usize>()
            ));
        }
        let further = further_crossings(&self.markers);
        if further > 0 {
            lines.push(format!(
                "and {further} Neimark–Sacker crossings of further exponents in classes already unstable"
            ));
        }
        lines
    }

    /// Counts of the events among the markers by kind, e.g. `2 folds, 4
    /// branch points`.
    pub fn marker_counts(&self) -> String {
        let kinds = [
            (MarkerKind::Fold, "fold", "folds"),
            (MarkerKind::BranchPoint, "branch point", "branch points"),
            (MarkerKind::RealCrossing, "real crossing", "real crossings"),
            (
                MarkerKind::PeriodDoubling,
                "period doubling",
                "period doublings",
            ),
            (
                MarkerKind::NeimarkSacker,
                "Neimark–Sacker",
                "Neimark–Sacker",
            ),
            (MarkerKind::Jump, "jump", "jumps"),
        ];
        let parts: Vec<String> = kinds
            .iter()
            .filter_map(|&(kind, one, many)| {
                let n = self
                    .markers
                    .iter()
                    .filter(|m| m.marker.kind == kind && m.marker.is_event())
                    .count();
                match n {
                    0 => None,
                    1 => Some(format!("1 {one}")),
                    _ => Some(format!("{n} {many}")),
                }
            })
            .collect();
        if parts.is_empty() {
            "no marker".into()
        } else {
            parts.join(", ")
        }
    }
}

fn kind_text(kind: MarkerKind) -> &'static str {
    match kind {
        MarkerKind::Fold => "fold",
        MarkerKind::BranchPoint => "branch point",
        MarkerKind::RealCrossing => "real crossing",
        MarkerKind::PeriodDoubling => "period doubling",
        MarkerKind::NeimarkSacker => "Neimark–Sacker",
        MarkerKind::Jump => "jump",
    }
}

fn hz_range(from: f64, to: f64) -> String {
    if (from - to).abs() < 5e-4 {
        format!("{from:.3} Hz")
    } else {
        format!("{from:.3}–{to:.3} Hz")
    }
}

/// `σ = 1, 2, 3` with a prefix and suffix, long runs of consecutive
/// classes shortened (`1–4, 7`); empty when there is none.
fn classes_text(classes: &[i64], prefix: &str, suffix: &str) -> String {
    if classes.is_empty() {
        return String::new();
    }
    let mut parts = Vec::new();
    let mut start = classes[0];
    let mut end = start;
    for &c in &classes[1..] {
        if c == end + 1 {
            end = c;
            continue;
        }
        parts.push(run_text(start, end));
        start = c;
        end = c;
    }
    parts.push(run_text(start, end));
    format!("{prefix}{}{suffix}", parts.join(", "))
}

fn run_text(start: i64, end: i64) -> String {
    match end - start {
        0 => start.to_string(),
        1 => format!("{start}, {end}"),
        _ => format!("{start}–{end}"),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn classes_are_written_as_runs() {
        assert_eq!(classes_text(&[], "σ = ", ""), "");
        assert_eq!(classes_text(&[0], "σ = ", ""), "σ = 0");
        assert_eq!(classes_text(&[1, 2], "σ = ", ""), "σ = 1, 2");
        assert_eq!(
            classes_text(&[1, 2, 3, 4, 7, 9, 10], "(σ = ", ")"),
            "(σ = 1–4, 7, 9, 10)"
        );
    }

    #[test]
    fn a_branch_of_one_frequency_is_one_frequency() {
        assert_eq!(hz_range(127.5, 127.5001), "127.500 Hz");
        assert_eq!(hz_range(127.5, 130.0), "127.500–130.000 Hz");
    }
}
