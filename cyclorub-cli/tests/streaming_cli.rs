//! `cyclorub run` puts every point on disk as it is computed: a run
//! stopped by Ctrl-C (SIGINT) or SIGTERM writes every point and says where
//! it stopped; a killed run (SIGKILL) leaves `branch.csv` readable with
//! every point written and `results.h5` with those of its last append; a
//! folder that holds a run is refused unless
//! `--overwrite`.

#![cfg(unix)]

use crate::common::{cyclorub, text};
use cyclorub::results::folder::BranchTable;
use cyclorub::results::hdf5;
use std::path::{Path, PathBuf};
use std::process::{Child, Command, Output, Stdio};
use std::time::{Duration, Instant};

fn scratch(name: &str) -> crate::common::Scratch {
    crate::common::scratch("streaming-cli", name)
}

/// A run of many small steps (tens of seconds to the end): long enough to
/// be stopped half-way.
const LONG: &str = r#"
[model]
sectors = 6

[harmonic_balance]
harmonics = 3
time_samples = 60

[continuation]
max_step = 2e-4
initial_step = 1e-4
max_points = 1000000
"#;

fn start_long(dir: &Path) -> (Child, PathBuf) {
    start_long_with(dir, &["--no-stability"])
}

fn start_long_with(dir: &Path, flags: &[&str]) -> (Child, PathBuf) {
    let case = dir.join("long.toml");
    std::fs::write(&case, LONG).unwrap();
    let out = dir.join("results");
    let child = Command::new(env!("CARGO_BIN_EXE_cyclorub"))
        .args(["run", case.to_str().unwrap()])
        .args(flags)
        .arg("--output")
        .arg(&out)
        .env("RUST_LOG", "warn")
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .expect("the cyclorub binary runs");
    (child, out)
}

/// Rows of `branch.csv` once it holds at least `rows` (within 60 s).
fn wait_for_rows(out: &Path, rows: usize) -> usize {
    let clock = Instant::now();
    loop {
        let lines = std::fs::read_to_string(out.join("branch.csv"))
            .map(|t| t.lines().count().saturating_sub(1))
            .unwrap_or(0);
        if lines >= rows {
            return lines;
        }
        assert!(
            clock.elapsed() < Duration::from_secs(60),
            "branch.csv has {lines} rows after 60 s"
        );
        std::thread::sleep(Duration::from_millis(20));
    }
}

fn signal(child: &Child, signal: i32) {
    let pid = i32::try_from(child.id()).expect("a pid");
    // SAFETY: kill(2) on the pid of a child this test spawned and has not
    // waited for yet.
    assert_eq!(unsafe { libc::kill(pid, signal) }, 0);
}

fn wait_at_most(mut child: Child, limit: Duration) -> Output {
    let clock = Instant::now();
    while child.try_wait().expect("waits").is_none() {
        if clock.elapsed() > limit {
            let _ = child.kill();
            panic!("the run did not stop within {limit:?}");
        }
        std::thread::sleep(Duration::from_millis(20));
    }
    child.wait_with_output().expect("output")
}

fn run_json(out: &Path) -> serde_json::Value {
    serde_json::from_str(&std::fs::read_to_string(out.join("run.json")).unwrap()).unwrap()
}

#[test]
fn ctrl_c_and_sigterm_stop_after_the_current_point_and_keep_every_point() {
    for (name, number) in [("sigint", libc::SIGINT), ("sigterm", libc::SIGTERM)] {
        let dir = scratch(name);
        let (child, out) = start_long(&dir);
        wait_for_rows(&out, 5);
        assert_eq!(run_json(&out)["status"], "running", "{name}");
        signal(&child, number);
        let output = wait_at_most(child, Duration::from_secs(30));
        let said = text(&output);
        assert_eq!(output.status.code(), Some(1), "{name}: {said}");
        assert!(said.contains("interrupted"), "{name}: {said}");
        let record = run_json(&out);
        assert_eq!(record["status"], "interrupted", "{name}");
        assert_eq!(record["stop"]["reason"], "interrupted", "{name}");
        let points = record["points"].as_u64().unwrap() as usize;
        let table = BranchTable::read(&out.join("branch.csv")).unwrap();
        assert_eq!(table.rows.len(), points, "{name}");
        assert!(points >= 5, "{name}");
        // The last point is the one the stop names.
        let last = table.rows.last().unwrap().frequency_hz;
        let stopped_at = record["stop"]["frequency_hz"].as_f64().unwrap();
        assert!((last - stopped_at).abs() < 1e-9 * last, "{name}");
        let data = hdf5::read(&out.join(hdf5::FILE_NAME)).unwrap();
        assert_eq!(data.points.len(), points, "{name}");
        let _ = std::fs::remove_dir_all(&dir);
    }
}

/// `branch.csv`'s `stable` column, per row (`None` where empty).
fn verdicts(out: &Path) -> Vec<Option<bool>> {
    let text = std::fs::read_to_string(out.join("branch.csv")).unwrap();
    let mut lines = text.lines();
    // The file may exist before its header is flushed.
    let Some(first) = lines.next().filter(|l| l.ends_with("unstable_exponents")) else {
        return Vec::new();
    };
    let header: Vec<&str> = first.split(',').collect();
    let column = header
        .iter()
        .position(|h| *h == "stable")
        .expect("branch.csv has the stability columns");
    lines
        .filter(|l| !l.is_empty())
        .map(|l| match l.split(',').nth(column) {
            Some("1") => Some(true),
            Some("0") => Some(false),
            _ => None,
        })
        .collect()
}

#[test]
fn stability_is_streamed_with_the_points_and_an_interrupted_run_keeps_the_verdicts() {
    let dir = scratch("stability");
    let (child, out) = start_long_with(&dir, &[]);
    // Verdicts are in branch.csv while the run goes on.
    let clock = Instant::now();
    while verdicts_or_none(&out).iter().flatten().count() < 5 {
        assert!(
            clock.elapsed() < Duration::from_secs(60),
            "no verdicts after 60 s"
        );
        std::thread::sleep(Duration::from_millis(20));
    }
    assert_eq!(run_json(&out)["status"], "running");
    signal(&child, libc::SIGINT);
    let output = wait_at_most(child, Duration::from_secs(30));
    assert_eq!(output.status.code(), Some(1), "{}", text(&output));
    let record = run_json(&out);
    assert_eq!(record["status"], "interrupted");
    let points = record["points"].as_u64().unwrap() as usize;
    let kept = verdicts(&out);
    assert_eq!(kept.len(), points, "branch.csv has the stability columns");
    // Every point checked before the stop keeps its verdict, in order: the
    // unchecked ones (queued when the signal came) are the last.
    let checked = kept.iter().take_while(|v| v.is_some()).count();
    assert!(checked >= 5, "{kept:?}");
    assert!(kept[checked..].iter().all(Option::is_none), "{kept:?}");
    // Off contact at the start of the range: stable.
    assert!(kept[..checked].iter().all(|v| *v == Some(true)), "{kept:?}");
    let stability = &record["stability"];
    if checked < points {
        assert_eq!(stability["status"], "not_computed");
        let reason = stability["reason"].as_str().unwrap();
        assert!(
            reason.contains("interrupted") && reason.contains("branch.csv"),
            "{reason}"
        );
    } else {
        assert_eq!(stability["status"], "computed");
    }
    let _ = std::fs::remove_dir_all(&dir);
}

/// [`verdicts`], empty while `branch.csv` is not there.
fn verdicts_or_none(out: &Path) -> Vec<Option<bool>> {
    if out.join("branch.csv").exists() {
        verdicts(out)
    } else {
        Vec::new()
    }
}

#[test]
fn a_killed_run_leaves_every_point_it_wrote() {
    let dir = scratch("sigkill");
    let (child, out) = start_long(&dir);
    wait_for_rows(&out, 3);
    // results.h5 is appended to at least every 2 s while points come: wait
    // for an append that holds 3 points (a fixed wait was too short on a
    // loaded machine, where points come slower). Any instant is a place a
    // kill can land, so a read meanwhile sees what a kill would leave.
    let clock = Instant::now();
    while hdf5::read(&out.join(hdf5::FILE_NAME)).map_or(0, |d| d.points.len()) < 3 {
        assert!(
            clock.elapsed() < Duration::from_secs(60),
            "results.h5 holds fewer than 3 points after 60 s"
        );
        std::thread::sleep(Duration::from_millis(50));
    }
    signal(&child, libc::SIGKILL);
    let _ = wait_at_most(child, Duration::from_secs(10));
    let table = BranchTable::read(&out.join("branch.csv")).expect("readable after a kill");
    assert!(table.rows.len() >= 3);
    for (i, row) in table.rows.iter().enumerate() {
        assert_eq!(row.point, i);
        assert!(row.frequency_hz > 0.0 && row.amplitudes.iter().all(|a| *a > 0.0));
    }
    assert_eq!(run_json(&out)["status"], "running");
    // results.h5 holds the points of its last append, the same as
    // branch.csv's (which prints 13 digits).
    let data = hdf5::read(&out.join(hdf5::FILE_NAME)).expect("results.h5 readable after a kill");
    assert!(data.points.len() >= 3, "{} points", data.points.len());
    assert!(data.points.len() <= table.rows.len());
    for (row, point) in table.rows.iter().zip(&data.points) {
        assert!((row.frequency_hz - point.frequency_hz).abs() <= 1e-12 * row.frequency_hz);
        for (a, b) in row.amplitudes.iter().zip(&point.amplitude) {
            assert!((a - b).abs() <= 1e-12 * a.abs(), "{a} vs {b}");
        }
        assert!(point.converged && !point.unknowns.is_empty());
    }
    // And by h5py (the HDF5 C library), when Python has it.
    let script = "import sys, h5py\nf = h5py.File(sys.argv[1], 'r')\nprint(f.attrs['status'], f['branch/frequency_hz'].shape[0], f['branch/unknowns'][()].shape[0])";
    let path = out.join(hdf5::FILE_NAME);
    match Command::new("python3")
        .args(["-c", script, path.to_str().unwrap()])
        .output()
    {
        Ok(o) if o.status.success() => {
            let said = String::from_utf8_lossy(&o.stdout).trim().to_string();
            let n = data.points.len();
            assert_eq!(said, format!("running {n} {n}"));
        }
        Ok(o) if String::from_utf8_lossy(&o.stderr).contains("No module named") => {
            eprintln!("h5py is not installed: its check is skipped");
        }
        Ok(o) => panic!("h5py failed: {}", String::from_utf8_lossy(&o.stderr)),
        Err(_) => eprintln!("python3 is not available: the h5py check is skipped"),
    }
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn a_folder_that_holds_a_run_is_refused_unless_overwrite() {
    let dir = scratch("overwrite");
    let out = dir.join("results");
    let out_text = out.to_str().unwrap();
    let first = cyclorub(&[
        "run",
        "--no-stability",
        "--at-hz",
        "100,110",
        "--output",
        out_text,
    ]);
    assert!(first.status.success(), "{}", text(&first));
    std::fs::write(out.join("notes.txt"), "mine").unwrap();
    let again = cyclorub(&[
        "run",
        "--no-stability",
        "--at-hz",
        "120",
        "--output",
        out_text,
    ]);
    assert_eq!(again.status.code(), Some(2), "{}", text(&again));
    assert!(text(&again).contains("--overwrite"), "{}", text(&again));
    assert_eq!(
        BranchTable::read(&out.join("branch.csv"))
            .unwrap()
            .rows
            .len(),
        2
    );
    let replaced = cyclorub(&[
        "run",
        "--no-stability",
        "--at-hz",
        "120",
        "--output",
        out_text,
        "--overwrite",
    ]);
    assert!(replaced.status.success(), "{}", text(&replaced));
    assert_eq!(
        BranchTable::read(&out.join("branch.csv"))
            .unwrap()
            .rows
            .len(),
        1
    );
    assert_eq!(
        std::fs::read_to_string(out.join("notes.txt")).unwrap(),
        "mine"
    );
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn a_signal_during_a_long_first_point_stops_within_its_evaluation() {
    // Issue 45 item 9: a first point of many harmonics spends minutes in
    // one evaluation (assembling the contact Jacobian); SIGTERM stopped it
    // only after (600 s on the case of the issue). The assembly now looks
    // at the interrupt as it goes.
    let dir = scratch("slow-first-point");
    let case = dir.join("slow.toml");
    std::fs::write(
        &case,
        "[model]\nsectors = 6\n[harmonic_balance]\nharmonics = 1000\ntime_samples = 2001\n",
    )
    .unwrap();
    let out = dir.join("results");
    let child = Command::new(env!("CARGO_BIN_EXE_cyclorub"))
        .args(["run", case.to_str().unwrap(), "--no-stability", "--output"])
        .arg(&out)
        .env("RUST_LOG", "warn")
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .expect("the cyclorub binary runs");
    // In the first point: run.json says running, no row yet.
    let clock = Instant::now();
    while !out.join("run.json").exists() {
        assert!(clock.elapsed() < Duration::from_secs(30));
        std::thread::sleep(Duration::from_millis(20));
    }
    std::thread::sleep(Duration::from_millis(1500));
    let rows = std::fs::read_to_string(out.join("branch.csv"))
        .map(|t| t.lines().count().saturating_sub(1))
        .unwrap_or(0);
    assert_eq!(rows, 0, "the first point is not that slow here");
    signal(&child, libc::SIGTERM);
    let stopped = Instant::now();
    let output = wait_at_most(child, Duration::from_secs(20));
    let waited = stopped.elapsed();
    assert_eq!(output.status.code(), Some(1), "{}", text(&output));
    assert!(
        text(&output).contains("interrupted before the first point"),
        "{}",
        text(&output)
    );
    println!("stopped {waited:?} after SIGTERM");
    assert!(waited < Duration::from_secs(10), "{waited:?}");
    let _ = std::fs::remove_dir_all(&dir);
}
