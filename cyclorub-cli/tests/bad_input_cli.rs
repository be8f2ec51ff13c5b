//! Bad inputs found by a hostile run (issue 23), each refused by the
//! process as it should be: exit code 2 (bad input) or 1 (a failure while
//! working), never a panic, the key or argument named in the message.

use crate::common::{cyclorub, Scratch};
use std::path::{Path, PathBuf};
use std::process::{Command, Output, Stdio};

fn scratch(name: &str) -> Scratch {
    crate::common::scratch("bad-input", name)
}

/// The base case (`N = 6`, `N_h = 3`, `N_t = 60`, 300 points) with
/// `model`, `harmonic_balance` and further tables' lines added.
fn case(dir: &Path, model: &str, harmonic_balance: &str, rest: &str) -> PathBuf {
    let sectors = if model.contains("sectors") {
        ""
    } else {
        "sectors = 6"
    };
    let hb = if harmonic_balance.is_empty() {
        "harmonics = 3\ntime_samples = 60"
    } else {
        harmonic_balance
    };
    let text = format!(
        "[model]\n{sectors}\n{model}\n[harmonic_balance]\n{hb}\n[continuation]\nmax_points = 300\n{rest}\n"
    );
    let path = dir.join("case.toml");
    std::fs::write(&path, text).unwrap();
    path
}

fn run(dir: &Path, case: &Path) -> Output {
    let out = dir.join("results");
    cyclorub(&[
        "run",
        case.to_str().unwrap(),
        "--output",
        out.to_str().unwrap(),
    ])
}

/// Exit code `code`, no panic, and every one of `parts` in stderr.
fn assert_refused(output: &Output, code: i32, parts: &[&str]) {
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert_eq!(output.status.code(), Some(code), "{stderr}");
    assert!(!stderr.contains("panicked"), "{stderr}");
    for part in parts {
        assert!(stderr.contains(part), "stderr lacks {part:?}: {stderr}");
    }
}

#[test]
fn a_huge_sector_count_is_refused_before_any_work() {
    let dir = scratch("sectors");
    let path = case(&dir, "sectors = 9223372036854775807", "", "");
    assert_refused(&run(&dir, &path), 2, &["model.sectors", "at most 10000"]);
}

#[test]
fn harmonics_beyond_memory_are_refused_before_any_work() {
    let dir = scratch("harmonics");
    let path = case(&dir, "", "harmonics = 1000000\ntime_samples = 2000001", "");
    assert_refused(
        &run(&dir, &path),
        2,
        &["too large", "harmonic_balance.harmonics", "GB"],
    );
    // Time samples alone.
    let path = case(&dir, "", "harmonics = 3\ntime_samples = 100000000", "");
    assert_refused(
        &run(&dir, &path),
        2,
        &["the time samples", "harmonic_balance.time_samples"],
    );
}

#[test]
fn a_sector_larger_than_dense_storage_allows_is_refused_up_front() {
    let dir = scratch("dofs");
    let masses = vec!["1.0"; 30_000].join(", ");
    let path = case(
        &dir,
        &format!(
            "masses = [{masses}]\nsprings = [{{ dofs = [1], stiffness = 1.0, link = \"ground\" }}]"
        ),
        "",
        "",
    );
    assert_refused(&run(&dir, &path), 2, &["model.masses", "at most 2000 dofs"]);
    // A Matrix Market file is refused from its size line, before its entries.
    let n = 20_000;
    std::fs::write(
        dir.join("big.mtx"),
        format!("%%MatrixMarket matrix coordinate real symmetric\n{n} {n} {n}\n1 1 1.0\n"),
    )
    .unwrap();
    let path = case(
        &dir,
        "kind = \"matrix_market\"\nmass_file = \"big.mtx\"\nstiffness_file = \"big.mtx\"",
        "",
        "",
    );
    assert_refused(&run(&dir, &path), 2, &["big.mtx:2", "limit 2000 rows"]);
}

#[test]
fn plan_arguments_beyond_the_limits_are_refused() {
    let output = cyclorub(&[
        "plan",
        "--sectors",
        "18446744073709551615",
        "--harmonics",
        "3",
        "--contact-dofs",
        "1",
    ]);
    assert_refused(
        &output,
        2,
        &["--sectors 18446744073709551615", "at most 10000"],
    );
    let output = cyclorub(&[
        "plan",
        "--sectors",
        "24",
        "--harmonics",
        "9223372036854775807",
        "--contact-dofs",
        "1",
    ]);
    assert_refused(&output, 2, &["--harmonics 9223372036854775807", "too many"]);
    // No wrapped arithmetic in the table: refused.
    let output = cyclorub(&[
        "plan",
        "--sectors",
        "24",
        "--harmonics",
        "3",
        "--contact-dofs",
        "18446744073709551615",
    ]);
    assert_refused(
        &output,
        2,
        &["--contact-dofs 18446744073709551615", "at most 2000"],
    );
    let output = cyclorub(&[
        "plan",
        "--sweep-sectors",
        "2..10",
        "--harmonics",
        "9223372036854775807",
    ]);
    assert_refused(&output, 2, &["--harmonics", "too many"]);
}

#[test]
fn plan_help_says_which_arguments_are_required() {
    let output = cyclorub(&["plan", "--help"]);
    let help = String::from_utf8_lossy(&output.stdout);
    for flag in ["--sectors <N>", "--contact-dofs <n>", "--harmonics <NH>"] {
        let line = help
            .lines()
            .skip_while(|l| !l.trim_start().starts_with(flag))
            .nth(1)
            .unwrap_or_else(|| panic!("{flag} missing: {help}"));
        assert!(line.contains("Required"), "{flag}: {line}");
    }
}

/// A full standard output is a failure to report (exit 1), not a panic.
#[test]
fn a_full_standard_output_is_reported() {
    let full = Path::new("/dev/full");
    if !full.exists() {
        return; // not Linux: nothing to write into
    }
    let commands: [&[&str]; 3] = [
        &[
            "plan",
            "--sectors",
            "24",
            "--harmonics",
            "3",
            "--contact-dofs",
            "1",
        ],
        &["modes", "--json", "--no-plot"],
        &["init"],
    ];
    for args in commands {
        let output = Command::new(env!("CARGO_BIN_EXE_cyclorub"))
            .args(args)
            .stdout(std::fs::OpenOptions::new().write(true).open(full).unwrap())
            .stderr(Stdio::piped())
            .output()
            .unwrap();
        assert_refused(&output, 1, &["cannot write to standard output"]);
    }
}

#[test]
fn a_mixed_excitation_needs_nonnegative_weights_not_both_zero() {
    let dir = scratch("mixed");
    let path = case(
        &dir,
        "",
        "",
        "[excitation]\nkind = \"mixed\"\nbackward_weight = -1.0",
    );
    assert_refused(
        &run(&dir, &path),
        2,
        &["excitation.backward_weight = -1", "≥ 0"],
    );
    let path = case(
        &dir,
        "",
        "",
        "[excitation]\nkind = \"mixed\"\nbackward_weight = 0.0\nforward_weight = 0.0",
    );
    assert_refused(
        &run(&dir, &path),
        2,
        &["excitation.forward_weight", "both 0"],
    );
}

#[test]
fn the_output_table_names_a_folder_and_each_sector_once() {
    let dir = scratch("output");
    let path = case(&dir, "", "", "[output]\ndirectory = \"\"");
    // Without --output: the case's folder is used.
    let output = cyclorub(&["run", path.to_str().unwrap()]);
    assert_refused(&output, 2, &["output.directory", "name a results folder"]);
    let path = case(&dir, "", "", "[output]\nsectors = [1, 1]");
    assert_refused(&run(&dir, &path), 2, &["output.sectors", "listed twice"]);
}

#[test]
fn a_results_folder_under_a_file_is_refused_before_the_solve() {
    let dir = scratch("under-file");
    std::fs::write(dir.join("a_file"), "").unwrap();
    let path = case(&dir, "", "", "");
    let folder = dir.join("a_file").join("results");
    let output = cyclorub(&[
        "run",
        path.to_str().unwrap(),
        "--output",
        folder.to_str().unwrap(),
    ]);
    assert_refused(&output, 2, &["cannot be used", "--output"]);
    // Nothing was solved: no summary of points.
    assert!(!String::from_utf8_lossy(&output.stdout).contains("points ("));
    let output = cyclorub(&[
        "run",
        path.to_str().unwrap(),
        "--output",
        dir.join("a_file").to_str().unwrap(),
    ]);
    assert_refused(&output, 2, &["a file, not a folder"]);
}

/// Issue 45 item 16: `simulate` and `plot` said "File exists (os error
/// 17)" of `--output /dev/full` where `run` said "is a file, not a
/// folder": one wording for the three, said before any work.
#[test]
fn an_output_that_is_a_file_is_worded_alike_by_run_simulate_and_plot() {
    let dir = scratch("output-file");
    let file = dir.join("a_file");
    std::fs::write(&file, "").unwrap();
    let path = case(&dir, "", "", "");
    let (case, file) = (path.to_str().unwrap(), file.to_str().unwrap());
    let under = format!("{file}/figures");
    // plot checks --output before it reads the results folder.
    let results = dir.to_str().unwrap();
    let mut outputs = vec![file, under.as_str()];
    if Path::new("/dev/full").exists() {
        outputs.push("/dev/full");
    }
    for output in outputs {
        for args in [
            vec!["run", case, "--output", output],
            vec![
                "simulate",
                case,
                "--at-hz",
                "150",
                "--periods",
                "2",
                "--output",
                output,
            ],
            vec!["plot", results, "--output", output],
        ] {
            let out = cyclorub(&args);
            let stderr = String::from_utf8_lossy(&out.stderr);
            println!("{args:?}: {stderr}");
            assert_refused(&out, 2, &["cannot be used", "is a file, not a folder"]);
            assert!(!stderr.contains("os error"), "{args:?}: {stderr}");
            assert!(!String::from_utf8_lossy(&out.stdout).contains("points ("));
        }
    }
}

#[test]
fn a_damping_matrix_must_dissipate() {
    let dir = scratch("damping");
    let path = case(
        &dir,
        "kind = \"matrices\"\nmass = [[1.0]]\nstiffness = [[1.0]]\n[model.damping]\nkind = \"matrix\"\nmatrix = [[-1.0]]",
        "",
        "",
    );
    assert_refused(
        &run(&dir, &path),
        2,
        &[
            "model.damping.matrix",
            "not positive semidefinite",
            "dissipate",
        ],
    );
}

#[test]
fn a_stiffness_that_does_not_hold_the_wheel_is_named() {
    let dir = scratch("stiffness");
    let singular = [
        ("springs = []", "model.springs"),
        (
            "kind = \"matrices\"\nmass = [[1.0, 0.0], [0.0, 1.0]]\nstiffness = [[0.0, 0.0], [0.0, 0.0]]",
            "model.stiffness",
        ),
    ];
    for (model, key) in singular {
        let path = case(&dir, model, "", "");
        assert_refused(
            &run(&dir, &path),
            2,
            &[key, "singular", "rigid-body motion"],
        );
    }
    let path = case(
        &dir,
        "kind = \"matrices\"\nmass = [[1.0, 0.0], [0.0, 1.0]]\nstiffness = [[1.0, 0.0], [0.0, -1.0]]",
        "",
        "",
    );
    assert_refused(
        &run(&dir, &path),
        2,
        &["model.stiffness", "not positive semidefinite"],
    );
    // A Matrix Market entry listed twice is summed: the message says so.
    std::fs::write(
        dir.join("k.mtx"),
        "%%MatrixMarket matrix coordinate real general\n2 2 4\n1 1 1.0\n2 2 1.0\n2 2 -3.0\n1 1 1.0\n",
    )
    .unwrap();
    std::fs::write(
        dir.join("m.mtx"),
        "%%MatrixMarket matrix coordinate real general\n2 2 2\n1 1 1.0\n2 2 1.0\n",
    )
    .unwrap();
    let path = case(
        &dir,
        "kind = \"matrix_market\"\nmass_file = \"m.mtx\"\nstiffness_file = \"k.mtx\"",
        "",
        "",
    );
    assert_refused(
        &run(&dir, &path),
        2,
        &["model.stiffness_file", "k.mtx", "listed twice", "summed"],
    );
}

#[test]
fn a_matrix_market_file_cut_in_its_last_number_is_refused() {
    let dir = scratch("cut");
    std::fs::write(
        dir.join("m.mtx"),
        "%%MatrixMarket matrix coordinate real general\n2 2 2\n1 1 1.0\n2 2 3.6",
    )
    .unwrap();
    let path = case(
        &dir,
        "kind = \"matrix_market\"\nmass_file = \"m.mtx\"\nstiffness_file = \"m.mtx\"",
        "",
        "",
    );
    assert_refused(&run(&dir, &path), 2, &["m.mtx:4", "2 2 3.6", "cut"]);
}

#[test]
fn zero_time_samples_are_blamed_on_time_samples() {
    let dir = scratch("time-samples");
    let path = case(&dir, "", "harmonics = 3\ntime_samples = 0", "");
    let output = run(&dir, &path);
    assert_refused(
        &output,
        2,
        &[
            "harmonic_balance.time_samples = 0",
            "2 × harmonic_balance.harmonics + 1 = 7",
        ],
    );
    assert!(!String::from_utf8_lossy(&output.stderr).contains("casing.order"));
}

#[test]
fn a_response_out_of_proportion_is_flagged() {
    let dir = scratch("plausible");
    let path = case(&dir, "", "", "[excitation]\nstatic_force = 1e9");
    let output = run(&dir, &path);
    let stdout = String::from_utf8_lossy(&output.stdout);
    assert!(!String::from_utf8_lossy(&output.stderr).contains("panicked"));
    assert!(
        stdout.contains("warning: the observed dof moves by up to"),
        "{stdout}"
    );
    assert!(stdout.contains("excitation.static_force"), "{stdout}");
    let json: serde_json::Value = serde_json::from_str(
        &std::fs::read_to_string(dir.join("results").join("run.json")).unwrap(),
    )
    .unwrap();
    assert_eq!(json["warnings"].as_array().map(Vec::len), Some(1), "{json}");
}
