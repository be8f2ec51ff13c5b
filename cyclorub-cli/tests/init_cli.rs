//! `cyclorub init` end to end: the default template is the default case,
//! every example is the file in `examples/` (so they cannot drift), the
//! list, and bad arguments (exit code 2).

use cyclorub::case::Case;
use cyclorub_app::template::{Example, EXAMPLES};
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

#[test]
fn every_example_is_the_file_in_examples() {
    let dir = examples_dir();
    for example in &EXAMPLES {
        let printed = stdout(&["--example", example.name]);
        let path = dir.join(format!("{}.toml", example.name));
        let on_disk = std::fs::read_to_string(&path).unwrap_or_else(|e| {
            panic!(
                "{}: {e}; regenerate with: cyclorub init --example {} > examples/{}.toml",
                path.display(),
                example.name,
                example.name
            )
        });
        assert!(
            printed == on_disk,
            "{} differs from `cyclorub init --example {}`; regenerate it with \
             cyclorub init --example {} > examples/{}.toml",
            path.display(),
            example.name,
            example.name,
            example.name
        );
        let case = Case::from_toml(&on_disk, &path).unwrap();
        case.validate().unwrap();
        assert_eq!(case, example.case());
    }
    // Nothing else in examples/ claims to be a generated case file.
    let on_disk: BTreeSet<String> = std::fs::read_dir(&dir)
        .unwrap()
        .filter_map(|e| e.ok()?.file_name().into_string().ok())
        .filter(|name| name.ends_with(".toml"))
        .collect();
    let expected: BTreeSet<String> = Example::names()
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
    assert_eq!(names, Example::names());
    assert!(text.contains("n24-mixed-h6-casing-h8"));
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
    for name in Example::names() {
        assert!(stderr.contains(name), "{name} missing from {stderr}");
    }
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

/// README's "Case file" section names every key of the template.
#[test]
fn the_readme_documents_every_key() {
    let readme =
        std::fs::read_to_string(Path::new(env!("CARGO_MANIFEST_DIR")).join("../README.md"))
            .unwrap();
    let section = readme
        .split("## Case file")
        .nth(1)
        .expect("README has a \"Case file\" section");
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
                "{key} missing from README"
            );
            count += 1;
        }
    }
    assert!(count >= 50, "{count}");
}
