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

use super::sector_files::SectorFiles;
use super::{key, FrameName, Keys, ModelSpec};
use crate::model::craig_bampton::{
    cache_folder_next_to, craig_bampton_cached, reduced_sector_model, CacheOutcome,
    CraigBamptonSettings, ReductionCache, ReductionError, SectorMatrix,
};
use crate::model::{Axis, ModelError, SectorModel, SECTOR_MAX_DOFS};
use faer::{c64, Mat};
use serde::{Deserialize, Serialize};
use std::path::{Path, PathBuf};

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

/// The node sets file (1-based node numbers of the coordinates file).
#[derive(Deserialize, Default)]
#[serde(deny_unknown_fields)]
pub(super) struct NodeSets {
    #[serde(default)]
    pub(super) clamped: Vec<usize>,
    #[serde(default)]
    pub(super) left_boundary: Vec<usize>,
    #[serde(default)]
    pub(super) right_boundary: Vec<usize>,
    #[serde(default)]
    pub(super) contact: Vec<usize>,
    #[serde(default)]
    pub(super) excitation: Vec<usize>,
    #[serde(default)]
    pub(super) observation: Vec<usize>,
}

/// Relative tolerance (times the largest coordinate) of the boundary
/// pairing by coordinates.
const PAIRING_TOLERANCE: f64 = 1e-6;

/// A text file read whole, with its key for errors.
pub(super) struct InputText {
    pub(super) key: String,
    pub(super) path: PathBuf,
    pub(super) text: String,
}

impl InputText {
    pub(super) fn read(
        name: &str,
        value: &Option<PathBuf>,
        dir: &Path,
    ) -> Result<Self, ModelError> {
        let file = value.as_ref().ok_or_else(|| {
            ModelError::invalid(key(name), "required with kind = \"finite_element\"")
        })?;
        let path = dir.join(file);
        let text = std::fs::read_to_string(&path).map_err(|source| ModelError::Io {
            key: key(name),
            path: path.clone(),
            source,
        })?;
        Ok(Self {
            key: format!("{} (\"{}\")", key(name), file.display()),
            path,
            text,
        })
    }

    pub(super) fn error(&self, line: usize, message: impl Into<String>) -> ModelError {
        ModelError::InputFile {
            key: self.key.clone(),
            path: self.path.clone(),
            line,
            message: message.into(),
        }
    }
}

/// Node coordinates from `node,x,y,z` lines (a header line allowed), the
/// nodes numbered `1..=n` each once, in any order.
pub(super) fn read_nodes(file: &InputText) -> Result<Vec<[f64; 3]>, ModelError> {
    let mut nodes: Vec<Option<([f64; 3], usize)>> = Vec::new();
    for (index, raw) in file.text.lines().enumerate() {
        let line = index + 1;
        let text = raw.trim();
        if text.is_empty() || text.starts_with('#') {
            continue;
        }
        let fields: Vec<&str> = text.split(',').map(str::trim).collect();
        if line == 1 && fields.first().is_some_and(|f| f.parse::<usize>().is_err()) {
            continue; // the header
        }
        if fields.len() != 4 {
            return Err(file.error(line, format!("`{text}` must be `node,x,y,z`")));
        }
        let node: usize = fields[0].parse().ok().filter(|&n| n >= 1).ok_or_else(|| {
            file.error(line, format!("node `{}` is not an integer ≥ 1", fields[0]))
        })?;
        let mut at = [0.0; 3];
        for (c, f) in at.iter_mut().zip(&fields[1..]) {
            *c = f
                .parse::<f64>()
                .ok()
                .filter(|v| v.is_finite())
                .ok_or_else(|| {
                    file.error(line, format!("coordinate `{f}` is not a finite number"))
                })?;
        }
        if nodes.len() < node {
            nodes.resize(node, None);
        }
        if let Some((_, first)) = nodes[node - 1] {
            return Err(file.error(
                line,
                format!("node {node} is already given on line {first}"),
            ));
        }
        nodes[node - 1] = Some((at, line));
    }
    nodes
        .iter()
        .enumerate()
        .map(|(n, v)| {
            v.map(|(at, _)| at).ok_or_else(|| {
                file.error(
                    0,
                    format!(
                        "node {} is missing: nodes are numbered 1..={} without gaps",
                        n + 1,
                        nodes.len()
                    ),
                )
            })
        })
        .collect()
}

/// The line of the `index`-th number of the array `name` in a TOML text.
pub(super) fn item_line(text: &str, name: &str, index: usize) -> usize {
    let mut inside = false;
    let mut count = 0;
    for (i, raw) in text.lines().enumerate() {
        let mut body = raw.split('#').next().unwrap_or("");
        if !inside {
            let trimmed = body.trim_start();
            // The key itself, not a longer one that starts with it.
            let Some(rest) = trimmed
                .strip_prefix(name)
                .filter(|r| r.starts_with([' ', '\t', '=']))
            else {
                continue;
            };
            let Some(value) = rest.trim_start().strip_prefix('=') else {
                continue;
            };
            inside = true;
            body = value;
        }
        let numbers = body
            .split(|c: char| !c.is_ascii_digit())
            .filter(|t| !t.is_empty())
            .count();
        if index < count + numbers {
            return i + 1;
        }
        count += numbers;
        if body.contains(']') {
            return 0;
        }
    }
    0
}

/// The 0-based nodes of list `name`, each present in the coordinates and
/// listed once (a repeat would shift the dof numbers of every node after
/// it, or pair a boundary node twice).
pub(super) fn nodes_of(
    file: &InputText,
    name: &str,
    list: &[usize],
    count: usize,
) -> Result<Vec<usize>, ModelError> {
    list.iter()
        .enumerate()
        .map(|(i, &n)| {
            if n == 0 || n > count {
                return Err(file.error(
                    item_line(&file.text, name, i),
                    format!(
                        "{name}[{}]: node {n} is not in the coordinates file (nodes 1..={count})",
                        i + 1
                    ),
                ));
            }
            if let Some(first) = list[..i].iter().position(|&m| m == n) {
                let why = match name {
                    "clamped" => "its dofs are fixed once",
                    "left_boundary" | "right_boundary" => {
                        "each left_boundary node pairs with one right_boundary twin"
                    }
                    _ => {
                        "the retained nodes' dofs are numbered in the sets' order, and a repeat \
                         would shift the dofs after it"
                    }
                };
                return Err(file.error(
                    item_line(&file.text, name, i),
                    format!(
                        "{name}[{}]: node {n} is already {name}[{}]; list each node once in a \
                         set ({why})",
                        i + 1,
                        first + 1
                    ),
                ));
            }
            Ok(n - 1)
        })
        .collect()
}

/// For each left boundary node, its right twin: the given order when it
/// fits (`x_R = R(α) x_L` within the tolerance), else matched by
/// coordinates.
pub(super) fn pair_boundaries(
    file: &InputText,
    coords: &[[f64; 3]],
    left: &[usize],
    right: &[usize],
    rotation: [[f64; 3]; 3],
) -> Result<Vec<usize>, ModelError> {
    if left.len() != right.len() {
        return Err(file.error(
            item_line(&file.text, "right_boundary", 0),
            format!(
                "{} left_boundary nodes but {} right_boundary nodes; each left node needs its twin",
                left.len(),
                right.len()
            ),
        ));
    }
    let scale = coords.iter().flatten().fold(0.0_f64, |m, v| m.max(v.abs()));
    let tolerance = PAIRING_TOLERANCE * scale.max(f64::MIN_POSITIVE);
    let turn = |p: [f64; 3]| {
        let mut q = [0.0; 3];
        for (d, row) in rotation.iter().enumerate() {
            q[d] = row[0] * p[0] + row[1] * p[1] + row[2] * p[2];
        }
        q
    };
    let distance = |a: [f64; 3], b: [f64; 3]| {
        ((a[0] - b[0]).powi(2) + (a[1] - b[1]).powi(2) + (a[2] - b[2]).powi(2)).sqrt()
    };
    if left
        .iter()
        .zip(right)
        .all(|(&l, &r)| distance(turn(coords[l]), coords[r]) <= tolerance)
    {
        return Ok(right.to_vec());
    }
    // Matched by coordinates: right nodes sorted by x, a window of ±tolerance.
    let mut sorted: Vec<usize> = right.to_vec();
    sorted.sort_by(|&a, &b| coords[a][0].total_cmp(&coords[b][0]));
    let mut used = vec![false; coords.len()];
    let mut out = Vec::with_capacity(left.len());
    for (i, &l) in left.iter().enumerate() {
        let target = turn(coords[l]);
        let start = sorted.partition_point(|&r| coords[r][0] < target[0] - tolerance);
        let found = sorted[start..]
            .iter()
            .take_while(|&&r| coords[r][0] <= target[0] + tolerance)
            .find(|&&r| !used[r] && distance(target, coords[r]) <= tolerance);
        match found {
            Some(&r) => {
                used[r] = true;
                out.push(r);
            }
            None => {
                let [x, y, z] = coords[l];
                let [a, b, c] = target;
                return Err(file.error(
                    item_line(&file.text, "left_boundary", i),
                    format!(
                        "left_boundary[{}]: node {} at ({x:.6e}, {y:.6e}, {z:.6e}) turned by 2π/N \
                         lands at ({a:.6e}, {b:.6e}, {c:.6e}), where no right_boundary node lies \
                         (tolerance {tolerance:.1e} m); check the sector count, the axis and the faces",
                        i + 1,
                        l + 1
                    ),
                ));
            }
        }
    }
    Ok(out)
}

/// The 3 dofs of each node.
pub(super) fn node_dofs(nodes: &[usize]) -> Vec<usize> {
    nodes
        .iter()
        .flat_map(|&n| (0..3).map(move |d| 3 * n + d))
        .collect()
}

impl ModelSpec {
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
        let mut digest = files.digest(b"cyclorub finite_element sector v1");
        digest
            .dofs(&files.clamped)
            .dofs(&files.left)
            .dofs(&files.right);
        digest.settings(self.sectors, files.frame, &settings);
        digest.bytes(&files.tolerance.to_le_bytes());
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
        let damping =
            self.damping
                .build(settings.retained.len() + internal_modes, case_dir, keys)?;
        let frames = self.retained_frames(&files, &retained_nodes)?;
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
        reduced_sector_model(self.sectors, &settings, &reduced, damping)
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
fn in_frames(a: &Mat<c64>, frames: &[Option<[[f64; 3]; 3]>]) -> Mat<c64> {
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
