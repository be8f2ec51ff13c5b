//! Writing `results.h5`: the datasets of a [`ResultsData`] with their units
//! and descriptions, in the layout of the module documentation.

use super::per_point::{columns, Contents, Sizes};
use super::put::{put_f64, put_f64_with, put_i64, text};
use super::{h5_error, Stage, CONVENTIONS, FORMAT, FORMAT_VERSION};
use crate::results::data::ResultsData;
use crate::results::ResultsError;
use hdf5_pure::{AttrValue, FileBuilder, LibVer};
use std::path::Path;

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

/// Writes `data` to `path` (replacing it), with every per-point dataset.
pub fn write(path: &Path, data: &ResultsData) -> Result<(), ResultsError> {
    write_with(path, data, Contents::ALL)
}

/// Writes `data` to `path` (replacing it), with the per-point datasets
/// `contents` asks for.
pub fn write_with(path: &Path, data: &ResultsData, contents: Contents) -> Result<(), ResultsError> {
    write_stage(path, data, contents, Stage::Complete, None)
}

/// Writes `data` to `path` through a temporary file renamed over it, so
/// that `path` always holds a whole file; `unknowns` overrides the
/// unknown count of a file without points.
pub(super) fn write_stage(
    path: &Path,
    data: &ResultsData,
    contents: Contents,
    stage: Stage,
    unknowns: Option<usize>,
) -> Result<(), ResultsError> {
    let n = data.sectors;
    let size = 2 * data.harmonics + 1;
    let nc = data.contact_dofs.len();
    let sizes = Sizes {
        unknowns: unknowns.unwrap_or(Sizes::of(data).unknowns),
        ..Sizes::of(data)
    };
    if let Some(bad) = data.points.iter().position(|q| {
        q.unknowns.len() != sizes.unknowns
            || q.observed.len() != n
            || q.observed.iter().any(|c| c.len() != size)
            || (contents.contact_harmonics && q.contact_force.len() != n * nc)
    }) {
        return Err(ResultsError::Input(format!(
            "point {bad} does not have the shape of the others (N = {n}, N_h = {}, {nc} contact dofs, {} unknowns)",
            data.harmonics, sizes.unknowns
        )));
    }
    let mut file = FileBuilder::new();
    file.with_libver_bounds(LibVer::V110, LibVer::V110);
    file.set_attr("format", text(FORMAT));
    file.set_attr("format_version", AttrValue::I64(FORMAT_VERSION));
    file.set_attr("cyclorub_version", text(env!("CARGO_PKG_VERSION")));
    file.set_attr("status", text(stage.name()));
    file.set_attr("sectors", AttrValue::I64(n as i64));
    file.set_attr("harmonics", AttrValue::I64(data.harmonics as i64));
    file.set_attr("time_samples", AttrValue::I64(data.time_samples as i64));
    file.set_attr("observed_dof", AttrValue::I64(data.observed_dof as i64));
    file.set_attr("observed_name", text(&data.observed_name));
    file.set_attr(
        "contact_dofs",
        AttrValue::I64Array(data.contact_dofs.iter().map(|&d| d as i64).collect()),
    );
    file.set_attr("mode", text(data.mode.word()));
    file.set_attr("case_json", text(&data.case_json));
    file.set_attr("basis_json", text(&data.basis_json));
    file.set_attr("stop_json", text(&data.stop_json));
    // −1: no gap (an optional value, read back as absent).
    file.set_attr(
        "gap_after",
        AttrValue::I64(data.gap_after.map_or(-1, |p| p as i64)),
    );
    file.set_attr("conventions", text(CONVENTIONS));

    let columns = columns(sizes, contents);
    let mut branch = file.create_group("branch");
    branch.set_attr(
        "description",
        text(match stage {
            Stage::Complete => "One entry per point of the branch, in continuation order.",
            Stage::Running => "One entry per point, in the order the run accepted them (with both ends, the sweep back's points follow the first sweep's).",
        }),
    );
    for column in columns.iter().filter(|c| c.group == "branch") {
        column.create(&mut branch, &data.points);
    }
    for (name, description) in [
        (
            "observed",
            "The observed dof (root attribute observed_dof) on every sector.",
        ),
        (
            "contact",
            "Contact state of every contact dof (root attribute contact_dofs) on every sector.",
        ),
    ] {
        let mut group = branch.create_group(name);
        group.set_attr("description", text(description));
        let full = format!("branch/{name}");
        for column in columns.iter().filter(|c| c.group == full) {
            column.create(&mut group, &data.points);
        }
        branch.add_group(group.finish());
    }
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

    if let Some(mistuning) = &data.mistuning {
        super::mistuning::write(&mut file, mistuning);
    }

    super::branches::write(&mut file, &data.branches);

    if let Some(h) = &data.histories {
        let nt = h.time_s.len();
        let mut peak = file.create_group("peak");
        peak.set_attr(
            "description",
            text("Time histories over one period at the point of largest amplitude."),
        );
        peak.set_attr("point", AttrValue::I64(h.point as i64));
        peak.set_attr("frequency_hz", AttrValue::F64(h.frequency_hz));
        put_f64_with(
            &mut peak,
            "time_s",
            &h.time_s,
            &[nt],
            "s",
            "instants",
            false,
        );
        put_f64_with(
            &mut peak,
            "displacement",
            &flat(&h.displacement, nt),
            &[h.displacement.len(), nt],
            "m",
            "observed displacement per sector",
            false,
        );
        put_f64_with(
            &mut peak,
            "velocity",
            &flat(&h.velocity, nt),
            &[h.velocity.len(), nt],
            "m/s",
            "observed velocity per sector",
            false,
        );
        put_f64_with(
            &mut peak,
            "contact_force",
            &flat(&h.contact_force, nt),
            &[n, nc, nt],
            "N",
            "contact force f >= 0 per sector and contact dof",
            false,
        );
        put_f64_with(
            &mut peak,
            "penetration",
            &flat(&h.penetration, nt),
            &[n, nc, nt],
            "m",
            "penetration x - g0 per sector and contact dof",
            false,
        );
        file.add_group(peak.finish());
    }
    let partial = path.with_extension("h5.partial");
    file.write(&partial).map_err(h5_error(path))?;
    std::fs::rename(&partial, path).map_err(|source| ResultsError::Io {
        path: path.to_path_buf(),
        source,
    })
}
