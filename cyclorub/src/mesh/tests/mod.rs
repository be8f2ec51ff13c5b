//! Tests of the open fan: the element against closed-form oracles (patch
//! test, a cantilever against Euler–Bernoulli), the sector against its
//! geometry (mass, rigid-body modes, cyclic conformity), the files against
//! the crate's own reader, and the first bending family per nodal diameter.

mod cyclic_modes;
mod element;
mod fan_checks;
mod files;

use super::SymmetricMatrix;
use faer::{c64, Mat, Side};

/// The full dense matrix of a stored lower triangle.
pub(super) fn dense(matrix: &SymmetricMatrix) -> Mat<f64> {
    let mut a = Mat::zeros(matrix.size, matrix.size);
    for (i, j, v) in matrix.entries() {
        a[(i, j)] = v;
        a[(j, i)] = v;
    }
    a
}

/// Eigenvalues of `K φ = λ M φ` (Hermitian `K`, Hermitian positive definite
/// `M`), ascending: Cholesky `M = L Lᴴ`, then the eigenvalues of
/// `L⁻¹ K L⁻ᴴ`. Non-finite results are refused.
pub(super) fn generalized_eigenvalues(k: &Mat<c64>, m: &Mat<c64>) -> Vec<f64> {
    let n = m.nrows();
    let llt = m.llt(Side::Lower).expect("mass positive definite");
    let l = llt.L();
    let mut y = k.clone();
    l.solve_lower_triangular_in_place(y.as_mut());
    let mut a: Mat<c64> = y.adjoint().to_owned();
    l.solve_lower_triangular_in_place(a.as_mut());
    let a = Mat::from_fn(n, n, |i, j| (a[(i, j)] + a[(j, i)].conj()) * 0.5);
    let mut values = a
        .self_adjoint_eigenvalues(Side::Lower)
        .expect("eigenvalues converge");
    assert!(
        values.iter().all(|v| v.is_finite()),
        "non-finite eigenvalue"
    );
    values.sort_by(f64::total_cmp);
    values
}

/// A real dense matrix as a complex one.
pub(super) fn complex(a: &Mat<f64>) -> Mat<c64> {
    Mat::from_fn(a.nrows(), a.ncols(), |i, j| c64::new(a[(i, j)], 0.0))
}

/// Frequencies (Hz) from eigenvalues `ω²`.
pub(super) fn hertz(values: &[f64]) -> Vec<f64> {
    values
        .iter()
        .map(|v| v.max(0.0).sqrt() / (2.0 * std::f64::consts::PI))
        .collect()
}
