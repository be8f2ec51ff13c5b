//! The contact term as a low-rank product, and the Schur complement's
//! inverse through it (docs/design.md §10).
//!
//! A class's contact matrix `C_c(μ) = D + ω E diag(μ + i k_col)` on its `r`
//! contact positions is, in Hill's harmonics, the Toeplitz matrix of the
//! linearized contact over one period: where the tip touches the casing
//! during a few time samples only (impacts, the fan's DLFT contact), its
//! rank is about the number of those samples, far below `r` (15 of 567
//! there, to 1e-13). With `D = L_D W_D` and `E = L_E W_E` (orthonormal
//! `L`), `C_c = L W(μ)`, `L = [L_D L_E]`, `W(μ) = [W_D; W_E diag(ω(μ + i k))]`,
//! and the Schur complement `S = I + C_c R` is inverted by Woodbury:
//! `S⁻¹ = I − L T⁻¹ W R`, `T = I + W R L` of the rank's order, with
//! `det S = det T` (Sylvester) for the contour's count.

use crate::stability::small_lu::SmallLu;
use faer::{c64, Mat};

const ZERO: c64 = c64 { re: 0.0, im: 0.0 };

/// The compression's accuracy: `‖A − L W‖_F ≤ ACCURACY ‖A‖_F`, checked.
const ACCURACY: f64 = 1e-13;

/// Contact positions from which the compression is tried.
pub(super) const COMPRESSED_FROM: usize = 40;

/// `A ≈ L W`: `left` `r × k` (orthonormal columns), `right` `k × r`, both
/// row-major.
struct Factors {
    rank: usize,
    left: Vec<c64>,
    right: Vec<c64>,
}

/// `A` (row-major `r × r`) as `L (Lᴴ A)`, `L` an orthonormal basis of
/// `A Ω` for fixed random `Ω` of 8, 16, 32, … columns, the first whose
/// product is `A` to [`ACCURACY`] (the check is made on the whole matrix:
/// the randomness chooses the basis, not the accuracy); `None` past
/// `largest` columns.
fn compress(a: &[c64], r: usize, largest: usize) -> Option<Factors> {
    let norm = a.iter().map(|z| z.norm_sqr()).sum::<f64>().sqrt();
    if norm == 0.0 {
        return Some(Factors {
            rank: 0,
            left: Vec::new(),
            right: Vec::new(),
        });
    }
    let matrix = Mat::from_fn(r, r, |i, j| a[i * r + j]);
    let mut k = 8;
    while k <= largest {
        let sketch = Mat::from_fn(r, k, |i, j| unit_phase((i * k + j) as u64));
        let basis = (&matrix * &sketch).qr().compute_thin_Q();
        let right = basis.adjoint() * &matrix;
        let residual = &matrix - &basis * &right;
        let error = residual.norm_l2();
        if error <= 0.5 * ACCURACY * norm {
            // The sketch's basis has k columns; the rank can be lower:
            // Qᴴ A = U Σ Vᴴ trimmed of its tail below the other half of
            // the accuracy, L = Q U_p, W = Σ_p V_pᴴ.
            let svd = right.thin_svd().ok()?;
            let values: Vec<f64> = (0..svd.S().dim()).map(|i| svd.S()[i].re).collect();
            let mut tail = 0.0;
            let mut p = values.len();
            while p > 0 && (tail + values[p - 1] * values[p - 1]).sqrt() <= 0.5 * ACCURACY * norm {
                tail += values[p - 1] * values[p - 1];
                p -= 1;
            }
            let left = &basis * svd.U().subcols(0, p);
            let v = svd.V();
            return Some(Factors {
                rank: p,
                left: (0..r * p).map(|e| left[(e / p, e % p)]).collect(),
                right: (0..p * r)
                    .map(|e| v[(e % r, e / r)].conj() * values[e / r])
                    .collect(),
            });
        }
        k *= 2;
    }
    None
}

/// A unit complex number of fixed pseudo-random phase for `index`
/// (SplitMix64, Steele, Lea & Flood 2014): reproducible probing and
/// sketching vectors.
pub(super) fn unit_phase(index: u64) -> c64 {
    let mut z = index.wrapping_add(0x9e37_79b9_7f4a_7c15);
    z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
    z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
    z ^= z >> 31;
    let t = (z >> 11) as f64 / (1u64 << 53) as f64;
    c64::cis(2.0 * std::f64::consts::PI * t)
}

/// `C_c(μ) = L W(μ)` on a class's contact positions.
pub(super) struct LowRankContact {
    r: usize,
    /// `ρ = ρ_D + ρ_E`.
    rank: usize,
    /// `[L_D L_E]`, `r × ρ` row-major.
    left: Vec<c64>,
    /// `W_D`, `ρ_D × r`.
    stiffness: Vec<c64>,
    /// `W_E`, `ρ_E × r`.
    damping: Vec<c64>,
    stiffness_rank: usize,
}

impl LowRankContact {
    /// `D` and `E` (row-major `r × r`) compressed, or `None` when `r` is
    /// small or their ranks together exceed a quarter of `r` (the dense
    /// Schur complement is then as cheap).
    pub(super) fn new(stiffness: &[c64], damping: &[c64], r: usize) -> Option<Self> {
        if r < COMPRESSED_FROM {
            return None;
        }
        let largest = r / 4;
        let d = compress(stiffness, r, largest)?;
        let e = compress(damping, r, largest)?;
        let rank = d.rank + e.rank;
        if rank > largest {
            return None;
        }
        let mut left = vec![ZERO; r * rank];
        for i in 0..r {
            left[i * rank..i * rank + d.rank]
                .copy_from_slice(&d.left[i * d.rank..(i + 1) * d.rank]);
            left[i * rank + d.rank..(i + 1) * rank]
                .copy_from_slice(&e.left[i * e.rank..(i + 1) * e.rank]);
        }
        Some(Self {
            r,
            rank,
            left,
            stiffness: d.right,
            damping: e.right,
            stiffness_rank: d.rank,
        })
    }

    /// `ρ`.
    pub(super) fn rank(&self) -> usize {
        self.rank
    }

    /// `S(μ)⁻¹` from the receptance `R` (zero between groups, `members[j]`
    /// the positions of `j`'s group; `R_lj = columns[j][local_dof[l]]`,
    /// `columns[j] = Z⁻¹ e_j` on its group's dofs) and the columns' factors
    /// `ω(μ + i k_col)`; `None` when `T` is singular.
    pub(super) fn schur_inverse(
        &self,
        factors: &[c64],
        columns: &[Vec<c64>],
        local_dof: &[usize],
        members: &[Vec<usize>],
    ) -> Option<SchurInverse> {
        let (r, rank) = (self.r, self.rank);
        // W R, ρ × r: R's column j lives on j's group.
        let mut weighted = vec![ZERO; rank * r];
        for a in 0..rank {
            let row = self.row_of_w(a);
            for j in 0..r {
                weighted[a * r + j] = members[j]
                    .iter()
                    .map(|&l| {
                        let w = if a < self.stiffness_rank {
                            row[l]
                        } else {
                            row[l] * factors[l]
                        };
                        w * columns[j][local_dof[l]]
                    })
                    .sum();
            }
        }
        // T = I + (W R) L.
        let mut core = vec![ZERO; rank * rank];
        for a in 0..rank {
            core[a * rank + a] = c64::new(1.0, 0.0);
            for j in 0..r {
                let w = weighted[a * r + j];
                if w == ZERO {
                    continue;
                }
                for (b, &l) in self.left[j * rank..(j + 1) * rank].iter().enumerate() {
                    core[a * rank + b] += w * l;
                }
            }
        }
        Some(SchurInverse::LowRank {
            weighted,
            core: SmallLu::new(core, rank)?,
            left: self.left.clone(),
        })
    }

    /// Row `a` of `W_D` or `W_E` (without the columns' factors).
    fn row_of_w(&self, a: usize) -> &[c64] {
        let r = self.r;
        if a < self.stiffness_rank {
            &self.stiffness[a * r..(a + 1) * r]
        } else {
            let b = a - self.stiffness_rank;
            &self.damping[b * r..(b + 1) * r]
        }
    }
}

/// `S(μ)⁻¹`: a dense LU of `S`, or Woodbury's through the low-rank contact.
pub(super) enum SchurInverse {
    /// The LU of `S`, `r × r`.
    Full(SmallLu),
    /// `W R` (`ρ × r`), the LU of `T = I + W R L` and `L` (`r × ρ`), all
    /// row-major.
    LowRank {
        weighted: Vec<c64>,
        core: SmallLu,
        left: Vec<c64>,
    },
}

impl SchurInverse {
    /// `S⁻¹ t` in place.
    pub(super) fn apply(&self, t: &mut [c64]) {
        match self {
            SchurInverse::Full(lu) => lu.solve(t),
            SchurInverse::LowRank {
                weighted,
                core,
                left,
            } => {
                let r = t.len();
                let rank = weighted.len() / r.max(1);
                let mut y: Vec<c64> = weighted
                    .chunks_exact(r)
                    .map(|row| row.iter().zip(t.iter()).map(|(w, x)| w * x).sum())
                    .collect();
                core.solve(&mut y);
                for (value, row) in t.iter_mut().zip(left.chunks_exact(rank.max(1))) {
                    *value -= row.iter().zip(&y).map(|(l, y)| l * y).sum::<c64>();
                }
            }
        }
    }

    /// `S⁻¹ B` in place for the `l` columns of `b`, `r × l` row-major.
    pub(super) fn solve_rows(&self, b: &mut [c64], l: usize) {
        match self {
            SchurInverse::Full(lu) => lu.solve_rows(b, l),
            SchurInverse::LowRank {
                weighted,
                core,
                left,
            } => {
                let r = b.len() / l.max(1);
                let rank = weighted.len() / r.max(1);
                // Y = (W R) B, ρ × l; T⁻¹ Y; B −= L Y.
                let mut y = vec![ZERO; rank * l];
                for (row, w) in y.chunks_exact_mut(l.max(1)).zip(weighted.chunks_exact(r)) {
                    for (&factor, source) in w.iter().zip(b.chunks_exact(l.max(1))) {
                        for (value, &x) in row.iter_mut().zip(source) {
                            *value += factor * x;
                        }
                    }
                }
                core.solve_rows(&mut y, l);
                for (target, coefficients) in b
                    .chunks_exact_mut(l.max(1))
                    .zip(left.chunks_exact(rank.max(1)))
                {
                    for (&factor, source) in coefficients.iter().zip(y.chunks_exact(l.max(1))) {
                        for (value, &x) in target.iter_mut().zip(source) {
                            *value -= factor * x;
                        }
                    }
                }
            }
        }
    }

    /// The argument of `det S` (`= det T` through the compression), rad.
    pub(super) fn determinant_argument(&self) -> f64 {
        match self {
            SchurInverse::Full(lu) | SchurInverse::LowRank { core: lu, .. } => {
                lu.determinant_argument()
            }
        }
    }
}
