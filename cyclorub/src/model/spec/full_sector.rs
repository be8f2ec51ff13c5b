//! The full (unreduced) finite-element sector of a `kind = "finite_element"`
//! table: its lowest frequencies per nodal diameter, the reference of the
//! Craig–Bampton models, read through the same files, parsers and checks
//! as [`ModelSpec::build`] and cached next to the Craig–Bampton models.

use super::finite_element::{
    node_dofs, nodes_of, pair_boundaries, read_nodes, reduction_error, InputText, NodeSets,
};
use super::{key, AxisName, FrameName, ModelKind, ModelSpec};
use crate::model::craig_bampton::{
    cache_folder_next_to, full_sector_frequencies, InputDigest, ReductionCache, SparseSector,
};
use crate::model::matrix_market::parse_matrix_market_sparse;
use crate::model::{Axis, BoundaryFrame, ModelError};
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
        if self.sectors == 0 {
            return Err(ModelError::invalid(
                key("sectors"),
                "0 is not allowed: the number of sectors N must be at least 1",
            ));
        }
        self.check_keys()?;
        if let Some(d) = self.dofs_per_node {
            if d != 3 {
                return Err(ModelError::invalid(
                    key("dofs_per_node"),
                    format!("{d} is not supported: solid elements have 3 dofs per node (x, y, z)"),
                ));
            }
        }
        let axis = match self.axis {
            Some(AxisName::X) => Axis::X,
            Some(AxisName::Y) => Axis::Y,
            Some(AxisName::Z) | None => Axis::Z,
        };
        let frame = match self.boundary_frame {
            Some(FrameName::Cartesian) => BoundaryFrame::Cartesian { axis },
            _ => BoundaryFrame::Cylindrical,
        };
        let tolerance = self.symmetry_tolerance()?;
        for (name, value) in [
            ("coordinates_file", &self.coordinates_file),
            ("node_sets_file", &self.node_sets_file),
            ("mass_file", &self.mass_file),
            ("stiffness_file", &self.stiffness_file),
        ] {
            if value.is_none() {
                return Err(ModelError::invalid(
                    key(name),
                    "required with kind = \"finite_element\"",
                ));
            }
        }
        let nodes_file = InputText::read("coordinates_file", &self.coordinates_file, case_dir)?;
        let sets_file = InputText::read("node_sets_file", &self.node_sets_file, case_dir)?;
        let mass = InputText::read("mass_file", &self.mass_file, case_dir)?;
        let stiffness = InputText::read("stiffness_file", &self.stiffness_file, case_dir)?;
        let coords = read_nodes(&nodes_file)?;
        let sets = parse_node_sets(&sets_file)?;
        let nodes = coords.len();
        let list = |name: &str, l: &[usize]| nodes_of(&sets_file, name, l, nodes);
        let clamped = node_dofs(&list("clamped", &sets.clamped)?);
        let left = list("left_boundary", &sets.left_boundary)?;
        let right = list("right_boundary", &sets.right_boundary)?;
        let rotation = axis.rotation(2.0 * std::f64::consts::PI / self.sectors as f64);
        let right = node_dofs(&pair_boundaries(
            &sets_file, &coords, &left, &right, rotation,
        )?);
        let left = node_dofs(&left);

        let mut digest = InputDigest::new();
        digest.field(b"cyclorub finite_element full sector v1");
        for f in [&mass, &stiffness] {
            digest.field(f.text.as_bytes());
        }
        digest.dofs(&clamped).dofs(&left).dofs(&right);
        digest
            .integer(self.sectors as u64)
            .field(format!("{frame:?}").as_bytes())
            .bytes(&tolerance.to_le_bytes());
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

        let m = parse_matrix_market_sparse(&mass.text, &mass.path)?;
        let k = parse_matrix_market_sparse(&stiffness.text, &stiffness.path)?;
        for (f, a) in [(&mass, &m), (&stiffness, &k)] {
            if a.nrows() != 3 * nodes || a.ncols() != 3 * nodes {
                return Err(f.error(
                    0,
                    format!(
                        "{}×{} matrix, but the coordinates file has {nodes} nodes: 3 dofs per \
                         node make {}",
                        a.nrows(),
                        a.ncols(),
                        3 * nodes
                    ),
                ));
            }
        }
        let sector = SparseSector {
            mass: m,
            stiffness: k,
            clamped,
            left_boundary: left,
            right_boundary: right,
            boundary_frame: frame,
            sectors: self.sectors,
            symmetry_tolerance: tolerance,
        };
        let frequencies = full_sector_frequencies(&sector, count)
            .map_err(|e| reduction_error(e, &mass, &stiffness, &sets_file))?;
        if let Err(e) = cache.store_full_sector(&digest, &frequencies) {
            tracing::warn!(
                "the full-sector frequencies could not be cached in {}: {e}",
                cache.full_sector_path(&digest).display()
            );
        }
        Ok(frequencies)
    }
}

/// The node sets file, a TOML error shown at its line (as the
/// Craig–Bampton loader shows it).
fn parse_node_sets(file: &InputText) -> Result<NodeSets, ModelError> {
    toml::from_str(&file.text).map_err(|e| {
        let line = e
            .span()
            .map_or(0, |s| file.text[..s.start].lines().count().max(1));
        file.error(line, e.message().to_string())
    })
}
