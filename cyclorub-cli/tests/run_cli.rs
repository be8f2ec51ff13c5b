//! `cyclorub run`: result files, fixed frequencies, early stops, bad input.

use crate::common::cyclorub;
use std::path::{Path, PathBuf};
use std::process::Output;

fn scratch(name: &str) -> crate::common::Scratch {
    crate::common::scratch("run-cli", name)
}

/// A short version of the paper's default case.
const SHORT: &str = r#"
[harmonic_balance]
harmonics = 5
time_samples = 240
[continuation]
start_hz = 120.0
end_hz = 124.0
"#;

fn write_case(dir: &Path, extra: &str) -> PathBuf {
    let path = dir.join("case.toml");
    std::fs::write(&path, format!("{SHORT}\n{extra}")).unwrap();
    path
}

fn stderr(output: &Output) -> String {
    String::from_utf8_lossy(&output.stderr).into_owned()
}

#[test]
fn run_writes_branch_csv_and_run_json() {
    let dir = scratch("files");
    let case = write_case(&dir, "");
    let out = dir.join("results");
    let output = cyclorub(&[
        "run",
        case.to_str().unwrap(),
        "--output",
        out.to_str().unwrap(),
    ]);
    assert!(output.status.success(), "{}", stderr(&output));
    let csv = std::fs::read_to_string(out.join("branch.csv")).unwrap();
    let header: Vec<&str> = csv.lines().next().unwrap().split(',').collect();
    assert_eq!(
        &header[..3],
        &["point", "frequency_hz", "amplitude_sector_1"]
    );
    assert_eq!(
        header
            .iter()
            .filter(|h| h.starts_with("amplitude_sector_"))
            .count(),
        24
    );
    assert!(header.contains(&"iterations") && header.contains(&"residual_norm"));
    let rows: Vec<Vec<f64>> = csv
        .lines()
        .skip(1)
        .map(|l| l.split(',').take(3).map(|v| v.parse().unwrap()).collect())
        .collect();
    assert!(rows.len() > 3);
    assert!((rows[0][1] - 120.0).abs() < 1e-9 && (rows.last().unwrap()[1] - 124.0).abs() < 1e-9);
    let json: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("run.json")).unwrap()).unwrap();
    assert_eq!(json["basis"]["kind"], "symmetry");
    // Traveling wave h = 1: one pair per harmonic, 2 N_h + 1 real unknowns.
    assert_eq!(json["basis"]["unknowns"], 11);
    assert_eq!(json["basis"]["sampled_sectors"], 1);
    assert_eq!(json["stop"]["reason"], "end_reached");
    assert_eq!(json["case"]["model"]["sectors"], 24);
    assert!(json["timings"]["solve_s"].as_f64().unwrap() >= 0.0);
}

#[test]
fn at_hz_solves_exactly_the_given_frequencies_and_basis_overrides() {
    let dir = scratch("at-hz");
    let case = write_case(&dir, "");
    for basis in ["symmetry", "physical"] {
        let out = dir.join(basis);
        let output = cyclorub(&[
            "run",
            case.to_str().unwrap(),
            "--output",
            out.to_str().unwrap(),
            "--basis",
            basis,
            "--at-hz",
            "121,122.5,123",
        ]);
        assert!(output.status.success(), "{}", stderr(&output));
        let csv = std::fs::read_to_string(out.join("branch.csv")).unwrap();
        let frequencies: Vec<f64> = csv
            .lines()
            .skip(1)
            .map(|l| l.split(',').nth(1).unwrap().parse().unwrap())
            .collect();
        assert_eq!(frequencies.len(), 3);
        for (f, e) in frequencies.iter().zip([121.0, 122.5, 123.0]) {
            assert!((f - e).abs() < 1e-9);
        }
        let json: serde_json::Value =
            serde_json::from_str(&std::fs::read_to_string(out.join("run.json")).unwrap()).unwrap();
        assert_eq!(json["basis"]["kind"], basis);
        assert_eq!(json["mode"], "at_frequencies");
    }
    // The two bases give the same amplitudes.
    let read = |b: &str| std::fs::read_to_string(dir.join(b).join("branch.csv")).unwrap();
    let (a, b) = (read("symmetry"), read("physical"));
    for (la, lb) in a.lines().skip(1).zip(b.lines().skip(1)) {
        let va: Vec<f64> = la
            .split(',')
            .skip(2)
            .take(24)
            .map(|v| v.parse().unwrap())
            .collect();
        let vb: Vec<f64> = lb
            .split(',')
            .skip(2)
            .take(24)
            .map(|v| v.parse().unwrap())
            .collect();
        for (x, y) in va.iter().zip(&vb) {
            assert!((x - y).abs() <= 1e-8 * y.abs(), "{x} vs {y}");
        }
    }
}

#[test]
fn a_run_stopped_early_keeps_its_points_and_says_why() {
    let dir = scratch("cap");
    let case = write_case(&dir, "[output]\nsectors = [1, 7]\n");
    let text = std::fs::read_to_string(&case)
        .unwrap()
        .replace("end_hz = 124.0", "end_hz = 124.0\nmax_points = 3");
    std::fs::write(&case, text).unwrap();
    let out = dir.join("results");
    let output = cyclorub(&[
        "run",
        case.to_str().unwrap(),
        "--output",
        out.to_str().unwrap(),
    ]);
    assert_eq!(output.status.code(), Some(1));
    assert!(
        stderr(&output).contains("stopped at its cap of 3 points"),
        "{}",
        stderr(&output)
    );
    let csv = std::fs::read_to_string(out.join("branch.csv")).unwrap();
    assert_eq!(csv.lines().count(), 4);
    assert!(csv.lines().next().unwrap().contains("amplitude_sector_7"));
    let json: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("run.json")).unwrap()).unwrap();
    assert_eq!(json["stop"]["reason"], "point_cap");
}

/// The paper's default case with steps that may not shrink: the sweep from
/// the start stops in the contact plateau's folds (step underflow), and the
/// sweep back from the end meets it. (Which rigid step does so depends on
/// the continuation's details: 0.05 went through once the tangent came
/// from the corrector's factors; 0.045 stops and is joined.)
const RIGID_STEPS: &str = r#"
[harmonic_balance]
harmonics = 5
time_samples = 240
[continuation]
initial_step = 0.045
min_step = 0.045
max_step = 0.045
"#;

#[test]
fn a_sweep_stopped_short_is_joined_by_the_sweep_back_from_the_end() {
    let dir = scratch("both-ends");
    let case = dir.join("case.toml");
    std::fs::write(&case, RIGID_STEPS).unwrap();
    let out = dir.join("results");
    let output = cyclorub(&[
        "run",
        case.to_str().unwrap(),
        "--output",
        out.to_str().unwrap(),
    ]);
    let stdout = String::from_utf8_lossy(&output.stdout);
    assert!(output.status.success(), "{stdout}\n{}", stderr(&output));
    assert!(
        stdout.contains("followed from both ends") && stdout.contains("joined"),
        "{stdout}"
    );
    let json: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("run.json")).unwrap()).unwrap();
    assert_eq!(json["stop"]["reason"], "end_reached");
    let sweeps = &json["sweeps"];
    assert_eq!(sweeps["from_start"]["reason"], "step_underflow");
    assert_eq!(sweeps["from_end"]["reason"], "met_other_sweep");
    let kept = sweeps["from_start_kept"].as_u64().unwrap();
    assert_eq!(sweeps["from_end"]["point"].as_u64().unwrap() + 1, kept);
    let start = json["case"]["continuation"]["start_hz"].as_f64().unwrap();
    let end = json["case"]["continuation"]["end_hz"].as_f64().unwrap();
    let csv = std::fs::read_to_string(out.join("branch.csv")).unwrap();
    let hz: Vec<f64> = csv
        .lines()
        .skip(1)
        .map(|l| l.split(',').nth(1).unwrap().parse().unwrap())
        .collect();
    assert_eq!(
        hz.len() as u64,
        kept + sweeps["from_end_points"].as_u64().unwrap()
    );
    assert!((hz[0] - start).abs() < 1e-9 * start, "{} vs {start}", hz[0]);
    assert!((hz[hz.len() - 1] - end).abs() < 1e-9 * end);
}

#[test]
fn points_streamed_in_the_order_of_both_sweeps_are_written_in_the_branchs_order() {
    use cyclorub::case::Case;
    use cyclorub::results::data::PointResults;
    use cyclorub::run::{run_keeping, RunOptions};
    let dir = scratch("both-ends-order");
    let case = Case::from_toml(RIGID_STEPS, &dir.join("case.toml")).unwrap();
    let options = RunOptions {
        output: dir.join("results"),
        basis: case.basis.kind,
        at_hz: None,
        stability: None,
        overwrite: false,
        interrupt: Default::default(),
    };
    let outcome = run_keeping(&case, &dir, &options, |_| {}).unwrap();
    let sweeps = outcome.branch.sweeps.as_ref().expect("both ends");
    assert!(sweeps.from_start_points > sweeps.from_start_kept);
    let table =
        cyclorub::results::folder::BranchTable::read(&dir.join("results/branch.csv")).unwrap();
    assert_eq!(table.rows.len(), outcome.branch.points.len());
    let dof = case.output.observed_dof - 1;
    let samples = case.harmonic_balance.time_samples;
    for (i, (point, row)) in outcome.branch.points.iter().zip(&table.rows).enumerate() {
        let again = PointResults::compute(&outcome.problem, point, dof, samples).unwrap();
        assert_eq!(again, outcome.data.points[i], "point {i}");
        assert_eq!(row.point, i);
        let hz = point.omega / (2.0 * std::f64::consts::PI);
        assert!((row.frequency_hz - hz).abs() <= 1e-11 * hz, "point {i}");
        for (a, b) in row.amplitudes.iter().zip(&again.amplitude) {
            assert!((a - b).abs() <= 1e-11 * b, "point {i}: {a} against {b}");
        }
    }
}

#[test]
fn bad_input_is_refused_before_any_work_with_the_key() {
    let dir = scratch("bad");
    let cases = [
        // The refused value is located by its line in the file.
        ("[casing]\ngap = -1e-3", "case.toml:10)"),
        ("[contact]\nstiffness = -1.0", "contact.stiffness"),
        (
            "[excitation]\nengine_order = 30",
            "excitation.engine_order = 30",
        ),
        (
            "[model]\nsectors = 24\n[casing]\ngapp = 3",
            "unknown field `gapp`",
        ),
    ];
    for (extra, expected) in cases {
        let case = write_case(&dir, extra);
        let output = cyclorub(&[
            "run",
            case.to_str().unwrap(),
            "--output",
            dir.join("r").to_str().unwrap(),
        ]);
        assert_eq!(
            output.status.code(),
            Some(2),
            "{extra}: {}",
            stderr(&output)
        );
        assert!(
            stderr(&output).contains(expected),
            "{extra}: {}",
            stderr(&output)
        );
    }
    // Keys of SHORT overridden: too few time samples, empty frequency range.
    for (from, to, expected) in [
        (
            "time_samples = 240",
            "time_samples = 8",
            "harmonic_balance.time_samples = 8",
        ),
        (
            "end_hz = 124.0",
            "end_hz = 120.0",
            "frequency range is empty",
        ),
    ] {
        let case = write_case(&dir, "");
        let text = std::fs::read_to_string(&case).unwrap().replace(from, to);
        std::fs::write(&case, text).unwrap();
        let output = cyclorub(&["run", case.to_str().unwrap()]);
        assert_eq!(output.status.code(), Some(2), "{}", stderr(&output));
        assert!(stderr(&output).contains(expected), "{}", stderr(&output));
    }
    let case = write_case(&dir, "");
    let output = cyclorub(&["run", case.to_str().unwrap(), "--basis", "magic"]);
    assert_eq!(output.status.code(), Some(2));
    assert!(stderr(&output).contains("allowed: symmetry, paper, nodal_diameter, full, physical"));
    let output = cyclorub(&["run", "/nonexistent/case.toml"]);
    assert_eq!(output.status.code(), Some(2));
    assert!(stderr(&output).contains("cannot read the case file"));
}

/// A mistuned wheel (issue 44) runs on the full wheel, its summary names
/// the amplification factor and the most responding sector, and a reduced
/// basis is refused with why.
#[test]
fn a_mistuned_run_prints_its_amplification_factor() {
    let dir = scratch("mistuned");
    let case = write_case(
        &dir,
        "[model]\nsectors = 6\n[mistuning]\nstandard_deviation = 0.02\nseed = 4\n",
    );
    let out = dir.join("results");
    let output = cyclorub(&[
        "run",
        case.to_str().unwrap(),
        "--basis",
        "physical",
        "--at-hz",
        "200,204,206",
        "--output",
        out.to_str().unwrap(),
    ]);
    let stdout = String::from_utf8_lossy(&output.stdout);
    assert!(output.status.success(), "{}{stdout}", stderr(&output));
    assert!(
        stdout.contains("mistuned wheel: amplification factor")
            && stdout.contains("most responding sector"),
        "{stdout}"
    );
    // Its stability is checked on its one class, the whole wheel.
    assert!(stdout.contains("stability (Hill, H = "), "{stdout}");
    // A point's check says so; a refinement whose whole-wheel eigenproblem
    // is too large (2 · 6 sectors · 21 pairs = 252 > 200) is refused before
    // its orbit is solved, and the point's own exponents are still printed.
    let point = cyclorub(&[
        "stability",
        out.to_str().unwrap(),
        "--point",
        "1",
        "--largest-eigenproblem",
        "200",
    ]);
    let (printed, warned) = (String::from_utf8_lossy(&point.stdout), stderr(&point));
    assert!(point.status.success(), "{warned}{printed}");
    assert!(
        printed.contains("on the whole wheel (mistuned: its one symmetry class)"),
        "{printed}"
    );
    assert!(
        warned.contains("not refined to 2 times the harmonics")
            && warned.contains("size 252, above the limit 200"),
        "{warned}"
    );
    assert!(out.join("plots").join("sector_peaks.svg").exists());
    // `cyclorub plot` redraws the mistuning figures too.
    let redrawn = dir.join("redrawn");
    let plot = cyclorub(&[
        "plot",
        out.to_str().unwrap(),
        "--output",
        redrawn.to_str().unwrap(),
    ]);
    assert!(plot.status.success(), "{}", stderr(&plot));
    for figure in ["sector_peaks.svg", "sector_amplitudes.svg"] {
        assert!(redrawn.join(figure).exists(), "{figure} not redrawn");
    }
    let refused = cyclorub(&[
        "run",
        case.to_str().unwrap(),
        "--output",
        out.to_str().unwrap(),
    ]);
    assert!(!refused.status.success());
    assert!(
        stderr(&refused).contains("cannot hold a mistuned wheel"),
        "{}",
        stderr(&refused)
    );
}
