//! The centrifugal preload of a `kind = "finite_element"` sector, on the
//! reduced model's dofs.

use super::finite_element::{reduction_error, retained_in_frames};
use super::sector_files::nodes::node_dofs;
use super::sector_files::SectorFiles;
use super::{key, FrameName, ModelKind, ModelSpec};
use crate::model::craig_bampton::{cache_folder_next_to, ReductionCache};
use crate::model::{ModelError, SectorModel};
use std::path::Path;

/// A static load on every sector alike (nodal diameter 0, harmonic 0) and
/// the sector's static response to it, on a model's dofs.
#[derive(Clone, Debug, PartialEq)]
pub struct StaticPreload {
    /// The force per model dof (N) whose static response on the model is
    /// [`Self::displacements`].
    pub forces: Vec<f64>,
    /// The static displacement per model dof (m).
    pub displacements: Vec<f64>,
}

impl ModelSpec {
    /// The centrifugal preload at `speed` (Ω, rad/s) of the finite-element
    /// sector this table builds into `model`: the body force `Ω² M r⊥` on
    /// the full sector (consistent mass, node coordinates, the table's
    /// axis), its static response on nodal diameter 0 solved on the full
    /// sparse sector, and that response read at the retained dofs (in their
    /// frames: radial, circumferential, axial with `contact_frame =
    /// "cylindrical"`).
    ///
    /// On the Craig–Bampton model the retained block of `K(0)` is the full
    /// sector's static condensation, so the force `K(0) [u_B; 0]` makes the
    /// model's static response exactly the full sector's at every retained
    /// dof. The modal coordinates carry none of it (their static part,
    /// which only moves interior nodes, is left out). Linear: the
    /// stiffening or softening by rotation is not modelled.
    pub fn centrifugal_preload(
        &self,
        case_dir: &Path,
        model: &SectorModel,
        speed: f64,
    ) -> Result<StaticPreload, ModelError> {
        if self.kind != ModelKind::FiniteElement {
            return Err(ModelError::invalid(
                "preload.centrifugal",
                format!(
                    "true with model.kind = \"{}\": the centrifugal force needs the mass matrix \
                     and node coordinates of kind = \"finite_element\"; give the static force \
                     per dof in preload.static_forces instead",
                    self.kind.name()
                ),
            ));
        }
        if !(speed.is_finite() && speed >= 0.0) {
            return Err(ModelError::invalid(
                "preload.speed",
                format!("{speed}: the rotation speed must be a finite number ≥ 0 (rad/s)"),
            ));
        }
        if self.boundary_frame != Some(FrameName::Cartesian) {
            return Err(ModelError::invalid(
                "preload.centrifugal",
                "true with the boundary dofs turning with the sector (model.boundary_frame \
                 absent or \"cylindrical\"): the centrifugal force is computed from the \
                 coordinates in the sector's Cartesian frame, which needs boundary_frame = \
                 \"cartesian\"; otherwise give the force per dof in preload.static_forces",
            ));
        }
        let files = self.read_sector_files(case_dir)?;
        let retained = files.retained_nodes()?;
        let frames = self.retained_frames(&files, &retained)?;
        let per_unit_speed = self.centrifugal_displacement_at_unit_speed(case_dir, &files)?;
        let full: Vec<f64> = per_unit_speed.iter().map(|u| speed * speed * u).collect();
        let mut displacements = retained_in_frames(&full, &retained, &frames);
        let dofs = model.dofs_per_sector();
        if displacements.len() > dofs {
            return Err(ModelError::invalid(
                key("kind"),
                format!(
                    "the model has {dofs} dofs per sector, fewer than the {} retained dofs of \
                     the node sets: build it from this table",
                    displacements.len()
                ),
            ));
        }
        displacements.resize(dofs, 0.0);
        let stiffness = model.nodal_diameter_matrices(0)?.stiffness;
        let forces = (0..dofs)
            .map(|r| {
                (0..dofs)
                    .map(|c| stiffness[(r, c)].re * displacements[c])
                    .sum()
            })
            .collect();
        Ok(StaticPreload {
            forces,
            displacements,
        })
    }

    /// The full sector's static displacement under its centrifugal load at
    /// 1 rad/s (every dof; linear in `Ω²`), read from the cache next to the
    /// case when it holds it, else computed (sparse Cholesky of `K(0)`)
    /// and stored. The digest covers the matrices, the coordinates, the
    /// axis, the node sets that hold and pair the sector, and the sector
    /// count.
    fn centrifugal_displacement_at_unit_speed(
        &self,
        case_dir: &Path,
        files: &SectorFiles,
    ) -> Result<Vec<f64>, ModelError> {
        let mut digest = files.digest(b"cyclorub finite_element centrifugal displacement v1");
        digest
            .dofs(&node_dofs(&files.clamped))
            .dofs(&node_dofs(&files.left))
            .dofs(&node_dofs(&files.right))
            .integer(self.sectors as u64)
            .field(format!("{:?} {:?}", files.frame, files.axis).as_bytes())
            .bytes(&files.tolerance.to_le_bytes());
        for point in &files.coords {
            for c in point {
                digest.bytes(&c.to_le_bytes());
            }
        }
        let cache = ReductionCache::new(cache_folder_next_to(case_dir));
        let dofs = 3 * files.coords.len();
        match cache.load_centrifugal(&digest, dofs) {
            Ok(values) => {
                tracing::info!(
                    "centrifugal displacement read from {}",
                    cache.centrifugal_path(&digest).display()
                );
                return Ok(values);
            }
            Err(reason) => {
                tracing::debug!("centrifugal displacement not read from the cache: {reason}");
            }
        }
        let error = |e| reduction_error(e, &files.mass, &files.stiffness, &files.sets_file);
        let sector = files.sparse_sector()?;
        let force = sector
            .centrifugal_force(&files.coords, files.axis, 1.0)
            .map_err(error)?;
        let values = sector.static_displacement(&force).map_err(error)?;
        if let Err(e) = cache.store_centrifugal(&digest, &values) {
            tracing::warn!(
                "the centrifugal displacement could not be cached in {}: {e}",
                cache.centrifugal_path(&digest).display()
            );
        }
        Ok(values)
    }
}
