//! The generalized Hermitian eigenproblem `K φ = λ M φ` of one nodal
//! diameter, by Cholesky `M = L Lᴴ` and the symmetric eigenproblem of
//! `L⁻¹ K L⁻ᴴ` (faer's general eigensolvers are not used: they can return
//! NaN on singular input).

use super::ModelError;
use faer::{c64, Mat, Side};

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
        let eig = a.self_adjoint_eigen(Side::Lower).map_err(failed)?;
        let values: Vec<f64> = eig.S().column_vector().iter().map(|x| x.re).collect();
        let w = l * eig.U();
        (values, Some(w))
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
        let eig = a.self_adjoint_eigen(Side::Lower).map_err(failed)?;
        let values: Vec<f64> = eig.S().column_vector().iter().copied().collect();
        (values, Some(l * eig.U()))
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
