//! The products of the contact Jacobian of a cyclic basis, block by block.
//!
//! `∂R/∂x = Z + G̃ (T_law Ḡ (a I + b Z) + T_displacement Ḡ)` (see
//! [`super::residual`]) has sparse factors: `Ḡ` maps the pairs of harmonic
//! `k` of one contact dof to that dof's harmonic-`k` coordinates on the
//! sampled sectors, and `G̃` maps back; `Z` is block-diagonal per pair; `T`
//! is made of `H × H` blocks per sampled sector and contact dof (the law's
//! and a friction node's six). Formed densely, `Ḡ Z` and `G̃ (T …)` cost
//! `O(n³)` each; here `Ḡ (a I + b Z)` is formed row by row on its
//! harmonic's unknowns (contiguous, [`Layout::cyclic`]), and each block
//! `t` of `T` adds `(G̃_β t) (Ḡ (a I + b Z))_β'` to `J`, with `G̃_β` the
//! few unknowns that read its row band `β` (the sampled sector and contact
//! dof of the block) and `β'` its column band.

use super::layout::{Layout, SectorMaps};
use crate::continuation::Interrupt;
use faer::linalg::matmul::matmul;
use faer::{Accum, Mat, MatMut, MatRef, Par};
use std::ops::Range;

/// A real matrix by rows, holding only its nonzeros.
#[derive(Clone, Debug, Default)]
struct RowSparse {
    starts: Vec<usize>,
    columns: Vec<usize>,
    values: Vec<f64>,
}

impl RowSparse {
    /// The nonzeros of `a` (exact zeros dropped: products skip them alike).
    fn from_dense(a: MatRef<'_, f64>) -> Self {
        let mut out = Self {
            starts: vec![0],
            ..Self::default()
        };
        for r in 0..a.nrows() {
            for c in 0..a.ncols() {
                let v = a[(r, c)];
                if v != 0.0 {
                    out.columns.push(c);
                    out.values.push(v);
                }
            }
            out.starts.push(out.columns.len());
        }
        out
    }

    fn rows(&self) -> usize {
        self.starts.len() - 1
    }

    /// The columns and values of row `r`.
    fn row(&self, r: usize) -> (&[usize], &[f64]) {
        let range = self.starts[r]..self.starts[r + 1];
        (&self.columns[range.clone()], &self.values[range])
    }

    /// `Σ_c A[r, c] x[c]`.
    fn row_dot(&self, r: usize, x: &[f64]) -> f64 {
        let (columns, values) = self.row(r);
        columns.iter().zip(values).map(|(&c, v)| v * x[c]).sum()
    }
}

/// Rows each stored on a range of columns, row-major and contiguous.
#[derive(Clone, Debug, Default)]
struct RangedRows {
    /// Where each row's values start.
    offsets: Vec<usize>,
    values: Vec<f64>,
}

impl RangedRows {
    fn new(ranges: &[Range<usize>]) -> Self {
        let mut offsets = Vec::with_capacity(ranges.len() + 1);
        let mut at = 0;
        for range in ranges {
            offsets.push(at);
            at += range.len();
        }
        offsets.push(at);
        Self {
            offsets,
            values: vec![0.0; at],
        }
    }

    fn row(&self, r: usize) -> &[f64] {
        &self.values[self.offsets[r]..self.offsets[r + 1]]
    }

    fn row_mut(&mut self, r: usize) -> &mut [f64] {
        &mut self.values[self.offsets[r]..self.offsets[r + 1]]
    }
}

/// One contact block of `T` in sector coordinates: its row band, its column
/// band, whether it multiplies the law's input `Ḡ (a I + b Z)` (else the
/// displacements `Ḡ`), and its `H × H` row-major values.
pub(super) struct ContactBlock<'a> {
    pub(super) row: usize,
    pub(super) column: usize,
    pub(super) law: bool,
    pub(super) values: &'a [f64],
}

/// The columns of `G̃` on one band of the sector coordinates (one sampled
/// sector and contact dof): the unknowns that read it and their weights.
#[derive(Clone, Debug, Default)]
struct Band {
    unknowns: Vec<usize>,
    /// Row-major, `unknowns.len() × H`.
    weights: Vec<f64>,
}

/// The sector maps of a cyclic layout by their nonzeros, with the buffers
/// of the contact Jacobian's products.
#[derive(Clone, Debug)]
pub(super) struct SectorProducts {
    /// `Ḡ`, sector coordinates ← unknowns.
    to_sectors: RowSparse,
    /// `G̃`, unknowns ← sector coordinates.
    from_sectors: RowSparse,
    /// Per sector coordinate, the unknowns of its harmonic: where its rows
    /// of `Ḡ` and `Ḡ Z` may be nonzero.
    row_unknowns: Vec<Range<usize>>,
    /// Per unknown, the unknowns of its block: where its row of `Z` may be
    /// nonzero.
    unknown_block: Vec<Range<usize>>,
    /// The blocks' unknowns (`Z` is block-diagonal on them).
    blocks: Vec<Range<usize>>,
    /// `G̃` by bands of `H` sector coordinates.
    bands: Vec<Band>,
    /// `Ḡ` on `row_unknowns`.
    displacement_operand: RangedRows,
    /// `Ḡ (a I + b Z)` on `row_unknowns`, per Jacobian.
    law_operand: RangedRows,
    /// `G̃_β t` for one block `t` of `T`, by columns.
    weighted: Vec<f64>,
    /// `H = 2 N_h + 1`.
    size: usize,
}

impl SectorProducts {
    /// The products of a layout with cyclic maps; `None` for the physical
    /// layout (identity maps, handled band by band).
    ///
    /// # Panics
    /// If the maps do not have the per-harmonic structure of
    /// [`Layout::cyclic`] (a bug, not a user error).
    pub(super) fn new(layout: &Layout) -> Option<Self> {
        let SectorMaps::Dense {
            to_sectors,
            from_sectors,
        } = &layout.maps
        else {
            return None;
        };
        let size = layout.coordinates();
        // Per harmonic, the span of its blocks' unknowns (None: no block).
        let mut harmonic_unknowns: Vec<Option<Range<usize>>> =
            vec![None; layout.harmonic_set.count()];
        let mut unknown_block = vec![0..0; layout.unknowns];
        let mut blocks = Vec::new();
        for block in &layout.blocks {
            let indices = block
                .slots
                .iter()
                .flat_map(|slot| std::iter::once(slot.re).chain(slot.im));
            let start = indices.clone().min().unwrap_or(0);
            let end = indices.clone().max().map_or(0, |m| m + 1);
            for u in indices {
                unknown_block[u] = start..end;
            }
            blocks.push(start..end);
            let range = &mut harmonic_unknowns[block.harmonic];
            *range = Some(match range.take() {
                Some(range) => range.start.min(start)..range.end.max(end),
                None => start..end,
            });
        }
        let harmonic_of = |coordinate: usize| coordinate.div_ceil(2);
        let row_unknowns: Vec<Range<usize>> = (0..layout.sector_coordinates())
            .map(|r| {
                harmonic_unknowns[harmonic_of(r % size)]
                    .clone()
                    .unwrap_or(0..0)
            })
            .collect();
        let to_sectors = RowSparse::from_dense(to_sectors.as_ref());
        let from_sectors = RowSparse::from_dense(from_sectors.as_ref());
        for (r, range) in row_unknowns.iter().enumerate() {
            let within = to_sectors.row(r).0.iter().all(|c| range.contains(c));
            assert!(within, "Ḡ reads the unknowns of one harmonic per row");
        }
        for u in 0..from_sectors.rows() {
            let within = from_sectors
                .row(u)
                .0
                .iter()
                .all(|&r| row_unknowns[r].contains(&u));
            assert!(within, "G̃ reads the coordinates of one harmonic per row");
        }
        let mut bands = vec![Band::default(); layout.sector_coordinates() / size];
        for u in 0..from_sectors.rows() {
            let (rows, values) = from_sectors.row(u);
            for (&r, &g) in rows.iter().zip(values) {
                let band = &mut bands[r / size];
                if band.unknowns.last() != Some(&u) {
                    band.unknowns.push(u);
                    band.weights.resize(band.weights.len() + size, 0.0);
                }
                let row = band.unknowns.len() - 1;
                band.weights[row * size + r % size] = g;
            }
        }
        let readers = bands.iter().map(|b| b.unknowns.len()).max().unwrap_or(0);
        let mut displacement_operand = RangedRows::new(&row_unknowns);
        for (r, range) in row_unknowns.iter().enumerate() {
            let (columns, values) = to_sectors.row(r);
            let row = displacement_operand.row_mut(r);
            for (&c, &v) in columns.iter().zip(values) {
                row[c - range.start] = v;
            }
        }
        Some(Self {
            law_operand: RangedRows::new(&row_unknowns),
            displacement_operand,
            weighted: vec![0.0; readers * size],
            size,
            blocks,
            bands,
            to_sectors,
            from_sectors,
            row_unknowns,
            unknown_block,
        })
    }

    /// `out = Z x` for a matrix `Z` block-diagonal on the layout's blocks
    /// (the dynamic stiffness and its derivative).
    pub(super) fn multiply_block_diagonal(&self, z: MatRef<'_, f64>, x: &[f64], out: &mut [f64]) {
        out.fill(0.0);
        for block in &self.blocks {
            for c in block.clone() {
                let v = x[c];
                if v == 0.0 {
                    continue;
                }
                for r in block.clone() {
                    out[r] += z[(r, c)] * v;
                }
            }
        }
    }

    /// `out = Ḡ x`.
    pub(super) fn to_sectors(&self, x: &[f64], out: &mut [f64]) {
        for (r, o) in out.iter_mut().enumerate() {
            *o = self.to_sectors.row_dot(r, x);
        }
    }

    /// `out += G̃ v`.
    pub(super) fn add_from_sectors(&self, v: &[f64], out: &mut [f64]) {
        for (u, o) in out.iter_mut().enumerate() {
            *o += self.from_sectors.row_dot(u, v);
        }
    }

    /// The unknowns that read the band starting at sector coordinate `row`.
    pub(super) fn readers(&self, row: usize) -> usize {
        self.bands[row / self.size].unknowns.len()
    }

    /// `J += G̃ (T_law Ḡ (a I + b Z) + T_displacement Ḡ)` for the contact
    /// blocks `blocks` of `T` and the dynamic stiffness `dynamic` (`Z`);
    /// `false` when `interrupt` was raised before the last block (the
    /// Jacobian is then incomplete).
    pub(super) fn add_contact_jacobian<'a>(
        &mut self,
        a: f64,
        b: f64,
        dynamic: MatRef<'_, f64>,
        blocks: impl IntoIterator<Item = ContactBlock<'a>>,
        jacobian: &mut Mat<f64>,
        interrupt: Option<&Interrupt>,
    ) -> bool {
        // Ḡ (a I + b Z), row by row on its harmonic: Z only within blocks.
        for (r, range) in self.row_unknowns.iter().enumerate() {
            let row = self.law_operand.row_mut(r);
            for (m, g) in row.iter_mut().zip(self.displacement_operand.row(r)) {
                *m = a * g;
            }
            if b == 0.0 {
                continue;
            }
            let (unknowns, values) = self.to_sectors.row(r);
            for (&u, &g) in unknowns.iter().zip(values) {
                let weight = b * g;
                for c in self.unknown_block[u].clone() {
                    row[c - range.start] += weight * dynamic[(u, c)];
                }
            }
        }
        // Each block t: J += (G̃_β t) (…)_β', the operand's rows living
        // on one harmonic's unknowns each.
        let size = self.size;
        for block in blocks {
            if interrupt.is_some_and(Interrupt::raised) {
                return false;
            }
            let band = &self.bands[block.row / size];
            let readers = band.unknowns.len();
            if readers == 0 {
                continue;
            }
            let weighted = &mut self.weighted[..readers * size];
            // (G̃_β t) as `readers × size`, column-major (a column per
            // entry `e` of the band): one blocked product, not a strided
            // loop (`readers · size²`: minutes at thousands of harmonics).
            matmul(
                MatMut::from_column_major_slice_mut(weighted, readers, size),
                Accum::Replace,
                MatRef::from_row_major_slice(&band.weights, readers, size),
                MatRef::from_row_major_slice(block.values, size, size),
                1.0,
                Par::Seq,
            );
            let operand = if block.law {
                &self.law_operand
            } else {
                &self.displacement_operand
            };
            for e in 0..size {
                if interrupt.is_some_and(Interrupt::raised) {
                    return false;
                }
                let r = block.column + e;
                let start = self.row_unknowns[r].start;
                let w = &weighted[e * readers..(e + 1) * readers];
                for (offset, &v) in operand.row(r).iter().enumerate() {
                    if v == 0.0 {
                        continue;
                    }
                    let column = jacobian.col_as_slice_mut(start + offset);
                    for (&u, w) in band.unknowns.iter().zip(w) {
                        column[u] += w * v;
                    }
                }
            }
        }
        true
    }
}
