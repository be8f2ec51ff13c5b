//! A trial point of a marker's location (docs/design.md §10, "Located")
//! and what a bracket of two of them tells: located, a jump, the exponent
//! nearest to the one expected.

use super::chord::{BRACKET_FRACTION, BRACKET_HZ, FOLD_FRACTION, JUMP_SHARE};
use crate::stability::{multiplier_angle, Exponent, Location, Marker, MarkerKind};
use std::f64::consts::PI;

/// One trial point: where on the chord, the solution, the tracked exponent.
#[derive(Clone)]
pub(super) struct Trial {
    pub(super) fraction: f64,
    pub(super) omega: f64,
    pub(super) exponent: Exponent,
    /// The branch's solution there.
    pub(super) solution: Vec<f64>,
}

/// The marker located at a jump of its exponent inside the bracket
/// `[lo, hi]`: placed at the bracket's end that is one of the marker's own
/// points if it is one (the point sits on the change of contact), else at
/// its growing end; the exponent is the growing side's.
pub(super) fn jump_at(marker: &Marker, lo: &Trial, hi: &Trial, solves: usize) -> Marker {
    let growing = if lo.exponent.re > hi.exponent.re {
        lo
    } else {
        hi
    };
    let place = match (lo.fraction, hi.fraction) {
        (f, _) if f <= 0.0 => lo,
        (_, f) if f >= 1.0 => hi,
        _ => growing,
    };
    Marker {
        fraction: place.fraction,
        frequency_hz: place.omega / (2.0 * PI),
        kind: MarkerKind::Jump,
        exponent: growing.exponent,
        located: Some(Location {
            bracket_hz: (hi.omega - lo.omega).abs() / (2.0 * PI),
            bracket_fraction: hi.fraction - lo.fraction,
            solves,
            angle: multiplier_angle(growing.exponent, growing.omega),
            by_count: false,
        }),
        ..marker.clone()
    }
}

/// Whether the bracket `[lo, hi]` locates its crossing: below
/// [`BRACKET_HZ`] in frequency and [`FOLD_FRACTION`] of the chord with
/// the real part within the growth tolerance (`tolerance · ω`: where two
/// exponents meet on the real axis and part, the real part moves fast over
/// a bracket already narrow in frequency), or below [`BRACKET_FRACTION`]
/// of the chord (where a real part not within the tolerance is a jump,
/// [`jumps`]).
pub(super) fn located(lo: &Trial, hi: &Trial, tolerance: f64) -> bool {
    let width = hi.fraction - lo.fraction;
    let near = lo.exponent.re.abs().min(hi.exponent.re.abs()) <= tolerance * lo.omega.min(hi.omega);
    ((hi.omega - lo.omega).abs() / (2.0 * PI) <= BRACKET_HZ && width <= FOLD_FRACTION && near)
        || width <= BRACKET_FRACTION
}

/// Whether the exponent jumps inside the bracket `[lo, hi]` closed to
/// [`BRACKET_FRACTION`] of the chord: it still holds more than
/// [`JUMP_SHARE`] of the change of the real part between the marker's two
/// points (`whole_change`). A smooth crossing, even a fold's square root,
/// holds a share of order `√width` (`1e-3`) there.
pub(super) fn jumps(lo: &Trial, hi: &Trial, whole_change: f64) -> bool {
    (hi.exponent.re - lo.exponent.re).abs() > JUMP_SHARE * whole_change
}

/// The exponent of `exponents` whose multiplier at `omega` is nearest to
/// `expected`'s (the same multiplier whatever strip copy).
pub(super) fn nearest(exponents: &[Exponent], expected: Exponent, omega: f64) -> Option<Exponent> {
    let target = expected.multiplier(omega);
    exponents.iter().copied().min_by(|x, y| {
        (x.multiplier(omega) - target)
            .norm()
            .total_cmp(&(y.multiplier(omega) - target).norm())
    })
}
