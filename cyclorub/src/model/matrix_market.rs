//! Matrix Market import (`.mtx`): real (or integer) coordinate matrices,
//! `general` or `symmetric`, the usual export of FE codes.

use super::ModelError;
use faer::sparse::{SparseColMat, Triplet};
use faer::Mat;
use std::path::Path;

/// Largest matrix accepted (rows): a sector's dofs are stored dense
/// ([`SECTOR_MAX_DOFS`](super::SECTOR_MAX_DOFS)), so a larger file is refused
/// from its size line, before any entry is read.
pub const MATRIX_MARKET_MAX_ROWS: usize = super::sector::SECTOR_MAX_DOFS;

/// Reads a Matrix Market file into a dense matrix. Duplicate entries are
/// summed; a `symmetric` file's entries are mirrored. `key` names the input
/// in error messages (e.g. `model.mass_file`).
pub fn read_matrix_market(path: &Path, key: &str) -> Result<Mat<f64>, ModelError> {
    let text = std::fs::read_to_string(path).map_err(|source| ModelError::Io {
        key: key.into(),
        path: path.to_path_buf(),
        source,
    })?;
    parse_matrix_market(&text, path)
}

/// Parses the text of a Matrix Market file (`path` only names it in errors).
pub fn parse_matrix_market(text: &str, path: &Path) -> Result<Mat<f64>, ModelError> {
    let parsed = parse_entries(text, path, Some(MATRIX_MARKET_MAX_ROWS))?;
    let mut a = Mat::<f64>::zeros(parsed.rows, parsed.cols);
    for &(i, j, v) in &parsed.entries {
        a[(i, j)] += v;
        if parsed.symmetric && i != j {
            a[(j, i)] += v;
        }
    }
    Ok(a)
}

/// Reads a Matrix Market file into a sparse matrix with both triangles
/// stored (a `symmetric` file's entries mirrored, duplicates summed), for
/// sectors too large to be dense. `key` names the input in error messages.
pub fn read_matrix_market_sparse(
    path: &Path,
    key: &str,
) -> Result<SparseColMat<usize, f64>, ModelError> {
    let text = std::fs::read_to_string(path).map_err(|source| ModelError::Io {
        key: key.into(),
        path: path.to_path_buf(),
        source,
    })?;
    parse_matrix_market_sparse(&text, path)
}

/// [`read_matrix_market_sparse`] of a file's text (`path` names it in errors).
pub(crate) fn parse_matrix_market_sparse(
    text: &str,
    path: &Path,
) -> Result<SparseColMat<usize, f64>, ModelError> {
    let parsed = parse_entries(text, path, None)?;
    let mut triplets = Vec::with_capacity(2 * parsed.entries.len());
    for &(i, j, v) in &parsed.entries {
        triplets.push(Triplet::new(i, j, v));
        if parsed.symmetric && i != j {
            triplets.push(Triplet::new(j, i, v));
        }
    }
    SparseColMat::try_new_from_triplets(parsed.rows, parsed.cols, &triplets).map_err(|e| {
        ModelError::MatrixMarket {
            path: path.to_path_buf(),
            line: 0,
            message: format!("cannot build the sparse matrix: {e:?}"),
        }
    })
}

/// The entries of a Matrix Market file as given (1-based indices made
/// 0-based; the lower triangle only for a `symmetric` file).
struct Parsed {
    rows: usize,
    cols: usize,
    symmetric: bool,
    entries: Vec<(usize, usize, f64)>,
}

/// Parses a Matrix Market file's text; `dense_limit` refuses larger
/// matrices from the size line.
fn parse_entries(
    text: &str,
    path: &Path,
    dense_limit: Option<usize>,
) -> Result<Parsed, ModelError> {
    let err = |line: usize, message: String| ModelError::MatrixMarket {
        path: path.to_path_buf(),
        line,
        message,
    };
    // A file cut inside its last number (`2 2 3.6` of `2 2 3.65e3`) would
    // read as a shorter number: a last entry must end its line.
    if !text.is_empty() && !text.ends_with('\n') {
        let (count, last) = text
            .lines()
            .enumerate()
            .last()
            .map_or((0, ""), |(i, l)| (i + 1, l));
        let trimmed = last.trim();
        if !trimmed.is_empty() && !trimmed.starts_with('%') {
            return Err(err(
                count,
                format!(
                    "the last line `{trimmed}` does not end with a line break: the file may be cut \
                     inside a number; a complete Matrix Market file ends with a newline"
                ),
            ));
        }
    }
    let mut lines = text.lines().enumerate().map(|(i, l)| (i + 1, l));
    let (_, header) = lines.next().ok_or_else(|| {
        err(
            1,
            "empty file; expected a `%%MatrixMarket matrix coordinate real general` header".into(),
        )
    })?;
    let words: Vec<String> = header
        .split_whitespace()
        .map(|w| w.to_ascii_lowercase())
        .collect();
    if words.first().map(String::as_str) != Some("%%matrixmarket") || words.len() != 5 {
        return Err(err(
            1,
            format!("header `{header}` is not a Matrix Market header; expected `%%MatrixMarket matrix coordinate real general` (or `symmetric`)"),
        ));
    }
    if words[1] != "matrix" {
        return Err(err(
            1,
            format!("object `{}` is not supported; allowed: matrix", words[1]),
        ));
    }
    if words[2] != "coordinate" {
        return Err(err(
            1,
            format!(
                "format `{}` is not supported; allowed: coordinate",
                words[2]
            ),
        ));
    }
    if words[3] != "real" && words[3] != "integer" {
        return Err(err(
            1,
            format!(
                "field `{}` is not supported; allowed: real, integer",
                words[3]
            ),
        ));
    }
    let symmetric = match words[4].as_str() {
        "general" => false,
        "symmetric" => true,
        other => {
            return Err(err(
                1,
                format!("symmetry `{other}` is not supported; allowed: general, symmetric"),
            ));
        }
    };
    let mut data = lines.filter(|(_, l)| {
        let t = l.trim();
        !t.is_empty() && !t.starts_with('%')
    });
    let (size_line, size_text) = data.next().ok_or_else(|| {
        err(
            0,
            "no size line (`rows columns entries`) after the header".into(),
        )
    })?;
    let sizes: Vec<usize> = size_text
        .split_whitespace()
        .map(str::parse)
        .collect::<Result<_, _>>()
        .map_err(|_| {
            err(
                size_line,
                format!("size line `{size_text}` must hold three integers: rows columns entries"),
            )
        })?;
    if sizes.len() != 3 {
        return Err(err(
            size_line,
            format!("size line `{size_text}` must hold three integers: rows columns entries"),
        ));
    }
    let (rows, cols, entries) = (sizes[0], sizes[1], sizes[2]);
    if dense_limit.is_some_and(|limit| rows.max(cols) > limit) {
        return Err(err(
            size_line,
            format!("{rows}×{cols} is too large for dense sector matrices (limit {MATRIX_MARKET_MAX_ROWS} rows)"),
        ));
    }
    if symmetric && rows != cols {
        return Err(err(
            size_line,
            format!("a symmetric matrix must be square, not {rows}×{cols}"),
        ));
    }
    let mut parsed = Parsed {
        rows,
        cols,
        symmetric,
        entries: Vec::with_capacity(entries.min(1 << 24)),
    };
    let mut count = 0usize;
    for (line, entry) in data {
        count += 1;
        if count > entries {
            return Err(err(
                line,
                format!("more entries than the {entries} announced on line {size_line}"),
            ));
        }
        let fields: Vec<&str> = entry.split_whitespace().collect();
        if fields.len() != 3 {
            return Err(err(
                line,
                format!("entry `{entry}` must be `row column value`"),
            ));
        }
        let index = |s: &str, n: usize, what: &str| -> Result<usize, ModelError> {
            let i: usize = s
                .parse()
                .map_err(|_| err(line, format!("{what} `{s}` is not a positive integer")))?;
            if i == 0 || i > n {
                return Err(err(line, format!("{what} {i} is out of range 1..={n}")));
            }
            Ok(i - 1)
        };
        let i = index(fields[0], rows, "row")?;
        let j = index(fields[1], cols, "column")?;
        let v: f64 = fields[2]
            .parse()
            .map_err(|_| err(line, format!("value `{}` is not a number", fields[2])))?;
        if !v.is_finite() {
            return Err(err(line, format!("value `{}` is not finite", fields[2])));
        }
        if symmetric && j > i {
            return Err(err(
                line,
                format!(
                    "entry ({}, {}) lies above the diagonal; a symmetric Matrix Market file holds the lower triangle only",
                    i + 1,
                    j + 1
                ),
            ));
        }
        parsed.entries.push((i, j, v));
    }
    if count < entries {
        return Err(err(
            text.lines().count(),
            format!(
                "the file ends here after {count} entries but {entries} are announced on line \
                 {size_line} (a truncated file, or a wrong count)"
            ),
        ));
    }
    Ok(parsed)
}
