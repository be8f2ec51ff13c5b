//! Errors of model building: each names the input (case-file key or file),
//! the offending value and what is allowed.

use super::input::{SectorInput, Subject};
use std::path::PathBuf;

/// Why a sector model could not be built or analysed.
#[derive(Debug, thiserror::Error)]
pub enum ModelError {
    /// A value of the `[model]` table (or of a library constructor) is not allowed.
    #[error("{key}: {message}")]
    Invalid {
        /// The key, e.g. `model.sectors` or `model.springs[2].dofs`.
        key: Subject,
        /// What is wrong and what is allowed.
        message: String,
    },
    /// A matrix is not square.
    #[error("{what}: the matrix is not square ({rows} rows, {cols} columns); sector matrices must be square")]
    NotSquare {
        /// Which matrix (key and file, once the caller named it).
        what: Subject,
        /// Number of rows.
        rows: usize,
        /// Number of columns.
        cols: usize,
    },
    /// A matrix that must be symmetric is not, beyond the tolerance.
    #[error(
        "{what}: the matrix is not symmetric: entry ({row}, {col}) = {value:e} but ({col}, {row}) = {transposed:e} \
         (allowed difference: {tolerance:e} times the largest entry; 1-based indices)"
    )]
    NotSymmetric {
        /// Which matrix (key and file, once the caller named it).
        what: Subject,
        /// 1-based row of the worst pair.
        row: usize,
        /// 1-based column of the worst pair.
        col: usize,
        /// Entry (row, col).
        value: f64,
        /// Entry (col, row).
        transposed: f64,
        /// The relative tolerance used.
        tolerance: f64,
    },
    /// A mass matrix is not positive definite (Cholesky failed).
    #[error("{what}: the mass matrix is not positive definite{}; every dof needs a positive mass", nd_suffix(*.nodal_diameter))]
    MassNotPositiveDefinite {
        /// Which matrix (key and file, once the caller named it).
        what: Subject,
        /// The signed nodal diameter where it failed, if per diameter.
        nodal_diameter: Option<i64>,
    },
    /// Two matrices that must have the same size do not.
    #[error("{what}: size {found}×{found} does not match {reference} ({expected}×{expected})")]
    SizeMismatch {
        /// Which matrix (key and file, once the caller named it).
        what: Subject,
        /// Its size.
        found: usize,
        /// What it must match.
        reference: Subject,
        /// The required size.
        expected: usize,
    },
    /// The left and right boundary lists of a finite-element sector do not
    /// pair dof by dof.
    #[error(
        "{left} / {right}: the boundary lists have unequal lengths ({left_dofs} left dofs, \
         {right_dofs} right dofs); they must pair dof by dof"
    )]
    UnequalBoundaries {
        /// The left list.
        left: Subject,
        /// The right list.
        right: Subject,
        /// Its length.
        left_dofs: usize,
        /// Its length.
        right_dofs: usize,
    },
    /// A dof appears twice in the boundary lists.
    #[error(
        "{at}: dof {dof} is already listed at {first}; a dof may appear once in the boundary lists"
    )]
    RepeatedBoundaryDof {
        /// Where it appears the second time.
        at: Subject,
        /// The dof (1-based).
        dof: usize,
        /// Where it appears first.
        first: Subject,
    },
    /// A value is not a finite number.
    #[error("{what}: entry ({row}, {col}) is {value}; only finite numbers are allowed (1-based indices)")]
    NotFinite {
        /// Which matrix (key and file, once the caller named it).
        what: Subject,
        /// 1-based row.
        row: usize,
        /// 1-based column.
        col: usize,
        /// The value.
        value: f64,
    },
    /// A Matrix Market file could not be read or parsed.
    #[error("{}: {message}", location(path, *line))]
    MatrixMarket {
        /// The file.
        path: PathBuf,
        /// 1-based line number (0 when the problem is not tied to a line).
        line: usize,
        /// What is wrong and what is allowed.
        message: String,
    },
    /// A case file is not valid TOML or its `[model]` table does not fit.
    #[error("{}: {message}", path.display())]
    CaseFile {
        /// The case file.
        path: PathBuf,
        /// The TOML error (line, column, key, allowed keys).
        message: String,
    },
    /// A file could not be opened.
    #[error("{key}: cannot read {}: {source}", path.display())]
    Io {
        /// The key naming the file.
        key: String,
        /// The file.
        path: PathBuf,
        /// The system error.
        source: std::io::Error,
    },
    /// An eigenvalue solver failed or returned non-finite values.
    #[error("eigenvalue problem of nodal diameter {nodal_diameter}: {message}")]
    Eigen {
        /// Signed nodal diameter.
        nodal_diameter: i64,
        /// What went wrong.
        message: String,
    },
    /// A line of an input file (node coordinates, node sets, a matrix) is
    /// wrong or refers to something missing.
    #[error("{key} ({}): {message}", location(path, *line))]
    InputFile {
        /// The key naming the file, e.g. `model.node_sets_file`.
        key: String,
        /// The file.
        path: PathBuf,
        /// 1-based line (0: not tied to a line).
        line: usize,
        /// What is wrong and what is allowed.
        message: String,
    },
    /// The Craig–Bampton reduction of a finite-element sector failed.
    #[error("{key}: {source}")]
    Reduction {
        /// The key (with its file) of the input that failed.
        key: String,
        /// What failed.
        source: crate::model::craig_bampton::ReductionError,
    },
    /// A dense matrix would be too large to hold.
    #[error("{what}: {size}×{size} dense matrix is too large (limit {limit} rows)")]
    TooLarge {
        /// Which matrix.
        what: String,
        /// Its size.
        size: usize,
        /// The limit.
        limit: usize,
    },
    /// The full wheel's eigenvalue solver failed or returned non-finite
    /// values (the modes of a mistuned wheel, which has no nodal diameter).
    #[error("eigenvalue problem of the full wheel: {message}")]
    WheelEigen {
        /// What went wrong.
        message: String,
    },
}

/// `path:line`, or `path` alone for line 0.
fn location(path: &std::path::Path, line: usize) -> String {
    match line {
        0 => path.display().to_string(),
        line => format!("{}:{line}", path.display()),
    }
}

fn nd_suffix(nodal_diameter: Option<i64>) -> String {
    match nodal_diameter {
        Some(s) => format!(" at nodal diameter {s}"),
        None => String::new(),
    }
}

impl ModelError {
    /// Whether the error is in what the user gave (a key, a matrix, a
    /// file), as opposed to a failure of the computation (an eigenvalue
    /// solver, a matrix too large to hold).
    pub fn is_input_error(&self) -> bool {
        use crate::model::craig_bampton::ReductionError as R;
        !matches!(
            self,
            Self::Eigen { .. }
                | Self::WheelEigen { .. }
                | Self::TooLarge { .. }
                | Self::Reduction {
                    source: R::NotConverged { .. } | R::NonFiniteResult { .. } | R::Sparse { .. },
                    ..
                }
        )
    }

    /// The same error with the caller's names for the sector inputs it is
    /// about: the case layer passes the case-file key of each input (and
    /// its file), the model layer having named them only as
    /// [`SectorInput`]s.
    pub fn named(self, name: impl Fn(SectorInput) -> String) -> Self {
        let name = &name;
        match self {
            Self::Invalid { key, message } => Self::Invalid {
                key: key.named(name),
                message,
            },
            Self::NotSquare { what, rows, cols } => Self::NotSquare {
                what: what.named(name),
                rows,
                cols,
            },
            Self::NotSymmetric {
                what,
                row,
                col,
                value,
                transposed,
                tolerance,
            } => Self::NotSymmetric {
                what: what.named(name),
                row,
                col,
                value,
                transposed,
                tolerance,
            },
            Self::MassNotPositiveDefinite {
                what,
                nodal_diameter,
            } => Self::MassNotPositiveDefinite {
                what: what.named(name),
                nodal_diameter,
            },
            Self::SizeMismatch {
                what,
                found,
                reference,
                expected,
            } => Self::SizeMismatch {
                what: what.named(name),
                found,
                reference: reference.named(name),
                expected,
            },
            Self::UnequalBoundaries {
                left,
                right,
                left_dofs,
                right_dofs,
            } => Self::UnequalBoundaries {
                left: left.named(name),
                right: right.named(name),
                left_dofs,
                right_dofs,
            },
            Self::RepeatedBoundaryDof { at, dof, first } => Self::RepeatedBoundaryDof {
                at: at.named(name),
                dof,
                first: first.named(name),
            },
            Self::NotFinite {
                what,
                row,
                col,
                value,
            } => Self::NotFinite {
                what: what.named(name),
                row,
                col,
                value,
            },
            other => other,
        }
    }

    /// Shorthand for [`ModelError::Invalid`].
    pub fn invalid(key: impl Into<Subject>, message: impl Into<String>) -> Self {
        Self::Invalid {
            key: key.into(),
            message: message.into(),
        }
    }
}
