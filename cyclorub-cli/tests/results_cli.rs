//! `cyclorub run` writes results.h5 and figures; `cyclorub plot` redraws
//! them; `cyclorub compare` judges two folders (exit 0, 1, 2).

use crate::common::{cyclorub, text};
use std::path::{Path, PathBuf};

fn scratch(name: &str) -> crate::common::Scratch {
    crate::common::scratch("results-cli", name)
}

/// A short version of the paper's default case, near its resonance.
const SHORT: &str = r#"
[harmonic_balance]
harmonics = 5
time_samples = 240
"#;

const FREQUENCIES: &str = "125.0,126.5,127.2,127.5";

/// Runs the short case on `basis` at fixed frequencies into `dir/name`.
fn run(dir: &Path, name: &str, basis: &str, extra: &str) -> PathBuf {
    let case = dir.join(format!("{name}.toml"));
    std::fs::write(&case, format!("{SHORT}\n{extra}")).unwrap();
    let out = dir.join(name);
    let output = cyclorub(&[
        "run",
        case.to_str().unwrap(),
        "--output",
        out.to_str().unwrap(),
        "--basis",
        basis,
        "--at-hz",
        FREQUENCIES,
        // The stability check and its figures are tested in the library.
        "--no-stability",
    ]);
    assert!(output.status.success(), "{}", text(&output));
    out
}

fn copy_folder(from: &Path, to: &Path) {
    std::fs::create_dir_all(to).unwrap();
    for entry in std::fs::read_dir(from).unwrap() {
        let entry = entry.unwrap();
        if entry.file_type().unwrap().is_file() {
            std::fs::copy(entry.path(), to.join(entry.file_name())).unwrap();
        }
    }
}

/// Multiplies the `column`-th field of data line `line` (1-based after
/// the header) of a CSV file by `factor`.
fn perturb(path: &Path, line: usize, column: usize, factor: f64) {
    let text = std::fs::read_to_string(path).unwrap();
    let mut lines: Vec<String> = text.lines().map(str::to_string).collect();
    let mut fields: Vec<String> = lines[line].split(',').map(str::to_string).collect();
    let value: f64 = fields[column].parse().unwrap();
    fields[column] = format!("{:.15e}", value * factor);
    lines[line] = fields.join(",");
    std::fs::write(path, lines.join("\n") + "\n").unwrap();
}

fn parse_svg(path: &Path) -> Vec<String> {
    let text = std::fs::read_to_string(path).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
    let document = roxmltree::Document::parse(&text)
        .unwrap_or_else(|e| panic!("{} is not valid SVG: {e}", path.display()));
    assert_eq!(document.root_element().tag_name().name(), "svg");
    document
        .descendants()
        .filter(|n| n.has_tag_name("text"))
        .filter_map(|n| n.text().map(|t| t.trim().to_string()))
        .collect()
}

#[test]
fn run_writes_results_h5_and_the_default_figures() {
    let dir = scratch("run");
    let out = run(&dir, "reduced", "symmetry", "");
    assert!(out.join("results.h5").is_file());
    for name in [
        "forced_response.svg",
        "cyclic_components.svg",
        "first_harmonic_components.svg",
        "frequency_vs_nodal_diameter.svg",
    ] {
        let texts = parse_svg(&out.join("plots").join(name));
        assert!(!texts.is_empty(), "{name} has no text");
    }
    let texts = parse_svg(&out.join("plots/forced_response.svg"));
    // A traveling wave: every sector alike, one curve and its linear one.
    assert!(
        texts.iter().any(|t| t == "sector 1 (all 24 alike)"),
        "{texts:?}"
    );
    assert!(texts.iter().any(|t| t == "linear, sector 1 (all 24 alike)"));
    // The CSV of harmonics only on demand (`[output] harmonics_csv`).
    for name in ["branch.csv", "run.json"] {
        assert!(out.join(name).is_file(), "{name}");
    }
    assert!(!out.join("observed_harmonics.csv").exists());
}

#[test]
fn plot_redraws_with_chosen_sectors_and_a_reference() {
    let dir = scratch("plot");
    let a = run(&dir, "reduced", "symmetry", "");
    let b = run(&dir, "full", "physical", "");
    let figures = dir.join("figures");
    let output = cyclorub(&[
        "plot",
        a.to_str().unwrap(),
        "--sectors",
        "1,5",
        "--at-hz",
        "127.2",
        "--reference",
        b.to_str().unwrap(),
        "--output",
        figures.to_str().unwrap(),
    ]);
    assert!(output.status.success(), "{}", text(&output));
    let texts = parse_svg(&figures.join("forced_response.svg"));
    for label in [
        "sector 1",
        "sector 5",
        "linear, sector 5",
        "reference (physical), sector 1",
        "reference (physical), sector 5",
    ] {
        assert!(
            texts.iter().any(|t| t == label),
            "{label:?} not in {texts:?}"
        );
    }
    let texts = parse_svg(&figures.join("cyclic_components.svg"));
    assert!(
        texts.iter().any(|t| t.contains("point 2, 127.2000 Hz")),
        "{texts:?}"
    );
    // Bad choices are bad input.
    let output = cyclorub(&["plot", a.to_str().unwrap(), "--sectors", "25"]);
    assert_eq!(output.status.code(), Some(2), "{}", text(&output));
    assert!(text(&output).contains("sector 25 does not exist"));
    let output = cyclorub(&["plot", dir.to_str().unwrap()]);
    assert_eq!(output.status.code(), Some(2), "{}", text(&output));
    assert!(text(&output).contains("results.h5"));
}

#[test]
fn compare_is_0_on_identical_folders_and_1_on_a_perturbed_one() {
    let dir = scratch("compare");
    // The reduced run's coordinates are read from results.h5, the full
    // one's from the CSV it was asked for.
    let reduced = run(&dir, "reduced", "symmetry", "");
    let full = run(&dir, "full", "physical", "[output]\nharmonics_csv = true");
    assert!(full.join("observed_harmonics.csv").is_file());
    // The same folder, and the reduced basis against the full model.
    for (a, b) in [(&reduced, &reduced), (&reduced, &full)] {
        let output = cyclorub(&[
            "compare",
            a.to_str().unwrap(),
            b.to_str().unwrap(),
            "--tolerance",
            "1e-7",
        ]);
        assert_eq!(output.status.code(), Some(0), "{}", text(&output));
        let out = text(&output);
        assert!(out.contains("4 points matched"), "{out}");
        assert!(out.contains("largest relative difference of observed amplitudes"));
        assert!(out.contains("largest relative difference of recovered displacements"));
    }
    // One amplitude 0.1 % off: caught, with where.
    let amplitude = dir.join("amplitude");
    copy_folder(&full, &amplitude);
    perturb(&amplitude.join("branch.csv"), 3, 2 + 4, 1.001);
    let output = cyclorub(&[
        "compare",
        reduced.to_str().unwrap(),
        amplitude.to_str().unwrap(),
        "--tolerance",
        "1e-6",
    ]);
    assert_eq!(output.status.code(), Some(1), "{}", text(&output));
    let out = text(&output);
    assert!(out.contains("sector 5, point 2 of A / 2 of B"), "{out}");
    // One harmonic coefficient off: the displacement check catches it.
    let harmonic = dir.join("harmonic");
    copy_folder(&full, &harmonic);
    perturb(&harmonic.join("observed_harmonics.csv"), 30, 4, 1.01);
    perturb(&harmonic.join("observed_harmonics.csv"), 30, 5, 1.01);
    let output = cyclorub(&[
        "compare",
        reduced.to_str().unwrap(),
        harmonic.to_str().unwrap(),
    ]);
    assert_eq!(output.status.code(), Some(1), "{}", text(&output));
    // A point the other run does not have is named, not compared.
    let shifted = dir.join("shifted");
    copy_folder(&full, &shifted);
    perturb(&shifted.join("branch.csv"), 1, 1, 1.01);
    let output = cyclorub(&[
        "compare",
        reduced.to_str().unwrap(),
        shifted.to_str().unwrap(),
    ]);
    assert_eq!(output.status.code(), Some(0), "{}", text(&output));
    assert!(text(&output).contains("3 points matched"));
    assert!(text(&output).contains("1 points of A not compared: 0 (125.000000 Hz"));
    assert!(
        text(&output).contains("on the 3 matched points only: 1 of A and 1 of B not compared"),
        "{}",
        text(&output)
    );
    // Asked to hold everywhere, the same comparison fails.
    let output = cyclorub(&[
        "compare",
        reduced.to_str().unwrap(),
        shifted.to_str().unwrap(),
        "--all-points",
    ]);
    assert_eq!(output.status.code(), Some(1), "{}", text(&output));
}

#[test]
fn compare_refuses_bad_input_with_exit_code_2() {
    let dir = scratch("bad");
    let a = run(&dir, "a", "symmetry", "");
    let other_gap = run(&dir, "other", "symmetry", "[casing]\ngap = 2e-3\n");
    let cases = [
        vec!["compare", a.to_str().unwrap(), "/nonexistent/folder"],
        vec!["compare", a.to_str().unwrap(), other_gap.to_str().unwrap()],
        vec![
            "compare",
            a.to_str().unwrap(),
            a.to_str().unwrap(),
            "--tolerance=-1",
        ],
    ];
    let expected = ["not a folder", "casing.gap", "--tolerance -1"];
    for (args, message) in cases.iter().zip(expected) {
        let output = cyclorub(args);
        assert_eq!(output.status.code(), Some(2), "{args:?}: {}", text(&output));
        assert!(
            text(&output).contains(message),
            "{args:?}: {}",
            text(&output)
        );
    }
    // A branch.csv that is not one.
    let broken = dir.join("broken");
    copy_folder(&a, &broken);
    std::fs::write(broken.join("branch.csv"), "not,a,branch\n1,2,3\n").unwrap();
    let output = cyclorub(&["compare", a.to_str().unwrap(), broken.to_str().unwrap()]);
    assert_eq!(output.status.code(), Some(2), "{}", text(&output));
}

/// Issue 45 item 5: `plot --reference` of another case is refused as
/// `compare` refuses it (exit 2, the flag and the key); a reference
/// without run.json cannot be checked: drawn, with a warning.
#[test]
fn plot_refuses_a_reference_of_another_case() {
    let dir = scratch("plot-other");
    let a = run(&dir, "a", "symmetry", "");
    let other = run(&dir, "other", "symmetry", "[casing]\ngap = 2e-3\n");
    let figures = dir.join("figures");
    let output = cyclorub(&[
        "plot",
        a.to_str().unwrap(),
        "--reference",
        other.to_str().unwrap(),
        "--output",
        figures.to_str().unwrap(),
    ]);
    let out = text(&output);
    assert_eq!(output.status.code(), Some(2), "{out}");
    assert!(
        out.contains(&format!("--reference {}", other.display()))
            && out.contains("not results of the same case")
            && out.contains("casing.gap"),
        "{out}"
    );
    assert!(!figures.exists(), "no figure drawn");
    std::fs::remove_file(other.join("run.json")).unwrap();
    let output = cyclorub(&[
        "plot",
        a.to_str().unwrap(),
        "--reference",
        other.to_str().unwrap(),
        "--output",
        figures.to_str().unwrap(),
    ]);
    let out = text(&output);
    assert_eq!(output.status.code(), Some(0), "{out}");
    assert!(out.contains("without checking"), "{out}");
}

/// Issue 45 item 6: a branch.csv cut mid-number in a finished run's folder
/// is a truncated file: `compare` fails with exit 2 naming the file and
/// its last line (it compared the whole lines and said "within the
/// tolerance").
#[test]
fn compare_refuses_a_truncated_branch_naming_the_file_and_the_line() {
    let dir = scratch("truncated");
    let a = run(&dir, "a", "symmetry", "");
    let cut = dir.join("cut");
    copy_folder(&a, &cut);
    let branch = cut.join("branch.csv");
    let whole = std::fs::read_to_string(&branch).unwrap();
    let lines = whole.lines().count();
    // Cut in the middle of the last line's amplitude.
    let last = whole.trim_end().rfind('\n').unwrap() + 1;
    std::fs::write(&branch, &whole[..last + 20]).unwrap();
    let output = cyclorub(&["compare", a.to_str().unwrap(), cut.to_str().unwrap()]);
    let out = text(&output);
    assert_eq!(output.status.code(), Some(2), "{out}");
    assert!(
        out.contains(&format!("{}: line {lines}:", branch.display()))
            && out.contains("the file is truncated"),
        "{out}"
    );
}

/// Issue 45 item 7: a results folder holding 0 points (a run stopped
/// before its first) has nothing to plot: exit 2, saying so, no figure.
#[test]
fn plot_of_a_folder_with_no_point_says_so_and_exits_2() {
    use cyclorub::results::hdf5;
    let dir = scratch("empty");
    let a = run(&dir, "a", "symmetry", "");
    let file = a.join(hdf5::FILE_NAME);
    let mut data = hdf5::read(&file).unwrap();
    data.points.clear();
    std::fs::remove_file(&file).unwrap();
    hdf5::write(&file, &data).unwrap();
    let figures = dir.join("figures");
    let output = cyclorub(&[
        "plot",
        a.to_str().unwrap(),
        "--output",
        figures.to_str().unwrap(),
    ]);
    let out = text(&output);
    assert_eq!(output.status.code(), Some(2), "{out}");
    assert!(
        out.contains("results.h5 holds 0 points") && out.contains("nothing to plot"),
        "{out}"
    );
    assert!(!figures.exists());
}

/// Issue 45 item 17: a results.h5 cut in half (a copy cut short) was
/// refused as "the attribute markers_json is missing": it is named a
/// truncated file, with its length and the one it was written with.
#[test]
fn plot_of_a_truncated_results_file_says_it_is_truncated() {
    use cyclorub::results::{hdf5, ResultsError};
    let dir = scratch("truncated-h5");
    let a = run(&dir, "a", "symmetry", "");
    let file = a.join(hdf5::FILE_NAME);
    let whole = std::fs::read(&file).unwrap();
    for length in [whole.len() / 2, 100] {
        std::fs::write(&file, &whole[..length]).unwrap();
        let error = hdf5::read(&file).unwrap_err();
        assert!(matches!(error, ResultsError::Read { .. }), "{error:?}");
        let output = cyclorub(&["plot", a.to_str().unwrap()]);
        let out = text(&output);
        assert_eq!(output.status.code(), Some(2), "{out}");
        assert!(
            out.contains("results.h5") && out.contains("the file is truncated"),
            "{out}"
        );
        assert!(!out.contains("is missing"), "{out}");
        if length > 100 {
            assert!(
                out.contains(&format!("{length} bytes of the {}", whole.len())),
                "{out}"
            );
        }
    }
}
