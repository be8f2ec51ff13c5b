//! A dense LU factorization with partial pivoting of a row-major matrix,
//! for the many systems of the structured Hill solvers: a group's dynamic
//! stiffness, a Schur complement on the contact dofs. Tiny ones are
//! factorized in place (no allocation beyond the matrix); from
//! [`LARGE`] rows on, by faer's blocked LU.

use faer::linalg::solvers::{PartialPivLu, Solve};
use faer::{c64, Mat};

/// From this order on, faer's LU is faster than the plain loops.
const LARGE: usize = 24;

/// A dense LU with partial pivoting.
pub(crate) enum SmallLu {
    /// The plain loops, row-major.
    Small(Plain),
    /// faer's blocked factorization.
    Large(Box<PartialPivLu<c64>>),
}

impl SmallLu {
    /// `None` when a pivot is zero or not finite.
    pub(crate) fn new(lu: Vec<c64>, n: usize) -> Option<Self> {
        if n < LARGE {
            return Plain::new(lu, n).map(SmallLu::Small);
        }
        let factored = Mat::from_fn(n, n, |r, c| lu[r * n + c]).partial_piv_lu();
        let u = factored.U();
        let regular = (0..n).all(|k| {
            let pivot = u[(k, k)];
            pivot.norm_sqr() > 0.0 && pivot.re.is_finite() && pivot.im.is_finite()
        });
        regular.then(|| SmallLu::Large(Box::new(factored)))
    }

    /// Solves in place.
    pub(crate) fn solve(&self, b: &mut [c64]) {
        match self {
            SmallLu::Small(plain) => plain.solve(b),
            SmallLu::Large(lu) => {
                let mut x = Mat::from_fn(b.len(), 1, |r, _| b[r]);
                lu.solve_in_place(x.as_mut());
                for (r, value) in b.iter_mut().enumerate() {
                    *value = x[(r, 0)];
                }
            }
        }
    }
}

impl SmallLu {
    /// Whether faer's blocked factorization holds it (a solve for many
    /// columns at once then pays).
    pub(crate) fn is_blocked(&self) -> bool {
        matches!(self, SmallLu::Large(_))
    }

    /// Solves in place for every column of `b`.
    pub(crate) fn solve_columns(&self, b: &mut Mat<c64>) {
        match self {
            SmallLu::Large(lu) => lu.solve_in_place(b.as_mut()),
            SmallLu::Small(plain) => {
                let mut column = vec![c64::new(0.0, 0.0); b.nrows()];
                for j in 0..b.ncols() {
                    for (i, value) in column.iter_mut().enumerate() {
                        *value = b[(i, j)];
                    }
                    plain.solve(&mut column);
                    for (i, value) in column.iter().enumerate() {
                        b[(i, j)] = *value;
                    }
                }
            }
        }
    }

    /// Solves in place for the `l` columns of `b`, an `n × l` row-major
    /// matrix (one pass over the factors for all the columns).
    pub(crate) fn solve_rows(&self, b: &mut [c64], l: usize) {
        match self {
            SmallLu::Small(plain) => plain.solve_rows(b, l),
            SmallLu::Large(lu) => {
                let n = b.len() / l.max(1);
                let mut x = Mat::from_fn(n, l, |r, c| b[r * l + c]);
                lu.solve_in_place(x.as_mut());
                for (r, row) in b.chunks_exact_mut(l.max(1)).enumerate() {
                    for (c, value) in row.iter_mut().enumerate() {
                        *value = x[(r, c)];
                    }
                }
            }
        }
    }

    /// The argument of the factorized matrix's determinant (the sum of the
    /// pivots' arguments, plus `π` for an odd permutation), rad.
    pub(crate) fn determinant_argument(&self) -> f64 {
        match self {
            SmallLu::Small(plain) => {
                let n = plain.n;
                let swaps = plain
                    .pivots
                    .iter()
                    .enumerate()
                    .filter(|(k, &p)| p != *k)
                    .count();
                let pivots: f64 = (0..n).map(|k| plain.lu[k * n + k].arg()).sum();
                pivots
                    + if swaps % 2 == 1 {
                        std::f64::consts::PI
                    } else {
                        0.0
                    }
            }
            SmallLu::Large(lu) => {
                let u = lu.U();
                let pivots: f64 = (0..u.nrows()).map(|k| u[(k, k)].arg()).sum();
                pivots
                    + if odd(lu.P().arrays().0) {
                        std::f64::consts::PI
                    } else {
                        0.0
                    }
            }
        }
    }
}

/// Whether a permutation (given as the images of `0..n`) is odd.
pub(crate) fn odd(images: &[usize]) -> bool {
    let mut seen = vec![false; images.len()];
    let mut transpositions = 0;
    for start in 0..images.len() {
        let mut i = start;
        let mut length = 0;
        while !seen[i] {
            seen[i] = true;
            i = images[i];
            length += 1;
        }
        if length > 0 {
            transpositions += length - 1;
        }
    }
    transpositions % 2 == 1
}

/// The plain loops' factorization, row-major.
pub(crate) struct Plain {
    n: usize,
    lu: Vec<c64>,
    pivots: Vec<usize>,
}

impl Plain {
    /// `None` when a pivot is zero or not finite.
    fn new(mut lu: Vec<c64>, n: usize) -> Option<Self> {
        let mut pivots = Vec::with_capacity(n);
        for k in 0..n {
            let p = (k..n).max_by(|&i, &j| {
                lu[i * n + k]
                    .norm_sqr()
                    .total_cmp(&lu[j * n + k].norm_sqr())
            })?;
            let pivot = lu[p * n + k];
            if !(pivot.norm_sqr() > 0.0 && pivot.re.is_finite() && pivot.im.is_finite()) {
                return None;
            }
            if p != k {
                for c in 0..n {
                    lu.swap(k * n + c, p * n + c);
                }
            }
            pivots.push(p);
            let inverse = pivot.inv();
            for i in k + 1..n {
                let f = lu[i * n + k] * inverse;
                lu[i * n + k] = f;
                if f != c64::new(0.0, 0.0) {
                    for c in k + 1..n {
                        let u = lu[k * n + c];
                        lu[i * n + c] -= f * u;
                    }
                }
            }
        }
        Some(Self { n, lu, pivots })
    }

    fn solve(&self, b: &mut [c64]) {
        let n = self.n;
        for (k, &p) in self.pivots.iter().enumerate() {
            b.swap(k, p);
        }
        for i in 0..n {
            let row = &self.lu[i * n..i * n + i];
            let sum: c64 = row.iter().zip(&b[..i]).map(|(l, x)| l * x).sum();
            b[i] -= sum;
        }
        for i in (0..n).rev() {
            let row = &self.lu[i * n + i + 1..(i + 1) * n];
            let sum: c64 = row.iter().zip(&b[i + 1..]).map(|(u, x)| u * x).sum();
            b[i] = (b[i] - sum) / self.lu[i * n + i];
        }
    }

    /// [`Self::solve`] for the `l` columns of the row-major `n × l` matrix
    /// `b` at once: each elimination updates a whole row, contiguous.
    fn solve_rows(&self, b: &mut [c64], l: usize) {
        let n = self.n;
        if l == 0 {
            return;
        }
        for (k, &p) in self.pivots.iter().enumerate() {
            if p != k {
                let (top, bottom) = b.split_at_mut(p * l);
                top[k * l..(k + 1) * l].swap_with_slice(&mut bottom[..l]);
            }
        }
        for i in 1..n {
            let (done, rest) = b.split_at_mut(i * l);
            let row = &mut rest[..l];
            for (k, &factor) in self.lu[i * n..i * n + i].iter().enumerate() {
                if factor == c64::new(0.0, 0.0) {
                    continue;
                }
                for (x, &y) in row.iter_mut().zip(&done[k * l..(k + 1) * l]) {
                    *x -= factor * y;
                }
            }
        }
        for i in (0..n).rev() {
            let (head, solved) = b.split_at_mut((i + 1) * l);
            let row = &mut head[i * l..];
            for (k, &factor) in self.lu[i * n + i + 1..(i + 1) * n].iter().enumerate() {
                if factor == c64::new(0.0, 0.0) {
                    continue;
                }
                for (x, &y) in row.iter_mut().zip(&solved[k * l..(k + 1) * l]) {
                    *x -= factor * y;
                }
            }
            let inverse = self.lu[i * n + i].inv();
            for x in row.iter_mut() {
                *x *= inverse;
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_determinants_argument_is_the_matrixs() {
        // Small and large orders, against the determinant of a permuted
        // triangular matrix computed by hand: P · T, det = sign(P) Π T_kk.
        for n in [3, 30] {
            let diagonal: Vec<c64> = (0..n)
                .map(|k| c64::cis(0.3 + 0.7 * k as f64) * (1.0 + k as f64))
                .collect();
            // Rows cycled by one: a permutation of sign (−1)^(n−1).
            let mut matrix = vec![c64::new(0.0, 0.0); n * n];
            for (k, &d) in diagonal.iter().enumerate() {
                let row = (k + 1) % n;
                matrix[row * n + k] = d;
                for c in k + 1..n {
                    matrix[row * n + c] = c64::new(0.1 * c as f64, -0.2);
                }
            }
            let lu = SmallLu::new(matrix, n).unwrap();
            let sign = if (n - 1) % 2 == 1 {
                std::f64::consts::PI
            } else {
                0.0
            };
            let expected = diagonal.iter().map(|d| d.arg()).sum::<f64>() + sign;
            let difference = lu.determinant_argument() - expected;
            let wrapped = difference
                - 2.0 * std::f64::consts::PI * (difference / (2.0 * std::f64::consts::PI)).round();
            assert!(wrapped.abs() < 1e-12, "n = {n}: {wrapped:e}");
        }
    }

    #[test]
    fn many_columns_at_once_solve_as_one_at_a_time() {
        // Small and large orders, a pivoting matrix, 5 columns: each
        // column of the row-major solve equals its own solve, and the
        // matrix times the solution gives the right-hand side back.
        for n in [1, 6, 30] {
            let entry = |r: usize, c: usize| {
                let diagonal = if r == c { 0.1 } else { 0.0 };
                let (r, c) = (r as f64, c as f64);
                c64::new(
                    (1.3 * r + 0.7 * c).sin() + diagonal,
                    (0.4 * r - 1.1 * c).cos(),
                )
            };
            let matrix: Vec<c64> = (0..n * n).map(|i| entry(i / n, i % n)).collect();
            let lu = SmallLu::new(matrix.clone(), n).unwrap();
            let l = 5;
            let rhs: Vec<c64> = (0..n * l)
                .map(|i| c64::new(i as f64 * 0.37 - 1.0, (i as f64).sqrt()))
                .collect();
            let mut rows = rhs.clone();
            lu.solve_rows(&mut rows, l);
            for j in 0..l {
                let mut column: Vec<c64> = (0..n).map(|i| rhs[i * l + j]).collect();
                lu.solve(&mut column);
                for i in 0..n {
                    let difference = (column[i] - rows[i * l + j]).norm();
                    assert!(difference < 1e-12 * column[i].norm().max(1.0), "n = {n}");
                }
                for i in 0..n {
                    let back: c64 = (0..n).map(|c| matrix[i * n + c] * rows[c * l + j]).sum();
                    assert!((back - rhs[i * l + j]).norm() < 1e-10, "n = {n}");
                }
            }
        }
    }

    #[test]
    fn the_parity_of_a_permutation_counts_its_transpositions() {
        assert!(!odd(&[0, 1, 2, 3]));
        assert!(odd(&[1, 0, 2, 3]));
        assert!(!odd(&[1, 2, 0]));
        assert!(odd(&[3, 0, 1, 2]));
    }
}
