//! `simulation.h5` (feature `hdf5`):
//!
//! ```text
//! /envelope/end_time_s        [P]         s
//! /envelope/frequency_hz      [P]         Hz
//! /envelope/maxima            [P, N]      m   largest observed displacement per period
//! /envelope/peak_force        [P, N]      N   largest contact force per period
//! /poincare/displacement      [P, N]      m   observed dof at each period's end
//! /poincare/velocity          [P, N]      m/s
//! /history/time_s             [S]         s   every step of the last periods
//! /history/displacement       [S, N]      m   observed dof
//! /history/velocity           [S, N]      m/s observed dof
//! /history/contact_displacement [S, N, n_c] m
//! /history/contact_velocity   [S, N, n_c] m/s
//! /history/contact_force      [S, N, n_c] N   (acts as −f on the blade)
//! ```

use super::run::SimulationOutcome;
use super::SimulateError;
use hdf5_pure::{make_f64_type, AttrValue, FileBuilder, GroupBuilder, LibVer};
use std::path::Path;

fn put(
    group: &mut GroupBuilder,
    name: &str,
    data: &[f64],
    shape: &[usize],
    unit: &str,
    description: &str,
) {
    let builder = group.create_dataset(name);
    if data.is_empty() {
        builder.with_dtype(make_f64_type());
    } else {
        builder.with_f64_data(data);
    }
    builder
        .with_shape(&shape.iter().map(|&s| s as u64).collect::<Vec<_>>())
        .set_attr("unit", AttrValue::VarLenString(unit.into()))
        .set_attr("description", AttrValue::VarLenString(description.into()));
}

/// Writes `simulation.h5`.
pub fn write(
    path: &Path,
    outcome: &SimulationOutcome,
    observed_dof: usize,
) -> Result<(), SimulateError> {
    let p = outcome.periods.len();
    let n = outcome.periods.first().map_or(0, |r| r.maxima.len());
    let mut file = FileBuilder::new();
    file.with_libver_bounds(LibVer::Earliest, LibVer::V18);
    file.set_attr(
        "format",
        AttrValue::VarLenString("cyclorub simulation".into()),
    );
    file.set_attr("format_version", AttrValue::I64(1));
    file.set_attr(
        "cyclorub_version",
        AttrValue::VarLenString(env!("CARGO_PKG_VERSION").into()),
    );
    file.set_attr("sectors", AttrValue::I64(n as i64));
    file.set_attr("observed_dof", AttrValue::I64(observed_dof as i64));
    file.set_attr("step_s", AttrValue::F64(outcome.step));
    let flat = |f: &dyn Fn(&super::PeriodRecord) -> &[f64]| -> Vec<f64> {
        outcome.periods.iter().flat_map(|r| f(r).to_vec()).collect()
    };
    let mut envelope = file.create_group("envelope");
    let times: Vec<f64> = outcome.periods.iter().map(|r| r.end_time).collect();
    let frequencies: Vec<f64> = outcome.periods.iter().map(|r| r.frequency_hz).collect();
    put(
        &mut envelope,
        "end_time_s",
        &times,
        &[p],
        "s",
        "time at the end of each excitation period",
    );
    put(
        &mut envelope,
        "frequency_hz",
        &frequencies,
        &[p],
        "Hz",
        "instantaneous excitation frequency at the end of each period",
    );
    put(
        &mut envelope,
        "maxima",
        &flat(&|r| &r.maxima),
        &[p, n],
        "m",
        "largest displacement of the observed dof over each period, per sector",
    );
    put(
        &mut envelope,
        "peak_force",
        &flat(&|r| &r.peak_force),
        &[p, n],
        "N",
        "largest contact force over each period, per sector",
    );
    file.add_group(envelope.finish());
    let mut poincare = file.create_group("poincare");
    put(
        &mut poincare,
        "displacement",
        &flat(&|r| &r.section_displacement),
        &[p, n],
        "m",
        "observed dof at the end of each period, per sector",
    );
    put(
        &mut poincare,
        "velocity",
        &flat(&|r| &r.section_velocity),
        &[p, n],
        "m/s",
        "observed dof's velocity at the end of each period, per sector",
    );
    file.add_group(poincare.finish());
    let h = &outcome.history;
    let s = h.time.len();
    let nc = h.contact_force.len().checked_div(s * n).unwrap_or(0);
    let mut history = file.create_group("history");
    put(
        &mut history,
        "time_s",
        &h.time,
        &[s],
        "s",
        "every step of the last periods",
    );
    put(
        &mut history,
        "displacement",
        &h.observed_displacement,
        &[s, n],
        "m",
        "observed dof per sector",
    );
    put(
        &mut history,
        "velocity",
        &h.observed_velocity,
        &[s, n],
        "m/s",
        "observed dof per sector",
    );
    put(
        &mut history,
        "contact_displacement",
        &h.contact_displacement,
        &[s, n, nc],
        "m",
        "contact dofs per sector",
    );
    put(
        &mut history,
        "contact_velocity",
        &h.contact_velocity,
        &[s, n, nc],
        "m/s",
        "contact dofs per sector",
    );
    put(
        &mut history,
        "contact_force",
        &h.contact_force,
        &[s, n, nc],
        "N",
        "contact force f >= 0 per sector and contact dof (acts as -f on the blade)",
    );
    file.add_group(history.finish());
    file.write(path).map_err(|e| SimulateError::Write {
        path: path.to_path_buf(),
        message: e.to_string(),
    })
}
