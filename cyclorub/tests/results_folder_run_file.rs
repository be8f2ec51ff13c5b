//! The one reader of a results folder (issue 41 item 4): `run.json` read
//! back typed (`ResultsFolder::record`) holds what the run recorded: the
//! case, the basis, the stop, the timings and a mistuned wheel's record
//! field for field (`MistuningSummary` mirrors the writer's
//! `MistuningRecord`, which sits above `results`).

use cyclorub::case::{BasisChoice, Case};
use cyclorub::results::folder::{read_run_case, MistuningSummary, ResultsFolder};
use cyclorub::run::{run, RunOptions};
use std::path::Path;

/// A linear mistuned wheel of 6 sectors (the casing 1 m away), solved at
/// a few frequencies on the full wheel.
fn mistuned_run(output: &Path) -> cyclorub::run::RunRecord {
    let text = "[model]\nsectors = 6\n[harmonic_balance]\nharmonics = 1\ntime_samples = 96\n\
                [casing]\ngap = 1.0\n[basis]\nkind = \"physical\"\n\
                [mistuning]\nstandard_deviation = 0.01\nseed = 4\n\
                [output]\nfigures = [\"svg\"]\n";
    let case = Case::from_toml(text, Path::new("case.toml")).expect("case");
    let options = RunOptions {
        output: output.to_path_buf(),
        basis: BasisChoice::Physical,
        at_hz: Some(vec![206.0, 208.0, 209.0, 210.0, 211.0, 212.0]),
        stability: None,
        overwrite: true,
        interrupt: Default::default(),
    };
    run(&case, Path::new("."), &options, |_| {}).expect("run")
}

#[test]
fn the_typed_run_json_holds_what_the_run_recorded() {
    let output = std::env::temp_dir().join(format!("cyclorub-run-file-{}", std::process::id()));
    let written = mistuned_run(&output);
    let folder = ResultsFolder::read(&output).expect("read");
    let record = &folder.record;
    assert!(!record.is_running());
    assert_eq!(record.case, written.case);
    assert_eq!(record.stop.as_ref(), Some(&written.stop));
    assert_eq!(
        record
            .basis_choice(&output.join("run.json"))
            .expect("basis"),
        BasisChoice::Physical
    );
    let timings = record.timings.as_ref().expect("timings");
    assert_eq!(timings.solve_s.to_bits(), written.timings.solve_s.to_bits());
    // The mistuning record, field for field, through JSON and back.
    let mistuning = written.mistuning.expect("a mistuned run has its record");
    let read = record.mistuning.clone().expect("read back");
    let expected = MistuningSummary {
        deviations: mistuning.deviations.clone(),
        sector_peaks_m: mistuning.sector_peaks_m.clone(),
        sector_peak_frequencies_hz: mistuning.sector_peak_frequencies_hz.clone(),
        most_responding_sector: mistuning.most_responding_sector,
        tuned_peak_m: mistuning.tuned_peak_m,
        tuned_reference: mistuning.tuned_reference.clone(),
        amplification_factor: mistuning.amplification_factor,
        no_factor_reason: mistuning.no_factor_reason.clone(),
    };
    assert_eq!(read, expected);
    // Serialized again, it is the writer's JSON.
    assert_eq!(
        serde_json::to_value(&read).expect("json"),
        serde_json::to_value(&mistuning).expect("json")
    );
    assert_eq!(
        folder.run.get("mistuning").cloned(),
        Some(serde_json::to_value(&mistuning).expect("json"))
    );
    assert_eq!(mistuning.deviations.len(), 6);
    // The CLI's reader of a run's case agrees.
    let (case, basis) = read_run_case(&output).expect("case");
    assert_eq!((case, basis), (written.case.clone(), BasisChoice::Physical));
    let _ = std::fs::remove_dir_all(&output);
}

#[cfg(feature = "hdf5")]
#[test]
fn with_the_results_file_the_reader_keeps_all_it_holds() {
    let output = std::env::temp_dir().join(format!("cyclorub-run-file-h5-{}", std::process::id()));
    mistuned_run(&output);
    let folder = ResultsFolder::read_with_results_file(&output).expect("read");
    let data = folder.data.as_ref().expect("results.h5 read");
    assert_eq!(data.points.len(), folder.branch.rows.len());
    // branch.csv's frequencies are printed text: equal to round-off.
    for (point, row) in data.points.iter().zip(&folder.branch.rows) {
        assert!((point.frequency_hz - row.frequency_hz).abs() <= 1e-12 * row.frequency_hz);
    }
    // The observed coordinates come from results.h5 (no
    // observed_harmonics.csv in this folder).
    let sector = folder.branch.sectors[0];
    assert_eq!(
        folder.harmonics.get(&(0, sector)),
        data.points[0].observed.get(sector - 1)
    );
    // A folder without results.h5, or no folder at all, is refused by name.
    std::fs::remove_file(output.join(cyclorub::results::hdf5::FILE_NAME)).expect("remove");
    let refused = ResultsFolder::read_with_results_file(&output).unwrap_err();
    assert!(
        refused.to_string().contains("has no results.h5"),
        "{refused}"
    );
    let missing = ResultsFolder::read(&output.join("nothing")).unwrap_err();
    assert!(missing.to_string().contains("no such folder"), "{missing}");
    let _ = std::fs::remove_dir_all(&output);
}
