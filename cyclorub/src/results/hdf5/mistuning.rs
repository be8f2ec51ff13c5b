//! The `/mistuning` group of `results.h5` (see the module's layout): a
//! mistuned run's deviations and per-sector peaks.

use super::h5_error;
use super::put::{put_f64, text};
use crate::results::data::MistuningData;
use crate::results::ResultsError;
use hdf5_pure::{AttrValue, FileBuilder};
use std::path::Path;

/// Adds the group to a file being built.
pub(super) fn write(file: &mut FileBuilder, data: &MistuningData) {
    let n = data.deviations.len();
    let mut group = file.create_group("mistuning");
    group.set_attr(
        "description",
        text("A mistuned wheel (issue 44): the blade stiffness of sector j scaled by 1 + δ_j, and each sector's peak of the observed dof along the curve (run.json's mistuning record)."),
    );
    group.set_attr(
        "most_responding_sector",
        AttrValue::I64(data.most_responding_sector as i64),
    );
    // NaN: absent (the tuned branch could not be solved).
    group.set_attr(
        "tuned_peak_m",
        AttrValue::F64(data.tuned_peak_m.unwrap_or(f64::NAN)),
    );
    group.set_attr(
        "amplification_factor",
        AttrValue::F64(data.amplification_factor.unwrap_or(f64::NAN)),
    );
    group.set_attr("tuned_reference", text(&data.tuned_reference));
    put_f64(
        &mut group,
        "deviations",
        &data.deviations,
        &[n],
        "1",
        "the blade stiffness deviation δ_j of every sector",
    );
    put_f64(
        &mut group,
        "sector_peak",
        &data.sector_peaks_m,
        &[n],
        "m",
        "each sector's largest amplitude of the observed dof along the curve (branch.csv's amplitude)",
    );
    put_f64(
        &mut group,
        "sector_peak_frequency_hz",
        &data.sector_peak_frequencies_hz,
        &[n],
        "Hz",
        "where each sector peaks",
    );
    file.add_group(group.finish());
}

/// Reads the group, if the file has one (`sectors` values expected).
pub(super) fn read(
    file: &hdf5_pure::File,
    path: &Path,
    sectors: usize,
) -> Result<Option<MistuningData>, ResultsError> {
    let Ok(group) = file.group("mistuning") else {
        return Ok(None);
    };
    let bad = |message: String| ResultsError::Read {
        path: path.to_path_buf(),
        message: format!("mistuning: {message}"),
    };
    let attrs = group.attrs().map_err(h5_error(path))?;
    let number = |key: &str| match attrs.get(key) {
        Some(AttrValue::F64(x)) => Ok((!x.is_nan()).then_some(*x)),
        _ => Err(bad(format!("the attribute {key} is missing"))),
    };
    let most_responding_sector = match attrs.get("most_responding_sector") {
        // 0: no converged point (run.json's record says the same).
        Some(AttrValue::I64(s)) if *s >= 0 => *s as usize,
        _ => return Err(bad("the attribute most_responding_sector is missing".into())),
    };
    let tuned_reference = attrs
        .get("tuned_reference")
        .and_then(|v| v.as_str().map(str::to_string))
        .ok_or_else(|| bad("the attribute tuned_reference is missing".into()))?;
    let f64s = |name: &str| -> Result<Vec<f64>, ResultsError> {
        let values = file
            .dataset(&format!("mistuning/{name}"))
            .map_err(h5_error(path))?
            .read_f64()
            .map_err(h5_error(path))?;
        if values.len() != sectors {
            return Err(bad(format!(
                "{name} holds {} values, expected one per sector ({sectors})",
                values.len()
            )));
        }
        Ok(values)
    };
    Ok(Some(MistuningData {
        deviations: f64s("deviations")?,
        sector_peaks_m: f64s("sector_peak")?,
        sector_peak_frequencies_hz: f64s("sector_peak_frequency_hz")?,
        most_responding_sector,
        tuned_peak_m: number("tuned_peak_m")?,
        amplification_factor: number("amplification_factor")?,
        tuned_reference,
    }))
}
