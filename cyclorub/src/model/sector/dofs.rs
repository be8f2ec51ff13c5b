//! What the sector's dofs are, beside its matrices: labels, the radius and
//! node of each dof (the node map of an imported sector), and the mistuning
//! field the wheel carries (issue 44).

use super::super::mistuning::Mistuning;
use super::super::ModelError;
use super::SectorModel;
use std::sync::Arc;

impl SectorModel {
    /// Replaces the dof labels (one per independent dof of a sector).
    pub fn with_dof_labels(mut self, labels: Vec<String>) -> Result<Self, ModelError> {
        if labels.len() != self.dofs_per_sector() {
            return Err(ModelError::invalid(
                "dof labels",
                format!(
                    "{} labels given for {} dofs per sector",
                    labels.len(),
                    self.dofs_per_sector()
                ),
            ));
        }
        self.labels = labels;
        Ok(self)
    }

    /// Sets the radius of each dof's node (`None` where there is no node,
    /// e.g. a modal coordinate), one per independent dof of a sector.
    pub fn with_dof_radii(mut self, radii: Vec<Option<f64>>) -> Result<Self, ModelError> {
        if radii.len() != self.dofs_per_sector() {
            return Err(ModelError::invalid(
                "dof radii",
                format!(
                    "{} radii given for {} dofs per sector",
                    radii.len(),
                    self.dofs_per_sector()
                ),
            ));
        }
        self.radii = radii;
        Ok(self)
    }

    /// Sets the node (1-based) of each dof (`None` where there is none,
    /// e.g. a modal coordinate), one per independent dof of a sector.
    pub fn with_dof_nodes(mut self, nodes: Vec<Option<usize>>) -> Result<Self, ModelError> {
        if nodes.len() != self.dofs_per_sector() {
            return Err(ModelError::invalid(
                "dof nodes",
                format!(
                    "{} nodes given for {} dofs per sector",
                    nodes.len(),
                    self.dofs_per_sector()
                ),
            ));
        }
        self.nodes = nodes;
        Ok(self)
    }

    /// The node (1-based, as in the coordinates file) of sector dof `dof`
    /// (0-based), when the model knows it.
    pub fn dof_node(&self, dof: usize) -> Option<usize> {
        self.nodes.get(dof).copied().flatten()
    }

    /// The distance to the rotation axis of the node of sector dof `dof`
    /// (0-based), m, when the model knows it.
    pub fn dof_radius(&self, dof: usize) -> Option<f64> {
        self.radii.get(dof).copied().flatten()
    }

    /// A readable name of sector dof `dof` (0-based): `m1`… for the academic
    /// model, `dof 17` (1-based original numbering) for imported sectors.
    pub fn dof_label(&self, dof: usize) -> String {
        self.labels
            .get(dof)
            .cloned()
            .unwrap_or_else(|| format!("dof {}", dof + 1))
    }

    /// The dof (0-based) whose label is `label` (e.g. `"m1"`, `"dof 17"`).
    pub fn dof_by_label(&self, label: &str) -> Option<usize> {
        self.labels.iter().position(|l| l == label)
    }

    /// The mistuning (issue 44), if the wheel is mistuned.
    pub fn mistuning(&self) -> Option<&Mistuning> {
        self.mistuning.as_deref()
    }

    /// Sets or drops the mistuning.
    pub(in crate::model) fn set_mistuning(&mut self, mistuning: Option<Arc<Mistuning>>) {
        self.mistuning = mistuning;
    }
}
