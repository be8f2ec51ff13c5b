//! Where stability changes along a branch, and how: a Floquet multiplier
//! leaves the unit circle at `+1` (in the reduced problem's own class a
//! fold where the branch turns, a branch point of that class where it goes
//! on; a symmetry-breaking branch point in another), at `−1` (period
//! doubling) or as a complex pair (Neimark–Sacker: a quasi-periodic
//! response).
//!
//! Each exponent is tracked from point to point: the exponents of all
//! classes at one point are matched to those at the next by their
//! multipliers `e^{λT}` (nearest first), the whole wheel's spectrum being
//! continuous along the branch whatever class a copy of an exponent sits
//! in. A marker is one tracked exponent crossing `Re λ = 0`, with
//! hysteresis: it counts once the exponent has gone past the band
//! `|Re λ| ≤ max(tolerance, 1e-6 ω)` on the other side, and is placed where
//! its real part vanishes (linear interpolation between the two points
//! around the last sign change). An exponent hovering in the band gives no
//! marker; one going out and back gives a pair only if it leaves the band
//! both ways.
//!
//! Within one step, a loss and a regain in the same class cancel: the
//! exponents' matching swapped (or two crossings happened that the step does
//! not resolve); the class's count of growing exponents is what it was.
//! A marker says whether it changes its class's stability
//! ([`Marker::class_changes`]): a class with no growing exponent gets one,
//! or loses its last, read from the class's largest real part with the same
//! band (so that a class's state never hinges on the matching). Those are
//! the events a designer reads; the others are further exponents of a class
//! already unstable crossing, kept in the list for the record.
//!
//! A marker is placed by interpolation between its two points; the front
//! door then locates each event on the branch re-solved between them
//! (`forced_response::locate_markers`, docs/design.md §10, "Located"),
//! which fills [`Marker::located`] and reads the kind again from the
//! multiplier's angle at the located point.

mod tracking;

pub use tracking::markers;

use super::spectrum::{Exponent, PointStability};
use serde::{Deserialize, Serialize};
use std::f64::consts::PI;

/// How a multiplier crosses the unit circle.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum MarkerKind {
    /// At `+1` in class 0 where the branch turns in frequency: a turning
    /// point of the branch.
    Fold,
    /// At `+1` in a class `σ ≠ 0`: a branch of lower symmetry starts here;
    /// in class 0 where the branch goes on in frequency: two branches of
    /// the same symmetry cross here.
    BranchPoint,
    /// At `+1` on the whole wheel solved without classes: a fold or a
    /// branch point (the symmetry of the perturbation is not told).
    RealCrossing,
    /// At `−1`: a response of twice the period starts here.
    PeriodDoubling,
    /// A complex pair: a quasi-periodic response starts here.
    NeimarkSacker,
    /// No multiplier passes through the unit circle: the exponent jumps
    /// across `Re λ = 0` where the contact changes (onset, loss, grazing of
    /// a time sample), the linearization being nonsmooth there. Found by
    /// locating a marker (`forced_response::locate_markers`): no smooth
    /// branch starts here.
    Jump,
}

/// A change of stability between two consecutive points.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Marker {
    /// The change lies between points `index` and `index + 1`.
    pub index: usize,
    /// Where between them, in `[0, 1]`: from the crossing exponent's real
    /// part interpolated linearly; once [`Self::located`], the fraction of
    /// the chord between the two points where the re-solved branch crosses.
    pub fraction: f64,
    /// Frequency at the crossing, Hz (interpolated, or located).
    pub frequency_hz: f64,
    /// How the multiplier crosses.
    pub kind: MarkerKind,
    /// The class's nodal diameter (`σ ≥ 0`: its conjugate class `−σ` crosses
    /// with it); `None` on the whole wheel solved without classes.
    pub nodal_diameter: Option<i64>,
    /// The crossing exponent, interpolated, or at the located point (its
    /// real part is ~0; for a [`MarkerKind::Jump`], the growing side's, clear
    /// of 0).
    pub exponent: Exponent,
    /// Whether stability is lost (`true`) or regained going along the branch.
    pub loses_stability: bool,
    /// The tracked exponent at point `index` (before the crossing).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub before: Option<Exponent>,
    /// The tracked exponent at point `index + 1` (after it).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub after: Option<Exponent>,
    /// Whether the class's stability changes here: it had no growing
    /// exponent before (stability lost) or has none after (regained).
    /// `false`: one more (or one fewer) growing exponent in a class that
    /// stays unstable.
    #[serde(default = "changes_by_default")]
    pub class_changes: bool,
    /// How the crossing was located on the branch re-solved between the
    /// two points (`None`: placed by interpolation only).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub located: Option<Location>,
}

/// How a marker was located (docs/design.md §10, "Located"): the branch
/// re-solved at intermediate points of the chord between the marker's two
/// points, and the tracked exponent's real part brought to 0 there (or
/// across its jump, for a [`MarkerKind::Jump`]).
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct Location {
    /// The width of the last bracket of the crossing, Hz.
    pub bracket_hz: f64,
    /// The same as a fraction of the chord between the two points.
    pub bracket_fraction: f64,
    /// Points of the branch solved to locate it.
    pub solves: usize,
    /// The multiplier's angle `Im λ · T` (rad, in `(−π, π]`) at the located
    /// point: 0 (or `±π`) to round-off for a real crossing, finite for a
    /// complex pair however slowly modulated.
    pub angle: f64,
    /// Located by the count of the class's growing exponents (bisection on
    /// the chord), not by one exponent followed through 0: the followed
    /// exponent jumps inside the bracket (exponents colliding, or the
    /// branch's solutions on the chord jumping near a fold). The marker's
    /// exponent is then the growing side's slowest growing one, and its
    /// kind the one Hill's label gave at its points.
    #[serde(default)]
    pub by_count: bool,
}

/// How close (rad) a multiplier's angle must be to 0 or π, on the growing
/// side of a crossing placed by interpolation, to count as real.
pub const REAL_ANGLE: f64 = 0.05;

/// The multiplier's angle `Im λ · T` of `exponent` at angular frequency
/// `omega`, in `(−π, π]`.
pub fn multiplier_angle(exponent: Exponent, omega: f64) -> f64 {
    let angle = (exponent.im * 2.0 * PI / omega + PI).rem_euclid(2.0 * PI) - PI;
    if angle <= -PI {
        PI
    } else {
        angle
    }
}

/// The kind of a crossing by its multiplier's angle `angle` (rad, see
/// [`multiplier_angle`]): real when within `real_angle` of 0, or of π
/// (period doubling), else complex. A real crossing is, in class 0, a fold
/// where the branch `turns` in frequency ([`frequency_turns`]) and a branch
/// point between branches of the same symmetry where it goes on through
/// it; a branch point in another class; a real crossing when the class is
/// not known (`class` `None`).
pub fn crossing_kind(angle: f64, class: Option<i64>, real_angle: f64, turns: bool) -> MarkerKind {
    if angle.abs() < real_angle {
        match class {
            None => MarkerKind::RealCrossing,
            Some(0) if turns => MarkerKind::Fold,
            Some(_) => MarkerKind::BranchPoint,
        }
    } else if angle.abs() > PI - real_angle {
        MarkerKind::PeriodDoubling
    } else {
        MarkerKind::NeimarkSacker
    }
}

/// Whether a branch of `count` points, the frequency of point `i` being
/// `omega(i)`, turns in frequency about its step from point `index` to the
/// next: that step goes the other way from the step before it or the one
/// after it (a fold's vertex lies in that step, or at one of its ends,
/// when its class-0 exponent crosses there). A branch of two points is
/// taken as turning (nothing tells).
pub fn frequency_turns(count: usize, omega: impl Fn(usize) -> f64, index: usize) -> bool {
    let step = |i: usize| (i + 1 < count).then(|| omega(i + 1) - omega(i));
    let Some(here) = step(index) else {
        return true;
    };
    let (before, after) = (index.checked_sub(1).and_then(step), step(index + 1));
    if before.is_none() && after.is_none() {
        return true;
    }
    before.is_some_and(|b| b * here < 0.0) || after.is_some_and(|a| here * a < 0.0)
}

impl Marker {
    /// Whether the marker is an event a designer reads (in the run's
    /// summary and on the figures): every crossing at `±1` (a fold, a branch
    /// point, a period doubling: a branch starts there), a Neimark–Sacker
    /// crossing when it changes its class's stability, and a jump (found by
    /// locating an event, it stays one).
    pub fn is_event(&self) -> bool {
        self.class_changes || self.kind != MarkerKind::NeimarkSacker
    }
}

/// How close in frequency (relative) two events of one kind and direction
/// are to be read as one: a whole set of nodal diameters crossing at first
/// contact.
pub const EVENT_GROUPING: f64 = 1e-4;

/// The events among `items` (in branch order; see [`Marker::is_event`]),
/// each group the events of one kind and direction within
/// [`EVENT_GROUPING`] of its first in frequency: what the run's summary
/// prints as one line and the forced-response figure draws as one symbol.
/// `marker` reads the marker of an item (a [`Marker`] itself, or a record
/// that holds one).
pub fn group_events<T>(items: &[T], marker: impl Fn(&T) -> &Marker) -> Vec<Vec<&T>> {
    let mut groups: Vec<Vec<&T>> = Vec::new();
    for item in items.iter().filter(|item| marker(item).is_event()) {
        let m = marker(item);
        let joins = groups
            .last()
            .and_then(|group| group.first())
            .is_some_and(|first| {
                let first = marker(first);
                first.kind == m.kind
                    && first.loses_stability == m.loses_stability
                    && (first.frequency_hz - m.frequency_hz).abs() < EVENT_GROUPING * m.frequency_hz
            });
        match groups.last_mut() {
            Some(group) if joins => group.push(item),
            _ => groups.push(vec![item]),
        }
    }
    groups
}

/// The nodal diameters of a group of markers, sorted, each once (none on
/// the whole wheel solved without classes).
pub fn nodal_diameters<'a>(markers: impl IntoIterator<Item = &'a Marker>) -> Vec<i64> {
    let mut diameters: Vec<i64> = markers
        .into_iter()
        .filter_map(|m| m.nodal_diameter)
        .collect();
    diameters.sort_unstable();
    diameters.dedup();
    diameters
}

/// Markers written before [`Marker::class_changes`] existed were all shown.
fn changes_by_default() -> bool {
    true
}

/// The stability of a branch: every point's and the markers between them.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct BranchStability {
    /// Harmonics of Hill's truncation.
    pub harmonics: usize,
    /// Points solved by Hill's method (the others were off contact).
    pub solved_by_hill: usize,
    /// Every point's exponents, in branch order.
    pub points: Vec<PointStability>,
    /// Where stability changes.
    pub markers: Vec<Marker>,
}
