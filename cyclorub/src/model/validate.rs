//! Checks on user matrices, each error naming the matrix.

use super::input::Subject;
use super::ModelError;
use faer::{Mat, Side};

/// Default relative tolerance on `|A_ij − A_ji|` (times the largest entry).
pub const DEFAULT_SYMMETRY_TOLERANCE: f64 = 1e-8;

/// Largest `symmetry_tolerance` a case may give: above 0.1 % of the largest
/// entry a difference is not rounding but a matrix that is not symmetric.
pub const MAX_SYMMETRY_TOLERANCE: f64 = 1e-3;

/// Square and finite.
pub(crate) fn check_square_finite(a: &Mat<f64>, what: &Subject) -> Result<(), ModelError> {
    if a.nrows() != a.ncols() {
        return Err(ModelError::NotSquare {
            what: what.clone(),
            rows: a.nrows(),
            cols: a.ncols(),
        });
    }
    check_finite(a, what)
}

/// Finite entries.
pub(crate) fn check_finite(a: &Mat<f64>, what: &Subject) -> Result<(), ModelError> {
    for j in 0..a.ncols() {
        for i in 0..a.nrows() {
            let v = a[(i, j)];
            if !v.is_finite() {
                return Err(ModelError::NotFinite {
                    what: what.clone(),
                    row: i + 1,
                    col: j + 1,
                    value: v,
                });
            }
        }
    }
    Ok(())
}

/// Size `n × n`.
pub(crate) fn check_size(
    a: &Mat<f64>,
    what: &Subject,
    n: usize,
    reference: &Subject,
) -> Result<(), ModelError> {
    if a.nrows() != a.ncols() {
        return Err(ModelError::NotSquare {
            what: what.clone(),
            rows: a.nrows(),
            cols: a.ncols(),
        });
    }
    if a.nrows() != n {
        return Err(ModelError::SizeMismatch {
            what: what.clone(),
            found: a.nrows(),
            reference: reference.clone(),
            expected: n,
        });
    }
    check_finite(a, what)
}

/// Symmetric within `tolerance` (relative to the largest entry); returns the
/// symmetrized matrix `(A + Aᵀ)/2`.
pub(crate) fn symmetrized(
    a: &Mat<f64>,
    what: &Subject,
    tolerance: f64,
) -> Result<Mat<f64>, ModelError> {
    check_square_finite(a, what)?;
    let n = a.nrows();
    let scale = (0..n)
        .flat_map(|j| (0..n).map(move |i| (i, j)))
        .fold(0.0_f64, |m, (i, j)| m.max(a[(i, j)].abs()));
    let mut worst = (0.0_f64, 0, 0);
    for j in 0..n {
        for i in (j + 1)..n {
            let d = (a[(i, j)] - a[(j, i)]).abs();
            if d > worst.0 {
                worst = (d, i, j);
            }
        }
    }
    if worst.0 > tolerance * scale {
        let (_, i, j) = worst;
        return Err(ModelError::NotSymmetric {
            what: what.clone(),
            row: i + 1,
            col: j + 1,
            value: a[(i, j)],
            transposed: a[(j, i)],
            tolerance,
        });
    }
    Ok(Mat::from_fn(n, n, |i, j| 0.5 * (a[(i, j)] + a[(j, i)])))
}

/// Positive definite (Cholesky succeeds).
pub(crate) fn check_positive_definite(a: &Mat<f64>, what: &Subject) -> Result<(), ModelError> {
    match a.llt(Side::Lower) {
        Ok(_) => Ok(()),
        Err(_) => Err(ModelError::MassNotPositiveDefinite {
            what: what.clone(),
            nodal_diameter: None,
        }),
    }
}
