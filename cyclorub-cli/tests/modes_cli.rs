//! `cyclorub modes`: table, JSON, plot, and errors with their exit codes;
//! on a finite-element case (the coarse open fan), the full sector's
//! frequencies beside the Craig–Bampton model's.

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

fn fixture(name: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../cyclorub/tests/fixtures/model")
        .join(name)
}

fn scratch(name: &str) -> crate::common::Scratch {
    crate::common::scratch("modes", name)
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
        // Not a finite-element case: no full-sector comparison.
        assert!(entry.get("full_sector_frequencies_hz").is_none(), "{entry}");
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

/// The coarse open fan (`cyclorub mesh fan --refine 1`): the table has, per
/// diameter and mode, the full sector's frequency, the Craig–Bampton
/// model's and their relative difference (the first bending within 1e-4,
/// as issue 20 asks; a Ritz projection is never below the full sector);
/// the plot has both with a legend; a second run reads the full sector's
/// frequencies from the cache, and its JSON has them with the differences;
/// `--no-full-sector` gives the reduced model's table alone.
#[test]
fn a_finite_element_case_shows_the_full_sector_beside_craig_bampton() {
    let dir = scratch("fan").join("fan");
    let _ = std::fs::remove_dir_all(&dir);
    let out = Command::new(env!("CARGO_BIN_EXE_cyclorub"))
        .args(["mesh", "fan", "--refine", "1", "--output"])
        .arg(&dir)
        .output()
        .expect("run cyclorub mesh");
    assert!(out.status.success(), "{}", text(&out.stderr));
    let case = dir.join("fan16.toml");
    let case = case.to_str().expect("utf-8");

    let out = modes(&[case, "--modes", "3"]);
    let (stdout, stderr) = (text(&out.stdout), text(&out.stderr));
    assert!(out.status.success(), "{stderr}");
    for header in ["full sector", "Craig–Bampton", "relative difference"] {
        assert!(stdout.contains(header), "{stdout}");
    }
    // One row per diameter 0..=8 and mode 1..=3, in order.
    let rows: Vec<(usize, usize, f64, f64, f64)> = stdout
        .lines()
        .filter_map(|line| {
            let f: Vec<&str> = line.split_whitespace().collect();
            let number = |i: usize| f.get(i)?.parse::<f64>().ok();
            Some((
                f.first()?.parse().ok()?,
                f.get(1)?.parse().ok()?,
                number(2)?,
                number(3)?,
                number(4)?,
            ))
        })
        .collect();
    assert_eq!(rows.len(), 27, "{stdout}");
    for (i, &(d, mode, full, reduced, difference)) in rows.iter().enumerate() {
        assert_eq!((d, mode), (i / 3, i % 3 + 1), "{stdout}");
        assert!(reduced >= full - 1e-3, "ND {d}, mode {mode}: {stdout}");
        // The columns are rounded to 1e-3 Hz, the difference to 3 digits.
        let expected = (reduced - full) / full;
        assert!(
            (difference - expected).abs() <= 1e-3 / full + 0.01 * difference.abs(),
            "ND {d}, mode {mode}: {difference} vs {expected}"
        );
        if mode == 1 {
            assert!((0.0..=1e-4).contains(&difference), "ND {d}: {stdout}");
        }
    }
    // Progress: a log line per diameter.
    assert!(stderr.contains("full sector, nodal diameter 8"), "{stderr}");
    let svg = std::fs::read_to_string(dir.join("modes.svg")).expect("plot written");
    assert!(
        svg.contains("Craig–Bampton (lines)") && svg.contains("full sector (open circles)"),
        "the legend is missing"
    );
    // 27 points of each model, and the legend's two markers.
    assert_eq!(svg.matches("<circle").count(), 2 * 27 + 2);

    let out = modes(&[case, "--modes", "2", "--json", "--no-plot"]);
    assert!(out.status.success(), "{}", text(&out.stderr));
    assert!(
        text(&out.stderr).contains("full-sector frequencies read from"),
        "{}",
        text(&out.stderr)
    );
    let json: serde_json::Value = serde_json::from_slice(&out.stdout).expect("JSON on stdout");
    let numbers = |v: &serde_json::Value| -> Vec<f64> {
        v.as_array()
            .expect("array")
            .iter()
            .map(|x| x.as_f64().expect("number"))
            .collect()
    };
    let nds = json["nodal_diameters"].as_array().expect("array");
    assert_eq!(nds.len(), 9);
    for (d, entry) in nds.iter().enumerate() {
        let reduced = numbers(&entry["frequencies_hz"]);
        let full = numbers(&entry["full_sector_frequencies_hz"]);
        let differences = numbers(&entry["relative_differences"]);
        assert_eq!((reduced.len(), full.len(), differences.len()), (2, 2, 2));
        for r in 0..2 {
            let expected = (reduced[r] - full[r]) / full[r];
            assert!((differences[r] - expected).abs() <= 1e-12, "ND {d}");
        }
        assert!((0.0..=1e-4).contains(&differences[0]), "ND {d}: {entry}");
        let (_, _, table_full, _, _) = rows[3 * d];
        assert!((full[0] - table_full).abs() <= 5e-4, "ND {d}");
    }

    let out = modes(&[case, "--no-full-sector", "--modes", "3", "--no-plot"]);
    let stdout = text(&out.stdout);
    assert!(out.status.success(), "{}", text(&out.stderr));
    assert!(
        !stdout.contains("full sector") && stdout.contains("mode 3"),
        "{stdout}"
    );
    std::fs::remove_dir_all(dir.parent().expect("scratch")).ok();
}

/// A mistuned case (issue 44): the tuned wheel per diameter, then the
/// mistuned wheel's modes with their localization and nodal-diameter
/// content, the library's values.
#[test]
fn a_mistuned_case_lists_the_mistuned_wheels_modes() {
    let dir = scratch("mistuned");
    let case = dir.join("case.toml");
    let deviations = "[0.03, -0.02, 0.05, 0.0, -0.04, 0.01]";
    std::fs::write(
        &case,
        format!("[model]\nsectors = 6\n[mistuning]\ndeviations = {deviations}\n"),
    )
    .expect("case");
    let path = case.to_str().expect("utf-8");
    let out = modes(&[path, "--json", "--no-plot", "--modes", "1"]);
    assert!(out.status.success(), "{}", text(&out.stderr));
    let json: serde_json::Value = serde_json::from_slice(&out.stdout).expect("JSON on stdout");
    let wheel = json["mistuned_wheel_modes"]
        .as_array()
        .expect("mistuned modes");
    // --modes 1: the first family, one mode per sector.
    assert_eq!(wheel.len(), 6);
    let parsed = cyclorub::case::Case::from_file(&case).expect("case");
    let model = parsed
        .mistuned(parsed.model.build(&dir).expect("model"), &dir)
        .expect("mistuned");
    let library = model.wheel_modes(6).expect("modes");
    for (mode, expected) in wheel.iter().zip(&library) {
        let f = mode["frequency_hz"].as_f64().expect("number");
        assert!((f - expected.frequency_hz).abs() <= 1e-12 * f, "{mode}");
        let (sector, share) = expected.localization();
        assert_eq!(mode["most_active_sector"], sector + 1);
        assert!((mode["localization"].as_f64().expect("number") - share).abs() < 1e-12);
        let shares: f64 = mode["nodal_diameter_shares"]
            .as_array()
            .expect("shares")
            .iter()
            .map(|v| v.as_f64().expect("number"))
            .sum();
        assert!((shares - 1.0).abs() < 1e-12, "{mode}");
    }
    let table = modes(&[path, "--no-plot"]);
    assert!(table.status.success(), "{}", text(&table.stderr));
    let stdout = text(&table.stdout);
    assert!(
        stdout.contains("The tuned wheel, per nodal diameter"),
        "{stdout}"
    );
    assert!(stdout.contains("localization"), "{stdout}");
    assert!(
        stdout.lines().filter(|l| l.contains("ND 1:")).count() >= 2,
        "{stdout}"
    );
}
