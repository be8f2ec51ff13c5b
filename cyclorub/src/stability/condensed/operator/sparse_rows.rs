//! The contact matrices `D` and `E` on the contact positions by their
//! nonzero entries, row by row: a contact node couples its own dofs across
//! the harmonics and no other node's, so on a wheel of many contact nodes
//! most of the `r × r` entries are zero (the open fan's 27 contact dofs at
//! 21 harmonics: 63 of 567 a row). The products that following an
//! exponent repeats skip them.

use faer::c64;

/// A square matrix's nonzero entries, row by row (compressed rows); a
/// matrix with more than [`DENSEST`] of its entries nonzero keeps them
/// all, its rows read as contiguous slices (faster there than gathering).
#[derive(Clone, Debug, Default)]
pub(super) struct SparseRows {
    /// Where each row's entries start in `columns` and `values` (one more
    /// than the rows).
    starts: Vec<usize>,
    /// Each entry's column.
    columns: Vec<usize>,
    values: Vec<c64>,
    /// Every entry kept: `values` holds the rows whole.
    whole: bool,
}

/// The share of nonzero entries above which every entry is kept.
const DENSEST: f64 = 0.25;

impl SparseRows {
    /// The nonzero entries of the `r × r` row-major matrix `dense`.
    pub(super) fn of(dense: &[c64], r: usize) -> Self {
        let zero = c64::new(0.0, 0.0);
        let nonzero = dense.iter().take(r * r).filter(|&&v| v != zero).count();
        if nonzero as f64 > DENSEST * (r * r) as f64 {
            return Self {
                starts: (0..=r).map(|i| i * r).collect(),
                columns: (0..r * r).map(|k| k % r).collect(),
                values: dense[..r * r].to_vec(),
                whole: true,
            };
        }
        let mut out = Self {
            starts: Vec::with_capacity(r + 1),
            ..Self::default()
        };
        out.starts.push(0);
        for row in dense.chunks_exact(r.max(1)).take(r) {
            for (column, &value) in row.iter().enumerate() {
                if value != zero {
                    out.columns.push(column);
                    out.values.push(value);
                }
            }
            out.starts.push(out.columns.len());
        }
        out
    }

    /// Rows.
    pub(super) fn rows(&self) -> usize {
        self.starts.len().saturating_sub(1)
    }

    /// Row `i`'s entries: `(column, value)`.
    pub(super) fn row(&self, i: usize) -> impl Iterator<Item = (usize, c64)> + '_ {
        let range = self.starts[i]..self.starts[i + 1];
        self.columns[range.clone()]
            .iter()
            .copied()
            .zip(self.values[range].iter().copied())
    }

    /// The matrix times `x`.
    pub(super) fn times(&self, x: &[c64]) -> Vec<c64> {
        if self.whole {
            let r = self.rows();
            return self
                .values
                .chunks_exact(r.max(1))
                .take(r)
                .map(|row| row.iter().zip(x).map(|(v, x)| v * x).sum())
                .collect();
        }
        (0..self.rows())
            .map(|i| self.row(i).map(|(c, v)| v * x[c]).sum())
            .collect()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The row-major square matrix `a` times `x`, entry by entry.
    fn dense_times(a: &[c64], x: &[c64]) -> Vec<c64> {
        a.chunks_exact(x.len())
            .map(|row| row.iter().zip(x).map(|(a, x)| a * x).sum())
            .collect()
    }

    /// The compressed product equals the dense one to the bit (the zeros
    /// skipped add nothing), rows without an entry giving zero.
    #[test]
    fn the_compressed_product_is_the_dense_one() {
        let r = 5;
        let dense: Vec<c64> = (0..r * r)
            .map(|k| {
                let (i, j) = (k / r, k % r);
                if (i + 2 * j) % 5 == 0 && i != 4 {
                    c64::new(1.0 + i as f64, -0.5 * j as f64 + 0.25)
                } else {
                    c64::new(0.0, 0.0)
                }
            })
            .collect();
        let x: Vec<c64> = (0..r)
            .map(|j| c64::new(0.3 * j as f64 - 1.0, 0.7 / (1.0 + j as f64)))
            .collect();
        let sparse = SparseRows::of(&dense, r);
        assert_eq!(sparse.times(&x), dense_times(&dense, &x));
        assert_eq!(sparse.rows(), r);
        assert_eq!(sparse.row(4).count(), 0);
        let stored: usize = (0..r).map(|i| sparse.row(i).count()).sum();
        let nonzero = dense.iter().filter(|v| **v != c64::new(0.0, 0.0)).count();
        assert_eq!(stored, nonzero);
        assert!(stored < r * r);
        // A denser matrix keeps every entry: the same product, every entry
        // read.
        let full: Vec<c64> = dense
            .iter()
            .enumerate()
            .map(|(k, &v)| if k % 2 == 0 { c64::new(2.0, 1.0) } else { v })
            .collect();
        let kept = SparseRows::of(&full, r);
        let expected = dense_times(&full, &x);
        assert_eq!(kept.times(&x), expected);
        assert_eq!((0..r).map(|i| kept.row(i).count()).sum::<usize>(), r * r);
        let by_rows: Vec<c64> = (0..r)
            .map(|i| kept.row(i).map(|(c, v)| v * x[c]).sum())
            .collect();
        assert_eq!(by_rows, expected);
    }

    /// A matrix without an entry (friction's velocity terms without a
    /// normal stiffness, or the reverse) gives a zero product of full
    /// length, not an empty one.
    #[test]
    fn a_matrix_without_an_entry_gives_zeros() {
        let r = 4;
        let zero = c64::new(0.0, 0.0);
        let empty = SparseRows::of(&vec![zero; r * r], r);
        let x = vec![c64::new(1.0, -2.0); r];
        assert_eq!(empty.times(&x), vec![zero; r]);
        assert_eq!(empty.rows(), r);
        assert!((0..r).all(|i| empty.row(i).count() == 0));
    }
}
