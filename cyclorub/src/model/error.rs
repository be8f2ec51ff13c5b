//! Errors of model building: each names the input (case-file key or file),
//! the offending value and what is allowed.

use std::path::PathBuf;

/// Why a sector model could not be built or analysed.
#[derive(Debug, thiserror::Error)]
pub enum ModelError {
    /// A value of the `[model]` table (or of a library constructor) is not allowed.
    #[error("{key}: {message}")]
    Invalid {
        /// The key, e.g. `model.sectors` or `model.springs[2].dofs`.
        key: String,
        /// What is wrong and what is allowed.
        message: String,
    },
    /// A matrix is not square.
    #[error("{what}: the matrix is not square ({rows} rows, {cols} columns); sector matrices must be square")]
    NotSquare {
        /// Which matrix (key and file).
        what: String,
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
        /// Which matrix (key and file).
        what: String,
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
        /// Which matrix (key and file).
        what: String,
        /// The signed nodal diameter where it failed, if per diameter.
        nodal_diameter: Option<i64>,
    },
    /// Two matrices that must have the same size do not.
    #[error("{what}: size {found}×{found} does not match {reference} ({expected}×{expected})")]
    SizeMismatch {
        /// Which matrix (key and file).
        what: String,
        /// Its size.
        found: usize,
        /// What it must match.
        reference: String,
        /// The required size.
        expected: usize,
    },
    /// A value is not a finite number.
    #[error("{what}: entry ({row}, {col}) is {value}; only finite numbers are allowed (1-based indices)")]
    NotFinite {
        /// Which matrix (key and file).
        what: String,
        /// 1-based row.
        row: usize,
        /// 1-based column.
        col: usize,
        /// The value.
        value: f64,
    },
    /// A Matrix Market file could not be read or parsed.
    #[error("{}:{line}: {message}", path.display())]
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
        !matches!(self, Self::Eigen { .. } | Self::TooLarge { .. })
    }

    /// Shorthand for [`ModelError::Invalid`].
    pub fn invalid(key: impl Into<String>, message: impl Into<String>) -> Self {
        Self::Invalid {
            key: key.into(),
            message: message.into(),
        }
    }
}
