//! `cyclorub modes`: table, JSON, plot, and errors with their exit codes.

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

fn fixture(name: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../cyclorub/tests/fixtures/model")
        .join(name)
}

fn scratch(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("cyclorub-modes-{}-{name}", std::process::id()));
    std::fs::create_dir_all(&dir).expect("scratch dir");
    dir
}

fn modes(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_cyclorub"))
        .arg("modes")
        .args(args)
        .output()
        .expect("run cyclorub")
}

fn text(bytes: &[u8]) -> String {
    String::from_utf8_lossy(bytes).into_owned()
}

#[test]
fn json_lists_every_nodal_diameter() {
    let case = fixture("academic.toml");
    let out = modes(&[case.to_str().expect("utf-8"), "--json", "--no-plot"]);
    assert!(out.status.success(), "{}", text(&out.stderr));
    let json: serde_json::Value = serde_json::from_slice(&out.stdout).expect("JSON on stdout");
    assert_eq!(json["sectors"], 24);
    let nds = json["nodal_diameters"].as_array().expect("array");
    assert_eq!(nds.len(), 13);
    for (d, entry) in nds.iter().enumerate() {
        assert_eq!(entry["nd"], d);
        let f: Vec<f64> = entry["frequencies_hz"]
            .as_array()
            .expect("frequencies")
            .iter()
            .map(|v| v.as_f64().expect("number"))
            .collect();
        assert_eq!(f.len(), 5);
        assert!(f.windows(2).all(|w| w[0] <= w[1]));
    }
    // Same values as the library.
    let model = cyclorub::model::SectorModel::academic(24).expect("academic");
    let lib = model.natural_frequencies().expect("frequencies");
    let first = nds[3]["frequencies_hz"][0].as_f64().expect("number");
    assert!((first - lib[3].1[0]).abs() <= 1e-12 * first);
}

#[test]
fn table_and_plot_next_to_the_case_file() {
    let dir = scratch("table");
    let case = dir.join("case.toml");
    std::fs::write(
        &case,
        "[model]\nkind = \"academic\"\nsectors = 45\n\n[excitation]\nanything = 1\n",
    )
    .expect("write case");
    let out = modes(&[case.to_str().expect("utf-8")]);
    assert!(out.status.success(), "{}", text(&out.stderr));
    let stdout = text(&out.stdout);
    assert!(stdout.contains("N = 45"), "{stdout}");
    assert!(stdout.contains("mode 5"), "{stdout}");
    // Nodal diameters 0..=22, one row each.
    let rows = stdout
        .lines()
        .filter(|l| l.split_whitespace().count() == 6)
        .count();
    assert_eq!(rows, 23, "{stdout}");
    let plot = dir.join("modes.svg");
    assert!(stdout.contains(&plot.display().to_string()), "{stdout}");
    let svg = std::fs::read_to_string(&plot).expect("plot written");
    assert!(svg.starts_with("<svg") && svg.contains("nodal diameter"));
    std::fs::remove_dir_all(&dir).ok();
}

#[test]
fn output_option_and_mode_limit() {
    let dir = scratch("output");
    let plot = dir.join("chain.svg");
    let case = fixture("chain.toml");
    let out = modes(&[
        case.to_str().expect("utf-8"),
        "--output",
        plot.to_str().expect("utf-8"),
        "--modes",
        "2",
        "--json",
    ]);
    assert!(out.status.success(), "{}", text(&out.stderr));
    let json: serde_json::Value = serde_json::from_slice(&out.stdout).expect("only JSON on stdout");
    assert_eq!(json["sectors"], 12);
    assert_eq!(
        json["nodal_diameters"][0]["frequencies_hz"]
            .as_array()
            .expect("array")
            .len(),
        2
    );
    assert!(text(&out.stderr).contains("chain.svg"));
    assert!(plot.exists());
    std::fs::remove_dir_all(&dir).ok();
}

#[test]
fn one_dof_oscillator() {
    let out = modes(&[
        fixture("oscillator.toml").to_str().expect("utf-8"),
        "--json",
        "--no-plot",
    ]);
    assert!(out.status.success(), "{}", text(&out.stderr));
    let json: serde_json::Value = serde_json::from_slice(&out.stdout).expect("JSON");
    let f = json["nodal_diameters"][0]["frequencies_hz"][0]
        .as_f64()
        .expect("number");
    let expected = 40.0_f64.sqrt() / (2.0 * std::f64::consts::PI);
    assert!((f - expected).abs() <= 1e-12 * expected);
}

#[test]
fn input_errors_exit_2_with_the_key() {
    let out = modes(&[
        fixture("errors/unknown_key.toml").to_str().expect("utf-8"),
        "--no-plot",
    ]);
    assert_eq!(out.status.code(), Some(2));
    let stderr = text(&out.stderr);
    assert!(
        stderr.contains("line 4") && stderr.contains("stifness"),
        "{stderr}"
    );

    let out = modes(&[
        fixture("errors/nonsymmetric.toml").to_str().expect("utf-8"),
        "--no-plot",
    ]);
    assert_eq!(out.status.code(), Some(2));
    assert!(text(&out.stderr).contains("not symmetric"));

    let out = modes(&["/nonexistent/case.toml", "--no-plot"]);
    assert_eq!(out.status.code(), Some(2));
    assert!(text(&out.stderr).contains("/nonexistent/case.toml"));
}
