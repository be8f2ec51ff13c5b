//! `results.h5`: the whole content of a run in one self-describing HDF5
//! file, written and read in pure Rust (the `hdf5-pure` crate: no HDF5
//! system library), readable by h5py and MATLAB's `h5read`.
//!
//! The file is in the HDF5 1.8 format (version 2 superblock), which every
//! MATLAB release with `h5read` opens. Arrays are stored row-major (C
//! order) with the shapes below; MATLAB shows them with the dimensions
//! reversed. Every dataset carries `unit` and `description` attributes.
//!
//! ```text
//! /                      attrs: format, format_version, cyclorub_version,
//!                        sectors, harmonics, time_samples, observed_dof,
//!                        contact_dofs (1-based), mode, case_json,
//!                        basis_json, stop_json, conventions, gap_after
//!                        (the last point before a gap in the branch, −1
//!                        when it has none)
//! /branch/frequency_hz   [P]             Hz
//! /branch/iterations     [P]
//! /branch/residual_norm  [P]
//! /branch/converged      [P]             1 or 0
//! /branch/unknowns       [P, U]          the basis' unknowns
//! /branch/observed/coordinates       [P, N, 2N_h+1]  m
//! /branch/observed/amplitude         [P, N]          m (branch.csv's)
//! /branch/observed/max_abs           [P, N]          m
//! /branch/observed/velocity_max_abs  [P, N]          m/s
//! /branch/observed/harmonic_amplitude [P, N, N_h+1]  m
//! /branch/contact/force_coordinates  [P, N, n_c, 2N_h+1]  N
//! /branch/contact/peak_force         [P, N, n_c]     N
//! /branch/contact/fraction           [P, N, n_c]
//! /branch/contact/max_penetration    [P, N, n_c]     m
//! /branch/contact/sectors_in_contact [P]
//! /branch/components/forward         [P, N_h+1, N/2+1]  m
//! /branch/components/backward        [P, N_h+1, N/2+1]  m
//! /linear/frequency_hz   [L]             Hz
//! /linear/amplitude      [L, N]          m
//! /modes/nodal_diameter  [D]
//! /modes/frequency_hz    [D, R]          Hz (NaN where a diameter has fewer modes)
//! /peak/…                time histories of the peak point (if any):
//!   attrs point, frequency_hz; time_s [N_t], displacement [N, N_t],
//!   velocity [N, N_t], contact_force [N, n_c, N_t], penetration [N, n_c, N_t]
//! ```

use super::components::CyclicComponents;
use super::data::{LinearResponse, PointHistories, PointResults, ResultsData};
use super::recovery::harmonic_amplitudes;
use super::ResultsError;
use hdf5_pure::{make_f64_type, make_i64_type, AttrValue, FileBuilder, LibVer};
use std::collections::HashMap;
use std::path::Path;

/// The name of the file in a results folder.
pub const FILE_NAME: &str = "results.h5";

/// The value of the root attribute `format`.
pub const FORMAT: &str = "cyclorub results";

/// The version of this layout.
pub const FORMAT_VERSION: i64 = 1;

const CONVENTIONS: &str = "Sectors are numbered 1..N in the text and stored 0-based along array \
axes (index j is sector j+1). Harmonic coordinates of a signal u(t) are [a0, Re X1, Im X1, ..., \
Re X_Nh, Im X_Nh] with u(t) = a0 + sum_k 2 Re(X_k exp(i k w t)); time samples are at \
w t_n = 2 pi n / N_t. Amplitude = largest displacement over the period toward the casing. The \
contact force f >= 0 acts as -f on the blade; penetration = x - g0 (> 0 in contact). Cyclic \
components: forward[k][d] and backward[k][d] are the amplitudes of the waves of nodal diameter d \
on harmonic k traveling forward (s = +d) and backward (s = -d) in blade numbering, the wave \
(s, k) being exp(i(k w t - s alpha (j - 1))); diameters 0 and N/2 are shown half forward, half \
backward. SI units.";

fn h5_error(path: &Path) -> impl Fn(hdf5_pure::Error) -> ResultsError + '_ {
    move |e| ResultsError::Hdf5 {
        path: path.to_path_buf(),
        message: e.to_string(),
    }
}

/// Where datasets can be created: the file's root or a group.
trait Container {
    fn dataset(&mut self, name: &str) -> &mut hdf5_pure::DatasetBuilder;
}

impl Container for FileBuilder {
    fn dataset(&mut self, name: &str) -> &mut hdf5_pure::DatasetBuilder {
        self.create_dataset(name)
    }
}

impl Container for hdf5_pure::GroupBuilder {
    fn dataset(&mut self, name: &str) -> &mut hdf5_pure::DatasetBuilder {
        self.create_dataset(name)
    }
}

fn text(value: &str) -> AttrValue {
    AttrValue::VarLenString(value.to_string())
}

fn described<'a>(
    builder: &'a mut hdf5_pure::DatasetBuilder,
    unit: &str,
    description: &str,
) -> &'a mut hdf5_pure::DatasetBuilder {
    builder
        .set_attr("unit", text(unit))
        .set_attr("description", text(description))
}

fn shape_u64(shape: &[usize]) -> Vec<u64> {
    shape.iter().map(|&s| s as u64).collect()
}

fn put_f64(
    group: &mut impl Container,
    name: &str,
    data: &[f64],
    shape: &[usize],
    unit: &str,
    description: &str,
) {
    let builder = group.dataset(name);
    if data.is_empty() {
        builder.with_dtype(make_f64_type());
    } else {
        builder.with_f64_data(data);
    }
    builder.with_shape(&shape_u64(shape));
    described(builder, unit, description);
}

fn put_i64(
    group: &mut impl Container,
    name: &str,
    data: &[i64],
    shape: &[usize],
    description: &str,
) {
    let builder = group.dataset(name);
    if data.is_empty() {
        builder.with_dtype(make_i64_type());
    } else {
        builder.with_i64_data(data);
    }
    builder.with_shape(&shape_u64(shape));
    described(builder, "1", description);
}

/// Flattens `[a][b]` vectors, checking that every row has `width` entries.
fn flat(rows: impl IntoIterator<Item = impl AsRef<[f64]>>, width: usize) -> Vec<f64> {
    let mut out = Vec::new();
    for row in rows {
        let row = row.as_ref();
        out.extend_from_slice(row);
        out.extend(std::iter::repeat_n(
            f64::NAN,
            width.saturating_sub(row.len()),
        ));
    }
    out
}

/// Writes `data` to `path` (overwriting it).
pub fn write(path: &Path, data: &ResultsData) -> Result<(), ResultsError> {
    let n = data.sectors;
    let size = 2 * data.harmonics + 1;
    let nc = data.contact_dofs.len();
    let p = data.points.len();
    let unknowns = data.points.first().map_or(0, |q| q.unknowns.len());
    if let Some(bad) = data.points.iter().position(|q| {
        q.unknowns.len() != unknowns
            || q.observed.len() != n
            || q.observed.iter().any(|c| c.len() != size)
            || q.contact_force.len() != n * nc
            || q.components.forward.len() != data.harmonics + 1
    }) {
        return Err(ResultsError::Input(format!(
            "point {bad} does not have the shape of the others (N = {n}, N_h = {}, {nc} contact dofs, {unknowns} unknowns)",
            data.harmonics
        )));
    }
    let mut file = FileBuilder::new();
    file.with_libver_bounds(LibVer::Earliest, LibVer::V18);
    file.set_attr("format", text(FORMAT));
    file.set_attr("format_version", AttrValue::I64(FORMAT_VERSION));
    file.set_attr("cyclorub_version", text(env!("CARGO_PKG_VERSION")));
    file.set_attr("sectors", AttrValue::I64(n as i64));
    file.set_attr("harmonics", AttrValue::I64(data.harmonics as i64));
    file.set_attr("time_samples", AttrValue::I64(data.time_samples as i64));
    file.set_attr("observed_dof", AttrValue::I64(data.observed_dof as i64));
    file.set_attr(
        "contact_dofs",
        AttrValue::I64Array(data.contact_dofs.iter().map(|&d| d as i64).collect()),
    );
    file.set_attr("mode", text(&data.mode));
    file.set_attr("case_json", text(&data.case_json));
    file.set_attr("basis_json", text(&data.basis_json));
    file.set_attr("stop_json", text(&data.stop_json));
    // −1: no gap (an optional value, read back as absent).
    file.set_attr(
        "gap_after",
        AttrValue::I64(data.gap_after.map_or(-1, |p| p as i64)),
    );
    file.set_attr("conventions", text(CONVENTIONS));

    let points = &data.points;
    let mut branch = file.create_group("branch");
    branch.set_attr(
        "description",
        text("One entry per point of the branch, in continuation order."),
    );
    let column = |f: &dyn Fn(&PointResults) -> f64| points.iter().map(f).collect::<Vec<f64>>();
    put_f64(
        &mut branch,
        "frequency_hz",
        &column(&|q| q.frequency_hz),
        &[p],
        "Hz",
        "excitation frequency",
    );
    put_i64(
        &mut branch,
        "iterations",
        &points
            .iter()
            .map(|q| q.iterations as i64)
            .collect::<Vec<_>>(),
        &[p],
        "Newton iterations",
    );
    put_f64(
        &mut branch,
        "residual_norm",
        &column(&|q| q.residual_norm),
        &[p],
        "1",
        "residual norm divided by the force scale",
    );
    put_i64(
        &mut branch,
        "converged",
        &points
            .iter()
            .map(|q| q.converged as i64)
            .collect::<Vec<_>>(),
        &[p],
        "1 if Newton converged, 0 otherwise",
    );
    put_f64(
        &mut branch,
        "unknowns",
        &flat(points.iter().map(|q| &q.unknowns), unknowns),
        &[p, unknowns],
        "m",
        "the unknowns of the basis solved on (layout in run.json's basis)",
    );
    let mut observed = branch.create_group("observed");
    observed.set_attr(
        "description",
        text("The observed dof (root attribute observed_dof) on every sector."),
    );
    put_f64(
        &mut observed,
        "coordinates",
        &flat(points.iter().flat_map(|q| &q.observed), size),
        &[p, n, size],
        "m",
        "harmonic coordinates [a0, Re X1, Im X1, ...] per point and sector",
    );
    put_f64(
        &mut observed,
        "amplitude",
        &flat(points.iter().map(|q| &q.amplitude), n),
        &[p, n],
        "m",
        "largest displacement over the period (toward the casing), as branch.csv",
    );
    put_f64(
        &mut observed,
        "max_abs",
        &flat(points.iter().map(|q| &q.max_abs), n),
        &[p, n],
        "m",
        "largest |displacement| over the period",
    );
    put_f64(
        &mut observed,
        "velocity_max_abs",
        &flat(points.iter().map(|q| &q.velocity_max_abs), n),
        &[p, n],
        "m/s",
        "largest |velocity| over the period",
    );
    put_f64(
        &mut observed,
        "harmonic_amplitude",
        &flat(
            points
                .iter()
                .flat_map(|q| q.observed.iter().map(|c| harmonic_amplitudes(c))),
            data.harmonics + 1,
        ),
        &[p, n, data.harmonics + 1],
        "m",
        "amplitude of each harmonic [|a0|, 2|X1|, ..., 2|X_Nh|]",
    );
    branch.add_group(observed.finish());
    let mut contact = branch.create_group("contact");
    contact.set_attr(
        "description",
        text("Contact state of every contact dof (root attribute contact_dofs) on every sector."),
    );
    put_f64(
        &mut contact,
        "force_coordinates",
        &flat(points.iter().flat_map(|q| &q.contact_force), size),
        &[p, n, nc, size],
        "N",
        "harmonic coordinates of the contact force f >= 0 (acting as -f on the blade)",
    );
    put_f64(
        &mut contact,
        "peak_force",
        &flat(points.iter().map(|q| &q.peak_force), n * nc),
        &[p, n, nc],
        "N",
        "largest contact force over the period",
    );
    put_f64(
        &mut contact,
        "fraction",
        &flat(points.iter().map(|q| &q.contact_fraction), n * nc),
        &[p, n, nc],
        "1",
        "fraction of the period in contact (penetration > 0 for a law, force > 0 for DLFT)",
    );
    put_f64(
        &mut contact,
        "max_penetration",
        &flat(points.iter().map(|q| &q.max_penetration), n * nc),
        &[p, n, nc],
        "m",
        "largest penetration x - g0 over the period",
    );
    put_i64(
        &mut contact,
        "sectors_in_contact",
        &points
            .iter()
            .map(|q| q.sectors_in_contact as i64)
            .collect::<Vec<_>>(),
        &[p],
        "number of sectors in contact at some instant of the period",
    );
    branch.add_group(contact.finish());
    let mut components = branch.create_group("components");
    components.set_attr(
        "description",
        text("Cyclic components of the observed dof: [point, harmonic k, nodal diameter d]."),
    );
    let m = n / 2 + 1;
    for (name, pick) in [
        (
            "forward",
            &(|c: &CyclicComponents| c.forward.clone())
                as &dyn Fn(&CyclicComponents) -> Vec<Vec<f64>>,
        ),
        ("backward", &|c: &CyclicComponents| c.backward.clone()),
    ] {
        put_f64(
            &mut components,
            name,
            &flat(points.iter().flat_map(|q| pick(&q.components)), m),
            &[p, data.harmonics + 1, m],
            "m",
            &format!("amplitude of the {name} traveling wave of nodal diameter d on harmonic k"),
        );
    }
    branch.add_group(components.finish());
    file.add_group(branch.finish());

    let mut linear = file.create_group("linear");
    linear.set_attr(
        "description",
        text("The linear response (no contact) of the observed dof."),
    );
    let l = data.linear.frequency_hz.len();
    put_f64(
        &mut linear,
        "frequency_hz",
        &data.linear.frequency_hz,
        &[l],
        "Hz",
        "frequencies",
    );
    put_f64(
        &mut linear,
        "amplitude",
        &flat(&data.linear.amplitude, n),
        &[l, n],
        "m",
        "largest displacement over the period, per frequency and sector",
    );
    file.add_group(linear.finish());

    let mut modes = file.create_group("modes");
    modes.set_attr(
        "description",
        text("Natural frequencies of the tuned wheel per nodal diameter."),
    );
    let d = data.natural_frequencies.len();
    let r = data
        .natural_frequencies
        .iter()
        .map(|(_, f)| f.len())
        .max()
        .unwrap_or(0);
    put_i64(
        &mut modes,
        "nodal_diameter",
        &data
            .natural_frequencies
            .iter()
            .map(|(d, _)| *d as i64)
            .collect::<Vec<_>>(),
        &[d],
        "nodal diameter",
    );
    put_f64(
        &mut modes,
        "frequency_hz",
        &flat(data.natural_frequencies.iter().map(|(_, f)| f), r),
        &[d, r],
        "Hz",
        "natural frequencies, increasing, per nodal diameter (NaN: none)",
    );
    file.add_group(modes.finish());

    if let Some(h) = &data.histories {
        let nt = h.time_s.len();
        let mut peak = file.create_group("peak");
        peak.set_attr(
            "description",
            text("Time histories over one period at the point of largest amplitude."),
        );
        peak.set_attr("point", AttrValue::I64(h.point as i64));
        peak.set_attr("frequency_hz", AttrValue::F64(h.frequency_hz));
        put_f64(&mut peak, "time_s", &h.time_s, &[nt], "s", "instants");
        put_f64(
            &mut peak,
            "displacement",
            &flat(&h.displacement, nt),
            &[h.displacement.len(), nt],
            "m",
            "observed displacement per sector",
        );
        put_f64(
            &mut peak,
            "velocity",
            &flat(&h.velocity, nt),
            &[h.velocity.len(), nt],
            "m/s",
            "observed velocity per sector",
        );
        put_f64(
            &mut peak,
            "contact_force",
            &flat(&h.contact_force, nt),
            &[n, nc, nt],
            "N",
            "contact force f >= 0 per sector and contact dof",
        );
        put_f64(
            &mut peak,
            "penetration",
            &flat(&h.penetration, nt),
            &[n, nc, nt],
            "m",
            "penetration x - g0 per sector and contact dof",
        );
        file.add_group(peak.finish());
    }
    file.write(path).map_err(h5_error(path))
}

/// Reads a results file back.
pub fn read(path: &Path) -> Result<ResultsData, ResultsError> {
    let file = hdf5_pure::File::open(path).map_err(h5_error(path))?;
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
    if version != Some(FORMAT_VERSION) {
        return Err(bad(format!(
            "format version {version:?}: this build reads version {FORMAT_VERSION}"
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
    let f64s =
        |name: &str, expected: &[Option<usize>]| -> Result<(Vec<f64>, Vec<usize>), ResultsError> {
            let dataset = file.dataset(name).map_err(h5_error(path))?;
            let shape: Vec<usize> = dataset
                .shape()
                .map_err(h5_error(path))?
                .into_iter()
                .map(|s| s as usize)
                .collect();
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
            let values = if shape.contains(&0) {
                Vec::new()
            } else {
                dataset.read_f64().map_err(h5_error(path))?
            };
            Ok((values, shape))
        };
    let i64s = |name: &str| -> Result<Vec<i64>, ResultsError> {
        let dataset = file.dataset(name).map_err(h5_error(path))?;
        let shape = dataset.shape().map_err(h5_error(path))?;
        if shape.contains(&0) {
            return Ok(Vec::new());
        }
        dataset.read_i64().map_err(h5_error(path))
    };
    let (frequency, shape) = f64s("branch/frequency_hz", &[None])?;
    let p = shape[0];
    let iterations = i64s("branch/iterations")?;
    let (residual, _) = f64s("branch/residual_norm", &[Some(p)])?;
    let converged = i64s("branch/converged")?;
    let (unknowns, shape) = f64s("branch/unknowns", &[Some(p), None])?;
    let u = shape[1];
    let (observed, _) = f64s(
        "branch/observed/coordinates",
        &[Some(p), Some(n), Some(size)],
    )?;
    let (amplitude, _) = f64s("branch/observed/amplitude", &[Some(p), Some(n)])?;
    let (max_abs, _) = f64s("branch/observed/max_abs", &[Some(p), Some(n)])?;
    let (velocity, _) = f64s("branch/observed/velocity_max_abs", &[Some(p), Some(n)])?;
    let (force, _) = f64s(
        "branch/contact/force_coordinates",
        &[Some(p), Some(n), Some(nc), Some(size)],
    )?;
    let (peak_force, _) = f64s("branch/contact/peak_force", &[Some(p), Some(n), Some(nc)])?;
    let (fraction, _) = f64s("branch/contact/fraction", &[Some(p), Some(n), Some(nc)])?;
    let (penetration, _) = f64s(
        "branch/contact/max_penetration",
        &[Some(p), Some(n), Some(nc)],
    )?;
    let in_contact = i64s("branch/contact/sectors_in_contact")?;
    let m = n / 2 + 1;
    let (forward, _) = f64s(
        "branch/components/forward",
        &[Some(p), Some(harmonics + 1), Some(m)],
    )?;
    let (backward, _) = f64s(
        "branch/components/backward",
        &[Some(p), Some(harmonics + 1), Some(m)],
    )?;
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
        points.push(PointResults {
            frequency_hz: frequency[i],
            iterations: iterations[i].max(0) as usize,
            residual_norm: residual[i],
            converged: converged[i] != 0,
            unknowns: slice(&unknowns, u),
            observed: rows(&slice(&observed, n * size), size),
            amplitude: slice(&amplitude, n),
            max_abs: slice(&max_abs, n),
            velocity_max_abs: slice(&velocity, n),
            contact_force: rows(&slice(&force, n * nc * size), size),
            peak_force: slice(&peak_force, n * nc),
            contact_fraction: slice(&fraction, n * nc),
            max_penetration: slice(&penetration, n * nc),
            sectors_in_contact: in_contact[i].max(0) as usize,
            components: CyclicComponents {
                sectors: n,
                harmonics,
                forward: rows(&slice(&forward, (harmonics + 1) * m), m),
                backward: rows(&slice(&backward, (harmonics + 1) * m), m),
            },
        });
    }
    let (linear_frequency, shape) = f64s("linear/frequency_hz", &[None])?;
    let (linear_amplitude, _) = f64s("linear/amplitude", &[Some(shape[0]), Some(n)])?;
    let diameters = i64s("modes/nodal_diameter")?;
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
        mode: string(&attrs, "mode")?,
        stop_json: string(&attrs, "stop_json")?,
        sectors: n,
        harmonics,
        time_samples: integer(&attrs, "time_samples")?,
        observed_dof: integer(&attrs, "observed_dof")?,
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
    })
}
