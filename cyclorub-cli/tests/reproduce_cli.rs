//! `cyclorub reproduce`: a small study end to end, and bad input refused
//! before any work.

use crate::common::cyclorub;

fn scratch(name: &str) -> crate::common::Scratch {
    crate::common::scratch("reproduce-cli", name)
}

fn text(bytes: &[u8]) -> String {
    String::from_utf8_lossy(bytes).into_owned()
}

/// A small standing-wave study: 6 sectors, 3 harmonics, into contact.
const SMALL: &str = r#"# cyclorub example small: N = 6, standing wave h = 1.
[model]
sectors = 6
[excitation]
kind = "standing"
engine_order = 1
amplitude = 2.0
[harmonic_balance]
harmonics = 3
time_samples = 48
[continuation]
max_points = 60
"#;

#[test]
fn a_small_study_is_reproduced_and_reported() {
    let dir = scratch("small");
    let cases = dir.join("cases");
    std::fs::create_dir_all(&cases).unwrap();
    std::fs::write(cases.join("small.toml"), SMALL).unwrap();
    let output = dir.join("report");
    let out = cyclorub(&[
        "reproduce",
        cases.to_str().unwrap(),
        "--output",
        output.to_str().unwrap(),
        "--laws",
        "regularized",
    ]);
    assert!(
        out.status.success(),
        "{}{}",
        text(&out.stdout),
        text(&out.stderr)
    );
    assert!(
        text(&out.stdout).contains("1 of 1 studies exact"),
        "{}",
        text(&out.stdout)
    );
    let markdown = std::fs::read_to_string(output.join("report.md")).unwrap();
    assert!(markdown.contains("## small — R-HBM"), "{markdown}");
    assert!(
        markdown.contains("N = 6, standing wave h = 1."),
        "{markdown}"
    );
    for basis in ["symmetry", "physical"] {
        let run = output.join("runs/small/regularized").join(basis);
        assert!(run.join("branch.csv").is_file(), "{}", run.display());
    }
    // The stability column and each checked run's line: the symmetry
    // basis per class, and the small full wheel without symmetry (its
    // eigenproblem, 2 · 5 dofs · 6 sectors · 7 harmonics = 420, is below
    // the reproduction's limit).
    assert!(markdown.contains("| verdict | stability |"), "{markdown}");
    assert!(
        markdown.contains("- stability, symmetry (Hill's method per symmetry class, H = 3"),
        "{markdown}"
    );
    assert!(
        markdown
            .contains("- stability, physical (Hill's method on the whole wheel, without symmetry"),
        "{markdown}"
    );
    let json: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(output.join("report.json")).unwrap())
            .unwrap();
    let runs = &json["studies"][0]["runs"];
    for (i, method) in [(0, "symmetry_classes"), (2, "full_wheel")] {
        let stability = &runs[i]["stability"];
        assert_eq!(stability["status"], "computed", "{stability}");
        assert_eq!(stability["method"], method, "{stability}");
        let points = stability["points"].as_u64().unwrap();
        assert!(points >= 10, "{stability}");
        let unstable = stability["unstable_points"].as_u64().unwrap();
        let in_stretches: u64 = stability["unstable"]
            .as_array()
            .unwrap()
            .iter()
            .map(|s| s["points"].as_u64().unwrap())
            .sum();
        assert_eq!(unstable, in_stretches, "{stability}");
    }

    assert!(output
        .join("figures/small-regularized-forced-response.svg")
        .is_file());
}

#[test]
fn bad_input_exits_2_with_what_is_allowed() {
    let dir = scratch("bad");
    let empty = dir.join("empty");
    std::fs::create_dir_all(&empty).unwrap();
    let out = cyclorub(&["reproduce", empty.to_str().unwrap()]);
    assert_eq!(out.status.code(), Some(2));
    assert!(
        text(&out.stderr).contains("no case file (*.toml)"),
        "{}",
        text(&out.stderr)
    );

    let cases = dir.join("cases");
    std::fs::create_dir_all(&cases).unwrap();
    std::fs::write(cases.join("small.toml"), SMALL).unwrap();
    let out = cyclorub(&["reproduce", cases.to_str().unwrap(), "--cases", "nope"]);
    assert_eq!(out.status.code(), Some(2));
    let message = text(&out.stderr);
    assert!(
        message.contains("--cases: no case named \"nope\"") && message.contains("small"),
        "{message}"
    );

    let out = cyclorub(&["reproduce", cases.to_str().unwrap(), "--laws", "coulomb"]);
    assert_eq!(out.status.code(), Some(2));
    assert!(
        text(&out.stderr).contains("allowed: regularized, dlft"),
        "{}",
        text(&out.stderr)
    );

    // A bad case is refused before any run: no report is written.
    std::fs::write(cases.join("broken.toml"), "[casing]\ngap = -1.0\n").unwrap();
    let output = dir.join("report");
    let out = cyclorub(&[
        "reproduce",
        cases.to_str().unwrap(),
        "--output",
        output.to_str().unwrap(),
    ]);
    assert_eq!(out.status.code(), Some(2));
    assert!(
        text(&out.stderr).contains("casing.gap"),
        "{}",
        text(&out.stderr)
    );
    assert!(!output.join("report.md").exists());
}
