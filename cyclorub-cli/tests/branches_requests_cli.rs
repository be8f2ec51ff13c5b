//! What `cyclorub branches` (and `run --branches`) refuse before any work,
//! and what a results folder keeps of them: an overwritten run starts with
//! no branches of the earlier one, a branch point switched at again says
//! it replaces its record.

use crate::common::{cyclorub, text};
use std::path::Path;

fn scratch(name: &str) -> crate::common::Scratch {
    crate::common::scratch("branches-requests", name)
}

/// Six academic sectors in contact, traveling h = 2 of `amplitude` N,
/// three harmonics; `extra` ends the file.
fn six_sectors(amplitude: f64, extra: &str) -> String {
    format!(
        "[model]\nkind = \"academic\"\nsectors = 6\n\
         [excitation]\nkind = \"traveling\"\nengine_order = 2\namplitude = {amplitude}\ndofs = [1]\n\
         [casing]\ngap = 1e-3\n\
         [contact]\nlaw = \"regularized\"\ndofs = [1]\nstiffness = 1e8\nregularization = 2.5\n\
         [harmonic_balance]\nharmonics = 3\ntime_samples = 60\n\
         [continuation]\nmax_points = 300\n\
         [output]\nfigures = [\"svg\"]\n{extra}"
    )
}

fn write_case(dir: &Path, name: &str, case: &str) -> String {
    let path = dir.join(format!("{name}.toml"));
    std::fs::write(&path, case).unwrap();
    path.to_str().unwrap().to_string()
}

fn json(path: &Path) -> serde_json::Value {
    serde_json::from_str(&std::fs::read_to_string(path).unwrap()).unwrap()
}

/// F02, F10, F11: `--overwrite` clears the earlier run's derived outputs;
/// `branches` keeps only this run's records and says when it replaces
/// one; a class is range-checked before any arithmetic; a marker that is
/// not a branch point is refused by name.
#[test]
fn an_overwritten_run_keeps_no_branches_of_the_earlier_one() {
    let dir = scratch("overwrite");
    let results = dir.join("r");
    let r = results.to_str().unwrap();
    let first = write_case(&dir, "first", &six_sectors(4.0, ""));
    // Stopped by the point cap past its branch point (exit code 1).
    let run = cyclorub(&["run", &first, "--output", r]);
    assert!(results.join("run.json").is_file(), "{}", text(&run));
    let out = cyclorub(&["branches", r, "--max-points", "3"]);
    assert!(out.status.success(), "{}", text(&out));
    assert!(results.join("branches").join("branches.json").is_file());
    std::fs::write(results.join("recovered_point0_dof1.csv"), "old\n").unwrap();

    // F10: out of range, however far, before any arithmetic.
    for class in [
        "-9223372036854775807",
        "-9223372036854775808",
        "9223372036854775807",
        "4",
    ] {
        let out = cyclorub(&[
            "branches",
            r,
            &format!("--class={class}"),
            "--max-points",
            "3",
        ]);
        assert_eq!(out.status.code(), Some(2), "{class}: {}", text(&out));
        assert!(
            text(&out).contains(&format!(
                "--class {class}: give a class σ with −N/2 < σ ≤ N/2 (N = 6: -2 to 3)"
            )),
            "{}",
            text(&out)
        );
    }
    // F11: a marker that is not a branch point.
    let record = json(&results.join("run.json"));
    let markers = record["stability"]["markers"].as_array().unwrap();
    if let Some(other) = markers.iter().position(|m| m["kind"] != "branch_point") {
        let out = cyclorub(&["branches", r, "--marker", &other.to_string()]);
        assert_eq!(out.status.code(), Some(2), "{}", text(&out));
        assert!(
            text(&out).contains(&format!("marker {other} is not a branch point")),
            "{}",
            text(&out)
        );
    }
    // A branch point switched at again: its record replaced, and said.
    if let Some(bp) = markers.iter().position(|m| m["kind"] == "branch_point") {
        let out = cyclorub(&[
            "branches",
            r,
            "--marker",
            &bp.to_string(),
            "--max-points",
            "2",
        ]);
        assert!(out.status.success(), "{}", text(&out));
        assert!(
            text(&out).contains("its record is replaced by this one (--max-points 2)"),
            "{}",
            text(&out)
        );
    }

    // Another force, the same folder overwritten: nothing of the first.
    let second = write_case(&dir, "second", &six_sectors(3.0, ""));
    let run = cyclorub(&["run", &second, "--output", r, "--overwrite"]);
    assert!(results.join("run.json").is_file(), "{}", text(&run));
    assert!(!results.join("branches").exists());
    assert!(!results.join("recovered_point0_dof1.csv").exists());
    // A branches.json left by an older version's overwrite: its entries
    // are not this run's, and are dropped with their CSVs.
    std::fs::create_dir_all(results.join("branches")).unwrap();
    std::fs::write(
        results.join("branches").join("class9_1.0000Hz.csv"),
        "old\n",
    )
    .unwrap();
    std::fs::write(
        results.join("branches").join("branches.json"),
        r#"[{"marker": 0, "marker_hz": 1.0, "class": 9, "parent_point": 0,
             "branch_point_hz": 1.0, "file": "branches/class9_1.0000Hz.csv"}]"#,
    )
    .unwrap();
    let out = cyclorub(&["branches", r, "--max-points", "3"]);
    assert!(out.status.success(), "{}", text(&out));
    assert!(!results
        .join("branches")
        .join("class9_1.0000Hz.csv")
        .exists());
    let listed = json(&results.join("branches").join("branches.json"));
    let recorded = json(&results.join("run.json"));
    assert_eq!(&listed, &recorded["branches"], "{listed}");
    assert!(listed.as_array().unwrap().iter().all(|b| b["class"] != 9));
    let _ = std::fs::remove_dir_all(&dir);
}

/// F09: `run --branches` is refused before the solve when the run can
/// have no branch point to switch at, and `branches` says why on a
/// physical run (exit code 2).
#[test]
fn branches_are_refused_before_the_solve_when_there_can_be_none() {
    let dir = scratch("refused");
    let no_stability = write_case(
        &dir,
        "s",
        &six_sectors(4.0, "[stability]\nenabled = false\n"),
    );
    let out_folder = dir.join("a");
    let out = cyclorub(&[
        "run",
        &no_stability,
        "--branches",
        "--output",
        out_folder.to_str().unwrap(),
    ]);
    assert_eq!(out.status.code(), Some(2), "{}", text(&out));
    assert!(
        text(&out).contains("[stability] enabled = false") && !text(&out).contains("give --class"),
        "{}",
        text(&out)
    );
    assert!(
        !out_folder.join("run.json").exists(),
        "refused before the solve"
    );
    let mistuned = six_sectors(
        4.0,
        "[basis]\nkind = \"physical\"\n[mistuning]\nstandard_deviation = 0.02\nseed = 3\n",
    );
    let physical = write_case(&dir, "p", &mistuned);
    let folder = dir.join("b");
    let b = folder.to_str().unwrap();
    let out = cyclorub(&["run", &physical, "--branches", "--output", b]);
    assert_eq!(out.status.code(), Some(2), "{}", text(&out));
    assert!(text(&out).contains("physical full wheel"), "{}", text(&out));
    assert!(
        !folder.join("run.json").exists(),
        "refused before the solve"
    );
    let run = cyclorub(&["run", &physical, "--output", b, "--at-hz", "200,204"]);
    assert!(run.status.success(), "{}", text(&run));
    let out = cyclorub(&["branches", b, "--marker", "0"]);
    assert_eq!(out.status.code(), Some(2), "{}", text(&out));
    assert!(text(&out).contains("physical full wheel"), "{}", text(&out));
    let _ = std::fs::remove_dir_all(&dir);
}
