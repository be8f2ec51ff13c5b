//! An exponent refined on the class's quadratic eigenproblem itself, by
//! Rayleigh functional iteration (P. Lancaster, "Lambda-matrices and
//! vibrating systems", 1966; A. Ruhe, SIAM J. Numer. Anal. 10, 1973):
//! `q ← Q(μ)⁻¹ Q'(μ) q`, then the Newton step of `qᴴ Q(μ) q = 0` in `μ`.
//! Each solve follows the class's structure (`super::operator`), so an
//! iteration costs what one node of the contour costs.

use super::operator::ClassOperator;
use faer::c64;

/// Iterations allowed for one exponent.
const MOST_ITERATIONS: usize = 30;

/// Inverse iterations at the guess before the Newton steps.
const PURIFYING: usize = 2;

/// Converged when the Newton step is below this relative to `max(1, |μ|)`
/// and the residual `‖Q(μ) q‖` below [`RESIDUAL`] relative to its terms.
const STEP: f64 = 1e-13;
/// A step below this that no longer halves is round-off.
const STALLED: f64 = 1e-9;
const RESIDUAL: f64 = 1e-9;

/// The exponent (`μ = λ/ω`) and unit vector that the iteration reaches from
/// `(guess, start)`, checked to have converged; `None` otherwise.
pub(super) fn refine(
    operator: &ClassOperator,
    guess: c64,
    start: Vec<c64>,
) -> Option<(c64, Vec<c64>)> {
    let mut q = start;
    normalize(&mut q)?;
    // Inverse iteration at the guess first: the start vector may hold
    // neighbouring exponents, which would pull the first Newton step away.
    let at_guess = match operator.factor(guess) {
        Some(f) => f,
        None => operator.factor(guess + c64::new(1e-14, 1e-14) * guess.norm().max(1.0))?,
    };
    for _ in 0..PURIFYING {
        let (_, slope) = operator.times(guess, &q);
        q = operator.solve(&at_guess, &slope);
        normalize(&mut q)?;
    }
    let mut mu = guess;
    let mut previous = f64::INFINITY;
    for _ in 0..MOST_ITERATIONS {
        let factored = match operator.factor(mu) {
            Some(f) => f,
            // μ is an exponent to round-off: step off it.
            None => operator.factor(mu + c64::new(1e-14, 1e-14) * mu.norm().max(1.0))?,
        };
        let (_, slope) = operator.times(mu, &q);
        q = operator.solve(&factored, &slope);
        normalize(&mut q)?;
        let (value, slope) = operator.times(mu, &q);
        let denominator = dot(&q, &slope);
        if denominator.norm() <= 0.0 || denominator.norm().is_nan() {
            return None;
        }
        let step = dot(&q, &value) / denominator;
        if !(step.re.is_finite() && step.im.is_finite()) {
            return None;
        }
        mu -= step;
        // Converged, or stalled at round-off (the step no longer shrinks).
        let size = step.norm();
        if size <= STEP * mu.norm().max(1.0) || (size <= STALLED && size > 0.5 * previous) {
            let (value, scale) = operator.residual(mu, &q);
            return (norm(&value) <= RESIDUAL * scale).then_some((mu, q));
        }
        previous = size;
    }
    None
}

/// `aᴴb`.
pub(super) fn dot(a: &[c64], b: &[c64]) -> c64 {
    a.iter().zip(b).map(|(x, y)| x.conj() * y).sum()
}

/// The Euclidean norm.
pub(super) fn norm(v: &[c64]) -> f64 {
    v.iter().map(|z| z.norm_sqr()).sum::<f64>().sqrt()
}

/// Scales `v` to unit norm; `None` when its norm is 0 or not finite.
pub(super) fn normalize(v: &mut [c64]) -> Option<()> {
    let n = norm(v);
    if !(n > 0.0 && n.is_finite()) {
        return None;
    }
    v.iter_mut().for_each(|z| *z /= n);
    Some(())
}
