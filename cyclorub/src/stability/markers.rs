//! Where stability changes along a branch, and how: a Floquet multiplier
//! leaves the unit circle at `+1` (a fold in the reduced problem's own
//! class, a symmetry-breaking branch point in another), at `−1` (period
//! doubling) or as a complex pair (Neimark–Sacker: a quasi-periodic
//! response).

use super::spectrum::{ClassSpectrum, Exponent, PointStability};
use serde::{Deserialize, Serialize};
use std::f64::consts::PI;

/// How a multiplier crosses the unit circle.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum MarkerKind {
    /// At `+1` in class 0: a turning point of the branch.
    Fold,
    /// At `+1` in another class: a branch of lower symmetry starts here.
    BranchPoint,
    /// At `+1` on the whole wheel solved without classes: a fold or a
    /// branch point (the symmetry of the perturbation is not told).
    RealCrossing,
    /// At `−1`: a response of twice the period starts here.
    PeriodDoubling,
    /// A complex pair: a quasi-periodic response starts here.
    NeimarkSacker,
}

/// A change of stability between two consecutive points.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Marker {
    /// The change lies between points `index` and `index + 1`.
    pub index: usize,
    /// Where between them, in `[0, 1]`, from the crossing exponent's real
    /// part interpolated linearly.
    pub fraction: f64,
    /// Frequency at the crossing, Hz (interpolated).
    pub frequency_hz: f64,
    /// How the multiplier crosses.
    pub kind: MarkerKind,
    /// The class's nodal diameter (`σ ≥ 0`: its conjugate class `−σ` crosses
    /// with it); `None` on the whole wheel solved without classes.
    pub nodal_diameter: Option<i64>,
    /// The crossing exponent, interpolated (its real part is ~0).
    pub exponent: Exponent,
    /// Whether stability is lost (`true`) or regained going along the branch.
    pub loses_stability: bool,
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

/// How close (rad) a multiplier's angle must be to 0 or π to count as a
/// real crossing.
const REAL_ANGLE: f64 = 0.05;

/// The markers along `points` (in branch order); `classes_known` is false
/// for the whole wheel solved as one block.
pub fn markers(points: &[PointStability], classes_known: bool) -> Vec<Marker> {
    let mut found = Vec::new();
    for (index, pair) in points.windows(2).enumerate() {
        let (a, b) = (&pair[0], &pair[1]);
        for class_a in a.classes.iter().filter(|c| c.nodal_diameter >= 0) {
            let Some(class_b) = b.class(class_a.nodal_diameter) else {
                continue;
            };
            let (na, nb) = (class_a.unstable(a.tolerance), class_b.unstable(b.tolerance));
            if na == nb {
                continue;
            }
            let loses = nb > na;
            let (growing_side, stable_point) = if loses {
                (class_b, (class_a, a.tolerance))
            } else {
                (class_a, (class_b, b.tolerance))
            };
            let growing_tolerance = if loses { b.tolerance } else { a.tolerance };
            let Some(growing) = newest(growing_side, growing_tolerance) else {
                continue;
            };
            let Some(settled) = nearest_settled(stable_point.0, stable_point.1, growing) else {
                continue;
            };
            let (before, after) = if loses {
                (settled, growing)
            } else {
                (growing, settled)
            };
            let tolerance = 0.5 * (a.tolerance + b.tolerance);
            let span = after.re - before.re;
            let fraction = if span.abs() > 0.0 {
                ((tolerance - before.re) / span).clamp(0.0, 1.0)
            } else {
                0.5
            };
            let omega = a.omega + fraction * (b.omega - a.omega);
            let exponent = Exponent {
                re: before.re + fraction * span,
                im: before.im + fraction * (after.im - before.im),
            };
            // The growing exponent has just crossed: its multiplier's angle
            // tells the kind (a real one may turn complex on the stable side).
            let angle = (growing.im * 2.0 * PI / omega + PI).rem_euclid(2.0 * PI) - PI;
            let kind = if angle.abs() < REAL_ANGLE {
                match (classes_known, class_a.nodal_diameter) {
                    (false, _) => MarkerKind::RealCrossing,
                    (true, 0) => MarkerKind::Fold,
                    (true, _) => MarkerKind::BranchPoint,
                }
            } else if angle.abs() > PI - REAL_ANGLE {
                MarkerKind::PeriodDoubling
            } else {
                MarkerKind::NeimarkSacker
            };
            found.push(Marker {
                index,
                fraction,
                frequency_hz: omega / (2.0 * PI),
                kind,
                nodal_diameter: classes_known.then_some(class_a.nodal_diameter),
                exponent,
                loses_stability: loses,
            });
        }
    }
    found
}

/// The exponent that does not grow nearest to `growing` (the one it came
/// from or goes to).
fn nearest_settled(class: &ClassSpectrum, tolerance: f64, growing: Exponent) -> Option<Exponent> {
    class
        .exponents
        .iter()
        .copied()
        .filter(|e| e.re <= tolerance)
        .min_by(|x, y| {
            let dx = (x.value() - growing.value()).norm();
            let dy = (y.value() - growing.value()).norm();
            dx.total_cmp(&dy)
        })
}

/// The growing exponent nearest the axis.
fn newest(class: &ClassSpectrum, tolerance: f64) -> Option<Exponent> {
    class
        .exponents
        .iter()
        .copied()
        .filter(|e| e.re > tolerance)
        .min_by(|x, y| x.re.total_cmp(&y.re))
}
