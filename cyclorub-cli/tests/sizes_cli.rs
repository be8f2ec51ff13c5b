//! Sizes that cannot fit (issue 19, item 6) are refused before any work,
//! under a capped address space: exit code 2, the key named with the
//! memory needed, never an allocation failure (SIGABRT).

#![cfg(unix)]

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

/// The address-space cap of every run here (`ulimit -v`, kB): 2 GB.
const CAP_KB: u64 = 2_000_000;

fn scratch(name: &str) -> crate::common::Scratch {
    crate::common::scratch("sizes", name)
}

/// `cyclorub args…` with its address space capped at [`CAP_KB`].
fn capped(args: &[&str]) -> Output {
    Command::new("sh")
        .arg("-c")
        .arg(format!("ulimit -v {CAP_KB} && exec \"$0\" \"$@\""))
        .arg(env!("CARGO_BIN_EXE_cyclorub"))
        .args(args)
        .env("RUST_LOG", "warn")
        .output()
        .expect("sh runs the cyclorub binary")
}

/// A small case (`N = 6`, `N_h = 3`, `N_t = 60`, 300 points) with `lines`
/// replacing its keys (`table.key = value`).
fn case(dir: &Path, lines: &[(&str, &str)]) -> PathBuf {
    let mut tables: Vec<(String, Vec<String>)> = vec![
        ("model".into(), vec!["sectors = 6".into()]),
        (
            "harmonic_balance".into(),
            vec!["harmonics = 3".into(), "time_samples = 60".into()],
        ),
        ("continuation".into(), vec!["max_points = 300".into()]),
    ];
    for (key, value) in lines {
        let (table, leaf) = key.rsplit_once('.').unwrap();
        let entry = match tables.iter_mut().find(|(t, _)| t == table) {
            Some(entry) => entry,
            None => {
                tables.push((table.to_string(), Vec::new()));
                tables.last_mut().unwrap()
            }
        };
        entry.1.retain(|l| !l.starts_with(&format!("{leaf} =")));
        entry.1.push(format!("{leaf} = {value}"));
    }
    let text: String = tables
        .iter()
        .map(|(t, keys)| format!("[{t}]\n{}\n", keys.join("\n")))
        .collect();
    let path = dir.join("case.toml");
    std::fs::write(&path, text).unwrap();
    path
}

/// Keys and values replacing a case's (`table.key`, value).
type Lines<'a> = &'a [(&'a str, &'a str)];

/// Exit code 2, no allocation failure, every one of `parts` in stderr.
fn assert_refused(output: &Output, parts: &[&str]) {
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert!(
        !stderr.contains("memory allocation"),
        "an allocation failed: {stderr}"
    );
    assert_eq!(output.status.code(), Some(2), "{stderr}");
    for part in parts {
        assert!(stderr.contains(part), "stderr lacks {part:?}: {stderr}");
    }
}

#[test]
fn absurd_sizes_of_a_run_are_refused_with_their_key() {
    let dir = scratch("run");
    let out = dir.join("results");
    let cases: &[(Lines, &[&str])] = &[
        (
            &[("model.sectors", "1000000")],
            &["model.sectors", "at most 10000"],
        ),
        // Every sector reported at the default sizes: 4.5 MB a point.
        (
            &[
                ("model.sectors", "10000"),
                ("harmonic_balance.harmonics", "10"),
                ("harmonic_balance.time_samples", "10000"),
                ("continuation.max_points", "5000"),
            ],
            &["model.sectors = 10000", "needs about", "GB"],
        ),
        (
            &[
                ("harmonic_balance.harmonics", "100000"),
                ("harmonic_balance.time_samples", "200001"),
            ],
            &["harmonic_balance.harmonics = 100000", "GB"],
        ),
        (
            &[("harmonic_balance.time_samples", "10000000000")],
            &["harmonic_balance.time_samples = 10000000000", "GB"],
        ),
        (
            &[("continuation.max_points", "1000000000000")],
            &["continuation.max_points = 1000000000000", "at most"],
        ),
    ];
    for (lines, parts) in cases {
        let path = case(&dir, lines);
        let output = capped(&[
            "run",
            path.to_str().unwrap(),
            "--output",
            out.to_str().unwrap(),
            "--no-stability",
        ]);
        assert_refused(&output, parts);
    }
    // The same small case with sane sizes runs under the same cap (exit 1:
    // its 300 points end before the range does).
    let path = case(&dir, &[]);
    let output = capped(&[
        "run",
        path.to_str().unwrap(),
        "--output",
        out.to_str().unwrap(),
        "--no-stability",
    ]);
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert!(matches!(output.status.code(), Some(0 | 1)), "{stderr}");
    assert!(out.join("branch.csv").is_file(), "{stderr}");
}

#[test]
fn absurd_sizes_of_a_simulation_are_refused_with_their_option() {
    let dir = scratch("simulate");
    let out = dir.join("simulation");
    let path = case(&dir, &[]);
    let path = path.to_str().unwrap();
    let out = out.to_str().unwrap();
    let runs: &[(&[&str], &[&str])] = &[
        (
            &["--periods", "1000000000000"],
            &["--periods = 1000000000000"],
        ),
        (
            &["--steps-per-period", "1000000000000"],
            &["--steps-per-period = 1000000000000"],
        ),
        (
            &["--periods", "1000000000", "--history-periods", "1000000000"],
            &["--history-periods = 1000000000"],
        ),
        (
            &["--sweep", "100..130", "--rate", "1e-9"],
            &["the sweep's periods (--sweep, --rate)"],
        ),
    ];
    for (extra, parts) in runs {
        let mut args = vec!["simulate", path, "--output", out];
        if !extra.contains(&"--sweep") {
            args.extend(["--at-hz", "120"]);
        }
        args.extend(extra.iter());
        assert_refused(&capped(&args), parts);
    }
    let wide = case(&dir, &[("model.sectors", "10000")]);
    assert_refused(
        &capped(&[
            "simulate",
            wide.to_str().unwrap(),
            "--at-hz",
            "120",
            "--output",
            out,
        ]),
        &["model.sectors = 10000", "GB"],
    );
}

#[test]
fn absurd_sizes_of_modes_and_plan_are_refused_by_their_range() {
    let dir = scratch("modes");
    let path = case(&dir, &[("model.sectors", "1000000")]);
    assert_refused(
        &capped(&["modes", path.to_str().unwrap(), "--no-plot"]),
        &["model.sectors", "at most 10000"],
    );
    assert_refused(
        &capped(&[
            "plan",
            "--sectors",
            "1000000",
            "--harmonics",
            "3",
            "--contact-dofs",
            "1",
        ]),
        &["--sectors 1000000", "at most 10000"],
    );
    assert_refused(
        &capped(&[
            "plan",
            "--sectors",
            "24",
            "--harmonics",
            "1000000000",
            "--contact-dofs",
            "1",
        ]),
        &["--harmonics 1000000000"],
    );
}

/// The default case, stability on, under address-space caps (kB) from
/// tight to the 2.5 GB of issue 45 item 19, where the run used to abort
/// (its stability check's threads reserve twice the L3 cache each for
/// faer's matrix products, which the estimate did not count): every run
/// ends with exit 0 or with exit 2 naming a key, never by a signal. On a
/// machine of 32 MiB of L3 and 2 threads, 450 MB refuses the check naming
/// `stability.enabled` (it aborted before); with a 480 MiB L3, 2.5 GB does.
#[test]
fn the_default_run_with_stability_ends_or_is_refused_under_an_address_space_cap() {
    for cap_kb in [450_000u64, 2_500_000] {
        let dir = scratch(&format!("stability-{cap_kb}"));
        let output = Command::new("sh")
            .arg("-c")
            .arg(format!("ulimit -v {cap_kb} && exec \"$0\" \"$@\""))
            .arg(env!("CARGO_BIN_EXE_cyclorub"))
            .args(["run", "--output", "results"])
            .current_dir(&dir)
            .env("RUST_LOG", "warn")
            .output()
            .expect("sh runs the cyclorub binary");
        let stderr = String::from_utf8_lossy(&output.stderr);
        assert!(
            !stderr.contains("memory allocation"),
            "cap {cap_kb} kB: an allocation failed: {stderr}"
        );
        match output.status.code() {
            Some(0) => {}
            Some(2) => assert!(
                stderr.contains("stability.enabled = true: the stability check")
                    || stderr.contains(" = "),
                "cap {cap_kb} kB: the refusal names no key: {stderr}"
            ),
            other => panic!("cap {cap_kb} kB: ended by {other:?}: {stderr}"),
        }
        let _ = std::fs::remove_dir_all(&dir);
    }
}
