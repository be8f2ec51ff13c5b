//! `kind = "finite_element"`: a sparse finite-element sector read from
//! Matrix Market files, node coordinates (`node,x,y,z` CSV) and node sets
//! (TOML), reduced by Craig–Bampton per nodal diameter, the reduced models
//! cached next to the case file.
//!
//! Dofs are 3 per node in node order (`x, y, z`). The retained dofs are
//! every dof of the contact nodes, then of the excitation nodes, then of
//! the observation nodes (in the node sets' order; each node listed once,
//! in one of these sets, neither clamped nor on the right boundary): the
//! case's dof numbers (`contact.dofs`, `excitation.dofs`,
//! `output.observed_dof`) count them from 1, followed by the modal
//! coordinates.

use super::sector_files::nodes::{node_dofs, InputText};
use super::sector_files::SectorFiles;
use super::{FrameName, Keys, ModelSpec};
use crate::model::craig_bampton::{
    cache_folder_next_to, craig_bampton_cached, reduced_sector_model, CacheOutcome,
    CraigBamptonSettings, InputDigest, ReducedNodalDiameter, ReductionCache, ReductionError,
    SectorMatrix,
};
use crate::model::{Axis, ModelError, SectorModel, SECTOR_MAX_DOFS};
use faer::{c64, Mat};
use serde::{Deserialize, Serialize};
use std::path::Path;

/// `[model.reduction]`: the Craig–Bampton reduction of a finite-element sector.
#[derive(Deserialize, Serialize, Clone, Debug, PartialEq, Eq)]
#[serde(deny_unknown_fields)]
pub struct ReductionSpec {
    /// Fixed-interface modes kept per nodal diameter (default 20, the paper's).
    #[serde(default = "default_internal_modes")]
    pub internal_modes: usize,
}

fn default_internal_modes() -> usize {
    20
}

impl ReductionSpec {
    /// Whether it holds the defaults (then a case file need not show it).
    pub fn is_default(&self) -> bool {
        *self == Self::default()
    }
}

impl Default for ReductionSpec {
    fn default() -> Self {
        Self {
            internal_modes: default_internal_modes(),
        }
    }
}

impl ModelSpec {
    /// The digest of every input of the sector's reduction (the cache key).
    pub(super) fn reduction_digest(
        &self,
        files: &SectorFiles,
        settings: &CraigBamptonSettings,
    ) -> InputDigest {
        let mut digest = files.digest(b"cyclorub finite_element sector v1");
        digest
            .dofs(&files.clamped)
            .dofs(&files.left)
            .dofs(&files.right);
        digest.settings(self.sectors, files.frame, settings);
        digest.bytes(&files.tolerance.to_le_bytes());
        digest
    }

    /// The finite-element sector of the table, reduced per nodal diameter.
    pub(super) fn finite_element_sector(
        &self,
        case_dir: &Path,
        keys: &Keys,
    ) -> Result<SectorModel, ModelError> {
        let internal_modes = self.reduction.internal_modes;
        if internal_modes > SECTOR_MAX_DOFS {
            return Err(ModelError::invalid(
                "model.reduction.internal_modes",
                format!(
                    "{internal_modes} is too many: the reduced sector is stored dense, at most \
                     {SECTOR_MAX_DOFS} dofs with the retained ones (the paper keeps 20)"
                ),
            ));
        }
        let files = self.read_sector_files(case_dir)?;
        let retained_nodes = files.retained_nodes()?;
        let settings = CraigBamptonSettings {
            retained: node_dofs(&retained_nodes),
            internal_modes,
        };
        let digest = self.reduction_digest(&files, &settings);
        let (mass, stiffness, sets_file) = (&files.mass, &files.stiffness, &files.sets_file);
        let cache = ReductionCache::new(cache_folder_next_to(case_dir));
        let reduced = match cache.load(&digest, self.sectors, &settings) {
            Ok(reduced) => {
                tracing::info!(
                    "Craig–Bampton models read from {}",
                    cache.path(&digest).display()
                );
                reduced
            }
            Err(_) => {
                let sector = files.sparse_sector()?;
                let (reduced, outcome) = craig_bampton_cached(&sector, &settings, &cache, &digest)
                    .map_err(|e| reduction_error(e, mass, stiffness, sets_file))?;
                if let CacheOutcome::Computed {
                    path,
                    store_error: Some(e),
                    ..
                } = &outcome
                {
                    tracing::warn!(
                        "the Craig–Bampton models could not be cached in {}: {e}",
                        path.display()
                    );
                }
                reduced
            }
        };
        self.reduced_model(&files, &retained_nodes, &settings, reduced, case_dir, keys)
    }

    /// The sector model of the reduced matrices `reduced` (diameters
    /// `0..=N/2`) of `files` reduced with `settings` on `retained_nodes`:
    /// the contact nodes turned into their frames, damping, labels, radii
    /// and nodes.
    pub(super) fn reduced_model(
        &self,
        files: &SectorFiles,
        retained_nodes: &[usize],
        settings: &CraigBamptonSettings,
        reduced: Vec<ReducedNodalDiameter>,
        case_dir: &Path,
        keys: &Keys,
    ) -> Result<SectorModel, ModelError> {
        let internal_modes = settings.internal_modes;
        let damping =
            self.damping
                .build(settings.retained.len() + internal_modes, case_dir, keys)?;
        let frames = self.retained_frames(files, retained_nodes)?;
        let reduced: Vec<_> = reduced
            .into_iter()
            .map(|mut r| {
                r.mass = in_frames(&r.mass, &frames);
                r.stiffness = in_frames(&r.stiffness, &frames);
                r
            })
            .collect();
        let labels = settings
            .retained
            .iter()
            .enumerate()
            .map(|(i, &d)| {
                let names = if frames[i / 3].is_some() {
                    ["r", "θ", "z"]
                } else {
                    ["x", "y", "z"]
                };
                format!("node {} {}", d / 3 + 1, names[d % 3])
            })
            .chain((1..=internal_modes).map(|r| format!("mode {r}")))
            .collect();
        let radii = retained_nodes
            .iter()
            .flat_map(|&n| [Some(radius(files.coords[n], files.axis)); 3])
            .chain(std::iter::repeat_n(None, internal_modes))
            .collect();
        let nodes = retained_nodes
            .iter()
            .flat_map(|&n| [Some(n + 1); 3])
            .chain(std::iter::repeat_n(None, internal_modes))
            .collect();
        reduced_sector_model(self.sectors, settings, &reduced, damping)
            .map_err(|e| e.named(|input| keys.of(input)))?
            .with_dof_labels(labels)?
            .with_dof_radii(radii)?
            .with_dof_nodes(nodes)
    }
}

impl ModelSpec {
    /// The frame of each retained node's three dofs in the reduced model:
    /// its cylindrical frame for a contact node with `contact_frame =
    /// "cylindrical"`, `None` (as read, Cartesian) otherwise.
    pub(super) fn retained_frames(
        &self,
        files: &SectorFiles,
        retained_nodes: &[usize],
    ) -> Result<Vec<Option<[[f64; 3]; 3]>>, ModelError> {
        let contact: Vec<usize> = files.nodes("contact", &files.sets.contact)?;
        let cylindrical = matches!(self.contact_frame, Some(FrameName::Cylindrical));
        retained_nodes
            .iter()
            .map(|n| {
                if !(cylindrical && contact.contains(n)) {
                    return Ok(None);
                }
                cylindrical_frame(files.coords[*n], files.axis)
                    .map(Some)
                    .ok_or_else(|| {
                        files.sets_file.error(
                            0,
                            format!(
                                "contact node {} lies on the rotation axis: it has no radial \
                                 direction for contact_frame = \"cylindrical\"",
                                n + 1
                            ),
                        )
                    })
            })
            .collect()
    }
}

/// The values `u` (3 per node, Cartesian, every node of the sector) at the
/// retained nodes' dofs, each node's turned into its frame where it has one.
pub(super) fn retained_in_frames(
    u: &[f64],
    retained_nodes: &[usize],
    frames: &[Option<[[f64; 3]; 3]>],
) -> Vec<f64> {
    retained_nodes
        .iter()
        .zip(frames)
        .flat_map(|(&n, frame)| {
            let v = [u[3 * n], u[3 * n + 1], u[3 * n + 2]];
            match frame {
                Some(r) => r.map(|row| row[0] * v[0] + row[1] * v[1] + row[2] * v[2]),
                None => v,
            }
        })
        .collect()
}

/// The unit vector of a rotation axis.
fn axis_direction(axis: Axis) -> [f64; 3] {
    match axis {
        Axis::X => [1.0, 0.0, 0.0],
        Axis::Y => [0.0, 1.0, 0.0],
        Axis::Z => [0.0, 0.0, 1.0],
    }
}

/// The distance of a point to the rotation axis (through the origin).
fn radius(point: [f64; 3], axis: Axis) -> f64 {
    let a = axis_direction(axis);
    let along = point[0] * a[0] + point[1] * a[1] + point[2] * a[2];
    (0..3)
        .map(|i| (point[i] - along * a[i]).powi(2))
        .sum::<f64>()
        .sqrt()
}

/// The rows `e_r`, `e_θ = a × e_r`, `e_z = a` of a node's cylindrical frame
/// about `axis` (`None` on the axis, where `e_r` is undefined): local
/// coordinates are `R u` for Cartesian `u`, and `e_θ` points in the
/// direction of rotation (counter-clockwise about `axis`).
fn cylindrical_frame(point: [f64; 3], axis: Axis) -> Option<[[f64; 3]; 3]> {
    let a = axis_direction(axis);
    let along = point[0] * a[0] + point[1] * a[1] + point[2] * a[2];
    let radial: Vec<f64> = (0..3).map(|i| point[i] - along * a[i]).collect();
    let length = radial.iter().map(|v| v * v).sum::<f64>().sqrt();
    let scale = point.iter().fold(0.0_f64, |m, v| m.max(v.abs()));
    if length <= 1e-12 * scale.max(f64::MIN_POSITIVE) {
        return None;
    }
    let r = [radial[0] / length, radial[1] / length, radial[2] / length];
    let theta = [
        a[1] * r[2] - a[2] * r[1],
        a[2] * r[0] - a[0] * r[2],
        a[0] * r[1] - a[1] * r[0],
    ];
    Some([r, theta, a])
}

/// `T A Tᵀ` for `T` block diagonal: the rotation `frames[i]` on the three
/// dofs of retained node `i` (the identity where `None` and on the modal
/// coordinates after the retained dofs).
pub(super) fn in_frames(a: &Mat<c64>, frames: &[Option<[[f64; 3]; 3]>]) -> Mat<c64> {
    let n = a.nrows();
    // T is applied on rows, then on columns: (T (T A)ᵀ)ᵀ with T real.
    let rotate_rows = |m: &Mat<c64>| -> Mat<c64> {
        let mut out = m.clone();
        for (node, frame) in frames.iter().enumerate() {
            let Some(r) = frame else { continue };
            for col in 0..n {
                let u = [
                    m[(3 * node, col)],
                    m[(3 * node + 1, col)],
                    m[(3 * node + 2, col)],
                ];
                for (i, row) in r.iter().enumerate() {
                    out[(3 * node + i, col)] = u[0] * row[0] + u[1] * row[1] + u[2] * row[2];
                }
            }
        }
        out
    };
    let half = rotate_rows(a);
    let turned = rotate_rows(&half.transpose().to_owned());
    turned.transpose().to_owned()
}

/// The first line of a Matrix Market text holding the entry `(row, col)`
/// or `(col, row)` (1-based), 0 when none does.
fn entry_line(text: &str, row: usize, col: usize) -> usize {
    text.lines()
        .position(|line| {
            let mut fields = line.split_whitespace().map(|f| f.parse::<usize>().ok());
            match (
                fields.next().flatten(),
                fields.next().flatten(),
                fields.next(),
            ) {
                (Some(i), Some(j), Some(_)) => (i, j) == (row, col) || (i, j) == (col, row),
                _ => false,
            }
        })
        .map_or(0, |i| i + 1)
}

/// A reduction error named by the file it is about (and the line of the
/// entry, for an entry that breaks symmetry or is not finite).
pub(super) fn reduction_error(
    e: ReductionError,
    mass: &InputText,
    stiffness: &InputText,
    sets: &InputText,
) -> ModelError {
    let file = |matrix: &SectorMatrix| match matrix {
        SectorMatrix::Mass => mass,
        SectorMatrix::Stiffness => stiffness,
    };
    let key = match &e {
        ReductionError::NotSymmetric {
            matrix, row, col, ..
        }
        | ReductionError::NotFinite {
            matrix, row, col, ..
        } => {
            let f = file(matrix);
            return f.error(entry_line(&f.text, *row, *col), e.to_string());
        }
        ReductionError::Size { matrix, .. }
        | ReductionError::NotPositiveDefinite { matrix, .. } => file(matrix).key.clone(),
        ReductionError::Invalid { what, .. } if what == "internal modes" => {
            "model.reduction.internal_modes".to_string()
        }
        ReductionError::Invalid { .. } => sets.key.clone(),
        _ => stiffness.key.clone(),
    };
    ModelError::Reduction { key, source: e }
}
