//! The lowest modes of a sparse Hermitian pencil `(K, M)`, `K` positive
//! definite, by subspace iteration with the sparse Cholesky factor of `K`
//! (shift-invert at zero) and a Rayleigh–Ritz step per iteration; and the
//! sparse-times-dense products it needs.

use super::error::ReductionError;
use crate::model::eigen::self_adjoint_eigen_by_qr;
use faer::linalg::solvers::Solve;
use faer::sparse::linalg::solvers::Llt;
use faer::sparse::SparseColMat;
use faer::{c64, Mat, Side};

/// Most subspace iterations before giving up.
const MAX_ITERATIONS: usize = 500;

/// Relative change of every wanted eigenvalue between two iterations below
/// which they are taken as converged (the vectors are then accurate to
/// about its square root, and Craig–Bampton's Ritz projection is
/// insensitive to first order to their error).
const EIGENVALUE_TOLERANCE: f64 = 1e-12;

/// `Y = A X` for a sparse `A` with both triangles stored.
pub(super) fn sparse_times(a: &SparseColMat<usize, c64>, x: &Mat<c64>) -> Mat<c64> {
    let col_ptr = a.symbolic().col_ptr();
    let rows = a.symbolic().row_idx();
    let values = a.val();
    let mut y = Mat::<c64>::zeros(a.nrows(), x.ncols());
    for c in 0..x.ncols() {
        let xc = x.col(c);
        let mut yc = y.col_mut(c);
        for j in 0..a.ncols() {
            let xj = xc[j];
            if xj == c64::new(0.0, 0.0) {
                continue;
            }
            for p in col_ptr[j]..col_ptr[j + 1] {
                yc[rows[p]] += values[p] * xj;
            }
        }
    }
    y
}

/// `(A + Aᴴ)/2`.
pub(super) fn hermitian_part(a: &Mat<c64>) -> Mat<c64> {
    Mat::from_fn(a.nrows(), a.ncols(), |i, j| {
        (a[(i, j)] + a[(j, i)].conj()) * 0.5
    })
}

/// Eigenpairs of the small dense pencil `(K, M)`, `M` Hermitian positive
/// definite: values ascending and `M`-orthonormal vectors; `None` when `M`
/// is not positive definite or the eigensolver fails. With `real`, the
/// pencil's imaginary parts (zero) are dropped and the vectors are real: a
/// complex eigensolver would give them arbitrary phases.
pub(super) fn dense_pencil(k: &Mat<c64>, m: &Mat<c64>, real: bool) -> Option<(Vec<f64>, Mat<c64>)> {
    if real {
        let re = |a: &Mat<c64>| Mat::from_fn(a.nrows(), a.ncols(), |i, j| a[(i, j)].re);
        let (values, vectors) = real_pencil(&re(k), &re(m))?;
        let vectors = Mat::from_fn(vectors.nrows(), vectors.ncols(), |i, j| {
            c64::new(vectors[(i, j)], 0.0)
        });
        return Some((values, vectors));
    }
    let llt = m.llt(Side::Lower).ok()?;
    let l = llt.L();
    let mut z = k.clone();
    l.solve_lower_triangular_in_place(z.as_mut());
    let mut a: Mat<c64> = z.adjoint().to_owned();
    l.solve_lower_triangular_in_place(a.as_mut());
    let a = hermitian_part(&a);
    // Not faer's `self_adjoint_eigen`: see `self_adjoint_eigen_by_qr`.
    let (values, mut vectors) = self_adjoint_eigen_by_qr(a.as_ref()).ok()?;
    if values.iter().any(|v| !v.is_finite()) {
        return None;
    }
    // Ascending values; the vectors `L⁻ᴴ U`.
    l.adjoint()
        .solve_upper_triangular_in_place(vectors.as_mut());
    Some((values, vectors))
}

/// [`dense_pencil`] in real arithmetic.
fn real_pencil(k: &Mat<f64>, m: &Mat<f64>) -> Option<(Vec<f64>, Mat<f64>)> {
    let n = m.nrows();
    let llt = m.llt(Side::Lower).ok()?;
    let l = llt.L();
    let mut z = k.clone();
    l.solve_lower_triangular_in_place(z.as_mut());
    let mut a: Mat<f64> = z.transpose().to_owned();
    l.solve_lower_triangular_in_place(a.as_mut());
    let a = Mat::from_fn(n, n, |i, j| 0.5 * (a[(i, j)] + a[(j, i)]));
    let (values, mut vectors) = self_adjoint_eigen_by_qr(a.as_ref()).ok()?;
    if values.iter().any(|v| !v.is_finite()) {
        return None;
    }
    l.transpose()
        .solve_upper_triangular_in_place(vectors.as_mut());
    Some((values, vectors))
}

/// A fixed, well-spread start block (a small xorshift generator, so that
/// every run gives the same bits).
fn start_block(rows: usize, cols: usize, real: bool) -> Mat<c64> {
    let mut state: u64 = 0x9E37_79B9_7F4A_7C15;
    let mut next = move || {
        state ^= state << 13;
        state ^= state >> 7;
        state ^= state << 17;
        (state >> 11) as f64 / (1u64 << 53) as f64 - 0.5
    };
    Mat::from_fn(rows, cols, |_, _| {
        let re = next();
        c64::new(re, if real { 0.0 } else { next() })
    })
}

/// The lowest `modes` eigenpairs of `K φ = λ M φ` given `K`'s sparse
/// Cholesky factor: values ascending and `M`-orthonormal vectors
/// (`n × modes`). Block size `max(2·modes, modes + 8)`, at most `n`. With
/// `real` (nodal diameters 0 and `N/2`, whose matrices are real), the
/// iterates stay exactly real, and so do the modes.
pub(super) fn lowest_modes(
    factor: &Llt<usize, c64>,
    mass: &SparseColMat<usize, c64>,
    modes: usize,
    nodal_diameter: i64,
    real: bool,
) -> Result<(Vec<f64>, Mat<c64>), ReductionError> {
    let n = mass.nrows();
    if modes == 0 {
        return Ok((Vec::new(), Mat::zeros(n, 0)));
    }
    let block = (2 * modes).max(modes + 8).min(n);
    let mut x = start_block(n, block, real);
    let mut mx = sparse_times(mass, &x);
    let mut previous: Option<Vec<f64>> = None;
    let mut change = f64::INFINITY;
    for iteration in 0..MAX_ITERATIONS {
        // Y = K⁻¹ M X; then K Y = M X, so Yᴴ K Y = Yᴴ M X needs no product
        // by K; and M X of the next iterate is (M Y) Q, one sparse product
        // per iteration.
        let mut y = mx.clone();
        factor.solve_in_place(y.as_mut());
        let my = sparse_times(mass, &y);
        let k_small = hermitian_part(&(y.adjoint() * &mx));
        let m_small = hermitian_part(&(y.adjoint() * &my));
        let (values, vectors) = dense_pencil(&k_small, &m_small, real).ok_or_else(|| {
            ReductionError::NonFiniteResult {
                nodal_diameter,
                what: format!(
                    "the Rayleigh–Ritz step of subspace iteration {}",
                    iteration + 1
                ),
            }
        })?;
        x = &y * &vectors;
        mx = &my * &vectors;
        tracing::debug!(
            "nodal diameter {nodal_diameter}: subspace iteration {}, lowest {:.6e}",
            iteration + 1,
            values[0]
        );
        // With the whole space in the block, the Ritz pairs are exact.
        if block == n {
            return Ok(finish(values, x, modes));
        }
        if let Some(previous) = &previous {
            change = (0..modes)
                .map(|i| (values[i] - previous[i]).abs() / values[i].abs())
                .fold(0.0, f64::max);
            if change <= EIGENVALUE_TOLERANCE {
                return Ok(finish(values, x, modes));
            }
        }
        previous = Some(values);
    }
    Err(ReductionError::NotConverged {
        nodal_diameter,
        modes,
        iterations: MAX_ITERATIONS,
        change,
    })
}

/// The first `modes` values and columns.
fn finish(mut values: Vec<f64>, x: Mat<c64>, modes: usize) -> (Vec<f64>, Mat<c64>) {
    values.truncate(modes);
    let vectors = x.subcols(0, modes).to_owned();
    (values, vectors)
}
