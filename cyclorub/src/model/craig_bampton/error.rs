//! Why a sparse sector could not be reduced: each error names the matrix,
//! the dof list or the nodal diameter that failed.

/// One of the two sector matrices.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum SectorMatrix {
    /// The mass.
    Mass,
    /// The stiffness.
    Stiffness,
}

impl std::fmt::Display for SectorMatrix {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(match self {
            Self::Mass => "the mass matrix",
            Self::Stiffness => "the stiffness matrix",
        })
    }
}

/// Why a Craig–Bampton reduction failed.
#[derive(Debug, thiserror::Error)]
pub enum ReductionError {
    /// A setting or a dof list is not allowed.
    #[error("{what}: {message}")]
    Invalid {
        /// The setting or list (e.g. `retained dofs[3]`, `internal modes`).
        what: String,
        /// The value and what is allowed.
        message: String,
    },
    /// A matrix is not square or does not match the other one's size.
    #[error("{matrix}: size {rows}×{cols}; the sector matrices must be square and of the same size ({expected} dofs)")]
    Size {
        /// Which matrix.
        matrix: SectorMatrix,
        /// Its rows.
        rows: usize,
        /// Its columns.
        cols: usize,
        /// The size it must have.
        expected: usize,
    },
    /// An entry is not a finite number.
    #[error("{matrix}: entry ({row}, {col}) is {value}; only finite numbers are allowed (1-based indices)")]
    NotFinite {
        /// Which matrix.
        matrix: SectorMatrix,
        /// 1-based row.
        row: usize,
        /// 1-based column.
        col: usize,
        /// The value.
        value: f64,
    },
    /// A matrix is not symmetric beyond the tolerance.
    #[error(
        "{matrix}: not symmetric: entry ({row}, {col}) = {value:e} but ({col}, {row}) = {transposed:e} \
         (allowed difference: {tolerance:e} times the largest entry; 1-based indices); the sector \
         matrices must be symmetric"
    )]
    NotSymmetric {
        /// Which matrix.
        matrix: SectorMatrix,
        /// 1-based row.
        row: usize,
        /// 1-based column.
        col: usize,
        /// Entry (row, col).
        value: f64,
        /// Entry (col, row).
        transposed: f64,
        /// The relative tolerance.
        tolerance: f64,
    },
    /// The fixed-interface block `A_II(s)` (all kept dofs but the retained
    /// ones) is not positive definite: the sparse Cholesky factorization
    /// met a non-positive pivot.
    #[error(
        "nodal diameter {nodal_diameter}: the interior block of {matrix} (retained dofs fixed) is not \
         positive definite{detail}; a sector must be clamped somewhere (or the retained dofs must hold \
         it) and its matrices positive semidefinite"
    )]
    NotPositiveDefinite {
        /// Which matrix.
        matrix: SectorMatrix,
        /// The nodal diameter.
        nodal_diameter: i64,
        /// Where it failed, if known.
        detail: String,
    },
    /// The full sector's `K(s)` (all dofs but the clamped ones, no
    /// reduction) is not positive definite: the sparse Cholesky
    /// factorization met a non-positive pivot.
    #[error(
        "nodal diameter {nodal_diameter}: the full sector's stiffness K(s) (clamped dofs removed) is \
         not positive definite{detail}; a sector must be clamped somewhere and its stiffness positive \
         semidefinite"
    )]
    FullSectorNotPositiveDefinite {
        /// The nodal diameter.
        nodal_diameter: i64,
        /// Where it failed, if known.
        detail: String,
    },
    /// The sparse eigensolver did not settle.
    #[error(
        "nodal diameter {nodal_diameter}: the {modes} fixed-interface modes did not converge in \
         {iterations} subspace iterations (worst relative change of an eigenvalue: {change:e})"
    )]
    NotConverged {
        /// The nodal diameter.
        nodal_diameter: i64,
        /// Modes sought.
        modes: usize,
        /// Iterations done.
        iterations: usize,
        /// The last relative change of the worst eigenvalue.
        change: f64,
    },
    /// A computed quantity is not finite (NaN or infinite).
    #[error("nodal diameter {nodal_diameter}: {what} holds a non-finite value; the inputs are too ill-conditioned")]
    NonFiniteResult {
        /// The nodal diameter.
        nodal_diameter: i64,
        /// What (e.g. `the reduced stiffness`).
        what: String,
    },
    /// faer refused to build or factor a sparse matrix (allocation, index
    /// overflow).
    #[error("nodal diameter {nodal_diameter}: {what}: {message}")]
    Sparse {
        /// The nodal diameter.
        nodal_diameter: i64,
        /// What was being done.
        what: String,
        /// faer's message.
        message: String,
    },
}

impl ReductionError {
    /// An [`ReductionError::Invalid`] error.
    pub(crate) fn invalid(what: impl Into<String>, message: impl Into<String>) -> Self {
        Self::Invalid {
            what: what.into(),
            message: message.into(),
        }
    }
}
