//! The generalized Hermitian eigenproblem `K φ = λ M φ` of one nodal
//! diameter, by Cholesky `M = L Lᴴ` and the symmetric eigenproblem of
//! `L⁻¹ K L⁻ᴴ` (faer's general eigensolvers are not used: they can return
//! NaN on singular input).
//!
//! Eigenvectors come from [`self_adjoint_eigen_by_qr`], never from faer's
//! `self_adjoint_eigen`: from order 128 that one solves the tridiagonal
//! problem by divide and conquer, whose backward error on the graded
//! pencils of finite-element wheels is far above round-off (issue 45
//! item 18; see the function's note).

use super::ModelError;
use faer::dyn_stack::{MemBuffer, MemStack};
use faer::linalg::evd::{
    self_adjoint_evd, self_adjoint_evd_scratch, ComputeEigenvectors, EvdError, SelfAdjointEvdParams,
};
use faer::traits::ComplexField;
use faer::{c64, Mat, MatRef, Par, Side, Spec};

/// Eigenvalues (ascending) and orthonormal eigenvectors of the self-adjoint
/// matrix whose lower triangle is `matrix`'s, with the tridiagonal QR
/// algorithm at every order.
///
/// Why not `Mat::self_adjoint_eigen`: faer 0.24.4 switches to divide and
/// conquer from order 128 when vectors are asked for. On the open fan's
/// reduced full wheel (848 rows, real entries, eigenvalues from 3.1e6 to
/// 7.2e12) its decomposition had `‖A U − U Λ‖ = 6.6e-4 ‖A‖`, real and
/// complex alike, and eigenvalues off by up to 1.7e7 (the lowest by 1e-5
/// to 1e-4 relative, depending on the path); LAPACK (`dsyevd`, `dsteqr`)
/// and the QR path here give `1e-14 ‖A‖` and agree to 1e-10. The values
/// alone (`self_adjoint_eigenvalues`) already use QR. QR with vectors
/// costs about the same here (368 ms against 328 ms at order 848).
pub(crate) fn self_adjoint_eigen_by_qr<T: ComplexField<Real = f64>>(
    matrix: MatRef<'_, T>,
) -> Result<(Vec<f64>, Mat<T>), EvdError> {
    let n = matrix.nrows();
    let mut params: Spec<SelfAdjointEvdParams, T> = Default::default();
    params.recursion_threshold = usize::MAX;
    let par = Par::Seq;
    let mut values = faer::diag::Diag::<T>::zeros(n);
    let mut vectors = Mat::<T>::zeros(n, n);
    let scratch = self_adjoint_evd_scratch::<T>(n, ComputeEigenvectors::Yes, par, params);
    self_adjoint_evd(
        matrix,
        values.as_mut(),
        Some(vectors.as_mut()),
        par,
        MemStack::new(&mut MemBuffer::new(scratch)),
        params,
    )?;
    let values = (0..n)
        .map(|i| faer::traits::math_utils::real(&values[i]))
        .collect();
    Ok((values, vectors))
}

/// Eigenvalues (ascending) and, if asked, `W = L·U` where `U` holds the
/// orthonormal eigenvectors of `L⁻¹ K L⁻ᴴ`: the mass-normalized mode shapes
/// are `Φ = L⁻ᴴ U`, so `M Φ = W`.
pub(crate) struct Modes {
    pub(crate) values: Vec<f64>,
    pub(crate) mass_times_shapes: Option<Mat<c64>>,
}

/// Solves `K φ = λ M φ` for Hermitian `K` and Hermitian positive definite `M`.
pub(crate) fn hermitian_modes(
    stiffness: &Mat<c64>,
    mass: &Mat<c64>,
    nodal_diameter: i64,
    with_shapes: bool,
) -> Result<Modes, ModelError> {
    let n = mass.nrows();
    let llt = mass
        .llt(Side::Lower)
        .map_err(|_| ModelError::MassNotPositiveDefinite {
            what: "mass".into(),
            nodal_diameter: Some(nodal_diameter),
        })?;
    let l = llt.L();
    let mut y = stiffness.clone();
    l.solve_lower_triangular_in_place(y.as_mut());
    let mut a: Mat<c64> = y.adjoint().to_owned();
    l.solve_lower_triangular_in_place(a.as_mut());
    let a = Mat::from_fn(n, n, |i, j| (a[(i, j)] + a[(j, i)].conj()) * 0.5);
    if (0..n).any(|i| (0..n).any(|j| !(a[(i, j)].re.is_finite() && a[(i, j)].im.is_finite()))) {
        return Err(ModelError::Eigen {
            nodal_diameter,
            message: "the stiffness matrix holds non-finite values after the mass factorization"
                .into(),
        });
    }
    let failed = |_| ModelError::Eigen {
        nodal_diameter,
        message: "the symmetric eigenvalue solver did not converge".into(),
    };
    let (values, mass_times_shapes) = if with_shapes {
        let (values, vectors) = self_adjoint_eigen_by_qr(a.as_ref()).map_err(failed)?;
        (values, Some(l * vectors))
    } else {
        let values = a.self_adjoint_eigenvalues(Side::Lower).map_err(failed)?;
        (values, None)
    };
    if values.iter().any(|v| !v.is_finite()) {
        return Err(ModelError::Eigen {
            nodal_diameter,
            message: "the eigenvalue solver returned non-finite values".into(),
        });
    }
    Ok(Modes {
        values,
        mass_times_shapes,
    })
}

/// `ω = √λ` in rad/s, with round-off negatives clamped to 0; a clearly
/// negative eigenvalue (an unstable stiffness) is an error.
pub(crate) fn angular_frequencies(
    values: &[f64],
    nodal_diameter: i64,
) -> Result<Vec<f64>, ModelError> {
    let scale = values.iter().fold(0.0_f64, |m, v| m.max(v.abs()));
    values
        .iter()
        .map(|&v| {
            if v >= 0.0 {
                Ok(v.sqrt())
            } else if -v <= 1e-9 * scale {
                Ok(0.0)
            } else {
                Err(ModelError::Eigen {
                    nodal_diameter,
                    message: format!(
                        "negative eigenvalue {v:e} (rad/s)²: the stiffness matrix is not positive semidefinite"
                    ),
                })
            }
        })
        .collect()
}

/// Real counterpart of [`hermitian_modes`] for the real diameters `0` and
/// `N/2` (about four times cheaper): eigenvalues and, if asked, `W = L·U`
/// (`M Φ = W`).
pub(crate) fn symmetric_modes(
    stiffness: &Mat<f64>,
    mass: &Mat<f64>,
    nodal_diameter: i64,
    with_shapes: bool,
) -> Result<(Vec<f64>, Option<Mat<f64>>), ModelError> {
    let n = mass.nrows();
    let llt = mass
        .llt(Side::Lower)
        .map_err(|_| ModelError::MassNotPositiveDefinite {
            what: "mass".into(),
            nodal_diameter: Some(nodal_diameter),
        })?;
    let l = llt.L();
    let mut y = stiffness.clone();
    l.solve_lower_triangular_in_place(y.as_mut());
    let mut a: Mat<f64> = y.transpose().to_owned();
    l.solve_lower_triangular_in_place(a.as_mut());
    let a = Mat::from_fn(n, n, |i, j| 0.5 * (a[(i, j)] + a[(j, i)]));
    if (0..n).any(|i| (0..n).any(|j| !a[(i, j)].is_finite())) {
        return Err(ModelError::Eigen {
            nodal_diameter,
            message: "the stiffness matrix holds non-finite values after the mass factorization"
                .into(),
        });
    }
    let failed = |_| ModelError::Eigen {
        nodal_diameter,
        message: "the symmetric eigenvalue solver did not converge".into(),
    };
    let (values, w) = if with_shapes {
        let (values, vectors) = self_adjoint_eigen_by_qr(a.as_ref()).map_err(failed)?;
        (values, Some(l * vectors))
    } else {
        (
            a.self_adjoint_eigenvalues(Side::Lower).map_err(failed)?,
            None,
        )
    };
    if values.iter().any(|v| !v.is_finite()) {
        return Err(ModelError::Eigen {
            nodal_diameter,
            message: "the eigenvalue solver returned non-finite values".into(),
        });
    }
    Ok((values, w))
}

#[cfg(test)]
#[path = "eigen_tests.rs"]
mod tests;
