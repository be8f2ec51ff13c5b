//! `cyclorub run CASE --branches`, then `cyclorub branches` again: each
//! bifurcated branch is in the results folder like the symmetric one, a
//! `results.h5` group (read back by the library and by h5py) and a
//! `run.json` entry, equal to `branches/branches.json` and the branch CSV;
//! switching at a branch point again replaces its records.

use crate::common::h5py::read_with_h5py;
use crate::common::{cyclorub, text};
use cyclorub::results::bifurcated::{BifurcatedBranchData, BranchSummary};
use cyclorub::results::folder::RunFile;
use cyclorub::results::hdf5;
use std::path::Path;

/// The N = 6 chain, traveling h = 2: class-3 branch points near 211.247
/// and 212.354 Hz (42 of the full wheel's 126 unknowns).
const SIX_SECTORS: &str = "[model]\nsectors = 6\n[excitation]\nengine_order = 2\n";

fn json(path: &Path) -> serde_json::Value {
    serde_json::from_str(&std::fs::read_to_string(path).unwrap()).unwrap()
}

/// The `/branches` group as h5py reads it: per subgroup its attributes and
/// each side's arrays.
const H5PY_BRANCHES: &str = r#"
import sys, json, h5py
f = h5py.File(sys.argv[1], "r")
out = {}
for name, g in f["branches"].items():
    a = dict(g.attrs)
    sides = []
    for s in sorted(k for k in g if k.startswith("side_")):
        h = g[s]
        assert h["frequency_hz"].attrs["unit"] == "Hz"
        assert h["sector_amplitude"].attrs["unit"] == "m"
        sides.append({
            "direction": float(h.attrs["direction"]),
            "stop_reason": h.attrs["stop_reason"],
            "frequency_hz": [float(x) for x in h["frequency_hz"][:]],
            "stable": [int(x) for x in h["stable"][:]],
            "sector_amplitude": [[float(x) for x in row] for row in h["sector_amplitude"][:]],
        })
    out[name] = {"order": int(a["order"]), "class": int(a["class"]), "marker": int(a["marker"]),
                 "parent_point": int(a["parent_point"]),
                 "branch_point_hz": float(a["branch_point_hz"]),
                 "basis_unknowns": int(a["basis_unknowns"]),
                 "full_unknowns": int(a["full_unknowns"]), "file": a["file"], "sides": sides}
print(json.dumps(out))
"#;

/// Checks the three records of `results` against each other: run.json's
/// entry is branches.json; each branch of results.h5 (read by the library)
/// summarizes to it, and holds its CSV's numbers (printed to ten digits);
/// h5py reads the same numbers as the library. Returns the library's read.
fn records_agree(results: &Path) -> Vec<BifurcatedBranchData> {
    let listed = json(&results.join("branches/branches.json"));
    assert_eq!(json(&results.join("run.json"))["branches"], listed);
    let summaries: Vec<BranchSummary> = serde_json::from_value(listed).unwrap();
    // And as a reader of the folder takes run.json, typed.
    let run_json = results.join("run.json");
    let typed = RunFile::parse(&run_json, &std::fs::read_to_string(&run_json).unwrap()).unwrap();
    assert_eq!(typed.branches, summaries);
    let data = hdf5::read(&results.join(hdf5::FILE_NAME)).unwrap();
    let branches = data.branches;
    let mine: Vec<BranchSummary> = branches.iter().map(|b| b.summary()).collect();
    assert_eq!(mine, summaries);
    for branch in &branches {
        let csv = std::fs::read_to_string(results.join(branch.file.as_ref().unwrap())).unwrap();
        let rows: Vec<Vec<&str>> = csv
            .lines()
            .skip(1)
            .map(|l| l.split(',').collect())
            .collect();
        let points: Vec<(f64, f64, &Option<bool>, &Vec<f64>)> = branch
            .sides
            .iter()
            .flat_map(|s| {
                s.frequency_hz
                    .iter()
                    .zip(&s.stable)
                    .zip(&s.sector_amplitudes_m)
                    .map(|((f, v), a)| (s.direction, *f, v, a))
            })
            .collect();
        assert_eq!(rows.len(), points.len());
        for (row, (direction, hz, stable, amplitudes)) in rows.iter().zip(points) {
            assert_eq!(
                row[0].parse::<f64>().unwrap().to_bits(),
                direction.to_bits()
            );
            assert!(
                (row[2].parse::<f64>().unwrap() - hz).abs() <= 1e-10,
                "{row:?} {hz}"
            );
            let word = stable.map_or("", |s| if s { "stable" } else { "unstable" });
            assert_eq!(row[3], word);
            assert_eq!(row.len(), 7 + amplitudes.len());
            for (cell, a) in row[7..].iter().zip(amplitudes) {
                let printed: f64 = cell.parse().unwrap();
                assert!((printed - a).abs() <= 1e-10 * a, "{cell} against {a:e}");
            }
        }
    }
    if let Some(read) = read_with_h5py(H5PY_BRANCHES, &results.join(hdf5::FILE_NAME)) {
        let read = read.as_object().unwrap();
        assert_eq!(read.len(), branches.len());
        for branch in &branches {
            let name = branch.file.as_ref().unwrap();
            let name = name
                .trim_start_matches("branches/")
                .trim_end_matches(".csv");
            let g = &read[name];
            assert_eq!(g["class"].as_i64(), Some(branch.class));
            assert_eq!(g["marker"].as_u64(), branch.marker.map(|m| m as u64));
            assert_eq!(g["parent_point"].as_u64(), Some(branch.parent_point as u64));
            assert_eq!(g["branch_point_hz"].as_f64(), branch.branch_point_hz);
            assert_eq!(g["basis_unknowns"].as_u64(), Some(42));
            assert_eq!(g["full_unknowns"].as_u64(), Some(126));
            let sides = g["sides"].as_array().unwrap();
            assert_eq!(sides.len(), branch.sides.len());
            for (h, side) in sides.iter().zip(&branch.sides) {
                assert_eq!(h["direction"].as_f64(), Some(side.direction));
                assert_eq!(h["stop_reason"].as_str(), Some(side.stop_reason.as_str()));
                let f: Vec<f64> = serde_json::from_value(h["frequency_hz"].clone()).unwrap();
                assert_eq!(f, side.frequency_hz);
                let a: Vec<Vec<f64>> =
                    serde_json::from_value(h["sector_amplitude"].clone()).unwrap();
                assert_eq!(a, side.sector_amplitudes_m);
                let v: Vec<i64> = serde_json::from_value(h["stable"].clone()).unwrap();
                let expected: Vec<i64> = side
                    .stable
                    .iter()
                    .map(|s| s.map_or(-1, i64::from))
                    .collect();
                assert_eq!(v, expected);
            }
        }
    }
    branches
}

#[test]
fn the_bifurcated_branches_are_in_results_h5_and_run_json_once() {
    let dir = crate::common::scratch("branch-records", "bifurcated");
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    let case = dir.join("case.toml");
    std::fs::write(&case, SIX_SECTORS).unwrap();
    let results = dir.join("results");
    let out = cyclorub(&[
        "run",
        case.to_str().unwrap(),
        "--output",
        results.to_str().unwrap(),
        "--branches",
    ]);
    assert!(out.status.success(), "{}", text(&out));
    let first = records_agree(&results);
    let located: Vec<f64> = first.iter().map(|b| b.branch_point_hz.unwrap()).collect();
    assert_eq!(located.len(), 2, "{located:?}");
    assert!((located[0] - 211.2471).abs() < 1e-3 && (located[1] - 212.3540).abs() < 1e-3);
    for branch in &first {
        assert_eq!((branch.class, branch.basis_unknowns), (3, Some(42)));
        assert_eq!(branch.full_unknowns, Some(126));
        // Both sides run until they cross the symmetric branch again.
        for side in &branch.sides {
            assert!(side.frequency_hz.len() > 100);
            assert_eq!(side.stop["reason"], "rejoined");
            assert!(side.stable.iter().all(Option::is_none));
        }
    }
    // The parent point is the symmetric branch's point before the crossing.
    let data = hdf5::read(&results.join(hdf5::FILE_NAME)).unwrap();
    for branch in &first {
        let before = data.points[branch.parent_point].frequency_hz;
        let after = data.points[branch.parent_point + 1].frequency_hz;
        let hz = branch.branch_point_hz.unwrap();
        assert!(
            before.min(after) <= hz && hz <= before.max(after),
            "{before} {hz} {after}"
        );
    }
    // Again at the first one, shorter and with stability: its records
    // replaced, the other's kept, nothing repeated.
    let marker = first[0].marker.unwrap().to_string();
    let out = cyclorub(&[
        "branches",
        results.to_str().unwrap(),
        "--marker",
        &marker,
        "--max-points",
        "3",
        "--stability",
    ]);
    assert!(out.status.success(), "{}", text(&out));
    let again = records_agree(&results);
    assert_eq!(again.len(), 2);
    assert_eq!(again[0], first[1]);
    assert_eq!(again[1].branch_point_hz, first[0].branch_point_hz);
    for side in &again[1].sides {
        assert_eq!(side.frequency_hz.len(), 3);
        assert!(side.stable.iter().all(Option::is_some));
    }
    // The rest of results.h5 is as the run wrote it.
    let now = hdf5::read(&results.join(hdf5::FILE_NAME)).unwrap();
    assert!(now.points == data.points, "the points changed");
    // Debug text: its NaN (no off-contact bound) compares equal there.
    let shown = |d: &cyclorub::results::data::ResultsData| format!("{:?}", d.stability);
    assert!(shown(&now) == shown(&data), "the stability changed");
    let _ = std::fs::remove_dir_all(&dir);
}

/// A folder whose run did not finish (run.json `running`: going on, or
/// killed) is refused before any work, naming the folder and its status.
#[test]
fn branches_of_an_unfinished_run_are_refused() {
    let dir = crate::common::scratch("branch-running", "unfinished");
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    let case = serde_json::to_value(cyclorub::case::Case::default()).unwrap();
    let run = serde_json::json!({"status": "running", "case": case, "output": "x"});
    std::fs::write(dir.join("run.json"), run.to_string()).unwrap();
    let out = cyclorub(&["branches", dir.to_str().unwrap()]);
    assert_eq!(out.status.code(), Some(2), "{}", text(&out));
    let said = text(&out);
    assert!(
        said.contains(dir.to_str().unwrap()) && said.contains("\"running\""),
        "{said}"
    );
    assert!(!dir.join("branches").exists());
}
