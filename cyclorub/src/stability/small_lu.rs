//! A small dense LU factorization with partial pivoting (row-major), for
//! the many tiny systems of the structured Hill solvers: a group's dynamic
//! stiffness, a Schur complement on the contact dofs.

use faer::c64;

/// A small dense LU with partial pivoting, row-major.
pub(crate) struct SmallLu {
    n: usize,
    lu: Vec<c64>,
    pivots: Vec<usize>,
}

impl SmallLu {
    /// `None` when a pivot is zero or not finite.
    pub(crate) fn new(mut lu: Vec<c64>, n: usize) -> Option<Self> {
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

    pub(crate) fn solve(&self, b: &mut [c64]) {
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
}
