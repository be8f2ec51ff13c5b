//! The node input of a `kind = "finite_element"` table: the coordinates
//! file, the node sets, the lines that name a node or an entry, and the
//! pairing of the left and right cyclic boundaries. Read by
//! `sector_files` (once per case) and used by the reduction
//! (`finite_element`), which uses `sector_files`, not the other way round.

use super::super::key;
use crate::model::ModelError;
use serde::Deserialize;
use std::path::{Path, PathBuf};

/// The node sets file (1-based node numbers of the coordinates file): the
/// sets the model reads, and any other named list (such as `blade`, which
/// `mistuning.blade_node_set` names).
#[derive(Deserialize, Default)]
pub(in crate::model::spec) struct NodeSets {
    #[serde(default)]
    pub(in crate::model::spec) clamped: Vec<usize>,
    #[serde(default)]
    pub(in crate::model::spec) left_boundary: Vec<usize>,
    #[serde(default)]
    pub(in crate::model::spec) right_boundary: Vec<usize>,
    #[serde(default)]
    pub(in crate::model::spec) contact: Vec<usize>,
    #[serde(default)]
    pub(in crate::model::spec) excitation: Vec<usize>,
    #[serde(default)]
    pub(in crate::model::spec) observation: Vec<usize>,
    /// Every other list, by name.
    #[serde(flatten)]
    pub(in crate::model::spec) others: std::collections::BTreeMap<String, Vec<usize>>,
}

/// Relative tolerance (times the largest coordinate) of the boundary
/// pairing by coordinates.
const PAIRING_TOLERANCE: f64 = 1e-6;

/// A text file read whole, with its key for errors.
pub(in crate::model::spec) struct InputText {
    pub(in crate::model::spec) key: String,
    pub(in crate::model::spec) path: PathBuf,
    pub(in crate::model::spec) text: String,
}

impl InputText {
    pub(in crate::model::spec) fn read(
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

    pub(in crate::model::spec) fn error(
        &self,
        line: usize,
        message: impl Into<String>,
    ) -> ModelError {
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
pub(in crate::model::spec) fn read_nodes(file: &InputText) -> Result<Vec<[f64; 3]>, ModelError> {
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
pub(in crate::model::spec) fn item_line(text: &str, name: &str, index: usize) -> usize {
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
pub(in crate::model::spec) fn nodes_of(
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
pub(in crate::model::spec) fn pair_boundaries(
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
pub(in crate::model::spec) fn node_dofs(nodes: &[usize]) -> Vec<usize> {
    nodes
        .iter()
        .flat_map(|&n| (0..3).map(move |d| 3 * n + d))
        .collect()
}
