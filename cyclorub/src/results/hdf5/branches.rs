//! The `/branches` group of `results.h5` (see the module's layout): the
//! bifurcated branches switched to at the branch points (`cyclorub
//! branches`), one subgroup per branch point of `branches.json`, each side's
//! points in a subgroup of it.

use super::h5_error;
use super::put::{put_f64, put_i64, text};
use crate::results::bifurcated::{BifurcatedBranchData, BifurcatedSide};
use crate::results::ResultsError;
use hdf5_pure::{AttrValue, FileBuilder};
use std::collections::HashMap;
use std::path::Path;

/// The subgroup of one side: `side_0` for `+v`, `side_1` for `−v`.
fn side_name(index: usize) -> String {
    format!("side_{index}")
}

/// The subgroups' names, in order: the CSV's name without `.csv`
/// (`class1_212.7022Hz`) for a branch switched to, `class3_marker12` (or
/// `class3_point40` when found by `--class`) for one that was not; a name
/// met twice gets its position appended.
fn names(branches: &[BifurcatedBranchData]) -> Vec<String> {
    let mut names: Vec<String> = Vec::with_capacity(branches.len());
    for (i, b) in branches.iter().enumerate() {
        let stem = b
            .file
            .as_deref()
            .and_then(|f| f.rsplit('/').next())
            .map(|f| f.trim_end_matches(".csv").to_string())
            .unwrap_or_else(|| match b.marker {
                Some(m) => format!("class{}_marker{m}", b.class),
                None => format!("class{}_point{}", b.class, b.parent_point),
            });
        let name = if names.contains(&stem) {
            format!("{stem}_{i}")
        } else {
            stem
        };
        names.push(name);
    }
    names
}

/// An optional count as an attribute (−1: absent).
fn count(value: Option<usize>) -> AttrValue {
    AttrValue::I64(value.map_or(-1, |v| v as i64))
}

/// Adds the group to a file being built (nothing when there is no branch).
pub(super) fn write(file: &mut FileBuilder, branches: &[BifurcatedBranchData]) {
    if branches.is_empty() {
        return;
    }
    let mut group = file.create_group("branches");
    group.set_attr(
        "description",
        text("The bifurcated branches switched to at the symmetric branch's branch points (cyclorub branches, docs/branches.md), one subgroup per branch point in the order of branches/branches.json (attribute order), each side's points in side_0 (+v) and side_1 (-v)."),
    );
    for (order, (branch, name)) in branches.iter().zip(names(branches)).enumerate() {
        let mut g = group.create_group(&name);
        g.set_attr("order", AttrValue::I64(order as i64));
        g.set_attr("marker", count(branch.marker));
        g.set_attr("marker_hz", AttrValue::F64(branch.marker_hz));
        g.set_attr("class", AttrValue::I64(branch.class));
        g.set_attr("parent_point", AttrValue::I64(branch.parent_point as i64));
        g.set_attr(
            "branch_point_hz",
            AttrValue::F64(branch.branch_point_hz.unwrap_or(f64::NAN)),
        );
        g.set_attr("basis_unknowns", count(branch.basis_unknowns));
        g.set_attr("full_unknowns", count(branch.full_unknowns));
        g.set_attr("file", text(branch.file.as_deref().unwrap_or("")));
        g.set_attr(
            "not_switched",
            text(branch.not_switched.as_deref().unwrap_or("")),
        );
        for (s, side) in branch.sides.iter().enumerate() {
            let p = side.frequency_hz.len();
            let n = side.sector_amplitudes_m.first().map_or(0, Vec::len);
            let mut h = g.create_group(&side_name(s));
            h.set_attr("direction", AttrValue::F64(side.direction));
            h.set_attr("stop_reason", text(&side.stop_reason));
            h.set_attr("stop_json", text(&side.stop.to_string()));
            put_f64(
                &mut h,
                "frequency_hz",
                &side.frequency_hz,
                &[p],
                "Hz",
                "frequency of each point, from the branch point on",
            );
            let stable: Vec<i64> = side
                .stable
                .iter()
                .map(|s| s.map_or(-1, i64::from))
                .collect();
            put_i64(
                &mut h,
                "stable",
                &stable,
                &[p],
                "1: no exponent grows in the enlarged basis's classes, 0: one does, -1: not checked",
            );
            let flat: Vec<f64> = side.sector_amplitudes_m.iter().flatten().copied().collect();
            put_f64(
                &mut h,
                "sector_amplitude",
                &flat,
                &[p, n],
                "m",
                "the observed dof's largest displacement over the period (toward the casing) on every sector",
            );
            g.add_group(h.finish());
        }
        group.add_group(g.finish());
    }
    file.add_group(group.finish());
}

/// Reads the group, if the file has one (`sectors` amplitudes a point).
pub(super) fn read(
    file: &hdf5_pure::File,
    path: &Path,
    sectors: usize,
) -> Result<Vec<BifurcatedBranchData>, ResultsError> {
    let Ok(group) = file.group("branches") else {
        return Ok(Vec::new());
    };
    let mut branches: Vec<(i64, BifurcatedBranchData)> = Vec::new();
    for name in group.groups().map_err(h5_error(path))? {
        let bad = |message: String| ResultsError::Read {
            path: path.to_path_buf(),
            message: format!("branches/{name}: {message}"),
        };
        let g = group.group(&name).map_err(h5_error(path))?;
        let attrs = g.attrs().map_err(h5_error(path))?;
        let integer = |key: &str| match attrs.get(key) {
            Some(AttrValue::I64(v)) => Ok(*v),
            _ => Err(bad(format!("the attribute {key} is missing"))),
        };
        let optional = |key: &str| integer(key).map(|v| usize::try_from(v).ok());
        let number = |attrs: &HashMap<String, AttrValue>, key: &str| match attrs.get(key) {
            Some(AttrValue::F64(x)) => Ok(*x),
            _ => Err(bad(format!("the attribute {key} is missing"))),
        };
        let words = |attrs: &HashMap<String, AttrValue>, key: &str| {
            attrs
                .get(key)
                .and_then(|v| v.as_str().map(str::to_string))
                .ok_or_else(|| bad(format!("the attribute {key} is missing")))
        };
        let nonempty = |s: String| (!s.is_empty()).then_some(s);
        let located = number(&attrs, "branch_point_hz")?;
        let mut sides = Vec::new();
        for s in 0.. {
            let Ok(h) = g.group(&side_name(s)) else {
                break;
            };
            let side_attrs = h.attrs().map_err(h5_error(path))?;
            let dataset = |key: &str| h.dataset(key).map_err(h5_error(path));
            let empty = |d: &hdf5_pure::Dataset| -> Result<bool, ResultsError> {
                Ok(d.shape().map_err(h5_error(path))?.contains(&0))
            };
            let frequency = dataset("frequency_hz")?;
            let frequency_hz = if empty(&frequency)? {
                Vec::new()
            } else {
                frequency.read_f64().map_err(h5_error(path))?
            };
            let p = frequency_hz.len();
            let stable = dataset("stable")?;
            let stable: Vec<Option<bool>> = if empty(&stable)? {
                Vec::new()
            } else {
                stable
                    .read_i64()
                    .map_err(h5_error(path))?
                    .into_iter()
                    .map(|v| (v >= 0).then_some(v == 1))
                    .collect()
            };
            let amplitude = dataset("sector_amplitude")?;
            let amplitudes = if empty(&amplitude)? {
                Vec::new()
            } else {
                amplitude.read_f64().map_err(h5_error(path))?
            };
            if stable.len() != p || amplitudes.len() != p * sectors {
                return Err(bad(format!(
                    "{}: {p} frequencies, {} verdicts and {} amplitudes ({sectors} sectors a point)",
                    side_name(s),
                    stable.len(),
                    amplitudes.len()
                )));
            }
            let stop_json = words(&side_attrs, "stop_json")?;
            sides.push(BifurcatedSide {
                direction: number(&side_attrs, "direction")?,
                frequency_hz,
                stable,
                sector_amplitudes_m: amplitudes
                    .chunks(sectors.max(1))
                    .map(<[f64]>::to_vec)
                    .collect(),
                stop: serde_json::from_str(&stop_json)
                    .map_err(|e| bad(format!("stop_json: {e}")))?,
                stop_reason: words(&side_attrs, "stop_reason")?,
            });
        }
        branches.push((
            integer("order")?,
            BifurcatedBranchData {
                marker: optional("marker")?,
                marker_hz: number(&attrs, "marker_hz")?,
                class: integer("class")?,
                parent_point: optional("parent_point")?
                    .ok_or_else(|| bad("parent_point is negative".into()))?,
                branch_point_hz: (!located.is_nan()).then_some(located),
                basis_unknowns: optional("basis_unknowns")?,
                full_unknowns: optional("full_unknowns")?,
                sides,
                file: nonempty(words(&attrs, "file")?),
                not_switched: nonempty(words(&attrs, "not_switched")?),
            },
        ));
    }
    branches.sort_by_key(|(order, _)| *order);
    Ok(branches.into_iter().map(|(_, b)| b).collect())
}
