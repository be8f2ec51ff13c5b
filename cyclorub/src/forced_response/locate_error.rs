//! Why a marker could not be located on the branch (docs/design.md §10,
//! "Located"): it then keeps its interpolated place.

use crate::stability::StabilityError;

/// Why a marker could not be located (it then keeps its interpolated place).
#[derive(Debug, thiserror::Error)]
pub enum LocateError {
    /// The marker's points are not on the branch given.
    #[error("the marker's points {index} and {next} are not on the branch of {points} points")]
    Points {
        /// The marker's first point.
        index: usize,
        /// The next.
        next: usize,
        /// Points of the branch.
        points: usize,
    },
    /// Newton did not converge at a trial point.
    #[error("Newton on the branch did not converge at {fraction:.6} of the chord (relative residual {residual:.2e})")]
    Newton {
        /// Where on the chord.
        fraction: f64,
        /// The last relative residual.
        residual: f64,
    },
    /// The residual's Jacobian is structured (a large problem): not formed.
    #[error("the problem ({unknowns} unknowns) solves with a structured Jacobian: locating forms the dense one")]
    Structured {
        /// Unknowns.
        unknowns: usize,
    },
    /// The residual failed.
    #[error("evaluating the residual: {0}")]
    Evaluation(String),
    /// The tracked exponent was not found at a trial point.
    #[error("the tracked exponent was not found again at {frequency_hz:.6} Hz")]
    Lost {
        /// Where.
        frequency_hz: f64,
    },
    /// The exponent found between the marker's points does not continue
    /// its two exponents.
    #[error("at {frequency_hz:.6} Hz the class's exponent nearest to the one expected is {off:.3e} from it in multiplier, its two ends {apart:.3e} apart: the marker's two exponents are not one exponent moving")]
    NotContinuous {
        /// Where.
        frequency_hz: f64,
        /// How far, in multiplier.
        off: f64,
        /// The ends' distance, in multiplier.
        apart: f64,
    },
    /// The followed exponent jumps across 0 inside a bracket closed to the
    /// chord's resolution, but the class grows as many exponents on both
    /// sides: the marker's two exponents are two exponents paired by the
    /// tracking, not one jumping.
    #[error("at {frequency_hz:.6} Hz the followed exponent jumps across 0, but the class grows {growing} exponents on both sides of the jump: the marker's two exponents are not one exponent")]
    PairedAtAJump {
        /// Where.
        frequency_hz: f64,
        /// The class's growing exponents on both sides.
        growing: usize,
    },
    /// The bracket closed on one of the marker's two points with the
    /// exponent clear of 0 on both sides and the contact the same: the
    /// chord's solutions lie on two sheets there (near a fold), not one
    /// exponent moving through 0.
    #[error("the crossing closes on the marker's point at {frequency_hz:.6} Hz with the exponent clear of 0 on both sides and the contact unchanged: the chord's solutions jump between two sheets there")]
    AtAnEnd {
        /// Where.
        frequency_hz: f64,
    },
    /// The bracket did not close within the trials allowed.
    #[error("the bracket did not close in {trials} trial points: {bracket_hz:.2e} Hz, {bracket_fraction:.2e} of the chord wide, the real part still {real_part:.2e} 1/s at its nearer end")]
    NotClosed {
        /// Trial points solved.
        trials: usize,
        /// Its width, Hz.
        bracket_hz: f64,
        /// Its width, fraction of the chord.
        bracket_fraction: f64,
        /// The smaller real part of its two ends, 1/s.
        real_part: f64,
    },
    /// Located by the count: the marker's class has as many growing
    /// exponents at both its points (its exponent lies within the band at
    /// one of them, or the tracking paired two different exponents).
    #[error("class {class} has {growing} exponents growing faster than 1e-6 ω at both of the marker's points: no change of the count to locate")]
    SameCount {
        /// The marker's class.
        class: i64,
        /// Its growing exponents at both points.
        growing: usize,
    },
    /// The marker has no exponent at its two points.
    #[error("the marker records no exponent at its two points")]
    NoExponents,
    /// The stability check failed.
    #[error(transparent)]
    Stability(#[from] StabilityError),
}
