//! Every pole of the contact resolvent inside an ellipse, by Beyn's
//! contour-integral method (W.-J. Beyn, "An integral method for solving
//! nonlinear eigenvalue problems", Linear Algebra Appl. 436, 2012,
//! Algorithm 2: the block-Hankel form for more poles than the resolvent's
//! size).
//!
//! The resolvent `F(μ) = P Q(μ)⁻¹ Pᵀ` is meromorphic, with a pole at each
//! exponent of the class seen from the contact, of residue `x yᴴ` (its
//! vector at the contact positions). The moments
//! `A_p = (1/2πi) ∮ ν(μ)ᵖ F(μ) dμ`, `ν = (μ − c)/ρ`, by the trapezoidal rule
//! on the ellipse (exponentially accurate for poles away from it), equal
//! `X diag(ν_i)ᵖ Yᴴ` over the poles inside; the block-Hankel matrices of
//! the moments give the `ν_i` as the eigenvalues of a small matrix. The
//! estimates are then refined one by one on `Q` itself
//! (`super::refine`): the contour only has to place them.

use super::low_rank::unit_phase;
use super::operator::ClassOperator;
use faer::{c64, Mat};
use rayon::prelude::*;
use std::f64::consts::PI;

/// An ellipse in the plane of `μ = λ/ω`, centred on the real axis.
#[derive(Clone, Copy, Debug)]
pub(super) struct Ellipse {
    /// Centre (real).
    pub(super) centre: f64,
    /// Semi-axis along the real direction.
    pub(super) real_axis: f64,
    /// Semi-axis along the imaginary direction.
    pub(super) imaginary_axis: f64,
}

impl Ellipse {
    /// `((Re μ − c)/a)² + (Im μ/b)²`: below 1 inside.
    pub(super) fn level(&self, mu: c64) -> f64 {
        let x = (mu.re - self.centre) / self.real_axis;
        let y = mu.im / self.imaginary_axis;
        x * x + y * y
    }

    fn radius(&self) -> f64 {
        self.real_axis.max(self.imaginary_axis)
    }
}

/// A pole's estimate: `μ` and its vector at the contact positions.
pub(super) type Estimate = (c64, Vec<c64>);

/// What the contour gives: the estimates, and how many times `det S`
/// winds round 0 along it (the exponents of `Q` inside minus the linear
/// wheel's, by the argument principle), `None` when its phase jumps too
/// much between nodes to be counted.
pub(super) struct Contour {
    /// The estimated poles inside (and some just outside).
    pub(super) estimates: Vec<Estimate>,
    /// The winding number of `det S`.
    pub(super) winding: Option<i64>,
}

/// The estimated poles of `operator`'s contact resolvent inside `ellipse`,
/// from `nodes` quadrature points, `probes` probing vectors and `moments`
/// block moments (so up to `moments · probes` poles), or `None` when a
/// factorization failed at every nudge of a node, the moments' SVD or
/// eigen solve failed, or the moments are full (as many poles as they can
/// hold: there may be more).
pub(super) fn poles_inside(
    operator: &ClassOperator,
    ellipse: &Ellipse,
    nodes: usize,
    moments: usize,
    probes: usize,
) -> Option<Contour> {
    let r = operator.positions();
    let l = probes.clamp(1, r.max(1));
    if r == 0 {
        return Some(Contour {
            estimates: Vec::new(),
            winding: Some(0),
        });
    }
    let probing = probing_vectors(r, l);
    let rho = ellipse.radius();
    // A_p V̂ for p = 0..2·moments − 1, each r × l row-major.
    let powers = 2 * moments;
    let mut sums = vec![vec![c64::new(0.0, 0.0); r * l]; powers];
    let mut arguments = Vec::with_capacity(nodes);
    // The nodes are factorized in parallel, a few per thread at a time (a
    // whole wheel's resolvent is large), and summed in their order, so the
    // moments do not depend on the threads.
    let batch = 2 * rayon::current_num_threads().max(1);
    for first in (0..nodes).step_by(batch) {
        let evaluated: Vec<_> = (first..(first + batch).min(nodes))
            .into_par_iter()
            .map(|j| {
                node(ellipse, j, nodes, operator, &probing)
                    .map(|(mu, weight, (resolvent, argument))| (mu, weight, resolvent, argument))
            })
            .collect::<Option<_>>()?;
        for (mu, weight, resolvent, argument) in evaluated {
            arguments.push(argument);
            let nu = (mu - c64::new(ellipse.centre, 0.0)) / rho;
            let mut factor = weight;
            for sum in sums.iter_mut() {
                for (s, value) in sum.iter_mut().zip(&resolvent) {
                    *s += factor * value;
                }
                factor *= nu;
            }
        }
    }
    let (rows, cols) = (moments * r, moments * l);
    let hankel = |shift: usize| {
        Mat::from_fn(rows, cols, |row, col| {
            let (bi, i) = (row / r, row % r);
            let (bj, j) = (col / l, col % l);
            sums[bi + bj + shift][i * l + j]
        })
    };
    let (h0, h1) = (hankel(0), hankel(1));
    let winding = winding(&arguments);
    let svd = h0.svd().ok()?;
    let (u, s, v) = (svd.U(), svd.S(), svd.V());
    let size = rows.min(cols);
    let largest = (0..size).map(|i| s[i].re).fold(0.0, f64::max);
    let none = Contour {
        estimates: Vec::new(),
        winding,
    };
    if !(largest > 0.0 && largest.is_finite()) {
        return Some(none);
    }
    let rank = (0..size).filter(|&i| s[i].re > RANK * largest).count();
    if rank == 0 {
        return Some(none);
    }
    // As many poles as the moments can hold: there may be more.
    if rank + 1 >= size {
        return None;
    }
    // M = U_kᴴ H₁ V_k Σ_k⁻¹.
    let uk = u.subcols(0, rank);
    let vk = v.subcols(0, rank);
    let mut reduced = uk.adjoint() * &h1 * vk;
    for c in 0..rank {
        let inverse = 1.0 / s[c].re;
        for row in 0..rank {
            reduced[(row, c)] *= inverse;
        }
    }
    let eigen = reduced.eigen().ok()?;
    let (values, vectors) = (eigen.S(), eigen.U());
    let mut out = Vec::with_capacity(rank);
    for i in 0..rank {
        let nu = values[i];
        let mu = c64::new(ellipse.centre, 0.0) + nu * rho;
        if !(mu.re.is_finite() && mu.im.is_finite()) {
            continue;
        }
        let vector: Vec<c64> = (0..r)
            .map(|row| (0..rank).map(|c| uk[(row, c)] * vectors[(c, i)]).sum())
            .collect();
        out.push((mu, vector));
    }
    Some(Contour {
        estimates: out,
        winding,
    })
}

/// The winding number of a closed sequence of arguments, each step taken
/// as the nearest turn; `None` when a step is near half a turn (the
/// nodes are too sparse there to tell which way the phase went).
fn winding(arguments: &[f64]) -> Option<i64> {
    let n = arguments.len();
    let mut total = 0.0;
    for j in 0..n {
        let step = arguments[(j + 1) % n] - arguments[j];
        let wrapped = step - 2.0 * PI * (step / (2.0 * PI)).round();
        if wrapped.abs() > 0.75 * PI {
            return None;
        }
        total += wrapped;
    }
    Some((total / (2.0 * PI)).round() as i64)
}

/// Singular values of the Hankel matrix below this share of the largest are
/// the quadrature's noise, not poles.
const RANK: f64 = 1e-10;

/// Node `j` of `nodes` on the ellipse and its weight `dμ/(2πi)`, nudged
/// along the ellipse when `Q` cannot be factorized there.
fn node(
    ellipse: &Ellipse,
    j: usize,
    nodes: usize,
    operator: &ClassOperator,
    probing: &Mat<c64>,
) -> Option<(c64, c64, (Vec<c64>, f64))> {
    for nudge in 0..4 {
        let theta = 2.0 * PI * (j as f64 + 0.5 + 1e-3 * nudge as f64) / nodes as f64;
        let (sin, cos) = theta.sin_cos();
        let mu = c64::new(
            ellipse.centre + ellipse.real_axis * cos,
            ellipse.imaginary_axis * sin,
        );
        let Some(resolvent) = operator.probed_resolvent(mu, probing) else {
            continue;
        };
        let derivative = c64::new(-ellipse.real_axis * sin, ellipse.imaginary_axis * cos);
        // dμ = μ'(θ) dθ, dθ = 2π/nodes; divided by 2πi.
        let weight = derivative / c64::new(0.0, nodes as f64);
        return Some((mu, weight, resolvent));
    }
    None
}

/// `l` fixed probing vectors of length `r`, as the columns of an `r × l`
/// matrix: the identity when `l = r`, otherwise unit phases drawn by a
/// fixed hash of the position, so that the run is reproducible and the
/// columns independent (phases in arithmetic progression along a row
/// would make every column a multiple of the first).
fn probing_vectors(r: usize, l: usize) -> Mat<c64> {
    Mat::from_fn(r, l, |i, j| {
        if l == r {
            return c64::new(if i == j { 1.0 } else { 0.0 }, 0.0);
        }
        unit_phase((i * l + j) as u64)
    })
}

/// How many times a contour that misses exponents is drawn again (twice
/// the nodes, one more moment each time) before the dense fallback.
const REDRAWN: usize = 1;

/// Estimates this far out (in the ellipse's level) still count as inside:
/// the contour places those near it less accurately.
const COUNTED: f64 = 1.05;

/// The contour on `ellipse` from `nodes` nodes and `moments` moments (with
/// `probes` probing vectors), drawn again with twice the nodes and one
/// more moment up to [`REDRAWN`] times while its estimates and the
/// `unseen` linear exponents do not account for the exponents inside
/// (`det S`'s winding plus the `inside` linear poles) or its moments are
/// full (there may be more poles than they hold); `None` when no drawing
/// passes.
pub(super) fn drawn(
    operator: &ClassOperator,
    ellipse: &Ellipse,
    nodes: usize,
    moments: usize,
    probes: usize,
    inside: usize,
    unseen: usize,
) -> Option<Contour> {
    for attempt in 0..=REDRAWN {
        let (nodes, moments) = (nodes << attempt, moments + attempt);
        let Some(contour) = poles_inside(operator, ellipse, nodes, moments, probes) else {
            tracing::debug!(
                "the contour ({nodes} nodes, {moments} moments) gave no estimates: its moments are full (there may be more poles than they hold) or a factorization failed"
            );
            continue;
        };
        let estimated = contour
            .estimates
            .iter()
            .filter(|(mu, _)| ellipse.level(*mu) < COUNTED)
            .count();
        // (Where the phase steps too far between nodes to be counted,
        // often near the lightly damped exponents the contour crosses
        // between, the check is not made.)
        let Some(winding) = contour.winding else {
            return Some(contour);
        };
        let expected = (winding + inside as i64).max(0) as usize;
        if estimated + unseen >= expected {
            return Some(contour);
        }
        tracing::debug!(
            "the contour ({nodes} nodes, {moments} moments) accounts for {} of the {expected} exponents inside",
            estimated + unseen
        );
    }
    None
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_probing_vectors_are_independent() {
        // Their smallest singular value against the largest: the columns of
        // phases in arithmetic progression (rank one) would give 0.
        let v = probing_vectors(40, 8);
        let svd = v.svd().unwrap();
        let s: Vec<f64> = (0..8).map(|i| svd.S()[i].re).collect();
        let (largest, smallest) = (
            s.iter().cloned().fold(0.0, f64::max),
            s.iter().cloned().fold(f64::INFINITY, f64::min),
        );
        assert!(smallest > 0.2 * largest, "{s:?}");
    }

    #[test]
    fn the_winding_of_a_power_of_the_node_is_its_exponent() {
        // arg((z − a)^k) along the unit circle: k turns for |a| < 1, none
        // for |a| > 1; too few nodes for the phase: no count.
        for (a, k, expected) in [(0.3, 3, 3), (0.3, -2, -2), (1.7, 4, 0)] {
            let arguments: Vec<f64> = (0..64)
                .map(|j| {
                    let z = c64::cis(2.0 * PI * j as f64 / 64.0) - c64::new(a, 0.0);
                    k as f64 * z.arg()
                })
                .collect();
            assert_eq!(winding(&arguments), Some(expected));
        }
        let sparse: Vec<f64> = (0..4).map(|j| 0.9 * PI * j as f64).collect();
        assert_eq!(winding(&sparse), None);
    }
}
