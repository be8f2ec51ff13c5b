//! Newton's system of the implicit scheme, `(I + G D) δ = r` on the
//! contact unknowns, solved on its active columns and factorized once for
//! as long as it serves.
//!
//! `G` is the contact flexibility (symmetric, given by columns), `D =
//! ∂φ/∂u` the contact forces' derivatives by their column nonzeros. A
//! column of `D` is zero where the contact unknown pushes nothing (a node
//! off the casing, its friction too): with `A` the others, `δ = r − (G
//! D)_{:,A} δ_A` and `(I + (G D)_{A,A}) δ_A = r_A`, one dense system of the
//! active set's size (on the open fan a fraction of its 432 unknowns may
//! be in contact).
//!
//! The factorization is kept: the implicit scheme solves with it again
//! (a chord iteration) while the residual contracts fast enough and the
//! active set is the same, which on a wheel rubbing for many steps saves
//! most factorizations. The converged answer is the same (the residual
//! test does not change); only the way there does.

use faer::dyn_stack::{MemBuffer, MemStack, StackReq};
use faer::linalg::lu::partial_pivoting::{factor, solve};
use faer::perm::PermRef;
use faer::{Mat, Par};

/// The nonzeros of one column of `∂φ/∂u`: (row, value), unused entries 0.
pub(super) type Column = [(usize, f64); 3];

/// Whether a column of `∂φ/∂u` has a nonzero.
fn is_active(column: &Column) -> bool {
    column.iter().any(|&(_, v)| v != 0.0)
}

/// `I + (G D)_{A,A}` factorized (LU with partial pivoting, one thread: the
/// systems are a few hundred unknowns at most, where faer's threads cost
/// more than they save), with `(G D)_{:,A}` and the active set.
pub(super) struct ActiveSystem {
    /// The active contact unknowns.
    active: Vec<usize>,
    /// `(G D)_{:,A}`, column-major: one column per active unknown.
    coupled: Vec<f64>,
    /// The LU factors in place, and the row permutation.
    factors: Mat<f64>,
    forward: Vec<usize>,
    inverse: Vec<usize>,
    /// The right-hand side `r_A`, then `δ_A`.
    right: Mat<f64>,
    buffer: Option<MemBuffer>,
    /// Whether the factors hold a factorization.
    factorized: bool,
}

impl Default for ActiveSystem {
    fn default() -> Self {
        Self {
            active: Vec::new(),
            coupled: Vec::new(),
            factors: Mat::new(),
            forward: Vec::new(),
            inverse: Vec::new(),
            right: Mat::new(),
            buffer: None,
            factorized: false,
        }
    }
}

impl std::fmt::Debug for ActiveSystem {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("ActiveSystem")
            .field("active", &self.active.len())
            .field("factorized", &self.factorized)
            .finish()
    }
}

impl ActiveSystem {
    /// Whether the kept factors are those of a matrix with the active set
    /// of `columns` (the slopes may have changed since).
    pub(super) fn kept_for(&self, columns: &[Column]) -> bool {
        if !self.factorized {
            return false;
        }
        let mut kept = self.active.iter();
        columns
            .iter()
            .enumerate()
            .filter(|(_, column)| is_active(column))
            .all(|(b, _)| kept.next() == Some(&b))
            && kept.next().is_none()
    }

    /// Drops the kept factorization (the next solve factorizes afresh).
    pub(super) fn forget(&mut self) {
        self.factorized = false;
    }

    /// Factorizes Newton's matrix of `columns` with the flexibility
    /// `g_columns` (`G` column-major: column `c` is `g_columns[c n..]`);
    /// `false` when it is singular or not finite.
    pub(super) fn factorize(&mut self, g_columns: &[f64], columns: &[Column]) -> bool {
        let unknowns = columns.len();
        self.factorized = false;
        self.active.clear();
        self.active.extend(
            columns
                .iter()
                .enumerate()
                .filter(|(_, column)| is_active(column))
                .map(|(b, _)| b),
        );
        let size = self.active.len();
        self.coupled.clear();
        self.coupled.resize(unknowns * size, 0.0);
        for (k, &b) in self.active.iter().enumerate() {
            let out = &mut self.coupled[k * unknowns..][..unknowns];
            for &(c, v) in &columns[b] {
                if v != 0.0 {
                    let g = &g_columns[c * unknowns..][..unknowns];
                    for (o, g) in out.iter_mut().zip(g) {
                        *o += g * v;
                    }
                }
            }
        }
        if self.factors.nrows() != size {
            self.factors = Mat::zeros(size, size);
            self.right = Mat::zeros(size, 1);
            self.forward = vec![0; size];
            self.inverse = vec![0; size];
            let need = StackReq::any_of(&[
                factor::lu_in_place_scratch::<usize, f64>(size, size, Par::Seq, Default::default()),
                solve::solve_in_place_scratch::<usize, f64>(size, 1, Par::Seq),
            ]);
            self.buffer = Some(MemBuffer::new(need));
        }
        for k in 0..size {
            let column = &self.coupled[k * unknowns..][..unknowns];
            for (i, &row) in self.active.iter().enumerate() {
                self.factors[(i, k)] = column[row] + if i == k { 1.0 } else { 0.0 };
            }
        }
        if size > 0 {
            let Some(buffer) = self.buffer.as_mut() else {
                return false;
            };
            factor::lu_in_place(
                self.factors.as_mut(),
                &mut self.forward,
                &mut self.inverse,
                Par::Seq,
                MemStack::new(buffer),
                Default::default(),
            );
        }
        let diagonal_fine = (0..size).all(|i| {
            let pivot = self.factors[(i, i)];
            pivot != 0.0 && pivot.is_finite()
        });
        self.factorized = diagonal_fine;
        diagonal_fine
    }

    /// Solves with the kept factors in place: `residual` (`r`) becomes
    /// `δ`; `false` when there are no factors or `δ` is not finite.
    pub(super) fn solve(&mut self, residual: &mut [f64]) -> bool {
        if !self.factorized {
            return false;
        }
        let size = self.active.len();
        if size == 0 {
            return residual.iter().all(|r| r.is_finite());
        }
        let Some(buffer) = self.buffer.as_mut() else {
            return false;
        };
        for (i, &a) in self.active.iter().enumerate() {
            self.right[(i, 0)] = residual[a];
        }
        let lu = self.factors.as_ref();
        solve::solve_in_place::<usize, f64, f64>(
            lu,
            lu,
            PermRef::new_checked(&self.forward, &self.inverse, size),
            self.right.as_mut(),
            Par::Seq,
            MemStack::new(buffer),
        );
        let unknowns = residual.len();
        for k in 0..size {
            let y = self.right[(k, 0)];
            let column = &self.coupled[k * unknowns..][..unknowns];
            for (r, c) in residual.iter_mut().zip(column) {
                *r -= c * y;
            }
        }
        // δ_A is the small system's solution exactly (not r_A − (G D)_{A,A}
        // δ_A in round-off).
        for (k, &a) in self.active.iter().enumerate() {
            residual[a] = self.right[(k, 0)];
        }
        residual.iter().all(|r| r.is_finite())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Solves `(I + G D) x = r` by elimination on the whole dense matrix.
    fn dense(g: &[f64], columns: &[Column], r: &[f64]) -> Vec<f64> {
        let n = r.len();
        let mut a = vec![0.0; n * n];
        for i in 0..n {
            for (b, column) in columns.iter().enumerate() {
                let product: f64 = column.iter().map(|&(c, v)| g[i * n + c] * v).sum();
                a[i * n + b] = product + if i == b { 1.0 } else { 0.0 };
            }
        }
        let mut x = r.to_vec();
        assert!(solve_dense(&mut a, &mut x, n));
        x
    }

    /// Gaussian elimination with partial pivoting, `a` row-major.
    fn solve_dense(a: &mut [f64], b: &mut [f64], n: usize) -> bool {
        for col in 0..n {
            let pivot_row = (col..n)
                .max_by(|&p, &q| a[p * n + col].abs().total_cmp(&a[q * n + col].abs()))
                .unwrap_or(col);
            let pivot = a[pivot_row * n + col];
            if pivot == 0.0 || !pivot.is_finite() {
                return false;
            }
            if pivot_row != col {
                for k in 0..n {
                    a.swap(col * n + k, pivot_row * n + k);
                }
                b.swap(col, pivot_row);
            }
            for row in col + 1..n {
                let factor = a[row * n + col] / pivot;
                if factor == 0.0 {
                    continue;
                }
                for k in col..n {
                    a[row * n + k] -= factor * a[col * n + k];
                }
                b[row] -= factor * b[col];
            }
        }
        for row in (0..n).rev() {
            let mut value = b[row];
            for k in row + 1..n {
                value -= a[row * n + k] * b[k];
            }
            b[row] = value / a[row * n + row];
        }
        true
    }

    fn close(found: &[f64], expected: &[f64]) {
        let largest = expected.iter().fold(0.0_f64, |m, v| m.max(v.abs()));
        for (x, y) in found.iter().zip(expected) {
            assert!((x - y).abs() < 1e-12 * largest, "{x} vs {y}");
        }
    }

    #[test]
    fn the_active_set_solve_is_the_whole_jacobians_and_its_factors_serve_again() {
        // 12 contact unknowns, a dense symmetric flexibility (so its rows
        // are its columns), columns of three nonzeros where active (every
        // third unknown off the casing, the others with coupled entries as
        // friction gives them).
        let n = 12;
        let value = |i: usize, j: usize| ((i * 7 + j * 13) % 17) as f64 / 17.0 - 0.4;
        let g: Vec<f64> = (0..n * n)
            .map(|k| {
                let (i, j) = (k / n, k % n);
                1e-3 * (value(i, j) + value(j, i)) + if i == j { 2e-2 } else { 0.0 }
            })
            .collect();
        let columns: Vec<Column> = (0..n)
            .map(|b| {
                if b % 3 == 0 {
                    [(b, 0.0), (b, 0.0), (b, 0.0)]
                } else {
                    [(b, 1e2 + b as f64), ((b + 4) % n, 3e1), ((b + 7) % n, -2e1)]
                }
            })
            .collect();
        let mut system = ActiveSystem::default();
        assert!(!system.kept_for(&columns));
        assert!(system.factorize(&g, &columns));
        assert_eq!(system.active.len(), 8);
        assert!(system.kept_for(&columns));
        for shift in [0.7, 1.9] {
            let r: Vec<f64> = (0..n).map(|i| (i as f64 * shift).sin()).collect();
            let mut found = r.clone();
            assert!(system.solve(&mut found));
            close(&found, &dense(&g, &columns, &r));
        }
        // Another active set is not the kept one.
        let mut other = columns.clone();
        other[0] = [(0, 5.0), (0, 0.0), (0, 0.0)];
        assert!(!system.kept_for(&other));
        other[0] = columns[0];
        other[1] = [(1, 0.0); 3];
        assert!(!system.kept_for(&other));
        system.forget();
        assert!(!system.kept_for(&columns));
        // No active column: δ = r.
        let off: Vec<Column> = vec![[(0, 0.0); 3]; n];
        let r: Vec<f64> = (0..n).map(|i| i as f64 - 3.5).collect();
        let mut same = r.clone();
        assert!(system.factorize(&g, &off));
        assert!(system.solve(&mut same));
        assert_eq!(same, r);
    }
}
