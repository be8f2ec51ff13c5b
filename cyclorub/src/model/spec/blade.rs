//! The blade of a `kind = "finite_element"` sector, for mistuning (issue
//! 44, docs/mistuning.md): a node set of the node sets file, the sector's
//! stiffness entries between two of its nodes, and the rows of each nodal
//! diameter's Craig–Bampton basis at its dofs, so that the blade stiffness
//! of sector `j` can be scaled by `1 + δ_j` in the reduced full wheel.

use super::finite_element::reduction_error;
use super::sector_files::nodes::node_dofs;
use super::sector_files::SectorFiles;
use super::{ModelKind, ModelSpec};
use crate::model::craig_bampton::{
    cache_folder_next_to, craig_bampton_with_rows, CraigBamptonSettings, ReducedWithRows,
    ReductionCache,
};
use crate::model::{ModelError, ReducedBlade, SectorModel};
use std::path::Path;

impl ModelSpec {
    /// The reduced finite-element sector (as [`ModelSpec::build`] gives it)
    /// and its blade, the node set `set` of the node sets file; `set_key`
    /// names the key that chose the set in messages. The reduction and the
    /// blade's bases are cached together (one computation for both).
    pub fn build_with_blade(
        &self,
        case_dir: &Path,
        set: &str,
        set_key: &str,
    ) -> Result<(SectorModel, ReducedBlade), ModelError> {
        if self.kind != ModelKind::FiniteElement {
            return Err(ModelError::invalid(
                set_key,
                format!(
                    "a blade node set (\"{set}\") is read with model.kind = \
                     \"finite_element\" only (this model is \"{}\")",
                    self.kind.name()
                ),
            ));
        }
        let files = self.read_sector_files(case_dir)?;
        let sets = &files.sets;
        let model_sets = [
            ("clamped", &sets.clamped),
            ("left_boundary", &sets.left_boundary),
            ("right_boundary", &sets.right_boundary),
            ("contact", &sets.contact),
            ("excitation", &sets.excitation),
            ("observation", &sets.observation),
        ];
        let named = model_sets
            .iter()
            .find(|(name, _)| *name == set)
            .map(|(_, list)| *list)
            .or_else(|| sets.others.get(set));
        let Some(list) = named else {
            let others: Vec<&str> = sets.others.keys().map(String::as_str).collect();
            return Err(ModelError::invalid(
                set_key,
                format!(
                    "the node sets file {} has no list named \"{set}\" ({}); give the \
                     blade's nodes as a list there (not its root section, shared with the \
                     disk), e.g. `blade = [...]` as `cyclorub mesh fan` writes it, or name \
                     another list",
                    files.sets_file.path.display(),
                    if others.is_empty() {
                        "it has none besides the model's sets: clamped, left_boundary, \
                         right_boundary, contact, excitation, observation"
                            .to_string()
                    } else {
                        format!("besides the model's sets it has: {}", others.join(", "))
                    },
                ),
            ));
        };
        let nodes = files.nodes(set, list)?;
        if nodes.is_empty() {
            return Err(ModelError::invalid(
                set_key,
                format!("the node set \"{set}\" is empty; name the blade's nodes"),
            ));
        }
        let blade_dofs = node_dofs(&nodes);
        let retained_nodes = files.retained_nodes()?;
        let settings = CraigBamptonSettings {
            retained: node_dofs(&retained_nodes),
            internal_modes: self.reduction.internal_modes,
        };
        let sector = files.sparse_sector()?;
        let (reduced, bases): (Vec<_>, Vec<_>) = self
            .reduction_with_rows(&files, &settings, &blade_dofs, case_dir, || {
                let what = format!("{set_key} = \"{set}\": blade dofs");
                craig_bampton_with_rows(&sector, &settings, &blade_dofs, &what).map_err(|e| {
                    reduction_error(e, &files.mass, &files.stiffness, &files.sets_file)
                })
            })?
            .into_iter()
            .unzip();
        let keys = self.keys();
        let model =
            self.reduced_model(&files, &retained_nodes, &settings, reduced, case_dir, &keys)?;
        model
            .check_stiffness_at_rest()
            .map_err(|e| e.named(|input| keys.of(input)))?;
        // The reduced coordinates of the retained nodes are turned into
        // their frames, q' = T q: u = V q = V Tᵀ q'.
        let frames = self.retained_frames(&files, &retained_nodes)?;
        let bases = bases
            .into_iter()
            .map(|mut v| {
                for (node, frame) in frames.iter().enumerate() {
                    let Some(r) = frame else { continue };
                    for row in 0..v.nrows() {
                        let old = [
                            v[(row, 3 * node)],
                            v[(row, 3 * node + 1)],
                            v[(row, 3 * node + 2)],
                        ];
                        for (a, ra) in r.iter().enumerate() {
                            v[(row, 3 * node + a)] =
                                old[0] * ra[0] + old[1] * ra[1] + old[2] * ra[2];
                        }
                    }
                }
                v
            })
            .collect();
        let mut local = vec![None; sector.size()];
        for (i, &d) in blade_dofs.iter().enumerate() {
            local[d] = Some(i);
        }
        let k = &sector.stiffness;
        let (col_ptr, rows, values) = (k.symbolic().col_ptr(), k.symbolic().row_idx(), k.val());
        let mut entries = Vec::new();
        for col in 0..k.ncols() {
            let Some(b) = local[col] else { continue };
            for p in col_ptr[col]..col_ptr[col + 1] {
                if let Some(a) = local[rows[p]] {
                    if values[p] != 0.0 {
                        entries.push((a, b, values[p]));
                    }
                }
            }
        }
        Ok((
            model,
            ReducedBlade {
                bases,
                stiffness: entries,
            },
        ))
    }

    /// The sector's reduction with its basis rows at `rows`, read from the
    /// cache next to the case when a sound file holds them (a study's
    /// patterns share one), else `compute`d and stored.
    fn reduction_with_rows(
        &self,
        files: &SectorFiles,
        settings: &CraigBamptonSettings,
        rows: &[usize],
        case_dir: &Path,
        compute: impl FnOnce() -> Result<ReducedWithRows, ModelError>,
    ) -> Result<ReducedWithRows, ModelError> {
        let mut digest = self.reduction_digest(files, settings);
        digest.field(b"basis rows").dofs(rows);
        let cache = ReductionCache::new(cache_folder_next_to(case_dir));
        let path = cache.rows_path(&digest);
        match cache.load_with_rows(&digest, self.sectors, settings, rows.len()) {
            Ok(reduced) => {
                tracing::info!(
                    "Craig–Bampton models and blade rows read from {}",
                    path.display()
                );
                Ok(reduced)
            }
            Err(reason) => {
                tracing::debug!("the blade rows are computed: {reason}");
                let reduced = compute()?;
                if let Err(e) = cache.store_with_rows(&digest, &reduced) {
                    tracing::warn!(
                        "the Craig–Bampton models and blade rows could not be cached in {}: {e}",
                        path.display()
                    );
                }
                Ok(reduced)
            }
        }
    }
}
