//! `cyclorub mesh fan` end to end on the coarse mesh: the files it writes,
//! what it prints, bad flags (exit code 2, naming the flag and what is
//! allowed) and an existing folder without `--overwrite`.

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

fn mesh(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_cyclorub"))
        .arg("mesh")
        .args(args)
        .output()
        .expect("the cyclorub binary runs")
}

/// A fresh (absent) scratch folder under the target directory.
fn scratch(name: &str) -> PathBuf {
    let dir = Path::new(env!("CARGO_TARGET_TMPDIR")).join(format!("mesh-cli-{name}"));
    let _ = std::fs::remove_dir_all(&dir);
    dir
}

fn text(bytes: &[u8]) -> String {
    String::from_utf8_lossy(bytes).into_owned()
}

#[test]
fn mesh_fan_writes_the_model_files_of_a_coarse_sector() {
    let dir = scratch("coarse");
    let out = mesh(&["fan", "--refine", "1", "--output", dir.to_str().unwrap()]);
    let stdout = text(&out.stdout);
    assert!(out.status.success(), "{}", text(&out.stderr));
    for file in [
        "sector_mass.mtx",
        "sector_stiffness.mtx",
        "nodes.csv",
        "node_sets.toml",
        "fan16.toml",
        "README.md",
    ] {
        let path = dir.join(file);
        let size = std::fs::metadata(&path).map(|m| m.len()).unwrap_or(0);
        assert!(size > 0, "{file} missing or empty");
        assert!(stdout.contains(&format!("{}", path.display())), "{stdout}");
    }
    assert!(
        stdout.contains("16 sectors, refine 1: 429 nodes, 1287 dofs"),
        "{stdout}"
    );
    assert!(stdout.contains("9 contact"), "{stdout}");
    let header = std::fs::read_to_string(dir.join("sector_stiffness.mtx")).unwrap();
    assert!(header.starts_with("%%MatrixMarket matrix coordinate real symmetric\n"));
    let case = std::fs::read_to_string(dir.join("fan16.toml")).unwrap();
    assert!(case.contains("kind = \"finite_element\"") && !case.contains("NOT RUNNABLE"));
    // Another sector count names its case file after it.
    let twelve = scratch("twelve");
    let out = mesh(&[
        "fan",
        "--sectors",
        "12",
        "--refine",
        "1",
        "--output",
        twelve.to_str().unwrap(),
    ]);
    assert!(out.status.success(), "{}", text(&out.stderr));
    assert!(twelve.join("fan12.toml").exists());
    for d in [dir, twelve] {
        std::fs::remove_dir_all(d).unwrap();
    }
}

#[test]
fn bad_flags_exit_2_naming_the_flag_and_what_is_allowed() {
    let dir = scratch("bad");
    let output = dir.to_str().unwrap();
    for (args, flag, allowed) in [
        (vec!["--sectors", "2"], "--sectors", "allowed 3 to 23"),
        (vec!["--sectors", "40"], "--sectors", "allowed 3 to 23"),
        (vec!["--refine", "0"], "--refine", "allowed 1"),
        (vec!["--refine", "9"], "--refine", "to 8"),
        (vec!["--sectors", "many"], "--sectors", "many"),
        (vec!["--refine", "-1"], "--refine", "-1"),
    ] {
        let mut all = vec!["fan", "--output", output];
        all.extend(&args);
        let out = mesh(&all);
        let stderr = text(&out.stderr);
        assert_eq!(out.status.code(), Some(2), "{args:?}: {stderr}");
        assert!(
            stderr.contains(flag) && stderr.contains(allowed),
            "{args:?}: {stderr}"
        );
    }
    // No folder is left behind by refused input.
    assert!(!dir.exists());
    let out = mesh(&["fan"]);
    assert_eq!(out.status.code(), Some(2));
    assert!(text(&out.stderr).contains("--output"));
}

#[test]
fn an_existing_folder_is_refused_without_overwrite() {
    let dir = scratch("existing");
    std::fs::create_dir_all(&dir).unwrap();
    std::fs::write(dir.join("notes.txt"), "mine").unwrap();
    let output = dir.to_str().unwrap();
    let out = mesh(&["fan", "--refine", "1", "--output", output]);
    let stderr = text(&out.stderr);
    assert_eq!(out.status.code(), Some(2), "{stderr}");
    assert!(
        stderr.contains("not empty") && stderr.contains("--overwrite"),
        "{stderr}"
    );
    assert!(!dir.join("sector_mass.mtx").exists());
    let out = mesh(&["fan", "--refine", "1", "--output", output, "--overwrite"]);
    assert!(out.status.success(), "{}", text(&out.stderr));
    assert!(dir.join("sector_mass.mtx").exists());
    assert_eq!(
        std::fs::read_to_string(dir.join("notes.txt")).unwrap(),
        "mine"
    );
    std::fs::remove_dir_all(dir).unwrap();
}
