//! Reading `results.h5` back into a [`ResultsData`], checking the format,
//! its version and the shape of every dataset; the cyclic components are
//! computed from the observed coordinates, as the run computed them.

use super::{h5_error, FORMAT, FORMAT_VERSION};
use crate::results::components::CyclicComponents;
use crate::results::data::{LinearResponse, PointHistories, PointResults, ResultsData};
use crate::results::ResultsError;
use hdf5_pure::{AttrValue, Datatype};
use std::collections::HashMap;
use std::path::Path;

/// Reads a results file back.
pub fn read(path: &Path) -> Result<ResultsData, ResultsError> {
    let file = hdf5_pure::File::open(path)
        .map_err(|e| truncated(path, None).unwrap_or(h5_error(path)(e)))?;
    // A file shorter than its superblock's end (a copy cut short, a full
    // disk) misses whatever was written last: say so, not which of its
    // parts happens to be read first.
    let superblock = file.superblock();
    let end = superblock
        .base_address
        .get()
        .saturating_add(superblock.eof_address);
    if let Some(error) = truncated(path, Some(end)) {
        return Err(error);
    }
    let attrs = file.root().attrs().map_err(h5_error(path))?;
    let bad = |message: String| ResultsError::Read {
        path: path.to_path_buf(),
        message,
    };
    let string = |attrs: &HashMap<String, AttrValue>, key: &str| {
        attrs
            .get(key)
            .and_then(|v| v.as_str().map(str::to_string))
            .ok_or_else(|| bad(format!("the attribute {key} is missing or not a string")))
    };
    let integer = |attrs: &HashMap<String, AttrValue>, key: &str| {
        attrs
            .get(key)
            .and_then(AttrValue::as_i64)
            .and_then(|v| usize::try_from(v).ok())
            .ok_or_else(|| bad(format!("the attribute {key} is missing or not an integer")))
    };
    if string(&attrs, "format")? != FORMAT {
        return Err(bad(format!("not a {FORMAT} file")));
    }
    let version = attrs.get("format_version").and_then(AttrValue::as_i64);
    if !matches!(version, Some(v) if (1..=FORMAT_VERSION).contains(&v)) {
        return Err(bad(format!(
            "format version {version:?}: this build reads versions 1 to {FORMAT_VERSION}"
        )));
    }
    let n = integer(&attrs, "sectors")?;
    let harmonics = integer(&attrs, "harmonics")?;
    let size = 2 * harmonics + 1;
    let contact_dofs: Vec<usize> = attrs
        .get("contact_dofs")
        .and_then(AttrValue::to_i64s)
        .ok_or_else(|| bad("the attribute contact_dofs is missing".into()))?
        .into_iter()
        .map(|d| d.max(0) as usize)
        .collect();
    let nc = contact_dofs.len();
    // A per-point dataset's shape is its points, then its entries' array
    // shape (format 2); format 1 stored the same values as an
    // N-dimensional dataset, which reads the same way.
    let f64s =
        |name: &str, expected: &[Option<usize>]| -> Result<(Vec<f64>, Vec<usize>), ResultsError> {
            let dataset = match file.dataset(name) {
                Ok(dataset) => dataset,
                // An entry of no values (no points' unknowns, no contact
                // dofs) has no dataset.
                Err(_) if expected.contains(&Some(0)) => {
                    return Ok((
                        Vec::new(),
                        expected.iter().map(|e| e.unwrap_or(0)).collect(),
                    ));
                }
                Err(e) => return Err(h5_error(path)(e)),
            };
            let mut shape: Vec<usize> = dataset
                .shape()
                .map_err(h5_error(path))?
                .into_iter()
                .map(|s| s as usize)
                .collect();
            let datatype = dataset.datatype().map_err(h5_error(path))?;
            let entry = match &datatype {
                Datatype::Array { dimensions, .. } => {
                    shape.extend(dimensions.iter().map(|&d| d as usize));
                    true
                }
                _ => false,
            };
            // A run killed between two appends can leave a dataset longer
            // than the point count: the extra entries are not read.
            let mut total = shape.iter().product::<usize>();
            if let (Some(first), Some(Some(points))) = (shape.first_mut(), expected.first()) {
                if *first > *points {
                    total = total / *first * *points;
                    *first = *points;
                }
            }
            let matches = shape.len() == expected.len()
                && shape
                    .iter()
                    .zip(expected)
                    .all(|(s, e)| e.is_none_or(|e| e == *s));
            if !matches {
                return Err(bad(format!(
                    "{name} has shape {shape:?}, expected {expected:?}"
                )));
            }
            let values = if total == 0 {
                Vec::new()
            } else if entry {
                let raw = dataset.read_raw().map_err(h5_error(path))?;
                if raw.len() < 8 * total {
                    return Err(bad(format!("{name} holds fewer values than its shape")));
                }
                raw.chunks_exact(8)
                    .take(total)
                    .map(|b| f64::from_le_bytes([b[0], b[1], b[2], b[3], b[4], b[5], b[6], b[7]]))
                    .collect()
            } else {
                let mut values = dataset.read_f64().map_err(h5_error(path))?;
                values.truncate(total);
                values
            };
            Ok((values, shape))
        };
    let i64s = |name: &str, points: Option<usize>| -> Result<Vec<i64>, ResultsError> {
        let dataset = file.dataset(name).map_err(h5_error(path))?;
        let shape = dataset.shape().map_err(h5_error(path))?;
        if shape.contains(&0) {
            return Ok(Vec::new());
        }
        let mut values = dataset.read_i64().map_err(h5_error(path))?;
        if let Some(p) = points {
            values.truncate(p);
        }
        Ok(values)
    };
    let (frequency, shape) = f64s("branch/frequency_hz", &[None])?;
    let p = shape[0];
    let iterations = i64s("branch/iterations", Some(p))?;
    let (residual, _) = f64s("branch/residual_norm", &[Some(p)])?;
    let converged = i64s("branch/converged", Some(p))?;
    let (unknowns, shape) = f64s("branch/unknowns", &[Some(p), None])?;
    let u = shape[1];
    let (observed, _) = f64s(
        "branch/observed/coordinates",
        &[Some(p), Some(n), Some(size)],
    )?;
    let (amplitude, _) = f64s("branch/observed/amplitude", &[Some(p), Some(n)])?;
    let (max_abs, _) = f64s("branch/observed/max_abs", &[Some(p), Some(n)])?;
    let (velocity, _) = f64s("branch/observed/velocity_max_abs", &[Some(p), Some(n)])?;
    // Kept only when the run was asked for it.
    let force = if file.dataset("branch/contact/force_coordinates").is_ok() {
        Some(
            f64s(
                "branch/contact/force_coordinates",
                &[Some(p), Some(n), Some(nc), Some(size)],
            )?
            .0,
        )
    } else {
        None
    };
    let (peak_force, _) = f64s("branch/contact/peak_force", &[Some(p), Some(n), Some(nc)])?;
    let (fraction, _) = f64s("branch/contact/fraction", &[Some(p), Some(n), Some(nc)])?;
    let (penetration, _) = f64s(
        "branch/contact/max_penetration",
        &[Some(p), Some(n), Some(nc)],
    )?;
    let in_contact = i64s("branch/contact/sectors_in_contact", Some(p))?;
    if iterations.len() != p || converged.len() != p || in_contact.len() != p {
        return Err(bad(
            "the branch datasets do not have one entry per point".into()
        ));
    }
    let rows = |v: &[f64], width: usize| -> Vec<Vec<f64>> {
        v.chunks(width.max(1)).map(<[f64]>::to_vec).collect()
    };
    let mut points = Vec::with_capacity(p);
    for i in 0..p {
        let slice = |v: &[f64], len: usize| v[i * len..(i + 1) * len].to_vec();
        let observed = rows(&slice(&observed, n * size), size);
        // Derived, not stored: the same function the run used.
        let components = CyclicComponents::from_sector_coordinates(&observed)
            .map_err(|e| bad(format!("point {i}: {e}")))?;
        points.push(PointResults {
            frequency_hz: frequency[i],
            iterations: iterations[i].max(0) as usize,
            residual_norm: residual[i],
            converged: converged[i] != 0,
            unknowns: slice(&unknowns, u),
            observed,
            amplitude: slice(&amplitude, n),
            max_abs: slice(&max_abs, n),
            velocity_max_abs: slice(&velocity, n),
            contact_force: force
                .as_ref()
                .map_or_else(Vec::new, |f| rows(&slice(f, n * nc * size), size)),
            peak_force: slice(&peak_force, n * nc),
            contact_fraction: slice(&fraction, n * nc),
            max_penetration: slice(&penetration, n * nc),
            sectors_in_contact: in_contact[i].max(0) as usize,
            components,
        });
    }
    let (linear_frequency, shape) = f64s("linear/frequency_hz", &[None])?;
    let (linear_amplitude, _) = f64s("linear/amplitude", &[Some(shape[0]), Some(n)])?;
    let diameters = i64s("modes/nodal_diameter", None)?;
    let (modes, shape) = f64s("modes/frequency_hz", &[Some(diameters.len()), None])?;
    let natural_frequencies = diameters
        .iter()
        .enumerate()
        .map(|(i, &d)| {
            let row = &modes[i * shape[1]..(i + 1) * shape[1]];
            (
                d.max(0) as usize,
                row.iter().cloned().filter(|f| !f.is_nan()).collect(),
            )
        })
        .collect();
    let histories = match file.group("peak") {
        Ok(group) => {
            let peak_attrs = group.attrs().map_err(h5_error(path))?;
            let point = integer(&peak_attrs, "point")?;
            let frequency_hz = match peak_attrs.get("frequency_hz") {
                Some(AttrValue::F64(f)) => *f,
                _ => return Err(bad("peak: the attribute frequency_hz is missing".into())),
            };
            let (time_s, shape) = f64s("peak/time_s", &[None])?;
            let nt = shape[0];
            let (displacement, _) = f64s("peak/displacement", &[Some(n), Some(nt)])?;
            let (velocity, _) = f64s("peak/velocity", &[Some(n), Some(nt)])?;
            let (force, _) = f64s("peak/contact_force", &[Some(n), Some(nc), Some(nt)])?;
            let (penetration, _) = f64s("peak/penetration", &[Some(n), Some(nc), Some(nt)])?;
            Some(PointHistories {
                point,
                frequency_hz,
                time_s,
                displacement: rows(&displacement, nt),
                velocity: rows(&velocity, nt),
                contact_force: rows(&force, nt),
                penetration: rows(&penetration, nt),
            })
        }
        Err(_) => None,
    };
    Ok(ResultsData {
        case_json: string(&attrs, "case_json")?,
        basis_json: string(&attrs, "basis_json")?,
        mode: string(&attrs, "mode")?.parse().map_err(&bad)?,
        stop_json: string(&attrs, "stop_json")?,
        sectors: n,
        harmonics,
        time_samples: integer(&attrs, "time_samples")?,
        observed_dof: integer(&attrs, "observed_dof")?,
        // Files written before the attribute existed name the dof by number.
        observed_name: string(&attrs, "observed_name")
            .unwrap_or_else(|_| format!("dof {}", integer(&attrs, "observed_dof").unwrap_or(0))),
        contact_dofs,
        points,
        linear: LinearResponse {
            frequency_hz: linear_frequency,
            amplitude: rows(&linear_amplitude, n),
        },
        natural_frequencies,
        histories,
        // Files written before the attribute existed have no gap.
        gap_after: match attrs.get("gap_after") {
            Some(AttrValue::I64(p)) if *p >= 0 => Some(*p as usize),
            _ => None,
        },
        stability: super::stability::read(&file, path, p)?,
        mistuning: super::mistuning::read(&file, path, n)?,
        branches: super::branches::read(&file, path, n)?,
    })
}

/// The error of a truncated file: `path` shorter than `end`, the length
/// its superblock gives, or (`end` unknown: the file could not be opened)
/// too short to hold even its superblock and root group.
fn truncated(path: &Path, end: Option<u64>) -> Option<ResultsError> {
    /// Fewer bytes than the smallest results file (superblock, root group
    /// and its attributes) holds.
    const SMALLEST: u64 = 1024;
    let length = std::fs::metadata(path).ok()?.len();
    let message = match end {
        Some(end) if length < end => format!(
            "the file is truncated: {length} bytes of the {end} it was written with (a copy cut \
             short, a disk that was full?); copy it again, or run the case again"
        ),
        None if length < SMALLEST => format!(
            "the file is truncated or is not a results file: {length} bytes; copy it again, or \
             run the case again"
        ),
        _ => return None,
    };
    Some(ResultsError::Read {
        path: path.to_path_buf(),
        message,
    })
}
