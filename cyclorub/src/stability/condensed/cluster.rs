//! A cluster of a class's exponents followed as one block (docs/design.md
//! §10, "following").
//!
//! Where exponents lie closer to one another than they move from one point
//! of the branch to the next (on the contact plateau, a family's copies a
//! few thousandths of `ω` apart; a standing wave's double exponents),
//! following each alone may converge to a neighbour's. The cluster is
//! followed instead as the invariant subspace of its exponents: subspace
//! inverse iteration at the cluster's centre `σ` (`V ← Q(σ)⁻¹ Q'(θ_i) x_i`
//! for each Ritz pair), with Rayleigh–Ritz on the projected quadratic
//! eigenproblem `Vᴴ Q(θ) V w = 0` (`Q` is quadratic in `μ`), which gives
//! the exponents nearest `σ` whatever their order. Each Ritz pair is then
//! refined on its own at its estimate (Rayleigh functional iteration),
//! where its neighbours no longer pull it away.

use super::operator::{ClassOperator, Factored};
use super::refine::{at_the_estimate, factor};
use super::Eigenpair;
use crate::stability::vectors::{dot, norm, normalize, orthonormalize};
use faer::linalg::solvers::Solve;
use faer::{c64, Mat};

/// Subspace iterations allowed.
const ITERATIONS: usize = 12;

/// The Ritz pairs are close enough to be refined one by one when each
/// residual `‖Q(θ) x‖` is below this share of its terms.
const CLOSE: f64 = 1e-5;

/// Or each Ritz value is closer to its exponent than this share of its
/// distance to the next Ritz value: refined alone, it converges to its own.
const SEPARATED: f64 = 0.05;

/// The cluster's exponents, as many as `starts` holds, from their values
/// and vectors at the previous point; `None` when the subspace loses rank,
/// the iteration does not settle, or a refinement fails.
pub(super) fn followed_together(
    operator: &ClassOperator,
    starts: &[(c64, &[c64])],
) -> Option<Vec<Eigenpair>> {
    let k = starts.len();
    if k == 0 {
        return Some(Vec::new());
    }
    let centre = starts.iter().map(|(mu, _)| *mu).sum::<c64>() / k as f64;
    let at_centre = factor(operator, centre)?;
    let mut basis: Vec<Vec<c64>> = Vec::with_capacity(k);
    for (_, vector) in starts {
        let mut v = vector.to_vec();
        if !orthonormalize(&basis, &mut v) {
            return None;
        }
        basis.push(v);
    }
    for _ in 0..ITERATIONS {
        let pairs = ritz_pairs(operator, &basis, centre)?;
        let settled = pairs.iter().enumerate().all(|(i, (theta, x))| {
            let (value, scale) = operator.residual(*theta, x);
            let (_, slope) = operator.times(*theta, x);
            // The distance to the nearest exponent, about (Q(θ + δ) x ≈ 0).
            let error = norm(&value) / norm(&slope).max(f64::MIN_POSITIVE);
            let gap = pairs
                .iter()
                .enumerate()
                .filter(|(j, _)| *j != i)
                .map(|(_, (other, _))| (other - theta).norm())
                .fold(f64::INFINITY, f64::min);
            norm(&value) <= CLOSE * scale || error <= SEPARATED * gap
        });
        if settled {
            return pairs
                .into_iter()
                .map(|(theta, x)| at_the_estimate(operator, theta, x))
                .collect();
        }
        basis = next_basis(operator, &at_centre, &pairs)?;
    }
    None
}

/// The Ritz pairs of `basis` nearest `centre`, as many as the basis has
/// vectors: the eigenpairs of `P₀ + θ P₁ + θ² P₂` (`P_j = Vᴴ A_j V`,
/// `Q(μ) = A₀ + μ A₁ + μ² A₂`), through its companion matrix (`P₂` is the
/// projected mass, times `ω²`: invertible), lifted to unit block vectors.
fn ritz_pairs(operator: &ClassOperator, basis: &[Vec<c64>], centre: c64) -> Option<Vec<Eigenpair>> {
    let k = basis.len();
    // A₀v and A₁v from Q(0), Q'(0); A₂v from Q'(1) = A₁ + 2A₂.
    let mut images: [Vec<Vec<c64>>; 3] = Default::default();
    for v in basis {
        let (a0, a1) = operator.times(c64::new(0.0, 0.0), v);
        let (_, slope) = operator.times(c64::new(1.0, 0.0), v);
        let a2: Vec<c64> = slope.iter().zip(&a1).map(|(s, a)| (s - a) * 0.5).collect();
        images[0].push(a0);
        images[1].push(a1);
        images[2].push(a2);
    }
    let projected = |j: usize| Mat::from_fn(k, k, |r, c| dot(&basis[r], &images[j][c]));
    let (p0, p1, p2) = (projected(0), projected(1), projected(2));
    let lu = p2.partial_piv_lu();
    let (s0, s1) = (lu.solve(&p0), lu.solve(&p1));
    let companion = Mat::from_fn(2 * k, 2 * k, |r, c| match (r < k, c < k) {
        (true, true) => c64::new(0.0, 0.0),
        (true, false) => c64::new(if c - k == r { 1.0 } else { 0.0 }, 0.0),
        (false, true) => -s0[(r - k, c)],
        (false, false) => -s1[(r - k, c - k)],
    });
    let eigen = companion.eigen().ok()?;
    let (values, vectors) = (eigen.S(), eigen.U());
    let mut order: Vec<usize> = (0..2 * k).collect();
    order.sort_by(|&a, &b| {
        (values[a] - centre)
            .norm()
            .total_cmp(&(values[b] - centre).norm())
    });
    order
        .into_iter()
        .take(k)
        .map(|i| {
            let theta = values[i];
            if !(theta.re.is_finite() && theta.im.is_finite()) {
                return None;
            }
            let mut x = vec![c64::new(0.0, 0.0); basis[0].len()];
            for (j, v) in basis.iter().enumerate() {
                let w = vectors[(j, i)];
                x.iter_mut().zip(v).for_each(|(a, b)| *a += w * b);
            }
            normalize(&mut x)?;
            Some((theta, x))
        })
        .collect()
}

/// The next basis: `Q(σ)⁻¹ Q'(θ_i) x_i` of each Ritz pair, orthonormalized
/// (`None` when they lose rank).
fn next_basis(
    operator: &ClassOperator,
    at_centre: &Factored,
    pairs: &[Eigenpair],
) -> Option<Vec<Vec<c64>>> {
    let mut basis: Vec<Vec<c64>> = Vec::with_capacity(pairs.len());
    for (theta, x) in pairs {
        let (_, slope) = operator.times(*theta, x);
        let mut v = operator.solve(at_centre, &slope);
        if !orthonormalize(&basis, &mut v) {
            return None;
        }
        basis.push(v);
    }
    Some(basis)
}
