//! `cyclorub branches RESULTS`: a branch-point marker of a run is switched
//! at, its bifurcated branch written (CSV, JSON, figure); so is a marker
//! where σ and −σ cross together (one vector of the two-dimensional
//! kernel followed).

use crate::common::{cyclorub, text};
use std::path::PathBuf;

/// Eight sectors, traveling h = 4: class 1 loses stability through a real
/// multiplier near 220.26 Hz, class 3 near 211.60 Hz through σ and −σ
/// together (a two-dimensional kernel: the class block's double real
/// eigenvalue changes sign, located at 211.596935 Hz).
const EIGHT_SECTORS: &str = "[model]\nsectors = 8\n[excitation]\nengine_order = 4\n";

#[test]
fn a_branch_point_marker_gives_a_bifurcated_branch_and_so_does_sigma_and_minus_sigma_together() {
    let dir = crate::common::scratch("branches-cli", "run");
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    let case = dir.join("case.toml");
    std::fs::write(&case, EIGHT_SECTORS).unwrap();
    let results: PathBuf = dir.join("results");
    let run = cyclorub(&[
        "run",
        case.to_str().unwrap(),
        "--output",
        results.to_str().unwrap(),
    ]);
    assert!(run.status.success(), "{}", text(&run));
    let record: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(results.join("run.json")).unwrap()).unwrap();
    let markers = record["stability"]["markers"].as_array().unwrap();
    let find = |class: i64, hz: f64| {
        markers
            .iter()
            .position(|m| {
                m["nodal_diameter"].as_i64() == Some(class)
                    && (m["frequency_hz"].as_f64().unwrap() - hz).abs() < 0.01
            })
            .unwrap()
    };
    let real = find(1, 220.256);
    let together = find(3, 211.597);
    let out = cyclorub(&[
        "branches",
        results.to_str().unwrap(),
        "--marker",
        &real.to_string(),
        "--max-points",
        "6",
    ]);
    assert!(out.status.success(), "{}", text(&out));
    let said = text(&out);
    assert!(said.contains("class 1 branch point at 220.25"), "{said}");
    let folder = results.join("branches");
    let json: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(folder.join("branches.json")).unwrap())
            .unwrap();
    let branch = &json[0];
    let located = branch["branch_point_hz"].as_f64().unwrap();
    assert!((located - 220.251).abs() < 0.001, "{located}");
    assert_eq!(branch["basis_unknowns"].as_u64(), Some(168));
    let file = results.join(branch["file"].as_str().unwrap());
    let table = std::fs::read_to_string(file).unwrap();
    // A header and six points on each side, every sector's amplitude.
    assert_eq!(table.lines().count(), 1 + 12, "{table}");
    assert!(table.lines().next().unwrap().ends_with("sector_8_m"));
    assert!(folder.join("branches.svg").is_file() && folder.join("branches.png").is_file());

    let out = cyclorub(&[
        "branches",
        results.to_str().unwrap(),
        "--marker",
        &together.to_string(),
        "--max-points",
        "2",
    ]);
    assert!(out.status.success(), "{}", text(&out));
    assert!(
        text(&out).contains("class 3 branch point at 211.5969"),
        "{}",
        text(&out)
    );
    // Without Hill's markers: the enlarged Jacobian finds the same crossing.
    let out = cyclorub(&[
        "branches",
        results.to_str().unwrap(),
        "--class",
        "1",
        "--max-points",
        "2",
    ]);
    assert!(out.status.success(), "{}", text(&out));
    assert!(
        text(&out).contains("class 1 branch point at 220.251"),
        "{}",
        text(&out)
    );
    // Its class block (the cosets of ±1) holds one crossing near the fold
    // at 212.702174 Hz: 212.702165 Hz. The one 8e-5 Hz from it (212.702245
    // Hz), which the whole new block listed for class 1 too, is class 2's:
    // `--class 2` finds it, at the same frequency.
    assert!(!text(&out).contains("212.702245"), "{}", text(&out));
    let out = cyclorub(&[
        "branches",
        results.to_str().unwrap(),
        "--class",
        "2",
        "--max-points",
        "2",
    ]);
    assert!(out.status.success(), "{}", text(&out));
    assert!(
        text(&out).contains("class 2 branch point at 212.702245"),
        "{}",
        text(&out)
    );
    let json: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(folder.join("branches.json")).unwrap())
            .unwrap();
    let mut files: Vec<&str> = json
        .as_array()
        .unwrap()
        .iter()
        .filter_map(|r| r["file"].as_str())
        .collect();
    for file in [
        "branches/class1_212.7022Hz.csv",
        "branches/class2_212.7022Hz.csv",
        "branches/class3_211.5969Hz.csv",
    ] {
        assert!(files.contains(&file), "{files:?}");
    }
    files.sort_unstable();
    let all = files.len();
    files.dedup();
    assert_eq!(files.len(), all, "{files:?}");
    let data = cyclorub::results::hdf5::read(&results.join("results.h5")).unwrap();
    let switched: Vec<&str> = data
        .branches
        .iter()
        .filter_map(|b| b.file.as_deref())
        .collect();
    assert_eq!(switched.len(), all);
    for branch in data.branches.iter().filter(|b| b.file.is_some()) {
        let table = std::fs::read_to_string(results.join(branch.file.as_ref().unwrap())).unwrap();
        let points: usize = branch.sides.iter().map(|s| s.frequency_hz.len()).sum();
        assert_eq!(table.lines().count(), 1 + points, "{:?}", branch.file);
    }
    let out = cyclorub(&["branches", results.to_str().unwrap(), "--marker", "100000"]);
    assert_eq!(out.status.code(), Some(2), "{}", text(&out));
    assert!(text(&out).contains("--marker 100000"), "{}", text(&out));
    let _ = std::fs::remove_dir_all(&dir);
}
