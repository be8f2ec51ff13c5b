//! A mistuned run's `results.h5` (issue 44 item 4): its `/mistuning` group
//! holds `run.json`'s record (deviations, per-sector peaks with their
//! units), and the peaks are the largest of the per-point sector
//! amplitudes the same file stores; read back in Rust and by h5py (the
//! HDF5 C library), when Python has it.

use crate::common::h5py::read_with_h5py;
use crate::mistuning::{case, deviations_toml};
use cyclorub::case::BasisChoice;
use cyclorub::results::hdf5;
use cyclorub::run::{run, RunOptions};
use std::path::Path;

#[test]
fn a_mistuned_runs_results_file_holds_its_sector_peaks_with_units() {
    let deviations = [0.03, -0.02, 0.05, 0.0, -0.04, 0.01];
    let case = case(&format!(
        "[model]\nsectors = 6\n[harmonic_balance]\nharmonics = 3\ntime_samples = 96\n\
         [casing]\ngap = 2e-4\n{}",
        deviations_toml(&deviations)
    ));
    let output = std::env::temp_dir().join(format!("cyclorub-mistuning-h5-{}", std::process::id()));
    let options = RunOptions {
        output: output.clone(),
        basis: BasisChoice::Physical,
        at_hz: Some(vec![195.0, 200.0, 204.0, 206.0, 210.0]),
        stability: None,
        overwrite: true,
        interrupt: Default::default(),
    };
    let record = run(&case, Path::new("."), &options, |_| {}).unwrap();
    let m = record
        .mistuning
        .expect("a mistuned run has a mistuning record");
    let path = output.join(hdf5::FILE_NAME);
    let data = hdf5::read(&path).unwrap();
    assert_eq!(data.mistuning, Some(m.data()));
    let stored = data.mistuning.unwrap();
    assert_eq!(stored.deviations, deviations);
    // Each sector's peak is the largest of its amplitudes along the curve
    // (/branch/observed/amplitude), and where it is.
    for j in 0..6 {
        let (at, largest) = data
            .points
            .iter()
            .filter(|p| p.converged)
            .map(|p| (p.frequency_hz, p.amplitude[j]))
            .fold((f64::NAN, 0.0_f64), |b, x| if x.1 > b.1 { x } else { b });
        assert_eq!(stored.sector_peaks_m[j], largest, "sector {}", j + 1);
        assert_eq!(stored.sector_peak_frequencies_hz[j], at, "sector {}", j + 1);
    }
    // A tuned run has no /mistuning group.
    let mut tuned = case.clone();
    tuned.mistuning = Default::default();
    run(&tuned, Path::new("."), &options, |_| {}).unwrap();
    assert_eq!(hdf5::read(&path).unwrap().mistuning, None);
    run(&case, Path::new("."), &options, |_| {}).unwrap();
    let script = r#"
import sys, json, h5py
g = h5py.File(sys.argv[1], "r")["mistuning"]
print(json.dumps({
    "units": [g[k].attrs["unit"] for k in ("deviations", "sector_peak", "sector_peak_frequency_hz")],
    "peaks": g["sector_peak"][()].tolist(),
    "factor": float(g.attrs["amplification_factor"]),
    "most": int(g.attrs["most_responding_sector"]),
}))
"#;
    let v = read_with_h5py(script, &path);
    let _ = std::fs::remove_dir_all(&output);
    let Some(v) = v else { return };
    assert_eq!(v["units"], serde_json::json!(["1", "m", "Hz"]));
    let peaks: Vec<f64> = serde_json::from_value(v["peaks"].clone()).unwrap();
    assert_eq!(peaks, m.sector_peaks_m);
    assert_eq!(v["factor"].as_f64(), m.amplification_factor);
    assert_eq!(v["most"].as_u64(), Some(m.most_responding_sector as u64));
}

/// A mistuned run whose points all fail to converge keeps what it has:
/// `run.json` and `results.h5` are written with its record, and the
/// figures that have nothing to draw (the sector curves) are skipped, not
/// an error that loses the run.
#[test]
fn a_mistuned_run_with_no_converged_point_keeps_its_results() {
    let case = case(&format!(
        "[model]\nsectors = 6\n[harmonic_balance]\nharmonics = 3\ntime_samples = 96\n\
         [casing]\ngap = 2e-5\n[continuation]\nmax_iterations = 1\ntolerance = 1e-14\n{}",
        deviations_toml(&[0.03, -0.02, 0.05, 0.0, -0.04, 0.01])
    ));
    let output =
        std::env::temp_dir().join(format!("cyclorub-mistuning-none-{}", std::process::id()));
    let options = RunOptions {
        output: output.clone(),
        basis: BasisChoice::Physical,
        at_hz: Some(vec![204.0, 206.0]),
        stability: None,
        overwrite: true,
        interrupt: Default::default(),
    };
    let record = run(&case, Path::new("."), &options, |_| {}).unwrap();
    let data = hdf5::read(&output.join(hdf5::FILE_NAME)).unwrap();
    assert!(
        data.points.iter().all(|p| !p.converged),
        "a point converged"
    );
    assert!(record.mistuning.is_some());
    assert!(output.join("run.json").is_file());
    assert!(!output
        .join("plots")
        .join(cyclorub::plot::mistuning::SECTOR_AMPLITUDES)
        .exists());
    let _ = std::fs::remove_dir_all(&output);
}

/// A wheel held away from the casing (a static force of −400 N on the tip,
/// one sector excited): no sector's largest value is positive, so none has
/// a peak. run.json records `null` rather than a negative "peak", the most
/// responding sector is 0, and results.h5 holds the same record with the
/// reason there is no amplification factor.
#[test]
fn a_wheel_held_away_from_the_casing_records_no_sector_peak() {
    let case = case(
        "[model]\nsectors = 6\n[excitation]\nkind = \"per_sector\"\n\
         amplitudes = [1.0, 0.0, 0.0, 0.0, 0.0, 0.0]\nphases = [0.0, 0.0, 0.0, 0.0, 0.0, 0.0]\n\
         static_force = -400.0\n[harmonic_balance]\nharmonics = 1\ntime_samples = 32\n\
         [casing]\ngap = 1.0\n[stability]\nenabled = false\n\
         [mistuning]\nstandard_deviation = 0.01\nseed = 1\n",
    );
    let output =
        std::env::temp_dir().join(format!("cyclorub-mistuning-away-{}", std::process::id()));
    let options = RunOptions {
        output: output.clone(),
        basis: BasisChoice::Physical,
        at_hz: Some(vec![100.0, 150.0]),
        stability: None,
        overwrite: true,
        interrupt: Default::default(),
    };
    let record = run(&case, Path::new("."), &options, |_| {}).unwrap();
    let m = record.mistuning.expect("a mistuning record");
    let data = hdf5::read(&output.join(hdf5::FILE_NAME)).unwrap();
    // Every point converged, and every sector stays on the far side.
    assert!(data.points.iter().all(|p| p.converged));
    assert!(data
        .points
        .iter()
        .all(|p| p.amplitude.iter().all(|&a| a < 0.0)));
    assert!(m.sector_peaks_m.iter().all(|p| p.is_nan()), "{m:?}");
    assert!(m.sector_peak_frequencies_hz.iter().all(|f| f.is_nan()));
    assert_eq!(m.most_responding_sector, 0);
    assert_eq!(m.tuned_peak_m, None);
    assert_eq!(m.amplification_factor, None);
    let reason = m.no_factor_reason.clone().expect("a reason");
    assert!(reason.contains("moves toward the casing"), "{reason}");
    let json: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(output.join("run.json")).unwrap()).unwrap();
    let peaks = json["mistuning"]["sector_peaks_m"].as_array().unwrap();
    assert!(peaks.iter().all(serde_json::Value::is_null), "{peaks:?}");
    // results.h5: NaN where run.json has null (so not equal by `==`), and
    // the reason, read back.
    let stored = data.mistuning.expect("a /mistuning group");
    assert!(stored.sector_peaks_m.iter().all(|p| p.is_nan()));
    assert_eq!(stored.most_responding_sector, 0);
    assert_eq!(stored.no_factor_reason.as_deref(), Some(reason.as_str()));
    // The folder's reader takes run.json's nulls as NaN.
    let folder = cyclorub::results::folder::ResultsFolder::read(&output).unwrap();
    let summary = folder.record.mistuning.expect("run.json's mistuning");
    assert!(summary.sector_peaks_m.iter().all(|p| p.is_nan()));
    assert_eq!(summary.no_factor_reason, Some(reason));
    let _ = std::fs::remove_dir_all(&output);
}
