//! The unknown layout: where each harmonic coefficient of each contact dof
//! lives in the real unknown vector, and the maps between the unknowns and
//! the sampled sectors' real harmonic coordinates (AFT-CP steps 1 and 5).
//!
//! Sector coordinates: for sampled sector `j`, contact dof `c`, the real
//! harmonic coordinates of `aft` (length `H = 2 N_h + 1`) at offset
//! `(j · n_c + c) · H`.
//!
//! Cyclic unknowns, in order: harmonic `k`, signed diameter `s ∈ S_k` (on
//! `k = 0` only `s ≥ 0`: `c_{−s} = conj(c_s)`), contact dof, then
//! `(Re, Im)` — one real only for `k = 0` and `s ∈ {0, N/2}`. Physical
//! unknowns are the sector coordinates themselves.

use crate::basis::{sector_map_inverse, BasisError, SpectralBasis};
use crate::cyclic::HarmonicSet;
use faer::Mat;
use std::f64::consts::PI;

/// Position of one complex (or real) coefficient in the unknown vector.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Slot {
    /// Index of the real part.
    pub re: usize,
    /// Index of the imaginary part; `None` for a real coefficient.
    pub im: Option<usize>,
}

/// What a block of unknowns describes: one signed pair of a cyclic basis,
/// or one harmonic of the whole wheel in physical coordinates.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum BlockKind {
    /// The wave `(s, k)`; on `k = 0` with `0 < s < N/2` it stands for the
    /// conjugate pair `±s` (its sector values count twice, as `2 Re`).
    Pair {
        /// Signed nodal diameter `s`.
        nodal_diameter: i64,
    },
    /// All sectors' dofs at once (the full reference).
    Wheel,
}

impl std::fmt::Display for BlockKind {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            Self::Pair { nodal_diameter } => write!(f, "nodal diameter {nodal_diameter}"),
            Self::Wheel => write!(f, "the whole wheel"),
        }
    }
}

/// A frequency in Hz for a message: six decimals in the range a wheel
/// vibrates in, scientific notation beyond (not 300 digits).
pub fn hertz(frequency_hz: f64) -> String {
    if frequency_hz.abs() < 1e7 {
        format!("{frequency_hz:.6}")
    } else {
        format!("{frequency_hz:.6e}")
    }
}

/// One block of unknowns: a harmonic, what it describes, and the slots of
/// its contact entries (cyclic: one per contact dof; physical: one per
/// sector and contact dof, sector-major).
#[derive(Clone, Debug)]
pub struct Block {
    /// Temporal harmonic `k`.
    pub harmonic: usize,
    /// A signed pair `(s, k)` of a cyclic basis, or harmonic `k` of the
    /// whole wheel in physical coordinates.
    pub kind: BlockKind,
    /// Where each contact entry's real and imaginary parts sit among the
    /// unknowns.
    pub slots: Vec<Slot>,
}

/// The maps between unknowns and sector coordinates.
#[derive(Clone, Debug)]
pub enum SectorMaps {
    /// Physical coordinates: the unknowns are the sector coordinates.
    Identity,
    /// Cyclic coordinates: `to_sectors` (`Ḡ`, all sampled sectors) and
    /// `from_sectors` (`G̃`, harmonic `k` read on its first `|S_k|` sectors);
    /// `from_sectors · to_sectors = I`.
    Dense {
        /// Unknowns → sector coordinates.
        to_sectors: Mat<f64>,
        /// Sector coordinates → unknowns.
        from_sectors: Mat<f64>,
    },
}

/// The layout of a harmonic balance problem.
#[derive(Clone, Debug)]
pub struct Layout {
    /// Number of sectors `N`.
    pub sectors: usize,
    /// The harmonics the blocks are on (`0..=N_h`), in their order.
    pub harmonic_set: HarmonicSet,
    /// Contact dofs per sector.
    pub contact_dofs: usize,
    /// Sectors sampled by the AFT (cyclic) or all sectors (physical).
    pub sampled_sectors: usize,
    /// Real unknowns solved for (the size of the Jacobian).
    pub unknowns: usize,
    /// The blocks, by harmonic.
    pub blocks: Vec<Block>,
    /// Unknowns ↔ sector coordinates.
    pub maps: SectorMaps,
}

impl Layout {
    /// The unknowns `x` of this layout written in the layout `finer` of the
    /// same wheel and basis with more harmonics: each block's entries
    /// copied to the block of the same harmonic and kind, the harmonics
    /// only `finer` has set to 0 (the truncated solution, as the start of
    /// a refined one). `None` when `finer` lacks one of this layout's
    /// blocks or entries.
    pub fn embed(&self, x: &[f64], finer: &Layout) -> Option<Vec<f64>> {
        if x.len() != self.unknowns || finer.sectors != self.sectors {
            return None;
        }
        let mut out = vec![0.0; finer.unknowns];
        for block in &self.blocks {
            let target = finer
                .blocks
                .iter()
                .find(|b| b.harmonic == block.harmonic && b.kind == block.kind)?;
            if target.slots.len() != block.slots.len() {
                return None;
            }
            for (from, to) in block.slots.iter().zip(&target.slots) {
                out[to.re] = x[from.re];
                match (from.im, to.im) {
                    (Some(a), Some(b)) => out[b] = x[a],
                    (None, None) => {}
                    _ => return None,
                }
            }
        }
        Some(out)
    }

    /// The highest harmonic `N_h`.
    pub fn harmonics(&self) -> usize {
        self.harmonic_set.highest()
    }

    /// Length of one sector coordinate vector, `2 N_h + 1`.
    pub fn coordinates(&self) -> usize {
        self.harmonic_set.coordinates()
    }

    /// Length of all sampled sectors' coordinates.
    pub fn sector_coordinates(&self) -> usize {
        self.sampled_sectors * self.contact_dofs * self.coordinates()
    }

    /// The layout of a cyclic basis with `contact_dofs` contact dofs per sector.
    pub fn cyclic(basis: &SpectralBasis, contact_dofs: usize) -> Result<Self, BasisError> {
        let n = basis.sectors();
        let harmonic_set = basis.harmonic_set();
        let mut blocks = Vec::new();
        let mut next = 0;
        for k in harmonic_set {
            for &s in basis.nodal_diameters(k) {
                if k == 0 && s < 0 {
                    continue;
                }
                let real = k == 0 && is_real_diameter(s, n);
                let slots = (0..contact_dofs)
                    .map(|_| {
                        let slot = Slot {
                            re: next,
                            im: (!real).then_some(next + 1),
                        };
                        next += if real { 1 } else { 2 };
                        slot
                    })
                    .collect();
                blocks.push(Block {
                    harmonic: k,
                    kind: BlockKind::Pair { nodal_diameter: s },
                    slots,
                });
            }
        }
        let mut layout = Self {
            sectors: n,
            harmonic_set,
            contact_dofs,
            sampled_sectors: basis.sampled_sectors(),
            unknowns: next,
            blocks,
            maps: SectorMaps::Identity,
        };
        layout.maps = layout.cyclic_maps(basis)?;
        Ok(layout)
    }

    /// The layout of the whole wheel in physical coordinates.
    pub fn physical(sectors: usize, harmonics: usize, contact_dofs: usize) -> Self {
        let harmonic_set = HarmonicSet::up_to(harmonics);
        let size = harmonic_set.coordinates();
        let blocks = harmonic_set
            .iter()
            .map(|k| Block {
                harmonic: k,
                kind: BlockKind::Wheel,
                slots: (0..sectors * contact_dofs)
                    .map(|entry| {
                        // The entry's coordinates of harmonic k: a0, or (Re, Im).
                        let range = HarmonicSet::coordinate_range(k);
                        let re = entry * size + range.start;
                        Slot {
                            re,
                            im: (range.len() == 2).then_some(re + 1),
                        }
                    })
                    .collect(),
            })
            .collect();
        Self {
            sectors,
            harmonic_set,
            contact_dofs,
            sampled_sectors: sectors,
            unknowns: sectors * contact_dofs * size,
            blocks,
            maps: SectorMaps::Identity,
        }
    }

    fn cyclic_maps(&self, basis: &SpectralBasis) -> Result<SectorMaps, BasisError> {
        let n = self.sectors;
        let size = self.coordinates();
        let rows = self.sector_coordinates();
        let mut to_sectors = Mat::<f64>::zeros(rows, self.unknowns);
        let mut from_sectors = Mat::<f64>::zeros(self.unknowns, rows);
        let alpha = 2.0 * PI / n as f64;
        for k in self.harmonic_set {
            let diameters = basis.nodal_diameters(k);
            if diameters.is_empty() {
                continue;
            }
            let inverse = sector_map_inverse(n, diameters)?;
            for block in self.blocks.iter().filter(|b| b.harmonic == k) {
                let BlockKind::Pair { nodal_diameter: s } = block.kind else {
                    continue;
                };
                let weight = if k == 0 && !is_real_diameter(s, n) {
                    2.0
                } else {
                    1.0
                };
                let p = diameters.iter().position(|&d| d == s).unwrap_or(0);
                for (c, slot) in block.slots.iter().enumerate() {
                    for j in 0..self.sampled_sectors {
                        let (sin, cos) = (-(s as f64) * alpha * j as f64).sin_cos();
                        let row = (j * self.contact_dofs + c) * size;
                        // X_{j,k} += c_s e^{−i s α j}.
                        if k == 0 {
                            to_sectors[(row, slot.re)] += weight * cos;
                            if let Some(im) = slot.im {
                                to_sectors[(row, im)] -= weight * sin;
                            }
                        } else {
                            let re_row = row + HarmonicSet::coordinate_range(k).start;
                            let im_row = re_row + 1;
                            to_sectors[(re_row, slot.re)] += cos;
                            to_sectors[(im_row, slot.re)] += sin;
                            if let Some(im) = slot.im {
                                to_sectors[(re_row, im)] -= sin;
                                to_sectors[(im_row, im)] += cos;
                            }
                        }
                        // c_s = Σ_{j < |S_k|} (V_k⁻¹)_{s j} X_{j,k}.
                        if j >= diameters.len() {
                            continue;
                        }
                        let v = inverse[(p, j)];
                        if k == 0 {
                            from_sectors[(slot.re, row)] += v.re;
                            if let Some(im) = slot.im {
                                from_sectors[(im, row)] += v.im;
                            }
                        } else {
                            let re_col = row + HarmonicSet::coordinate_range(k).start;
                            let im_col = re_col + 1;
                            from_sectors[(slot.re, re_col)] += v.re;
                            from_sectors[(slot.re, im_col)] -= v.im;
                            if let Some(im) = slot.im {
                                from_sectors[(im, re_col)] += v.im;
                                from_sectors[(im, im_col)] += v.re;
                            }
                        }
                    }
                }
            }
        }
        Ok(SectorMaps::Dense {
            to_sectors,
            from_sectors,
        })
    }
}

impl Layout {
    /// Squared weights of the unknowns in the arc-length norm: the mean
    /// square over all `N` sectors of the sector coordinates (Parseval), so
    /// that cyclic and physical layouts measure the same step.
    pub fn norm_weights(&self) -> Vec<f64> {
        let mut weights = vec![1.0; self.unknowns];
        for block in &self.blocks {
            let weight = match block.kind {
                BlockKind::Wheel => 1.0 / self.sectors as f64,
                BlockKind::Pair { nodal_diameter } => {
                    if block.harmonic == 0 && !is_real_diameter(nodal_diameter, self.sectors) {
                        2.0
                    } else {
                        1.0
                    }
                }
            };
            for slot in &block.slots {
                weights[slot.re] = weight;
                if let Some(im) = slot.im {
                    weights[im] = weight;
                }
            }
        }
        weights
    }
}

/// `s = 0`, or `s = N/2` for even `N`: a standing pattern with real sector values.
pub fn is_real_diameter(nodal_diameter: i64, sectors: usize) -> bool {
    nodal_diameter == 0 || (sectors.is_multiple_of(2) && 2 * nodal_diameter == sectors as i64)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::cyclic::LoadCase;

    /// The layout's blocks are on the harmonics of its set, in the set's
    /// order, each contact entry holding the set's real parts of its
    /// harmonic (one for a real static pattern).
    fn check_blocks_against_the_set(layout: &Layout) {
        let set = layout.harmonic_set;
        let positions: Vec<usize> = layout
            .blocks
            .iter()
            .map(|b| {
                set.position(b.harmonic)
                    .expect("a block on a harmonic of the set")
            })
            .collect();
        assert!(positions.windows(2).all(|w| w[0] <= w[1]), "set order");
        let mut unknowns = 0;
        for block in &layout.blocks {
            for slot in &block.slots {
                let parts = 1 + usize::from(slot.im.is_some());
                let expected = match block.kind {
                    // A static ±s pair holds one complex amplitude.
                    BlockKind::Pair { nodal_diameter }
                        if !is_real_diameter(nodal_diameter, layout.sectors) =>
                    {
                        2
                    }
                    _ => HarmonicSet::real_parts(block.harmonic),
                };
                assert_eq!(parts, expected);
                unknowns += parts;
            }
        }
        assert_eq!(unknowns, layout.unknowns);
        assert_eq!(layout.coordinates(), set.coordinates());
        assert_eq!(layout.harmonics(), set.highest());
    }

    #[test]
    fn a_block_and_a_frequency_read_as_words_in_messages() {
        assert_eq!(
            BlockKind::Pair { nodal_diameter: -1 }.to_string(),
            "nodal diameter -1"
        );
        assert_eq!(BlockKind::Wheel.to_string(), "the whole wheel");
        assert_eq!(hertz(198.246348), "198.246348");
        assert_eq!(hertz(1e300), "1.000000e300");
    }

    #[test]
    fn cyclic_layouts_follow_their_harmonic_set() {
        // N = 24, traveling h = 6 with a casing h_c = 8 (docs/design.md §3):
        // harmonics without pairs stay in the set.
        let load = LoadCase {
            sectors: 24,
            excitation: Some(crate::cyclic::ExcitationPattern::Traveling { engine_order: 6 }),
            casing_order: Some(8),
        };
        for harmonics in [1, 4, 10] {
            let basis = SpectralBasis::symmetry(&load, harmonics).unwrap();
            let layout = Layout::cyclic(&basis, 2).unwrap();
            assert_eq!(layout.harmonic_set, HarmonicSet::up_to(harmonics));
            check_blocks_against_the_set(&layout);
            let full = Layout::cyclic(&SpectralBasis::full(6, harmonics).unwrap(), 1).unwrap();
            check_blocks_against_the_set(&full);
            // The full basis holds every pair of every harmonic of the set.
            for k in full.harmonic_set {
                let pairs = full.blocks.iter().filter(|b| b.harmonic == k).count();
                assert_eq!(pairs, if k == 0 { 4 } else { 6 });
            }
        }
    }

    #[test]
    fn physical_layouts_are_the_sets_coordinates_entry_by_entry() {
        let layout = Layout::physical(3, 4, 2);
        check_blocks_against_the_set(&layout);
        let set = layout.harmonic_set;
        assert_eq!(layout.blocks.len(), set.count());
        for (block, k) in layout.blocks.iter().zip(set) {
            assert_eq!(block.harmonic, k);
            for (entry, slot) in block.slots.iter().enumerate() {
                let range = HarmonicSet::coordinate_range(k);
                assert_eq!(slot.re, entry * set.coordinates() + range.start);
                assert_eq!(slot.im, (range.len() == 2).then_some(slot.re + 1));
            }
        }
    }
}
