//! One class's quadratic eigenproblem `Q(μ) q = 0`, evaluated through its
//! structure: a small factorization per group and a Schur complement on
//! the contact positions.
//!
//! With `μ = λ/ω`, each group `g` (a pair `(s, k)`) has the dynamic
//! stiffness `Z_g(μ) = ω²(μ + ik)² M + ω(μ + ik) C + K` of its diameter, and
//! the contact adds on the contact positions `P` (a contact dof of a group)
//! the matrix `C_c(μ) = D + ω E diag(μ + i k_col)`: `D` the stiffness
//! coefficients, `E` the velocity ones (friction), `k_col` the harmonic of
//! the column's group. So `Q(μ) = Z(μ) + Pᵀ C_c(μ) P`, and with the
//! receptance `R = P Z⁻¹ Pᵀ` (block diagonal over groups) and
//! `S = I + C_c R`:
//! - `Q⁻¹ = Z⁻¹ − Z⁻¹Pᵀ S⁻¹ C_c P Z⁻¹` (Woodbury);
//! - `P Q⁻¹ Pᵀ = R S⁻¹`, the contact resolvent, whose poles are the
//!   exponents seen from the contact (those of `Q`, not those of `Z`).

mod products;
mod sparse_rows;

use super::low_rank::{LowRankContact, SchurInverse};
use crate::stability::hill::{group_offsets, Group};
use crate::stability::small_lu::SmallLu;
use faer::{c64, Mat};
pub(super) use products::Applied;
use sparse_rows::SparseRows;

const ZERO: c64 = c64 { re: 0.0, im: 0.0 };
const ONE: c64 = c64 { re: 1.0, im: 0.0 };

/// A group's `M`, `C` and `K`, row-major (the hot loops read them as
/// slices, not through faer's checked indexing).
struct RowMajor {
    dofs: usize,
    mass: Vec<c64>,
    damping: Vec<c64>,
    stiffness: Vec<c64>,
}

impl RowMajor {
    fn of(dynamics: &crate::stability::hill::LocalDynamics) -> Self {
        let n = dynamics.dofs();
        let rows = |m: &Mat<c64>| {
            let mut out = Vec::with_capacity(n * n);
            for r in 0..n {
                out.extend((0..n).map(|c| m[(r, c)]));
            }
            out
        };
        Self {
            dofs: n,
            mass: rows(dynamics.mass()),
            damping: rows(dynamics.damping()),
            stiffness: rows(dynamics.stiffness()),
        }
    }
}

/// A class's block with its contact positions, ready to be evaluated.
pub(super) struct ClassOperator<'a> {
    groups: &'a [Group],
    /// The distinct dynamics of the groups (harmonics of one diameter
    /// share theirs), row-major, and each group's.
    matrices: Vec<RowMajor>,
    group_matrices: Vec<usize>,
    offsets: Vec<usize>,
    /// Dofs of all groups.
    m: usize,
    omega: f64,
    /// The block dofs the contact couples (sorted) and the group of each.
    contact: Vec<usize>,
    contact_group: Vec<usize>,
    /// The contact positions of each position's group (`R` is zero
    /// between groups).
    members: Vec<Vec<usize>>,
    /// The contact positions of each group.
    group_positions: Vec<Vec<usize>>,
    /// Each contact position's dof within its group.
    local_dof: Vec<usize>,
    /// `D` on the contact positions, `r × r` row-major, N/m.
    stiffness: Vec<c64>,
    /// `E` likewise, N·s/m (zero without friction).
    damping: Vec<c64>,
    /// `D` and `E` by their nonzero entries, for the products.
    stiffness_rows: SparseRows,
    damping_rows: SparseRows,
    /// Whether `E` has an entry (friction).
    velocity_terms: bool,
    /// `D` and `E` as low-rank products, where that pays ([`LowRankContact`]).
    low_rank: Option<LowRankContact>,
}

/// `Q(μ)` factorized by its structure.
pub(super) struct Factored {
    groups: Vec<SmallLu>,
    /// `Z⁻¹ e_j` on its group's dofs, for each contact position `j`.
    columns: Vec<Vec<c64>>,
    /// Where it was factorized.
    mu: c64,
    /// `S⁻¹`, `S = I + C_c R`.
    schur: SchurInverse,
}

impl<'a> ClassOperator<'a> {
    /// From a block's groups and its contact entries `(row, column, value)`
    /// on the groups' dofs (`coupling` N/m, `damping` N·s/m); `None` when an
    /// entry lies outside the groups.
    pub(super) fn new(
        groups: &'a [Group],
        coupling: &[(usize, usize, c64)],
        damping: &[(usize, usize, c64)],
        omega: f64,
    ) -> Option<Self> {
        Self::built(groups, coupling, damping, omega, true)
    }

    /// [`Self::new`], the contact compressed only when `compressed` (the
    /// tests compare both ways).
    pub(super) fn built(
        groups: &'a [Group],
        coupling: &[(usize, usize, c64)],
        damping: &[(usize, usize, c64)],
        omega: f64,
        compressed: bool,
    ) -> Option<Self> {
        let (offsets, m) = group_offsets(groups);
        let mut contact: Vec<usize> = coupling
            .iter()
            .chain(damping)
            .flat_map(|&(r, c, _)| [r, c])
            .collect();
        contact.sort_unstable();
        contact.dedup();
        if contact.last().is_some_and(|&d| d >= m) {
            return None;
        }
        let mut index = vec![usize::MAX; m];
        for (i, &d) in contact.iter().enumerate() {
            index[d] = i;
        }
        let r = contact.len();
        let dense = |entries: &[(usize, usize, c64)]| {
            let mut out = vec![ZERO; r * r];
            for &(row, col, value) in entries {
                out[index[row] * r + index[col]] += value;
            }
            out
        };
        let contact_group: Vec<usize> = contact
            .iter()
            .map(|&d| offsets.partition_point(|&o| o <= d) - 1)
            .collect();
        let members = contact_group
            .iter()
            .map(|&g| (0..r).filter(|&j| contact_group[j] == g).collect())
            .collect();
        let mut seen: Vec<*const crate::stability::hill::LocalDynamics> = Vec::new();
        let mut matrices = Vec::new();
        let group_matrices = groups
            .iter()
            .map(|g| {
                let key = std::sync::Arc::as_ptr(&g.dynamics);
                match seen.iter().position(|&k| k == key) {
                    Some(i) => i,
                    None => {
                        seen.push(key);
                        matrices.push(RowMajor::of(&g.dynamics));
                        matrices.len() - 1
                    }
                }
            })
            .collect();
        let (stiffness, damping_matrix) = (dense(coupling), dense(damping));
        let low_rank = if compressed {
            LowRankContact::new(&stiffness, &damping_matrix, r)
        } else {
            None
        };
        let mut group_positions = vec![Vec::new(); groups.len()];
        for (j, &g) in contact_group.iter().enumerate() {
            group_positions[g].push(j);
        }
        let local_dof = contact
            .iter()
            .zip(&contact_group)
            .map(|(&d, &g)| d - offsets[g])
            .collect();
        Some(Self {
            stiffness_rows: SparseRows::of(&stiffness, r),
            damping_rows: SparseRows::of(&damping_matrix, r),
            group_positions,
            local_dof,
            members,
            matrices,
            group_matrices,
            groups,
            offsets,
            m,
            omega,
            stiffness,
            velocity_terms: !damping.is_empty(),
            damping: damping_matrix,
            contact,
            contact_group,
            low_rank,
        })
    }

    /// Dofs of all groups.
    pub(super) fn dofs(&self) -> usize {
        self.m
    }

    /// Contact positions `r`.
    pub(super) fn positions(&self) -> usize {
        self.contact.len()
    }

    /// The rank of the compressed contact, `None` when it is not
    /// compressed.
    pub(super) fn contact_rank(&self) -> Option<usize> {
        self.low_rank.as_ref().map(LowRankContact::rank)
    }

    /// The groups.
    pub(super) fn groups(&self) -> &[Group] {
        self.groups
    }

    /// Where each group's dofs start.
    pub(super) fn offsets(&self) -> &[usize] {
        &self.offsets
    }

    /// `C_c(μ)`.
    fn contact_matrix(&self, mu: c64) -> Vec<c64> {
        let mut out = self.stiffness.clone();
        if !self.velocity_terms {
            return out;
        }
        let r = self.contact.len();
        let factors = self.column_factors(mu);
        // Row by row (the matrices are row-major).
        for (row, damping) in out.chunks_exact_mut(r).zip(self.damping.chunks_exact(r)) {
            for ((value, &e), &factor) in row.iter_mut().zip(damping).zip(&factors) {
                *value += e * factor;
            }
        }
        out
    }

    /// `C_c(μ) u` for a contact vector `u`, without forming `C_c`.
    fn contact_times(&self, mu: c64, u: &[c64]) -> Vec<c64> {
        let mut out = self.stiffness_rows.times(u);
        if self.velocity_terms {
            let moved: Vec<c64> = self
                .column_factors(mu)
                .iter()
                .zip(u)
                .map(|(f, x)| f * x)
                .collect();
            for (value, e) in out.iter_mut().zip(self.damping_rows.times(&moved)) {
                *value += e;
            }
        }
        out
    }

    /// `ω(μ + i k_col)` of each contact position's column.
    fn column_factors(&self, mu: c64) -> Vec<c64> {
        self.contact_group
            .iter()
            .map(|&g| (mu + c64::new(0.0, self.groups[g].harmonic as f64)) * self.omega)
            .collect()
    }

    /// `Z_g(μ)` of group `index`, row-major.
    fn dynamic_stiffness(&self, index: usize, mu: c64) -> Vec<c64> {
        let d = &self.matrices[self.group_matrices[index]];
        let z = mu + c64::new(0.0, self.groups[index].harmonic as f64);
        let (a2, a1) = (z * z * (self.omega * self.omega), z * self.omega);
        d.mass
            .iter()
            .zip(&d.damping)
            .zip(&d.stiffness)
            .map(|((&m, &c), &k)| m * a2 + c * a1 + k)
            .collect()
    }

    /// `Q(μ)` factorized, or `None` when a pivot vanishes (`μ` an exponent
    /// of a group or of the class to round-off).
    pub(super) fn factor(&self, mu: c64) -> Option<Factored> {
        let (groups, columns, schur) = self.parts(mu)?;
        Some(Factored {
            groups,
            columns,
            mu,
            schur,
        })
    }

    /// `F(μ) V̂ = R S⁻¹ V̂` (`F = P Q(μ)⁻¹ Pᵀ`), `r × l` row-major, through
    /// one dense LU of `S` (of `T` where the contact is compressed) solved
    /// for the `l` probing columns `probing`
    /// (`r × l`; the identity gives `F` itself), and the argument of
    /// `det S(μ) = det Q(μ) / det Z(μ)` (for the count of exponents inside
    /// the contour).
    pub(super) fn probed_resolvent(&self, mu: c64, probing: &Mat<c64>) -> Option<(Vec<c64>, f64)> {
        let (_, columns, schur) = self.parts(mu)?;
        let r = self.contact.len();
        let l = probing.ncols();
        let mut solved = vec![ZERO; r * l];
        for (i, row) in solved.chunks_exact_mut(l.max(1)).enumerate() {
            for (j, value) in row.iter_mut().enumerate() {
                *value = probing[(i, j)];
            }
        }
        schur.solve_rows(&mut solved, l);
        let mut out = vec![ZERO; r * l];
        for i in 0..r {
            for &m in &self.members[i] {
                let a = columns[m][self.local_dof[i]];
                let source = &solved[m * l..(m + 1) * l];
                for (value, &x) in out[i * l..(i + 1) * l].iter_mut().zip(source) {
                    *value += a * x;
                }
            }
        }
        let finite = out.iter().all(|z| z.re.is_finite() && z.im.is_finite());
        let argument = schur.determinant_argument();
        (finite && argument.is_finite()).then_some((out, argument))
    }

    /// The group factorizations, `Z⁻¹` at the contact positions, `C_c(μ)`,
    /// `R(μ)` and `S(μ)⁻¹`, or `None` when a pivot vanishes.
    #[allow(clippy::type_complexity)]
    fn parts(&self, mu: c64) -> Option<(Vec<SmallLu>, Vec<Vec<c64>>, SchurInverse)> {
        let groups: Vec<SmallLu> = (0..self.groups.len())
            .map(|g| {
                let n = self.matrices[self.group_matrices[g]].dofs;
                SmallLu::new(self.dynamic_stiffness(g, mu), n)
            })
            .collect::<Option<_>>()?;
        let r = self.contact.len();
        // Z⁻¹ e_j for every contact position, a group's at once.
        let mut columns: Vec<Vec<c64>> = vec![Vec::new(); r];
        for (g, positions) in self.group_positions.iter().enumerate() {
            if positions.is_empty() {
                continue;
            }
            let n = self.groups[g].dynamics.dofs();
            if !groups[g].is_blocked() {
                for &j in positions {
                    let mut e = vec![ZERO; n];
                    e[self.local_dof[j]] = ONE;
                    groups[g].solve(&mut e);
                    columns[j] = e;
                }
                continue;
            }
            let mut units = Mat::<c64>::zeros(n, positions.len());
            for (c, &j) in positions.iter().enumerate() {
                units[(self.local_dof[j], c)] = ONE;
            }
            groups[g].solve_columns(&mut units);
            for (c, &j) in positions.iter().enumerate() {
                columns[j] = units.col(c).iter().copied().collect();
            }
        }
        if let Some(low_rank) = &self.low_rank {
            let factors = self.column_factors(mu);
            let schur =
                low_rank.schur_inverse(&factors, &columns, &self.local_dof, &self.members)?;
            return Some((groups, columns, schur));
        }
        let contact_matrix = self.contact_matrix(mu);
        let mut schur = vec![ZERO; r * r];
        for i in 0..r {
            schur[i * r + i] = ONE;
            for l in 0..r {
                let c = contact_matrix[i * r + l];
                if c == ZERO {
                    continue;
                }
                // R is zero between groups: only l's group contributes.
                for &j in &self.members[l] {
                    schur[i * r + j] += c * columns[j][self.local_dof[l]];
                }
            }
        }
        let schur = SchurInverse::Full(SmallLu::new(schur, r)?);
        Some((groups, columns, schur))
    }

    /// `Q(μ)⁻¹ b` on the block's dofs.
    pub(super) fn solve(&self, f: &Factored, b: &[c64]) -> Vec<c64> {
        let mut x = b.to_vec();
        for ((g, &o), lu) in self.groups.iter().zip(&self.offsets).zip(&f.groups) {
            lu.solve(&mut x[o..o + g.dynamics.dofs()]);
        }
        let on_contact: Vec<c64> = self.contact.iter().map(|&d| x[d]).collect();
        let mut t = self.contact_times(f.mu, &on_contact);
        f.schur.apply(&mut t);
        for (j, &u) in t.iter().enumerate() {
            let o = self.offsets[self.contact_group[j]];
            for (row, &value) in f.columns[j].iter().enumerate() {
                x[o + row] -= value * u;
            }
        }
        x
    }

    /// The block vector `v = −Z(μ)⁻¹ Pᵀ C_c(μ) u` of a contact vector `u`:
    /// an eigenvector of `Q(μ)` when `u = P v` is one of the contact
    /// resolvent's pole at `μ` (`Q v = 0` is `Z v = −Pᵀ C_c P v`). Group
    /// factorizations only; `None` when one meets a zero pivot.
    pub(super) fn eigenvector_of_contact(&self, mu: c64, u: &[c64]) -> Option<Vec<c64>> {
        let mut x = vec![ZERO; self.m];
        for (&d, force) in self.contact.iter().zip(self.contact_times(mu, u)) {
            x[d] -= force;
        }
        for (g, &o) in self.offsets.iter().enumerate() {
            let n = self.matrices[self.group_matrices[g]].dofs;
            SmallLu::new(self.dynamic_stiffness(g, mu), n)?.solve(&mut x[o..o + n]);
        }
        Some(x)
    }

    /// `Q⁻¹ Pᵀ u`: the block vector whose contact positions carry `u`'s
    /// force.
    pub(super) fn lift(&self, f: &Factored, u: &[c64]) -> Vec<c64> {
        let mut b = vec![ZERO; self.m];
        for (&d, &value) in self.contact.iter().zip(u) {
            b[d] += value;
        }
        self.solve(f, &b)
    }

    /// The share of a block vector's norm on the contact positions.
    pub(super) fn contact_share(&self, q: &[c64]) -> f64 {
        let total: f64 = q.iter().map(|z| z.norm_sqr()).sum();
        let contact: f64 = self.contact.iter().map(|&d| q[d].norm_sqr()).sum();
        (contact / total.max(f64::MIN_POSITIVE)).sqrt()
    }
}
