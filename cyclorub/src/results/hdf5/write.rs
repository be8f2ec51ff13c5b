//! Writing `results.h5`: the datasets of a [`ResultsData`] with their units
//! and descriptions, in the layout of the module documentation.

use super::{h5_error, CONVENTIONS, FORMAT, FORMAT_VERSION};
use crate::results::components::CyclicComponents;
use crate::results::data::{PointResults, ResultsData};
use crate::results::recovery::harmonic_amplitudes;
use crate::results::ResultsError;
use hdf5_pure::{make_f64_type, make_i64_type, AttrValue, FileBuilder, LibVer};
use std::path::Path;

/// Where datasets can be created: the file's root or a group.
pub(super) trait Container {
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

pub(super) fn text(value: &str) -> AttrValue {
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

pub(super) fn put_f64(
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

pub(super) fn put_i64(
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

    if let Some(stability) = &data.stability {
        super::stability::write(&mut file, stability);
    }

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
