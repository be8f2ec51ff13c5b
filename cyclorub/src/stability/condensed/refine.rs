//! An exponent refined on the class's quadratic eigenproblem itself, by
//! Rayleigh functional iteration (P. Lancaster, "Lambda-matrices and
//! vibrating systems", 1966; A. Ruhe, SIAM J. Numer. Anal. 10, 1973):
//! `q ← Q(μ)⁻¹ Q'(μ) q`, then the Newton step of `qᴴ Q(μ) q = 0` in `μ`.
//! Each solve follows the class's structure (`super::operator`), so an
//! iteration costs what one node of the contour costs.
//!
//! [`refine`] starts from an estimate of unknown quality (the contour's);
//! [`at_the_estimate`] finishes one already close (a followed exponent, a
//! cluster's Ritz pair), with at most a few factorizations.

use super::operator::{Applied, ClassOperator, Factored};
use super::{Eigenpair, ACCURATE};
use crate::stability::vectors::{dot, norm, normalize};
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
    let mut applied = operator.applied(&q);
    // The first iteration is at the guess, whose factorization is at hand.
    let mut at_hand = Some(at_guess);
    for _ in 0..MOST_ITERATIONS {
        let factored = match at_hand.take() {
            Some(f) => f,
            None => match operator.factor(mu) {
                Some(f) => f,
                // μ is an exponent to round-off: step off it.
                None => operator.factor(mu + c64::new(1e-14, 1e-14) * mu.norm().max(1.0))?,
            },
        };
        let size = inverse_step(operator, &factored, &mut mu, &mut q, &mut applied)?;
        // Converged, or stalled at round-off (the step no longer shrinks).
        if size <= STEP * mu.norm().max(1.0) || (size <= STALLED && size > 0.5 * previous) {
            let (value, scale) = operator.residual(mu, &q);
            return (norm(&value) <= RESIDUAL * scale).then_some((mu, q));
        }
        previous = size;
    }
    None
}

/// The Newton step, relative to `max(1, |μ|)`, at which an estimate
/// refined at itself has converged.
const CONVERGED: f64 = 1e-12;

/// Factorizations at the estimate allowed.
const AT_THE_ESTIMATE: usize = 4;

/// The step (relative to `max(1, |μ|)`) below which an estimate's residual
/// is worth testing.
const CLOSE: f64 = 1e-7;

/// Rayleigh functional iteration at the estimate `(mu, q)` itself (its
/// fixed point is the eigenpair of `Q`, which a kept shift's is only
/// near). Converged when the Newton step is at round-off of `μ` and
/// `‖Q(μ) q‖` at round-off of its terms (the test the contour's estimates
/// pass).
pub(super) fn at_the_estimate(
    operator: &ClassOperator,
    mut mu: c64,
    mut q: Vec<c64>,
) -> Option<Eigenpair> {
    let mut previous = f64::INFINITY;
    let mut applied = operator.applied(&q);
    for _ in 0..AT_THE_ESTIMATE {
        let at_estimate = factor(operator, mu)?;
        let step = inverse_step(operator, &at_estimate, &mut mu, &mut q, &mut applied)?;
        // Converged, or stalled at round-off (the step no longer shrinks).
        if step <= CONVERGED * mu.norm().max(1.0) || (step <= STALLED && step > 0.5 * previous) {
            let (value, scale) = operator.residual(mu, &q);
            return (norm(&value) <= ACCURATE * scale).then_some((mu, q));
        }
        // A small step from a close estimate: the iteration converges
        // cubically there, so the residual is usually at round-off already
        // (the contour's estimates pass the same test), which spares a
        // factorization.
        if step <= CLOSE * mu.norm().max(1.0) {
            let (value, scale) = operator.residual(mu, &q);
            if norm(&value) <= ACCURATE * scale {
                return Some((mu, q));
            }
        }
        // Farther: residual inverse iterations on the same factorization
        // before another one (they contract while `μ` stays near it).
        if let Some(pair) =
            with_the_same_factorization(operator, &at_estimate, mu, q.clone(), applied.clone())
        {
            return Some(pair);
        }
        previous = step;
    }
    None
}

/// Residual inverse iterations kept on one factorization at most.
const SAME_FACTORIZATION: usize = 8;

/// Residual inverse iteration (A. Neumaier, "Residual inverse iteration for
/// the nonlinear eigenvalue problem", SIAM J. Numer. Anal. 22, 1985) with
/// `factored` at a shift `σ` near `μ`: `q ← q − Q(σ)⁻¹ Q(μ) q`, then the
/// Newton step of `qᴴ Q(μ) q = 0`. It converges linearly, at a rate of
/// order `|μ − σ|`, for the cost of solves only; the pair is returned when
/// the step reaches round-off and the residual passes [`at_the_estimate`]'s
/// test, `None` as soon as the steps stop contracting fast (a new
/// factorization is then cheaper). `applied` holds `q`'s products.
pub(super) fn with_the_same_factorization(
    operator: &ClassOperator,
    factored: &Factored,
    mut mu: c64,
    mut q: Vec<c64>,
    mut applied: Applied,
) -> Option<Eigenpair> {
    let mut previous = f64::INFINITY;
    for _ in 0..SAME_FACTORIZATION {
        let (value, _) = operator.at(&applied, mu);
        let correction = operator.solve(factored, &value);
        for (x, c) in q.iter_mut().zip(&correction) {
            *x -= c;
        }
        normalize(&mut q)?;
        applied = operator.applied(&q);
        let size = newton_step(operator, &mut mu, &q, &applied)?;
        let scale = mu.norm().max(1.0);
        if size <= CONVERGED * scale || (size <= CLOSE * scale && size > 0.5 * previous) {
            let (value, terms) = operator.residual(mu, &q);
            return (norm(&value) <= ACCURATE * terms).then_some((mu, q));
        }
        // Contracting by less than ten a step: refactorize instead.
        if size > 0.1 * previous {
            return None;
        }
        previous = size;
    }
    None
}

/// `Q(μ)` factorized, stepping off `μ` when it is an exponent to round-off.
pub(super) fn factor(operator: &ClassOperator, mu: c64) -> Option<Factored> {
    operator
        .factor(mu)
        .or_else(|| operator.factor(mu + c64::new(1e-14, 1e-14) * mu.norm().max(1.0)))
}

/// One inverse iteration `q ← Q(σ)⁻¹ Q'(μ) q` with `factored` at `σ`, then
/// the Newton step of `qᴴ Q(μ) q = 0`; returns the step's size. `applied`
/// holds `q`'s products ([`ClassOperator::applied`]) on entry and the new
/// `q`'s on return (the next step evaluates it again at the new `μ`).
pub(super) fn inverse_step(
    operator: &ClassOperator,
    factored: &Factored,
    mu: &mut c64,
    q: &mut Vec<c64>,
    applied: &mut Applied,
) -> Option<f64> {
    let (_, slope) = operator.at(applied, *mu);
    *q = operator.solve(factored, &slope);
    normalize(q)?;
    *applied = operator.applied(q);
    newton_step(operator, mu, q, applied)
}

/// The Newton step of the Rayleigh functional `qᴴ Q(μ) q = 0` in `μ`
/// (`q` fixed): `μ ← μ − qᴴQ(μ)q / qᴴQ'(μ)q`; returns the step's size,
/// `None` when the derivative vanishes or the step is not finite.
/// `applied` holds `q`'s products.
fn newton_step(
    operator: &ClassOperator,
    mu: &mut c64,
    q: &[c64],
    applied: &Applied,
) -> Option<f64> {
    let (value, slope) = operator.at(applied, *mu);
    let denominator = dot(q, &slope);
    if !(denominator.norm() > 0.0 && denominator.norm().is_finite()) {
        return None;
    }
    let step = dot(q, &value) / denominator;
    if !(step.re.is_finite() && step.im.is_finite()) {
        return None;
    }
    *mu -= step;
    Some(step.norm())
}
