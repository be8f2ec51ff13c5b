//! The files of a `kind = "finite_element"` table read once, in one order,
//! with one set of checks: the Craig–Bampton model, the full sector's
//! frequencies and the static preload all start here.

pub(super) mod nodes;

use super::{key, AxisName, FrameName, ModelSpec};
use crate::model::craig_bampton::{InputDigest, SparseSector};
use crate::model::matrix_market::parse_matrix_market_sparse;
use crate::model::{Axis, BoundaryFrame, ModelError};
use nodes::{item_line, node_dofs, nodes_of, pair_boundaries, read_nodes, InputText, NodeSets};
use std::path::Path;

/// A finite-element sector's inputs, read and checked, matrices not yet
/// parsed (a cached reduction does not need them).
pub(super) struct SectorFiles {
    pub(super) sets_file: InputText,
    pub(super) mass: InputText,
    pub(super) stiffness: InputText,
    /// Node coordinates, m (node `n` at index `n − 1`).
    pub(super) coords: Vec<[f64; 3]>,
    pub(super) sets: NodeSets,
    pub(super) axis: Axis,
    pub(super) frame: BoundaryFrame,
    pub(super) tolerance: f64,
    /// Clamped nodes, 0-based.
    pub(super) clamped: Vec<usize>,
    /// Left boundary nodes, 0-based.
    pub(super) left: Vec<usize>,
    /// The right twin of each left node, 0-based.
    pub(super) right: Vec<usize>,
    sectors: usize,
}

impl ModelSpec {
    /// Reads and checks the files of a `kind = "finite_element"` table:
    /// `dofs_per_node`, the axis and boundary frame, the symmetry
    /// tolerance, every file named before any is read, the node sets and
    /// the pairing of the boundary faces.
    pub(super) fn read_sector_files(&self, case_dir: &Path) -> Result<SectorFiles, ModelError> {
        if let Some(d) = self.dofs_per_node {
            if d != 3 {
                return Err(ModelError::invalid(
                    key("dofs_per_node"),
                    format!("{d} is not supported: solid elements have 3 dofs per node (x, y, z)"),
                ));
            }
        }
        if self.sectors == 0 {
            return Err(ModelError::invalid(
                key("sectors"),
                "0 is not allowed: the number of sectors N must be at least 1",
            ));
        }
        // As for the other kinds, boundary dofs turn with the sector unless
        // said Cartesian; the axis also turns the left face onto the right
        // one when the pairs are matched by coordinates.
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
        let sets: NodeSets = toml::from_str(&sets_file.text).map_err(|e| {
            let line = e
                .span()
                .map_or(0, |s| sets_file.text[..s.start].lines().count().max(1));
            sets_file.error(line, e.message().to_string())
        })?;
        let count = coords.len();
        let list = |name: &str, l: &[usize]| nodes_of(&sets_file, name, l, count);
        let clamped = list("clamped", &sets.clamped)?;
        let left = list("left_boundary", &sets.left_boundary)?;
        let right = list("right_boundary", &sets.right_boundary)?;
        let rotation = axis.rotation(2.0 * std::f64::consts::PI / self.sectors as f64);
        let right = pair_boundaries(&sets_file, &coords, &left, &right, rotation)?;
        Ok(SectorFiles {
            sets_file,
            mass,
            stiffness,
            coords,
            sets,
            axis,
            frame,
            tolerance,
            clamped,
            left,
            right,
            sectors: self.sectors,
        })
    }
}

impl SectorFiles {
    /// The 0-based nodes of node set `name` (its list `l`).
    pub(super) fn nodes(&self, name: &str, l: &[usize]) -> Result<Vec<usize>, ModelError> {
        nodes_of(&self.sets_file, name, l, self.coords.len())
    }

    /// The nodes whose dofs a reduced model keeps: the contact, then the
    /// excitation, then the observation nodes. Each is in one of these
    /// sets only (a node in two would be kept once, and every dof number
    /// after it would name another node than the user meant), and is
    /// neither clamped nor on the right boundary (whose dofs are not
    /// independent).
    pub(super) fn retained_nodes(&self) -> Result<Vec<usize>, ModelError> {
        // A case has at least one contact dof, numbered from the contact
        // nodes' dofs: without contact nodes its `contact.dofs` (and every
        // dof number after) would name excitation or observation dofs.
        if self.sets.contact.is_empty() {
            let (line, what) = match key_line(&self.sets_file.text, "contact") {
                0 => (0, "no contact set"),
                l => (l, "contact = []: the contact set is empty"),
            };
            return Err(self.sets_file.error(
                line,
                format!(
                    "{what}: list the nodes that touch the casing (at least one); their dofs \
                     are the model's first dofs, which the case's contact.dofs number"
                ),
            ));
        }
        let mut retained: Vec<(usize, &str, usize)> = Vec::new();
        for (name, l) in [
            ("contact", &self.sets.contact),
            ("excitation", &self.sets.excitation),
            ("observation", &self.sets.observation),
        ] {
            for (i, n) in self.nodes(name, l)?.into_iter().enumerate() {
                let line = item_line(&self.sets_file.text, name, i);
                let at = format!("{name}[{}]: node {}", i + 1, n + 1);
                if let Some((_, other, j)) = retained.iter().find(|(m, ..)| *m == n) {
                    return Err(self.sets_file.error(
                        line,
                        format!(
                            "{at} is already {other}[{}]; a node belongs to one of contact, \
                             excitation and observation (its dofs are kept once, numbered in \
                             the sets' order: to excite or observe a contact node, give its \
                             contact dofs' numbers in the case)",
                            j + 1
                        ),
                    ));
                }
                if let Some(j) = self.clamped.iter().position(|&m| m == n) {
                    return Err(self.sets_file.error(
                        line,
                        format!(
                            "{at} is also clamped[{}]: a clamped node does not move; its dofs \
                             cannot be {name} dofs (take it out of one of the two sets)",
                            j + 1
                        ),
                    ));
                }
                if let Some(j) = self.right.iter().position(|&m| m == n) {
                    return Err(self.sets_file.error(
                        line,
                        format!(
                            "{at} is also on the right boundary (the twin of left_boundary[{}], \
                             node {}): its dofs are the next sector's left ones; list its left \
                             twin in {name} instead",
                            j + 1,
                            self.left[j] + 1
                        ),
                    ));
                }
                retained.push((n, name, i));
            }
        }
        Ok(retained.into_iter().map(|(n, ..)| n).collect())
    }

    /// A digest of the tag `tag` (what the cached result is) and the
    /// matrices' bytes; the caller adds what else the result depends on.
    pub(super) fn digest(&self, tag: &[u8]) -> InputDigest {
        let mut digest = InputDigest::new();
        digest.field(tag);
        for f in [&self.mass, &self.stiffness] {
            digest.field(f.text.as_bytes());
        }
        digest
    }

    /// The sector's sparse matrices, parsed and sized against the
    /// coordinates, with its clamped and boundary dofs.
    pub(super) fn sparse_sector(&self) -> Result<SparseSector, ModelError> {
        let count = self.coords.len();
        let m = parse_matrix_market_sparse(&self.mass.text, &self.mass.path)?;
        let k = parse_matrix_market_sparse(&self.stiffness.text, &self.stiffness.path)?;
        for (f, a) in [(&self.mass, &m), (&self.stiffness, &k)] {
            if a.nrows() != 3 * count || a.ncols() != 3 * count {
                return Err(f.error(
                    0,
                    format!(
                        "{}×{} matrix, but the coordinates file has {count} nodes: 3 dofs per \
                         node make {}",
                        a.nrows(),
                        a.ncols(),
                        3 * count
                    ),
                ));
            }
        }
        Ok(SparseSector {
            mass: m,
            stiffness: k,
            clamped: node_dofs(&self.clamped),
            left_boundary: node_dofs(&self.left),
            right_boundary: node_dofs(&self.right),
            boundary_frame: self.frame,
            sectors: self.sectors,
            symmetry_tolerance: self.tolerance,
        })
    }
}

/// The 1-based line of key `name` in TOML text `text` (0 if it is not
/// there).
fn key_line(text: &str, name: &str) -> usize {
    text.lines()
        .position(|raw| {
            raw.trim_start()
                .strip_prefix(name)
                .is_some_and(|r| r.trim_start().starts_with('='))
        })
        .map_or(0, |i| i + 1)
}
