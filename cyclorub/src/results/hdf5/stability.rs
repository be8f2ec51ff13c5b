//! The `/stability` group of `results.h5` (see the module's layout).

use super::h5_error;
use super::put::{put_f64, put_i64, text};
use crate::results::stability::{StabilityData, LEADING};
use crate::results::ResultsError;
use hdf5_pure::{AttrValue, FileBuilder};
use std::path::Path;

/// Adds the group to a file being built.
pub(super) fn write(file: &mut FileBuilder, data: &StabilityData) {
    let (p, c) = (data.stable.len(), data.classes.len());
    let mut group = file.create_group("stability");
    group.set_attr(
        "description",
        text("Floquet exponents by Hill's method per symmetry class (nodal diameter of the perturbation); a point is unstable when an exponent has a positive real part."),
    );
    group.set_attr("harmonics", AttrValue::I64(data.harmonics as i64));
    let markers = serde_json::to_string(&data.markers).unwrap_or_else(|_| "[]".into());
    group.set_attr("markers_json", text(&markers));
    put_i64(
        &mut group,
        "nodal_diameter",
        &data.classes,
        &[c],
        "the classes' nodal diameters σ",
    );
    let stable: Vec<i64> = data.stable.iter().map(|&s| i64::from(s)).collect();
    put_i64(&mut group, "stable", &stable, &[p], "1: no exponent grows");
    let unstable: Vec<i64> = data.unstable_exponents.iter().map(|&u| u as i64).collect();
    put_i64(
        &mut group,
        "unstable_exponents",
        &unstable,
        &[p],
        "growing exponents of the wheel",
    );
    let flat = |values: &[Vec<Vec<f64>>]| -> Vec<f64> {
        values.iter().flatten().flatten().copied().collect()
    };
    put_f64(
        &mut group,
        "leading_re",
        &flat(&data.leading_re),
        &[p, c, LEADING],
        "1/s",
        "real parts of each class's exponents of largest real part (NaN: fewer)",
    );
    put_f64(
        &mut group,
        "leading_im",
        &flat(&data.leading_im),
        &[p, c, LEADING],
        "rad/s",
        "their imaginary parts",
    );
    put_f64(
        &mut group,
        "off_contact_bound",
        &data.off_contact_bound,
        &[p],
        "rad/s",
        "off contact: how far at most the contact moves the linear exponents (NaN: Hill's method)",
    );
    file.add_group(group.finish());
}

/// Reads the group, if the file has one (`points` rows expected).
pub(super) fn read(
    file: &hdf5_pure::File,
    path: &Path,
    points: usize,
) -> Result<Option<StabilityData>, ResultsError> {
    let Ok(group) = file.group("stability") else {
        return Ok(None);
    };
    let bad = |message: String| ResultsError::Read {
        path: path.to_path_buf(),
        message: format!("stability: {message}"),
    };
    let attrs = group.attrs().map_err(h5_error(path))?;
    let harmonics = match attrs.get("harmonics") {
        Some(AttrValue::I64(h)) if *h >= 0 => *h as usize,
        _ => return Err(bad("the attribute harmonics is missing".into())),
    };
    let markers = attrs
        .get("markers_json")
        .and_then(|v| v.as_str().map(str::to_string))
        .ok_or_else(|| bad("the attribute markers_json is missing".into()))?;
    let markers = serde_json::from_str(&markers).map_err(|e| bad(format!("markers_json: {e}")))?;
    let i64s = |name: &str| -> Result<Vec<i64>, ResultsError> {
        let dataset = file
            .dataset(&format!("stability/{name}"))
            .map_err(h5_error(path))?;
        if dataset.shape().map_err(h5_error(path))?.contains(&0) {
            return Ok(Vec::new());
        }
        dataset.read_i64().map_err(h5_error(path))
    };
    let f64s = |name: &str, expected: usize| -> Result<Vec<f64>, ResultsError> {
        let dataset = file
            .dataset(&format!("stability/{name}"))
            .map_err(h5_error(path))?;
        let values = if dataset.shape().map_err(h5_error(path))?.contains(&0) {
            Vec::new()
        } else {
            dataset.read_f64().map_err(h5_error(path))?
        };
        if values.len() != expected {
            return Err(bad(format!(
                "{name} holds {} values, expected {expected}",
                values.len()
            )));
        }
        Ok(values)
    };
    let classes = i64s("nodal_diameter")?;
    let c = classes.len();
    let stable = i64s("stable")?;
    let unstable = i64s("unstable_exponents")?;
    if stable.len() != points || unstable.len() != points {
        return Err(bad(format!("{} rows for {points} points", stable.len())));
    }
    let nest = |flat: Vec<f64>| -> Vec<Vec<Vec<f64>>> {
        // No class (no point checked by classes): an empty row a point.
        if c == 0 {
            return vec![Vec::new(); points];
        }
        flat.chunks(c * LEADING)
            .map(|row| row.chunks(LEADING).map(<[f64]>::to_vec).collect())
            .collect()
    };
    Ok(Some(StabilityData {
        harmonics,
        stable: stable.iter().map(|&s| s == 1).collect(),
        unstable_exponents: unstable.iter().map(|&u| u.max(0) as usize).collect(),
        leading_re: nest(f64s("leading_re", points * c * LEADING)?),
        leading_im: nest(f64s("leading_im", points * c * LEADING)?),
        off_contact_bound: f64s("off_contact_bound", points)?,
        classes,
        markers,
    }))
}
