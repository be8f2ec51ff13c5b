//! The full (unreduced) finite-element sector of a `kind = "finite_element"`
//! table: its lowest frequencies per nodal diameter, the reference of the
//! Craig–Bampton models, read through the same files, parsers and checks
//! as [`ModelSpec::build`] and cached next to the Craig–Bampton models.

use super::finite_element::reduction_error;
use super::sector_files::nodes::node_dofs;
use super::{key, ModelKind, ModelSpec};
use crate::model::craig_bampton::{cache_folder_next_to, full_sector_frequencies, ReductionCache};
use crate::model::ModelError;
use std::path::Path;

impl ModelSpec {
    /// The lowest `count` natural frequencies (Hz, ascending) of the full
    /// finite-element sector (every dof but the clamped ones, sparse, no
    /// reduction) for each unsigned nodal diameter `0..=N/2`, as
    /// `(diameter, frequencies)`: the shape of
    /// [`SectorModel::natural_frequencies`](crate::model::SectorModel::natural_frequencies)
    /// of the Craig–Bampton model built by [`ModelSpec::build`], so that the
    /// two match mode by mode. Only with `kind = "finite_element"`.
    ///
    /// **Cache.** The frequencies are stored in `.cyclorub-cache` next to
    /// the case file (beside the Craig–Bampton models), in
    /// `full-sector-<digest>.bin`, the digest covering what they depend on:
    /// the bytes of the mass and stiffness files, the clamped and boundary
    /// dofs, `sectors`, `boundary_frame`, `axis` and `symmetry_tolerance`,
    /// but not `[model.reduction]` (changing the internal modes keeps the
    /// reference) nor the count: the file records its count and serves any
    /// count up to it; a larger count is computed again and overwrites it.
    /// A file that is corrupt, truncated or of another input is recomputed;
    /// one that cannot be written is logged as a warning, not an error.
    pub fn full_sector_frequencies(
        &self,
        case_dir: &Path,
        count: usize,
    ) -> Result<Vec<(usize, Vec<f64>)>, ModelError> {
        if self.kind != ModelKind::FiniteElement {
            return Err(ModelError::invalid(
                key("kind"),
                format!(
                    "\"{}\": the full sector's frequencies are computed for kind = \
                     \"finite_element\" only (the other kinds are not reduced)",
                    self.kind.name()
                ),
            ));
        }
        if count == 0 {
            return Err(ModelError::invalid(
                "full-sector frequencies",
                "0 asked for: ask for at least one frequency per nodal diameter",
            ));
        }
        self.check_keys()?;
        let files = self.read_sector_files(case_dir)?;
        let mut digest = files.digest(b"cyclorub finite_element full sector v1");
        digest
            .dofs(&node_dofs(&files.clamped))
            .dofs(&node_dofs(&files.left))
            .dofs(&node_dofs(&files.right));
        digest
            .integer(self.sectors as u64)
            .field(format!("{:?}", files.frame).as_bytes())
            .bytes(&files.tolerance.to_le_bytes());
        let cache = ReductionCache::new(cache_folder_next_to(case_dir));
        let reason = match cache.load_full_sector(&digest, self.sectors, count) {
            Ok(frequencies) => {
                tracing::info!(
                    "full-sector frequencies read from {}",
                    cache.full_sector_path(&digest).display()
                );
                return Ok(frequencies);
            }
            Err(reason) => reason,
        };
        tracing::debug!("full-sector frequencies not read from the cache: {reason}");

        let sector = files.sparse_sector()?;
        let frequencies = full_sector_frequencies(&sector, count)
            .map_err(|e| reduction_error(e, &files.mass, &files.stiffness, &files.sets_file))?;
        if let Err(e) = cache.store_full_sector(&digest, &frequencies) {
            tracing::warn!(
                "the full-sector frequencies could not be cached in {}: {e}",
                cache.full_sector_path(&digest).display()
            );
        }
        Ok(frequencies)
    }
}
