//! `cyclorub init` end to end: the default template is the default case,
//! every example (academic and open fan) is the file in `examples/` (so
//! they cannot drift), the list, and bad arguments (exit code 2).

use cyclorub::case::Case;
use cyclorub_app::template::{example_names, EXAMPLES, FAN_EXAMPLES, FAN_FOLDER};
use std::collections::BTreeSet;
use std::path::{Path, PathBuf};
use std::process::{Command, Output};

fn init(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_cyclorub"))
        .arg("init")
        .args(args)
        .output()
        .expect("the cyclorub binary runs")
}

fn stdout(args: &[&str]) -> String {
    let out = init(args);
    assert!(
        out.status.success(),
        "init {args:?}: {}",
        String::from_utf8_lossy(&out.stderr)
    );
    String::from_utf8(out.stdout).expect("UTF-8")
}

fn examples_dir() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../examples")
}

/// A fresh scratch folder under the target directory.
fn scratch(name: &str) -> PathBuf {
    let dir = Path::new(env!("CARGO_TARGET_TMPDIR")).join(name);
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

#[test]
fn init_prints_the_default_case_with_comments() {
    let text = stdout(&[]);
    let case = Case::from_toml(&text, Path::new("case.toml")).unwrap();
    assert_eq!(case, Case::default());
    for key in [
        "[model]",
        "[model.damping]",
        "[excitation]",
        "[casing]",
        "[contact]",
        "[harmonic_balance]",
        "[continuation]",
        "[basis]",
        "[output]",
        "time_samples = 10000",
        "# start_hz = ",
        "# end_hz = ",
    ] {
        assert!(text.contains(key), "{key} missing:\n{text}");
    }
    // Every set key has a comment line just above it.
    let lines: Vec<&str> = text.lines().collect();
    for (i, line) in lines.iter().enumerate() {
        let is_key = !line.starts_with('#')
            && !line.starts_with('[')
            && !line.starts_with(' ')
            && !line.starts_with(']')
            && line.contains(" = ");
        if is_key {
            assert!(lines[i - 1].starts_with("# "), "no comment above {line:?}");
        }
    }
}

/// The file `examples/NAME.toml`, which must be what `cyclorub init
/// --example NAME` prints, parsed and checked (keys and values only: the
/// fan examples' mesh files are not committed).
fn example_file(name: &str) -> Case {
    let printed = stdout(&["--example", name]);
    let path = examples_dir().join(format!("{name}.toml"));
    let on_disk = std::fs::read_to_string(&path).unwrap_or_else(|e| {
        panic!(
            "{}: {e}; regenerate with: cyclorub init --example {name} > examples/{name}.toml",
            path.display()
        )
    });
    assert!(
        printed == on_disk,
        "{} differs from `cyclorub init --example {name}`; regenerate it with \
         cyclorub init --example {name} > examples/{name}.toml",
        path.display()
    );
    let case = Case::from_toml(&on_disk, &path).unwrap();
    case.validate().unwrap();
    case
}

#[test]
fn every_example_is_the_file_in_examples() {
    let dir = examples_dir();
    for example in &EXAMPLES {
        assert_eq!(example_file(example.name), example.case());
    }
    for example in &FAN_EXAMPLES {
        let case = example_file(example.name);
        assert_eq!(case, example.case());
        // The model files are in the fan folder next to the examples.
        for file in [&case.model.mass_file, &case.model.node_sets_file] {
            let file = file.as_ref().expect("a fan example names its model files");
            assert!(file.starts_with(FAN_FOLDER), "{}", file.display());
        }
    }
    // Nothing else in examples/ claims to be a generated case file.
    let on_disk: BTreeSet<String> = std::fs::read_dir(&dir)
        .unwrap()
        .filter_map(|e| e.ok()?.file_name().into_string().ok())
        .filter(|name| name.ends_with(".toml"))
        .collect();
    let expected: BTreeSet<String> = example_names()
        .iter()
        .map(|n| format!("{n}.toml"))
        .collect();
    assert_eq!(on_disk, expected);
}

#[test]
fn list_names_every_example() {
    let text = stdout(&["--list"]);
    let names: Vec<&str> = text
        .lines()
        .map(|l| l.split_whitespace().next().unwrap())
        .collect();
    assert_eq!(names, example_names());
    assert!(text.contains("n24-mixed-h6-casing-h8"));
    assert!(text.contains("fan16-partly-standing-h7"));
    assert!(text.contains("f_ex = 0.3 N, friction 0.15"));
    assert!(text.contains("casing h_c = 8, p = 0.05 c"));
    assert!(text.contains("f_ex = 1.75 N"));
}

#[test]
fn an_unknown_example_exits_2_with_the_list() {
    let out = init(&["--example", "n24-travelling-h1"]);
    assert_eq!(out.status.code(), Some(2));
    assert!(out.stdout.is_empty());
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(stderr.contains("n24-travelling-h1"), "{stderr}");
    for name in example_names() {
        assert!(stderr.contains(name), "{name} missing from {stderr}");
    }
}

/// A fan example run before its mesh is written names the key and the
/// file it could not read (exit code 2).
#[test]
fn a_fan_example_without_its_mesh_names_the_missing_file() {
    let dir = scratch("init_fan_without_mesh");
    let case = dir.join("fan16-traveling-h1.toml");
    std::fs::write(&case, stdout(&["--example", "fan16-traveling-h1"])).unwrap();
    let run = Command::new(env!("CARGO_BIN_EXE_cyclorub"))
        .arg("run")
        .arg(&case)
        .arg("--output")
        .arg(dir.join("results"))
        .output()
        .unwrap();
    assert_eq!(run.status.code(), Some(2));
    let stderr = String::from_utf8_lossy(&run.stderr);
    assert!(stderr.contains("model."), "{stderr}");
    assert!(stderr.contains(FAN_FOLDER), "{stderr}");
}

#[test]
fn list_and_example_together_exit_2() {
    let out = init(&["--list", "--example", "n24-traveling-h1"]);
    assert_eq!(out.status.code(), Some(2));
    let out = init(&["--example"]);
    assert_eq!(out.status.code(), Some(2));
}

#[test]
fn the_printed_template_is_a_case_file_the_other_commands_take() {
    let dir = scratch("init_template_runs");
    let case = dir.join("case.toml");
    std::fs::write(&case, stdout(&[])).unwrap();
    let modes = Command::new(env!("CARGO_BIN_EXE_cyclorub"))
        .args(["modes", "--no-plot", "--json"])
        .arg(&case)
        .output()
        .unwrap();
    assert!(
        modes.status.success(),
        "{}",
        String::from_utf8_lossy(&modes.stderr)
    );
    let results = dir.join("results");
    let run = Command::new(env!("CARGO_BIN_EXE_cyclorub"))
        .arg("run")
        .arg(&case)
        .arg("--output")
        .arg(&results)
        .args(["--at-hz", "120,125"])
        .output()
        .unwrap();
    assert!(
        run.status.success(),
        "{}",
        String::from_utf8_lossy(&run.stderr)
    );
    assert!(results.join("branch.csv").is_file());
}

/// The case-file reference (docs/case-file.md) names every key of the
/// template.
#[test]
fn the_reference_documents_every_key() {
    let section =
        std::fs::read_to_string(Path::new(env!("CARGO_MANIFEST_DIR")).join("../docs/case-file.md"))
            .unwrap();
    let text = stdout(&[]);
    let mut count = 0;
    for line in text.lines() {
        let line = line.strip_prefix("# ").unwrap_or(line);
        if let Some(table) = line.strip_prefix('[').and_then(|l| l.strip_suffix(']')) {
            assert!(section.contains(&format!("`[{table}]`")), "[{table}]");
            continue;
        }
        let Some((key, _)) = line.split_once(" = ") else {
            continue;
        };
        if key.chars().all(|c| c.is_ascii_lowercase() || c == '_') {
            assert!(
                section.contains(&format!("`{key}`")),
                "{key} missing from docs/case-file.md"
            );
            count += 1;
        }
    }
    assert!(count >= 50, "{count}");
}
