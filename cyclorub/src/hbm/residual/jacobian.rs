//! The contact part of the Jacobian: the law's derivative blocks `T`
//! (Eq. 69) applied to sector coordinates, gathered per contact signal, and
//! added to a dense `∂R/∂x`.

use super::super::friction;
use super::super::sector_products::ContactBlock;
use super::HarmonicBalance;
use faer::linalg::matmul::matmul;
use faer::{Accum, Mat, MatRef, Par};

impl HarmonicBalance {
    /// `T v` for sector coordinates `v`: the law's part of the contact
    /// derivative (`T = F diag(df/dq) F⁻¹` on each normal signal and, with
    /// friction, its image on the node's tangential signals).
    pub(super) fn apply_derivative_blocks(&self, v: &[f64]) -> Vec<f64> {
        let size = self.layout.coordinates();
        let mut out = vec![0.0; v.len()];
        let times = |block: &[f64], from: usize, to: usize, out: &mut [f64]| {
            for r in 0..size {
                out[to + r] += (0..size)
                    .map(|c| block[r * size + c] * v[from + c])
                    .sum::<f64>();
            }
        };
        for (index, block) in self.derivative_blocks.chunks_exact(size * size).enumerate() {
            let band = self.normal_band(index);
            times(block, band, band, &mut out);
            if let Some(friction) = &self.friction {
                let tangents = self.tangent_bands(index);
                for (b, &(row, column)) in friction::BLOCKS.iter().enumerate() {
                    if column == friction::Column::Normal {
                        times(
                            friction.block(index, b, size),
                            band,
                            tangents[row],
                            &mut out,
                        );
                    }
                }
            }
        }
        out
    }

    /// The contact blocks of `∂R/∂x` in sector coordinates: the law's `T`
    /// on every normal signal and, with friction, the tangential rows'
    /// blocks.
    pub(super) fn contact_blocks(&self) -> Vec<ContactBlock<'_>> {
        let size = self.layout.coordinates();
        let mut out = Vec::new();
        for (index, block) in self.derivative_blocks.chunks_exact(size * size).enumerate() {
            let band = self.normal_band(index);
            out.push(ContactBlock {
                row: band,
                column: band,
                law: true,
                values: block,
            });
            if let Some(friction) = &self.friction {
                let tangents = self.tangent_bands(index);
                for (b, &(row, column)) in friction::BLOCKS.iter().enumerate() {
                    let (from, law) = match column {
                        friction::Column::Normal => (band, true),
                        friction::Column::Circumferential => (tangents[0], false),
                        friction::Column::Axial => (tangents[1], false),
                    };
                    out.push(ContactBlock {
                        row: tangents[row],
                        column: from,
                        law,
                        values: friction.block(index, b, size),
                    });
                }
            }
        }
        out
    }

    /// Multiply-adds of one assembly of the contact Jacobian
    /// ([`Self::add_contact_jacobian`]) for the law's weight `b` on `Z`: on
    /// a cyclic basis, `readers · H²` a block (`G̃_β t`, `readers` the
    /// unknowns of its row band); on the physical layout, `H² n` a law
    /// block when `b ≠ 0` (`t Z_β'`), `H²` otherwise. For the first
    /// point's time estimate ([`crate::memory::IterationCost`]).
    pub fn jacobian_assembly_products(&self) -> f64 {
        let size = self.layout.coordinates() as f64;
        let b = self.law.input().residual;
        let n = self.layout.unknowns as f64;
        self.contact_blocks()
            .iter()
            .map(|block| match &self.products {
                Some(products) => products.readers(block.row) as f64 * size * size,
                None if block.law && b != 0.0 => size * size * n,
                None => size * size,
            })
            .sum()
    }

    /// `J += G̃ (T_law Ḡ (a I + b Z) + T_displacement Ḡ)`, the contact part
    /// of `∂R/∂x` ([`Self::contact_blocks`]): band by band for the physical
    /// layout, through the maps' nonzeros for a cyclic one.
    /// `false` when the interrupt was raised during the assembly (the
    /// Jacobian is then incomplete).
    pub(super) fn add_contact_jacobian(&mut self, a: f64, b: f64, jacobian: &mut Mat<f64>) -> bool {
        let size = self.layout.coordinates();
        if let Some(mut products) = self.products.take() {
            let complete = products.add_contact_jacobian(
                a,
                b,
                self.linear.dynamic.as_ref(),
                self.contact_blocks(),
                jacobian,
                self.interrupt.as_ref(),
            );
            self.products = Some(products);
            return complete;
        }
        // Physical: Ḡ = G̃ = I, no n × n temporary.
        for block in self.contact_blocks() {
            let (row, column) = (block.row, block.column);
            let t = MatRef::from_row_major_slice(block.values, size, size);
            let weight = if block.law { a } else { 1.0 };
            if block.law && b != 0.0 {
                matmul(
                    jacobian.as_mut().subrows_mut(row, size),
                    Accum::Add,
                    t,
                    self.linear.dynamic.as_ref().subrows(column, size),
                    b,
                    Par::Seq,
                );
            }
            for r in 0..size {
                for c in 0..size {
                    jacobian[(row + r, column + c)] += weight * t[(r, c)];
                }
            }
        }
        true
    }
}
