//! A mistuned run's outputs read converged points only and give no
//! amplification factor they cannot stand behind (a curve cut off by the
//! point cap, points that did not converge, no motion toward the casing):
//! run.json and the summary say why. `[mistuning]` keys that would be
//! ignored, or a blade that cannot be, are refused with their line.

use crate::common::{cyclorub, text};
use std::path::Path;

fn scratch(name: &str) -> crate::common::Scratch {
    crate::common::scratch("mistuning-outputs", name)
}

/// Six academic sectors in contact (gap 1 mm), three harmonics, mistuned
/// by given deviations on the full wheel; `continuation` and `extra` end
/// the `[continuation]` table and the file.
fn mistuned(continuation: &str, extra: &str) -> String {
    format!(
        "[model]\nkind = \"academic\"\nsectors = 6\n\
         [excitation]\nkind = \"traveling\"\nengine_order = 1\namplitude = 4.0\ndofs = [1]\n\
         [casing]\ngap = 1e-3\n\
         [contact]\nlaw = \"regularized\"\ndofs = [1]\nstiffness = 1e8\nregularization = 2.5\n\
         [harmonic_balance]\nharmonics = 3\ntime_samples = 60\n\
         [basis]\nkind = \"physical\"\n\
         [output]\nfigures = [\"svg\"]\n\
         [stability]\nenabled = false\n\
         [mistuning]\ndeviations = [0.01, -0.01, 0.02, 0, 0, 0.03]\n{extra}\
         [continuation]\n{continuation}"
    )
}

fn run_case(dir: &Path, name: &str, text_of_case: &str, more: &[&str]) -> std::process::Output {
    let case = dir.join(format!("{name}.toml"));
    std::fs::write(&case, text_of_case).unwrap();
    let out = dir.join(name);
    let mut args = vec![
        "run",
        case.to_str().unwrap(),
        "--output",
        out.to_str().unwrap(),
    ];
    args.extend_from_slice(more);
    cyclorub(&args)
}

fn mistuning_record(dir: &Path, name: &str) -> serde_json::Value {
    let run: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(dir.join(name).join("run.json")).unwrap())
            .unwrap();
    run["mistuning"].clone()
}

/// F01: a curve stopped by the point cap peaks at its last point; its
/// ratio to the tuned peak is no amplification factor.
#[test]
fn a_curve_cut_off_by_the_point_cap_gives_no_amplification_factor() {
    let dir = scratch("capped");
    let out = run_case(&dir, "capped", &mistuned("max_points = 10\n", ""), &[]);
    let said = text(&out);
    assert!(
        said.contains("no amplification factor: the mistuned curve stopped before the end"),
        "{said}"
    );
    let record = mistuning_record(&dir, "capped");
    assert!(record.get("amplification_factor").is_none(), "{record}");
    assert!(
        record["no_factor_reason"]
            .as_str()
            .unwrap()
            .contains("cap of 10 points"),
        "{record}"
    );
    // study marks the row the same way.
    let cases = dir.join("study_cases");
    std::fs::create_dir_all(&cases).unwrap();
    std::fs::write(cases.join("capped.toml"), mistuned("max_points = 10\n", "")).unwrap();
    let study_out = dir.join("study");
    let study = cyclorub(&[
        "study",
        cases.to_str().unwrap(),
        "--output",
        study_out.to_str().unwrap(),
    ]);
    // An unfinished row makes the study incomplete: exit code 3, counted
    // on the last line.
    assert_eq!(study.status.code(), Some(3), "{}", text(&study));
    let last = String::from_utf8_lossy(&study.stdout);
    let last = last.lines().last().unwrap_or("");
    assert!(
        last.starts_with("1 of 1 cases unfinished") && last.contains("capped (cap of 10 points)"),
        "{last}"
    );
    let table = std::fs::read_to_string(study_out.join("study.csv")).unwrap();
    let lines: Vec<&str> = table.lines().collect();
    let header: Vec<&str> = lines[0].split(',').collect();
    let column = |name: &str| header.iter().position(|h| *h == name).unwrap();
    let cells: Vec<&str> = lines[1].split(',').collect();
    assert_eq!(cells[column("finished")], "false", "{table}");
    assert_eq!(cells[column("amplification_factor")], "", "{table}");
    assert!(
        cells[column("no_factor_reason")].contains("stopped before the end"),
        "{table}"
    );
    let _ = std::fs::remove_dir_all(&dir);
}

/// F07: points Newton left are no response: no −inf, no negative
/// amplitude, the same frequencies compared, a sentence when no factor.
#[test]
fn unconverged_points_are_left_out_of_the_peaks_and_the_factor() {
    let dir = scratch("unconverged");
    // Every point unconverged: no peak at all.
    let out = run_case(
        &dir,
        "none",
        &mistuned("max_iterations = 1\n", ""),
        &["--at-hz", "210"],
    );
    let said = text(&out);
    assert!(!said.contains("inf"), "{said}");
    assert!(said.contains("no amplification factor: "), "{said}");
    let record = mistuning_record(&dir, "none");
    assert!(record.get("amplification_factor").is_none(), "{record}");
    assert_eq!(record["most_responding_sector"], 0, "{record}");
    // 210 Hz does not converge on the mistuned wheel (it does on the tuned
    // one): the factor compares 205 Hz alone, as a run at 205 Hz does.
    let both = run_case(&dir, "both", &mistuned("", ""), &["--at-hz", "210,205"]);
    let alone = run_case(&dir, "alone", &mistuned("", ""), &["--at-hz", "205"]);
    assert!(alone.status.success(), "{}", text(&alone));
    assert!(text(&both).contains("1 not converged"), "{}", text(&both));
    let (a, b) = (
        mistuning_record(&dir, "both"),
        mistuning_record(&dir, "alone"),
    );
    // Equal to Newton's tolerance (the 205 Hz points start from other
    // guesses).
    for key in ["tuned_peak_m", "amplification_factor"] {
        let (x, y) = (a[key].as_f64().unwrap(), b[key].as_f64().unwrap());
        assert!((x - y).abs() <= 1e-9 * y, "{key}: {a}\n{b}");
    }
    // Far above resonance nothing moves toward the casing: said, with no
    // negative amplitude and no success sentence in place of a factor.
    let far = run_case(&dir, "far", &mistuned("", ""), &["--at-hz", "1e6"]);
    let said = text(&far);
    assert!(
        said.contains("no amplification factor: no sector of the mistuned wheel moves toward"),
        "{said}"
    );
    assert!(
        !said.contains(" -") && !said.contains("amplification factor the tuned"),
        "{said}"
    );
    // study reads converged points only and calls such a case unfinished.
    let cases = dir.join("study_cases");
    std::fs::create_dir_all(&cases).unwrap();
    std::fs::write(
        cases.join("none.toml"),
        mistuned("max_iterations = 1\n", ""),
    )
    .unwrap();
    let study_out = dir.join("study");
    let study = cyclorub(&[
        "study",
        cases.to_str().unwrap(),
        "--output",
        study_out.to_str().unwrap(),
        "--at-hz",
        "210",
    ]);
    assert_eq!(study.status.code(), Some(3), "{}", text(&study));
    assert!(
        text(&study).contains("1 of 1 cases unfinished (finished = false in study.csv): none (1 of 1 points not converged)"),
        "{}",
        text(&study)
    );
    let table = std::fs::read_to_string(study_out.join("study.csv")).unwrap();
    let lines: Vec<&str> = table.lines().collect();
    let header: Vec<&str> = lines[0].split(',').collect();
    let column = |name: &str| header.iter().position(|h| *h == name).unwrap();
    let cells: Vec<&str> = lines[1].split(',').collect();
    assert_eq!(cells[column("finished")], "false", "{table}");
    assert_eq!(cells[column("peak_amplitude_m")], "", "{table}");
    assert_eq!(cells[column("amplification_factor")], "", "{table}");
    let _ = std::fs::remove_dir_all(&dir);
}

/// F08: keys that would be ignored, an empty list, a blade that cannot
/// be, and a reduced basis: refused before any work (exit code 2), named
/// and located.
#[test]
fn mistuning_keys_that_cannot_hold_are_refused_with_their_line() {
    let dir = scratch("keys");
    let tuned = |mistuning: &str| {
        mistuned("", "").replace(
            "[mistuning]\ndeviations = [0.01, -0.01, 0.02, 0, 0, 0.03]\n",
            mistuning,
        )
    };
    let matrices = "[model]\nkind = \"matrices\"\nsectors = 6\n\
         mass = [[0.2, 0.0], [0.0, 0.3]]\n\
         stiffness = [[2e6, -2e6], [-2e6, 3.6e6]]\n\
         stiffness_coupling = [[0.0, 0.0], [0.0, -5e5]]\n\
         [excitation]\ndofs = [1]\n[contact]\ndofs = [1]\n[basis]\nkind = \"physical\"\n\
         [mistuning]\ndeviations = [0.01, -0.01, 0.02, 0, 0, 0.03]\nblade_dofs = [1]\n";
    let cases: Vec<(&str, String, &str)> = vec![
        (
            "seed",
            mistuned("", "seed = 4\n"),
            "mistuning.seed = 4: only with mistuning.standard_deviation",
        ),
        (
            "distribution",
            mistuned("", "distribution = \"uniform\"\n"),
            "mistuning.distribution = \"uniform\": only with",
        ),
        (
            "dofs_only",
            tuned("[mistuning]\nblade_dofs = [1, 99]\n"),
            "mistuning.blade_dofs = [1, 99]: dof 99 is out of range",
        ),
        (
            "node_set_only",
            tuned("[mistuning]\nblade_node_set = \"blade\"\n"),
            "mistuning.blade_node_set = \"blade\": a blade node set is read with",
        ),
        (
            "empty",
            tuned("[mistuning]\ndeviations = []\n"),
            "give one deviation per sector",
        ),
        (
            "twice",
            mistuned("", "blade_dofs = [1, 1, 2]\n"),
            "mistuning.blade_dofs = [1, 1, 2]: dof 1 is listed twice",
        ),
        (
            "no_spring",
            mistuned("", "blade_dofs = [1, 3]\n"),
            "mistuning.blade_dofs = [1, 3]: no spring",
        ),
        (
            "one_dof",
            matrices.to_string(),
            "mistuning.blade_dofs = [1]: name at least two dofs",
        ),
    ];
    for (name, case_text, expected) in cases {
        let out = run_case(&dir, name, &case_text, &[]);
        let said = text(&out);
        assert_eq!(out.status.code(), Some(2), "{name}: {said}");
        assert!(said.contains(expected), "{name}: {said}");
        if name != "empty" {
            assert!(
                said.contains(&format!("(at {}", dir.join(name).display())),
                "{name}: {said}"
            );
        }
    }
    // A reduced basis is an input error too, located like the others.
    let reduced = mistuned("", "").replace("kind = \"physical\"", "kind = \"symmetry\"");
    let out = run_case(&dir, "reduced", &reduced, &[]);
    let said = text(&out);
    assert_eq!(out.status.code(), Some(2), "{said}");
    assert!(
        said.contains("basis.kind = \"symmetry\": cannot hold a mistuned wheel")
            && said.contains("reduced.toml:"),
        "{said}"
    );
    let _ = std::fs::remove_dir_all(&dir);
}
