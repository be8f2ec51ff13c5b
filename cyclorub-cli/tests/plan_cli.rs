//! `cyclorub plan` end to end: Table 2 for N = 24, JSON keys, the signed
//! pairs of one engine order, the sweep, and bad arguments (exit code 2).

use serde_json::Value;
use std::process::{Command, Output};

fn plan(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_cyclorub"))
        .arg("plan")
        .args(args)
        .output()
        .expect("the cyclorub binary runs")
}

fn json(args: &[&str]) -> Value {
    let out = plan(args);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    serde_json::from_slice(&out.stdout).expect("valid JSON")
}

/// Table 2: engine order, K, reduced size, sectors for AFT-CP, reduction.
const TABLE_2: [(u64, u64, u64, u64, f64); 13] = [
    (0, 1, 21, 1, 95.8),
    (1, 12, 252, 12, 50.0),
    (2, 6, 126, 6, 75.0),
    (3, 4, 84, 4, 83.3),
    (4, 3, 63, 3, 87.5),
    (5, 12, 252, 12, 50.0),
    (6, 2, 42, 2, 91.7),
    (7, 12, 252, 12, 50.0),
    (8, 3, 63, 3, 87.5),
    (9, 4, 84, 4, 83.3),
    (10, 6, 126, 6, 75.0),
    (11, 12, 252, 12, 50.0),
    (12, 1, 21, 1, 95.8),
];

#[test]
fn json_for_24_sectors_matches_table_2() {
    let rows = json(&[
        "--sectors",
        "24",
        "--harmonics",
        "10",
        "--contact-dofs",
        "1",
        "--json",
    ]);
    let rows = rows.as_array().expect("an array of rows");
    // Default: both rules, every engine order 0..=12.
    assert_eq!(rows.len(), 26);
    for rule in ["paper", "symmetry"] {
        let of_rule: Vec<&Value> = rows.iter().filter(|r| r["rule"] == rule).collect();
        assert_eq!(of_rule.len(), 13);
        for (row, &(h, k, reduced, aft, reduction)) in of_rule.iter().zip(TABLE_2.iter()) {
            for key in [
                "sectors",
                "engine_order",
                "rule",
                "K",
                "reduced_size",
                "full_size",
                "sectors_for_aft",
                "reduction_percent",
                "harmonics",
            ] {
                assert!(row.get(key).is_some(), "missing key {key}");
            }
            assert_eq!(row["sectors"], 24);
            assert_eq!(row["engine_order"], h);
            if rule == "paper" {
                assert_eq!(row["K"], k, "K for h = {h}");
            } else {
                assert!(row["K"].is_null());
            }
            assert_eq!(row["reduced_size"], reduced, "{rule}, h = {h}");
            assert_eq!(row["full_size"], 504);
            assert_eq!(row["sectors_for_aft"], aft);
            let r = row["reduction_percent"].as_f64().unwrap();
            assert!((r - reduction).abs() <= 0.05, "{rule}, h = {h}: {r}");
            let harmonics = row["harmonics"].as_array().unwrap();
            assert_eq!(harmonics.len(), 11);
            assert_eq!(harmonics[3]["k"], 3);
            assert!(harmonics[3]["signed_nodal_diameters"].is_array());
        }
    }
}

#[test]
fn text_table_for_24_sectors_has_the_rows_of_table_2() {
    let out = plan(&[
        "--sectors",
        "24",
        "--harmonics",
        "10",
        "--contact-dofs",
        "1",
    ]);
    assert!(out.status.success());
    let text = String::from_utf8(out.stdout).unwrap();
    assert!(text.contains("504 unknowns"));
    for (h, k, reduced, aft, reduction) in TABLE_2 {
        let wanted = [
            h.to_string(),
            k.to_string(),
            reduced.to_string(),
            aft.to_string(),
            format!("{reduction:.1}"),
        ];
        let found = text.lines().any(|line| {
            let fields: Vec<&str> = line.split_whitespace().collect();
            fields.len() >= 5
                && fields[..5] == wanted.iter().map(String::as_str).collect::<Vec<_>>()[..]
        });
        assert!(found, "no row {wanted:?} in\n{text}");
    }
}

#[test]
fn one_engine_order_shows_its_signed_pairs() {
    let rows = json(&[
        "--sectors",
        "24",
        "--harmonics",
        "10",
        "--contact-dofs",
        "1",
        "--engine-order",
        "6",
        "--excitation",
        "traveling",
        "--casing-order",
        "8",
        "--rule",
        "symmetry",
        "--json",
    ]);
    let rows = rows.as_array().unwrap();
    assert_eq!(rows.len(), 1);
    let row = &rows[0];
    assert_eq!(row["reduced_size"], 63);
    assert_eq!(row["sectors_for_aft"], 3);
    let on = |k: usize| -> Vec<i64> {
        row["harmonics"][k]["signed_nodal_diameters"]
            .as_array()
            .unwrap()
            .iter()
            .map(|v| v.as_i64().unwrap())
            .collect()
    };
    assert_eq!(on(0), vec![-8, 0, 8]);
    assert_eq!(on(1), vec![-6, 2, 10]);
    assert_eq!(on(2), vec![-4, 4, 12]);
    assert_eq!(on(3), vec![-10, -2, 6]);
    // The text output lists them too.
    let out = plan(&[
        "--sectors",
        "24",
        "--harmonics",
        "10",
        "--contact-dofs",
        "1",
        "--engine-order",
        "3",
        "--excitation",
        "traveling",
        "--rule",
        "paper",
    ]);
    let text = String::from_utf8(out.stdout).unwrap();
    assert!(text.contains("k =  4: {12}"), "{text}");
    assert!(text.contains("k =  5: {9}"), "{text}");
}

#[test]
fn sweep_reports_grouped_means() {
    let v = json(&["--harmonics", "10", "--sweep-sectors", "2..150", "--json"]);
    let groups = v["groups"].as_array().unwrap();
    let even = groups.iter().find(|g| g["class"] == "even").unwrap();
    let m = even["over_engine_orders"]["with_parity"].as_f64().unwrap();
    assert!((m - 62.4).abs() < 0.05, "{m}");
    assert_eq!(v["rows"].as_array().unwrap().len(), 149);
    let out = plan(&["--harmonics", "10", "--sweep-sectors", "20..=30"]);
    assert!(out.status.success());
    let text = String::from_utf8(out.stdout).unwrap();
    assert!(text.contains("odd non-prime N") && text.contains("prime N"));
}

#[test]
fn one_sector_is_valid() {
    let rows = json(&[
        "--sectors",
        "1",
        "--harmonics",
        "3",
        "--contact-dofs",
        "2",
        "--json",
    ]);
    let rows = rows.as_array().unwrap();
    assert_eq!(rows.len(), 2);
    for row in rows {
        assert_eq!(row["reduced_size"], 14);
        assert_eq!(row["full_size"], 14);
        assert_eq!(row["harmonics"][2]["signed_nodal_diameters"][0], 0);
    }
}

fn assert_usage_error(args: &[&str], needles: &[&str]) {
    let out = plan(args);
    assert_eq!(out.status.code(), Some(2), "args {args:?}");
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(!stderr.contains("panicked"), "{stderr}");
    for needle in needles {
        assert!(
            stderr.contains(needle),
            "{args:?}: {needle:?} not in {stderr}"
        );
    }
}

#[test]
fn bad_arguments_exit_2_with_a_message() {
    let base = ["--harmonics", "10", "--contact-dofs", "1"];
    let with = |extra: &[&'static str]| -> Vec<&'static str> {
        base.iter().copied().chain(extra.iter().copied()).collect()
    };
    assert_usage_error(&with(&["--sectors", "0"]), &["--sectors", "at least 1"]);
    assert_usage_error(
        &with(&["--sectors", "24", "--engine-order", "24"]),
        &["--engine-order", "0..=23"],
    );
    assert_usage_error(
        &with(&["--sectors", "24", "--engine-order", "-1"]),
        &["--engine-order"],
    );
    assert_usage_error(
        &["--sectors", "24", "--harmonics", "0", "--contact-dofs", "1"],
        &["--harmonics", "at least 1"],
    );
    assert_usage_error(
        &with(&["--sectors", "24", "--excitation", "rotating"]),
        &["--excitation", "traveling", "standing", "mixed"],
    );
    assert_usage_error(
        &with(&["--sectors", "24", "--rule", "mine"]),
        &["--rule", "paper", "symmetry", "both"],
    );
    assert_usage_error(
        &["--harmonics", "10", "--sweep-sectors", "9..3"],
        &["--sweep-sectors"],
    );
    assert_usage_error(
        &["--harmonics", "10", "--sweep-sectors", "abc"],
        &["--sweep-sectors"],
    );
    assert_usage_error(
        &["--harmonics", "10", "--contact-dofs", "1"],
        &["--sectors"],
    );
}
