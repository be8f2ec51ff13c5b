//! `Debug` and `Clone` of [`HarmonicBalance`].

use super::HarmonicBalance;

impl std::fmt::Debug for HarmonicBalance {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("HarmonicBalance")
            .field("unknowns", &self.layout.unknowns)
            .field("sampled_sectors", &self.layout.sampled_sectors)
            .field("law", &self.law)
            .field("aft", &self.aft)
            .finish()
    }
}

/// A clone keeps everything built (layout, condensed linear part, AFT
/// plans, sector maps, law, casing) and the buffers as they are, so a
/// problem is built once and copied, e.g. for a writer that recovers
/// points while the solve goes on. The clone watches no interrupt (the
/// one raised on the original stops the original's solve only; see
/// `watch_interrupt`).
impl Clone for HarmonicBalance {
    fn clone(&self) -> Self {
        Self {
            layout: self.layout.clone(),
            linear: self.linear.clone(),
            aft: self.aft.clone(),
            law: self.law.clone(),
            casing: self.casing.clone(),
            normal_dofs: self.normal_dofs,
            gap_samples: self.gap_samples.clone(),
            friction: self.friction.clone(),
            sector_coordinates: self.sector_coordinates.clone(),
            sector_displacements: self.sector_displacements.clone(),
            sector_forces: self.sector_forces.clone(),
            reading: self.reading.clone(),
            force: self.force.clone(),
            slope: self.slope.clone(),
            derivative_blocks: self.derivative_blocks.clone(),
            law_variable: self.law_variable.clone(),
            piece: self.piece,
            force_scale: self.force_scale,
            products: self.products.clone(),
            structured: self.structured.clone(),
            interrupt: None,
        }
    }
}
