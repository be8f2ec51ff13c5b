//! `cyclorub simulate`: the files of a run, a start from a results folder,
//! and bad input with its exit code.

use std::process::{Command, Output};

pub(crate) fn scratch(name: &str) -> crate::common::Scratch {
    crate::common::scratch("simulate", name)
}

pub(crate) fn cyclorub(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_cyclorub"))
        .args(args)
        .output()
        .expect("run cyclorub")
}

pub(crate) fn text(bytes: &[u8]) -> String {
    String::from_utf8_lossy(bytes).into_owned()
}

/// A wheel of 6 academic sectors, N_h = 10 on 1200 instants.
/// `cyclorub run CASE --at-hz FREQUENCIES --no-stability --output RESULTS`,
/// checked to succeed: the results a simulation starts from or is drawn
/// against.
pub(crate) fn run_at(case: &str, frequencies: &str, results: &str) {
    let run = cyclorub(&[
        "run",
        case,
        "--at-hz",
        frequencies,
        "--no-stability",
        "--output",
        results,
    ]);
    assert!(run.status.success(), "{}", text(&run.stderr));
}

pub(crate) fn small_case(dir: &std::path::Path) -> String {
    let path = dir.join("case.toml");
    std::fs::write(
        &path,
        "[model]\nsectors = 6\n[harmonic_balance]\nharmonics = 10\ntime_samples = 1200\n",
    )
    .unwrap();
    path.display().to_string()
}

#[test]
fn a_run_from_a_results_point_starts_on_its_amplitude_and_writes_its_files() {
    let dir = scratch("from");
    let case = small_case(&dir);
    let results = dir.join("results").display().to_string();
    let run = cyclorub(&["run", &case, "--at-hz", "150", "--output", &results]);
    assert!(run.status.success(), "{}", text(&run.stderr));
    let output = dir.join("simulation");
    let out = output.display().to_string();
    let simulate = cyclorub(&[
        "simulate",
        &case,
        "--from",
        &results,
        "--point",
        "0",
        "--periods",
        "3",
        "--steps-per-period",
        "512",
        "--output",
        &out,
    ]);
    assert!(simulate.status.success(), "{}", text(&simulate.stderr));
    assert!(text(&simulate.stdout).contains("all periods integrated"));
    for file in [
        "simulation.csv",
        "simulation.json",
        "simulation.h5",
        "plots/envelope.svg",
        "plots/time_history.svg",
        "plots/spectrum.svg",
        "plots/waterfall.svg",
    ] {
        assert!(output.join(file).is_file(), "{file}");
        // A PNG beside each figure ([output] figures' default).
        if let Some(stem) = file.strip_suffix(".svg") {
            assert!(output.join(format!("{stem}.png")).is_file(), "{stem}.png");
        }
    }
    // The observed dof named as the user knows it.
    let envelope = std::fs::read_to_string(output.join("plots/envelope.svg")).unwrap();
    assert!(envelope.contains("m1, the blade tip"), "envelope title");
    // Sector 1 and the extremes of the last period are plotted by default.
    let record = std::fs::read_to_string(output.join("simulation.json")).unwrap();
    assert!(record.contains("\"plotted_sectors\": [\n    1"), "{record}");
    // The first period's maxima are the branch's amplitudes (a linear point:
    // only the time step separates them).
    let branch = std::fs::read_to_string(dir.join("results/branch.csv")).unwrap();
    let row: Vec<f64> = branch
        .lines()
        .nth(1)
        .unwrap()
        .split(',')
        .skip(2)
        .take(6)
        .map(|v| v.parse().unwrap())
        .collect();
    let csv = std::fs::read_to_string(output.join("simulation.csv")).unwrap();
    assert_eq!(csv.lines().count(), 4, "a header and 3 periods");
    let first: Vec<f64> = csv
        .lines()
        .nth(1)
        .unwrap()
        .split(',')
        .skip(3)
        .take(6)
        .map(|v| v.parse().unwrap())
        .collect();
    for (a, b) in first.iter().zip(&row) {
        assert!((a - b).abs() < 1e-4 * b, "{a} vs {b}");
    }
}

#[test]
fn bad_input_names_the_flag_and_exits_2() {
    let dir = scratch("bad");
    let case = small_case(&dir);
    let out = dir.join("simulation").display().to_string();
    let bad = cyclorub(&[
        "simulate",
        &case,
        "--at-hz",
        "150",
        "--perturb",
        "1e-6:9",
        "--output",
        &out,
    ]);
    assert_eq!(bad.status.code(), Some(2));
    let message = text(&bad.stderr);
    assert!(
        message.contains("--perturb 1e-6:9") && message.contains("1..=6"),
        "{message}"
    );
    let sectors = cyclorub(&[
        "simulate",
        &case,
        "--at-hz",
        "150",
        "--plot-sectors",
        "2,7",
        "--output",
        &out,
    ]);
    assert_eq!(sectors.status.code(), Some(2));
    let message = text(&sectors.stderr);
    assert!(
        message.contains("--plot-sectors") && message.contains("1..=6"),
        "{message}"
    );
    let none = cyclorub(&["simulate", &case, "--output", &out]);
    assert_eq!(none.status.code(), Some(2));
    assert!(text(&none.stderr).contains("--at-hz"));
    // Issue 45 item 15: a start so far out that the state overflows stops
    // at the first step that is not finite, and writes nothing of it.
    let huge_out = dir.join("huge");
    let huge = cyclorub(&[
        "simulate",
        &case,
        "--at-hz",
        "150",
        "--periods",
        "2",
        "--perturb",
        "1e300",
        "--output",
        &huge_out.display().to_string(),
    ]);
    assert_eq!(huge.status.code(), Some(1), "{}", text(&huge.stderr));
    let message = text(&huge.stderr);
    assert!(
        message.contains("diverged")
            && message.contains("--perturb")
            && message.contains("period 1"),
        "{message}"
    );
    for file in ["simulation.csv", "simulation.h5", "simulation.json"] {
        assert!(!huge_out.join(file).exists(), "{file} written");
    }
}

#[test]
fn a_perturbation_along_a_floquet_mode_needs_a_point_and_a_class_it_has() {
    let dir = scratch("exponent");
    let case = small_case(&dir);
    let out = dir.join("simulation").display().to_string();
    let alone = cyclorub(&[
        "simulate",
        &case,
        "--at-hz",
        "150",
        "--perturb",
        "1e-9:EXPONENT=1",
        "--output",
        &out,
    ]);
    assert_eq!(alone.status.code(), Some(2));
    let message = text(&alone.stderr);
    assert!(
        message.contains("--perturb 1e-9:EXPONENT=1") && message.contains("--from"),
        "{message}"
    );
    let results = dir.join("results").display().to_string();
    let run = cyclorub(&["run", &case, "--at-hz", "150", "--output", &results]);
    assert!(run.status.success(), "{}", text(&run.stderr));
    let from = |perturb: &str| {
        cyclorub(&[
            "simulate",
            &case,
            "--from",
            &results,
            "--point",
            "0",
            "--perturb",
            perturb,
            "--periods",
            "2",
            "--output",
            &out,
        ])
    };
    // A traveling wave on 6 sectors has the classes −2..=3.
    let missing = from("1e-9:EXPONENT=4");
    assert_eq!(missing.status.code(), Some(2));
    let message = text(&missing.stderr);
    assert!(
        message.contains("--perturb 1e-9:EXPONENT=4") && message.contains("-2, -1, 0, 1, 2, 3"),
        "{message}"
    );
    let along = from("1e-9:EXPONENT=-1");
    assert!(along.status.success(), "{}", text(&along.stderr));
    assert!(
        text(&along.stderr).contains("leading exponent of class -1"),
        "{}",
        text(&along.stderr)
    );
}

#[test]
fn a_sweep_draws_the_branch_of_its_own_case_and_refuses_another() {
    let dir = scratch("reference");
    let case = small_case(&dir);
    let results = dir.join("results").display().to_string();
    run_at(&case, "200,204,208,212", &results);
    let sweep = |case: &str, out: &str| {
        cyclorub(&[
            "simulate",
            case,
            "--sweep",
            "200..212",
            "--rate",
            "250",
            "--steps-per-period",
            "64",
            "--reference",
            &results,
            "--output",
            out,
        ])
    };
    let out = dir.join("simulation");
    let simulate = sweep(&case, &out.display().to_string());
    assert!(simulate.status.success(), "{}", text(&simulate.stderr));
    let svg = std::fs::read_to_string(out.join("plots/envelope.svg")).unwrap();
    assert!(svg.contains("harmonic balance"), "the branch is not drawn");
    // A run of another wheel is refused, naming the flag and the key.
    let other = dir.join("other.toml");
    std::fs::write(
        &other,
        "[model]\nsectors = 8\n[harmonic_balance]\nharmonics = 10\ntime_samples = 1200\n",
    )
    .unwrap();
    let refused = sweep(
        &other.display().to_string(),
        &dir.join("other").display().to_string(),
    );
    assert_eq!(refused.status.code(), Some(2), "{}", text(&refused.stderr));
    let message = text(&refused.stderr);
    assert!(
        message.contains("--reference") && message.contains("model.sectors"),
        "{message}"
    );
    // At a fixed frequency on a point of the branch: what the wheel
    // settled to against the branch there.
    let fixed_out = dir.join("fixed").display().to_string();
    let fixed = cyclorub(&[
        "simulate",
        &case,
        "--from",
        &results,
        "--point",
        "1",
        "--periods",
        "40",
        "--reference",
        &results,
        "--output",
        &fixed_out,
    ]);
    assert!(fixed.status.success(), "{}", text(&fixed.stderr));
    let said = text(&fixed.stdout);
    assert!(said.contains("settled: periodic"), "{said}");
    let line = said
        .lines()
        .find(|l| l.starts_with("harmonic balance at 204.0000 Hz"))
        .unwrap_or_else(|| panic!("{said}"));
    let percent: f64 = line
        .split(" is ")
        .nth(1)
        .and_then(|t| t.split(' ').next())
        .and_then(|t| t.parse().ok())
        .unwrap_or_else(|| panic!("{line}"));
    // Within 0.1 % of the branch (the peak read between the 256 samples of
    // a period, and the harmonic truncation of a contact point).
    assert!(percent.abs() < 0.1, "{line}");
    let record: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(dir.join("fixed/simulation.json")).unwrap())
            .unwrap();
    assert_eq!(record["attractor"]["kind"], "periodic");
    assert_eq!(
        record["reference_amplitudes_m"].as_array().unwrap().len(),
        1
    );
}

/// Issue 45 item 4: `--from` a results folder of another case (6 sectors
/// against 7, or only the excitation amplitude changed) is refused as
/// `cyclorub compare` refuses the pair: exit 2, the flag and the keys.
#[test]
fn a_start_from_the_results_of_another_case_is_refused() {
    let dir = scratch("from-other");
    let case = small_case(&dir);
    let results = dir.join("results").display().to_string();
    run_at(&case, "150", &results);
    for (name, extra, key) in [
        ("sectors", "[model]\nsectors = 7\n", "model.sectors"),
        (
            "amplitude",
            "[model]\nsectors = 6\n[excitation]\namplitude = 5.0\n",
            "excitation.amplitude",
        ),
    ] {
        let other = dir.join(format!("{name}.toml"));
        std::fs::write(
            &other,
            format!("{extra}[harmonic_balance]\nharmonics = 10\ntime_samples = 1200\n"),
        )
        .unwrap();
        let out = dir.join(format!("sim-{name}")).display().to_string();
        let simulate = cyclorub(&[
            "simulate",
            &other.display().to_string(),
            "--from",
            &results,
            "--point",
            "0",
            "--periods",
            "1",
            "--output",
            &out,
        ]);
        let message = text(&simulate.stderr);
        assert_eq!(simulate.status.code(), Some(2), "{name}: {message}");
        assert!(
            message.contains(&format!("--from {results}"))
                && message.contains("not results of the same case")
                && message.contains(key),
            "{name}: {message}"
        );
        assert!(
            !std::path::Path::new(&out).exists(),
            "{name}: nothing written"
        );
    }
}
