//! Maps between the pairs of one harmonic and the sampled sectors (Sec. 2.2,
//! Eq. 14, and the AFT-CP of Sec. 3.4.1 in complex form).
//!
//! Harmonic `k` with signed diameters `s_0..s_{n−1}` is sampled on sectors
//! `1..=n`; its complex coefficients `c` give the sector coefficients
//! `X = V c` with `V[j][p] = exp(−i s_p α j)`, `j = 0..n−1` (sector `j + 1`).
//! `V` is a Vandermonde matrix of distinct `N`-th roots of unity; for the
//! cosets every rule produces it is a scaled DFT (condition number 1).

use super::{BasisError, SpectralBasis};
use faer::linalg::solvers::DenseSolveCore;
use faer::{c64, Mat, MatRef};
use std::f64::consts::PI;

/// The sector map `V[j][p] = exp(−i s_p α j)` of the signed diameters
/// `nodal_diameters` on the first `n = nodal_diameters.len()` sectors.
pub fn sector_map(sectors: usize, nodal_diameters: &[i64]) -> Mat<c64> {
    let n = sectors.max(1) as i64;
    let alpha = 2.0 * PI / n as f64;
    Mat::from_fn(nodal_diameters.len(), nodal_diameters.len(), |j, p| {
        // Reduce s j modulo N through integers: the angle stays exact.
        let m = (nodal_diameters[p].rem_euclid(n) * (j as i64 % n)).rem_euclid(n);
        let angle = -alpha * m as f64;
        c64::new(angle.cos(), angle.sin())
    })
}

/// The inverse of [`sector_map`]: sector coefficients to pair coefficients.
/// Fails if two diameters coincide modulo `N` (the map is then singular) or
/// if the computed inverse is not finite.
pub fn sector_map_inverse(sectors: usize, nodal_diameters: &[i64]) -> Result<Mat<c64>, BasisError> {
    let singular = || BasisError::SingularSectorMap {
        sectors,
        nodal_diameters: nodal_diameters.to_vec(),
    };
    if sectors == 0 {
        return Err(BasisError::NoSectors(sectors));
    }
    let n = sectors as i64;
    let mut reduced: Vec<i64> = nodal_diameters.iter().map(|s| s.rem_euclid(n)).collect();
    reduced.sort_unstable();
    if reduced.windows(2).any(|w| w[0] == w[1]) {
        return Err(singular());
    }
    let v = sector_map(sectors, nodal_diameters);
    let count = nodal_diameters.len();
    if count == 0 {
        return Ok(v);
    }
    // A coset s_0 + (N/n)Z of n diameters makes V a phase times the n-point
    // DFT: V⁻¹ = Vᴴ / n exactly. Every rule builds such sets.
    let inverse = if is_coset(n, &reduced) {
        Mat::from_fn(count, count, |p, j| v[(j, p)].conj() / count as f64)
    } else {
        v.full_piv_lu().inverse()
    };
    let finite = (0..count).all(|i| {
        (0..count).all(|j| inverse[(i, j)].re.is_finite() && inverse[(i, j)].im.is_finite())
    });
    if finite {
        Ok(inverse)
    } else {
        Err(singular())
    }
}

/// Whether sorted distinct residues modulo `n` form a coset of the subgroup
/// of order `residues.len()`: equally spaced by `n / len`.
fn is_coset(n: i64, residues: &[i64]) -> bool {
    let count = residues.len() as i64;
    if count == 0 || n % count != 0 {
        return false;
    }
    let step = n / count;
    residues
        .iter()
        .all(|&r| (r - residues[0]).rem_euclid(step) == 0)
}

/// An upper bound on the 2-norm condition number of [`sector_map`], cheap
/// for any size: the Gram matrix `G = Vᴴ V` has the closed-form entries
/// `G_pq = Σ_j ω^{(s_p − s_q) j}` (geometric sums), and Gershgorin's discs
/// put its eigenvalues in `[n − R, n + R]` with `R` the largest off-diagonal
/// row sum, so `cond(V) ≤ √((n + R)/(n − R))`. Infinite when `R ≥ n`
/// (which does not prove singularity). Exactly 1 for the cosets of a
/// subgroup, up to round-off.
pub fn condition_number_bound(sectors: usize, nodal_diameters: &[i64]) -> f64 {
    let n = sectors.max(1) as i64;
    let count = nodal_diameters.len();
    if count == 0 {
        return 1.0;
    }
    let alpha = 2.0 * PI / n as f64;
    let size = count as f64;
    let mut radius: f64 = 0.0;
    for (p, &sp) in nodal_diameters.iter().enumerate() {
        let mut row = 0.0;
        for (q, &sq) in nodal_diameters.iter().enumerate() {
            if p == q {
                continue;
            }
            let d = (sp - sq).rem_euclid(n);
            if d == 0 {
                return f64::INFINITY;
            }
            // |Σ_{j<n} z^j| = |sin(n θ/2) / sin(θ/2)| with z = e^{iθ}.
            let theta = alpha * d as f64;
            let m = ((d * count as i64) % n) as f64 * alpha;
            row += ((0.5 * m).sin() / (0.5 * theta).sin()).abs();
        }
        radius = radius.max(row);
    }
    if radius >= size {
        f64::INFINITY
    } else {
        ((size + radius) / (size - radius)).sqrt()
    }
}

/// The 2-norm condition number `σ_max / σ_min` of a square complex matrix
/// by its singular values: 1 for an empty matrix, infinite if it is
/// singular or the SVD fails. (In unoptimized builds faer's generic SVD is
/// slow: prefer [`condition_number_bound`] for large sweeps.)
pub fn condition_number(matrix: MatRef<'_, c64>) -> f64 {
    if matrix.nrows() == 0 || matrix.ncols() == 0 {
        return 1.0;
    }
    match matrix.singular_values() {
        Ok(values) => {
            let largest = values.iter().copied().fold(0.0, f64::max);
            let smallest = values.iter().copied().fold(f64::INFINITY, f64::min);
            if smallest > 0.0 {
                largest / smallest
            } else {
                f64::INFINITY
            }
        }
        Err(_) => f64::INFINITY,
    }
}

impl SpectralBasis {
    /// The sector map of harmonic `k` ([`sector_map`]); empty above `N_h`.
    pub fn sector_map(&self, harmonic: usize) -> Mat<c64> {
        sector_map(self.sectors(), self.nodal_diameters(harmonic))
    }

    /// The inverse sector map of harmonic `k` ([`sector_map_inverse`]).
    pub fn sector_map_inverse(&self, harmonic: usize) -> Result<Mat<c64>, BasisError> {
        sector_map_inverse(self.sectors(), self.nodal_diameters(harmonic))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn repeated_diameters_are_singular() {
        let e = sector_map_inverse(8, &[1, 9]);
        assert!(matches!(e, Err(BasisError::SingularSectorMap { .. })));
    }

    #[test]
    fn full_set_is_perfectly_conditioned() {
        let v = sector_map(7, &[-3, -2, -1, 0, 1, 2, 3]);
        assert!((condition_number(v.as_ref()) - 1.0).abs() < 1e-12);
    }
}
