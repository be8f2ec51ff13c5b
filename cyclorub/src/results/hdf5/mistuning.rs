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
    // Absent when the factor is given, as in run.json.
    if let Some(reason) = &data.no_factor_reason {
        group.set_attr("no_factor_reason", text(reason));
    }
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
    // Absent: the factor was given, or the file predates the attribute.
    let no_factor_reason = match attrs.get("no_factor_reason") {
        None => None,
        Some(value) => Some(
            value
                .as_str()
                .map(str::to_string)
                .ok_or_else(|| bad("the attribute no_factor_reason is not text".into()))?,
        ),
    };
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
        no_factor_reason,
    }))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Two sectors' record, without a factor for `reason`.
    fn data(reason: Option<&str>) -> MistuningData {
        MistuningData {
            deviations: vec![0.01, -0.01],
            sector_peaks_m: vec![1e-4, f64::NAN],
            sector_peak_frequencies_hz: vec![200.0, f64::NAN],
            most_responding_sector: 1,
            tuned_peak_m: Some(9e-5),
            amplification_factor: None,
            tuned_reference: "the tuned wheel's nonlinear branch".into(),
            no_factor_reason: reason.map(str::to_string),
        }
    }

    /// Writes `data` as the only group of a file and reads it back.
    fn round_trip(name: &str, data: &MistuningData) -> MistuningData {
        let path = std::env::temp_dir().join(format!(
            "cyclorub-h5-mistuning-{}-{name}.h5",
            std::process::id()
        ));
        let mut file = FileBuilder::new();
        write(&mut file, data);
        file.write(&path).expect("write");
        let read_back = read(&hdf5_pure::File::open(&path).expect("open"), &path, 2)
            .expect("read")
            .expect("a mistuning group");
        let _ = std::fs::remove_file(&path);
        read_back
    }

    #[test]
    fn the_reason_without_a_factor_is_read_back() {
        let reason = "the mistuned curve stopped before the end of its frequency range";
        let read_back = round_trip("reason", &data(Some(reason)));
        assert_eq!(read_back.no_factor_reason.as_deref(), Some(reason));
        assert_eq!(read_back.amplification_factor, None);
    }

    #[test]
    fn a_file_without_the_reason_reads_as_none() {
        // Files written before the attribute (and runs with a factor) have
        // no `no_factor_reason`.
        let read_back = round_trip("none", &data(None));
        assert_eq!(read_back.no_factor_reason, None);
        assert_eq!(read_back.tuned_peak_m, Some(9e-5));
    }
}
