//! Bifurcated branches as a results folder keeps them (docs/branches.md):
//! each branch point switched at (or why not), its sides point by point
//! ([`BifurcatedBranchData`]: the `/branches` group of `results.h5`) and
//! their summary ([`BranchSummary`]: `run.json`'s `branches` entry and
//! `branches/branches.json`). Switching at a branch point again replaces
//! its earlier record ([`merge`]).

use serde::{Deserialize, Serialize};

/// One side of a bifurcated branch, point by point (the branch point itself
/// not included).
#[derive(Clone, Debug, PartialEq)]
pub struct BifurcatedSide {
    /// `+1` along the class's null vector, `−1` against it.
    pub direction: f64,
    /// Frequency of each point, Hz.
    pub frequency_hz: Vec<f64>,
    /// Each point's stability in the enlarged basis's own classes (`None`:
    /// not checked).
    pub stable: Vec<Option<bool>>,
    /// `[point][sector]`: the observed dof's largest displacement over the
    /// period (toward the casing) on every sector, m.
    pub sector_amplitudes_m: Vec<Vec<f64>>,
    /// Why the side stopped, as `branches.json` writes it (`reason` and its
    /// details).
    pub stop: serde_json::Value,
    /// Why the side stopped, in words.
    pub stop_reason: String,
}

/// A branch point of the symmetric branch: the bifurcated branch switched
/// to there, or why it was not.
#[derive(Clone, Debug, PartialEq)]
pub struct BifurcatedBranchData {
    /// Its marker's position in `run.json`'s `stability.markers` (`None`:
    /// found along the branch by the enlarged Jacobian, `--class`).
    pub marker: Option<usize>,
    /// The marker's frequency (or the point's before the crossing), Hz.
    pub marker_hz: f64,
    /// The class `σ` (nodal diameter) of the crossing.
    pub class: i64,
    /// The parent point: the symmetric branch's point (index in
    /// `results.h5`'s `/branch`) after which the crossing lies.
    pub parent_point: usize,
    /// The located branch point's frequency, Hz (`None`: not switched).
    pub branch_point_hz: Option<f64>,
    /// Real unknowns of the enlarged basis.
    pub basis_unknowns: Option<usize>,
    /// Real unknowns of the full wheel on the same contact dofs.
    pub full_unknowns: Option<usize>,
    /// The sides, `+v` then `−v` (empty: not switched).
    pub sides: Vec<BifurcatedSide>,
    /// Its CSV in the results folder (`branches/class1_212.7022Hz.csv`).
    pub file: Option<String>,
    /// Why it was not switched at.
    pub not_switched: Option<String>,
}

/// The summary of one side ([`BifurcatedSide`] without its points).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct SideSummary {
    /// `+1` along the null vector, `−1` against it.
    pub direction: f64,
    /// Number of points.
    pub points: usize,
    /// Points where an exponent grows (`None`: stability not checked).
    pub unstable_points: Option<usize>,
    /// Why it stopped (`reason` and its details).
    pub stop: serde_json::Value,
    /// Why it stopped, in words.
    #[serde(default)]
    pub stop_reason: String,
    /// Frequency of its first point, Hz.
    pub from_hz: Option<f64>,
    /// Frequency of its last point, Hz.
    pub to_hz: Option<f64>,
    /// The largest sector amplitude along the side, m.
    pub peak_amplitude_m: Option<f64>,
    /// Its sector (1-based).
    pub peak_sector: Option<usize>,
    /// Its frequency, Hz.
    pub peak_hz: Option<f64>,
}

/// The summary of a branch point ([`BifurcatedBranchData`] without the
/// sides' points): `run.json`'s `branches` entry, `branches.json`'s record.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct BranchSummary {
    /// Its marker's position in `run.json`'s `stability.markers`.
    pub marker: Option<usize>,
    /// The marker's frequency, Hz.
    pub marker_hz: f64,
    /// The class `σ`.
    pub class: i64,
    /// The symmetric branch's point after which the crossing lies.
    #[serde(default)]
    pub parent_point: Option<usize>,
    /// The located branch point, Hz.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub branch_point_hz: Option<f64>,
    /// Real unknowns of the enlarged basis.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub basis_unknowns: Option<usize>,
    /// Real unknowns of the full wheel.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub full_unknowns: Option<usize>,
    /// The sides.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub sides: Vec<SideSummary>,
    /// Its CSV in the results folder.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub file: Option<String>,
    /// Why it was not switched at.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub not_switched: Option<String>,
}

impl BifurcatedSide {
    /// The side's summary: its range, how many points are unstable, and
    /// its largest sector amplitude (the first point and sector where it
    /// is reached).
    pub fn summary(&self) -> SideSummary {
        let mut peak: Option<(f64, usize, f64)> = None;
        for (amplitudes, &hz) in self.sector_amplitudes_m.iter().zip(&self.frequency_hz) {
            let (most, largest) = most_responding(amplitudes);
            if peak.is_none_or(|(a, _, _)| largest > a) {
                peak = Some((largest, most + 1, hz));
            }
        }
        let checked = self.stable.iter().all(Option::is_some);
        SideSummary {
            direction: self.direction,
            points: self.frequency_hz.len(),
            unstable_points: checked
                .then(|| self.stable.iter().filter(|s| **s == Some(false)).count()),
            stop: self.stop.clone(),
            stop_reason: self.stop_reason.clone(),
            from_hz: self.frequency_hz.first().copied(),
            to_hz: self.frequency_hz.last().copied(),
            peak_amplitude_m: peak.map(|p| p.0),
            peak_sector: peak.map(|p| p.1),
            peak_hz: peak.map(|p| p.2),
        }
    }
}

/// The most responding sector (0-based, the first of equal ones) and its
/// amplitude.
pub fn most_responding(amplitudes: &[f64]) -> (usize, f64) {
    amplitudes.iter().enumerate().fold(
        (0, f64::MIN),
        |(b, m), (j, a)| if *a > m { (j, *a) } else { (b, m) },
    )
}

impl BifurcatedBranchData {
    /// The summary of `run.json` and `branches.json`.
    pub fn summary(&self) -> BranchSummary {
        BranchSummary {
            marker: self.marker,
            marker_hz: self.marker_hz,
            class: self.class,
            parent_point: Some(self.parent_point),
            branch_point_hz: self.branch_point_hz,
            basis_unknowns: self.basis_unknowns,
            full_unknowns: self.full_unknowns,
            sides: self.sides.iter().map(BifurcatedSide::summary).collect(),
            file: self.file.clone(),
            not_switched: self.not_switched.clone(),
        }
    }

    fn place(&self) -> Place {
        Place {
            class: self.class,
            branch_point_hz: self.branch_point_hz,
            marker_hz: self.marker_hz,
        }
    }
}

impl BranchSummary {
    fn place(&self) -> Place {
        Place {
            class: self.class,
            branch_point_hz: self.branch_point_hz,
            marker_hz: self.marker_hz,
        }
    }
}

/// Where a record was switched at (or asked for).
struct Place {
    class: i64,
    branch_point_hz: Option<f64>,
    marker_hz: f64,
}

impl Place {
    /// Whether a new record at `self` replaces `old`: the same class and
    /// the same located branch point (a record not switched: the same
    /// marker frequency), to 1e-9.
    fn replaces(&self, old: &Place) -> bool {
        let close = |a: f64, b: Option<f64>| b.is_some_and(|b| (a - b).abs() <= 1e-9 * a.abs());
        self.class == old.class
            && match self.branch_point_hz {
                Some(hz) => close(hz, old.branch_point_hz),
                None => close(self.marker_hz, Some(old.marker_hz)),
            }
    }
}

/// A record of a branch point that a newer one of the same place replaces.
pub trait Record {
    /// Whether `self` (new) replaces `old`.
    fn replaces(&self, old: &Self) -> bool;
}

impl Record for BifurcatedBranchData {
    fn replaces(&self, old: &Self) -> bool {
        self.place().replaces(&old.place())
    }
}

impl Record for BranchSummary {
    fn replaces(&self, old: &Self) -> bool {
        self.place().replaces(&old.place())
    }
}

/// The `earlier` records none of `new` replaces, then `new`: a branch
/// point switched at again is kept once, with its last result.
pub fn merge<T: Record + Clone>(earlier: &[T], new: &[T]) -> Vec<T> {
    earlier
        .iter()
        .filter(|old| !new.iter().any(|n| n.replaces(old)))
        .chain(new)
        .cloned()
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    fn record(class: i64, marker_hz: f64, located: Option<f64>) -> BranchSummary {
        BranchSummary {
            marker: None,
            marker_hz,
            class,
            parent_point: Some(3),
            branch_point_hz: located,
            basis_unknowns: None,
            full_unknowns: None,
            sides: Vec::new(),
            file: None,
            not_switched: None,
        }
    }

    #[test]
    fn a_branch_point_switched_at_again_is_kept_once() {
        let earlier = vec![
            record(1, 212.7, Some(212.702165)),
            record(1, 220.26, Some(220.251022)),
            record(3, 211.6, None),
        ];
        let new = vec![
            record(1, 212.71, Some(212.702165 * (1.0 + 1e-12))),
            record(3, 211.6, None),
        ];
        let all = merge(&earlier, &new);
        let places: Vec<(i64, f64)> = all.iter().map(|r| (r.class, r.marker_hz)).collect();
        assert_eq!(places, [(1, 220.26), (1, 212.71), (3, 211.6)]);
        // Another class at the same frequency is another branch point.
        let other = merge(&earlier, &[record(2, 212.7, Some(212.702165))]);
        assert_eq!(other.len(), 4);
    }
}
