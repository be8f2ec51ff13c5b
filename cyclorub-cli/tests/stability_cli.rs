//! `cyclorub stability RESULTS`: the exponents of one point of a results
//! folder, per symmetry class, are the library's for that point; bad
//! folders and points are refused with exit code 2, naming what is wrong.
//! (`cyclorub recover` is in recover_cli.rs, a run's converged sizes in
//! stability_sizes_cli.rs.)

use crate::common::{cyclorub, text};
use cyclorub::case::Case;
use cyclorub::forced_response::prepare;
use cyclorub::results::hdf5;
use cyclorub::stability::{Stability, StabilitySettings};
use std::path::{Path, PathBuf};

pub(crate) fn scratch(name: &str) -> crate::common::Scratch {
    crate::common::scratch("stability-cli", name)
}

/// The default wheel cut to 6 sectors, with few harmonics.
pub(crate) const TINY: &str = r#"
[model]
sectors = 6

[harmonic_balance]
harmonics = 3
time_samples = 60

[output]
peak_histories = true
"#;

/// Up the resonance of diameter 1 (208.7 Hz linear), each point from the
/// last: the last three touch the casing (amplitude above the 1 mm gap).
pub(crate) const FREQUENCIES: &str = "206,208,209,210,212";

pub(crate) fn run_tiny(dir: &Path) -> (PathBuf, PathBuf) {
    let case = dir.join("tiny.toml");
    std::fs::write(&case, TINY).unwrap();
    let out = dir.join("results");
    let output = cyclorub(&[
        "run",
        case.to_str().unwrap(),
        "--output",
        out.to_str().unwrap(),
        "--at-hz",
        FREQUENCIES,
        "--no-stability",
    ]);
    assert!(output.status.success(), "{}", text(&output));
    (case, out)
}

#[test]
fn the_json_spectrum_of_a_point_is_the_librarys_and_bad_points_are_refused() {
    let dir = scratch("tiny");
    let (case_path, out) = run_tiny(&dir);
    let data = hdf5::read(&out.join(hdf5::FILE_NAME)).unwrap();
    let p = data.peak_point().expect("a converged point");
    let point = &data.points[p];

    let output = cyclorub(&[
        "stability",
        out.to_str().unwrap(),
        "--point",
        &p.to_string(),
        "--json",
    ]);
    assert!(output.status.success(), "{}", text(&output));
    let json: serde_json::Value = serde_json::from_slice(&output.stdout).unwrap();
    assert_eq!(json["point"], p);
    // The refined orbit (twice the harmonics) and the error estimate.
    assert_eq!(json["refined"]["harmonics"], 6, "{json}");
    let estimate = json["refined"]["estimate"].as_f64().unwrap();
    assert!(estimate.is_finite() && estimate >= 0.0, "{estimate}");
    assert_eq!(json["frequency_hz"].as_f64(), Some(point.frequency_hz));

    // The same point through the library, from the case file itself.
    let case = Case::from_file_checked(&case_path).unwrap();
    let prepared = prepare(&case, &dir, case.basis.kind).unwrap();
    let check = Stability::new(
        &prepared.model,
        &prepared.problem,
        &prepared.case.contact_dofs(),
        &StabilitySettings::default(),
    )
    .unwrap();
    let omega = 2.0 * std::f64::consts::PI * point.frequency_hz;
    let expected = check.point(&point.unknowns, omega).unwrap();
    assert!(
        expected.off_contact_bound.is_none(),
        "the peak is in contact: Hill's method runs"
    );
    let classes = json["classes"].as_array().unwrap();
    assert_eq!(classes.len(), expected.classes.len());
    for (got, want) in classes.iter().zip(&expected.classes) {
        assert_eq!(got["nodal_diameter"], want.nodal_diameter);
        let exponents = got["exponents"].as_array().unwrap();
        assert_eq!(exponents.len(), want.exponents.len());
        for (g, w) in exponents.iter().zip(&want.exponents) {
            let (re, im) = (g["re"].as_f64().unwrap(), g["im"].as_f64().unwrap());
            let error = (re - w.re).hypot(im - w.im);
            assert!(
                error <= 1e-10 * w.re.hypot(w.im),
                "class σ = {}: {re} {im}i against {} {}i",
                want.nodal_diameter,
                w.re,
                w.im
            );
        }
    }
    assert_eq!(json["stable"], expected.stable());

    // The condensed solver (the default) and the dense eigenproblem in
    // the same region: the same exponents, class by class.
    let output = cyclorub(&[
        "stability",
        out.to_str().unwrap(),
        "--point",
        &p.to_string(),
        "--json",
        "--solver",
        "dense-region",
    ]);
    assert!(output.status.success(), "{}", text(&output));
    let dense: serde_json::Value = serde_json::from_slice(&output.stdout).unwrap();
    assert_eq!(dense["solver"], "dense-region");
    assert_eq!(json["solver"], "condensed");
    let exponents = |v: &serde_json::Value| -> Vec<Vec<(f64, f64)>> {
        v["classes"]
            .as_array()
            .unwrap()
            .iter()
            .map(|c| {
                c["exponents"]
                    .as_array()
                    .unwrap()
                    .iter()
                    .map(|e| (e["re"].as_f64().unwrap(), e["im"].as_f64().unwrap()))
                    .collect()
            })
            .collect()
    };
    for (a, b) in exponents(&json).iter().zip(exponents(&dense)) {
        assert_eq!(a.len(), b.len(), "{a:?} vs {b:?}");
        for x in a {
            let nearest = b
                .iter()
                .map(|y| (x.0 - y.0).hypot(x.1 - y.1))
                .fold(f64::INFINITY, f64::min);
            assert!(nearest < 1e-8 * omega, "{x:?}: {nearest:e}");
        }
    }

    // The table: every class, then the verdict.
    let output = cyclorub(&[
        "stability",
        out.to_str().unwrap(),
        "--point",
        &p.to_string(),
    ]);
    assert!(output.status.success(), "{}", text(&output));
    let table = String::from_utf8_lossy(&output.stdout);
    assert!(table.contains("class σ = 0: "), "{table}");
    assert!(table.contains("solved by: condensed"), "{table}");
    assert!(table.contains("error estimate: "), "{table}");
    // The verdict follows the classes; the refined orbit's, then the
    // finest refinement's come last.
    let verdict = if expected.stable() {
        "stable"
    } else {
        "unstable"
    };
    assert!(table.lines().any(|l| l.starts_with(verdict)), "{table}");
    assert!(table.lines().any(|l| l.starts_with("refined: ")), "{table}");
    let last = table.lines().last().unwrap();
    assert!(
        last.starts_with("refined: ") || last.starts_with("finest: "),
        "{table}"
    );

    // A point beyond the branch: exit 2, naming the flag and the range.
    let count = data.points.len();
    let output = cyclorub(&[
        "stability",
        out.to_str().unwrap(),
        "--point",
        &count.to_string(),
    ]);
    assert_eq!(output.status.code(), Some(2), "{}", text(&output));
    let message = String::from_utf8_lossy(&output.stderr);
    assert!(message.contains(&format!("--point {count}")), "{message}");
    assert!(
        message.contains(&format!("0 to {}", count - 1)),
        "{message}"
    );
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn folders_that_are_not_results_are_refused_with_exit_code_2() {
    let dir = scratch("bad");
    let missing = dir.join("nowhere");
    let output = cyclorub(&["stability", missing.to_str().unwrap()]);
    assert_eq!(output.status.code(), Some(2), "{}", text(&output));
    assert!(
        text(&output).contains("no such folder"),
        "{}",
        text(&output)
    );

    let output = cyclorub(&["stability", dir.to_str().unwrap()]);
    assert_eq!(output.status.code(), Some(2), "{}", text(&output));
    assert!(
        text(&output).contains("has no run.json"),
        "{}",
        text(&output)
    );

    let output = cyclorub(&["stability", dir.to_str().unwrap(), "--harmonics", "0"]);
    assert_eq!(output.status.code(), Some(2), "{}", text(&output));
    assert!(text(&output).contains("--harmonics 0"), "{}", text(&output));
    let _ = std::fs::remove_dir_all(&dir);
}

/// `cyclorub stability` reads the case back from run.json: every kind of
/// case file survives the trip through JSON unchanged.
#[test]
fn every_kind_of_case_reads_back_from_its_json() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("..");
    let mut texts: Vec<(String, String)> = Vec::new();
    for folder in ["examples", "cyclorub/tests/fixtures/model"] {
        for entry in std::fs::read_dir(root.join(folder)).unwrap() {
            let path = entry.unwrap().path();
            if path.extension().is_some_and(|e| e == "toml") {
                let text = std::fs::read_to_string(&path).unwrap();
                texts.push((path.display().to_string(), text));
            }
        }
    }
    for (name, text) in [
        ("dlft wall", "[contact]\nlaw = \"dlft\"\nwall_stiffness = 1e8\n"),
        (
            "per sector",
            "[model]\nsectors = 3\n[excitation]\nkind = \"per_sector\"\namplitudes = [1, 0.5, 0.25]\nphases = [0, 1, 2]\n",
        ),
        (
            "gaps per dof",
            "[contact]\ndofs = [1, 2]\n[casing]\ngap = [1e-3, 2e-3]\norder = 2\namplitude = 5e-5\n",
        ),
        (
            "matrix damping",
            "[model]\nkind = \"matrices\"\nsectors = 4\nmass = [[1.0]]\nstiffness = [[2.0]]\nstiffness_coupling = [[-0.5]]\n[model.damping]\nkind = \"matrix\"\nmatrix = [[0.1]]\n[excitation]\ndofs = [1]\n",
        ),
        ("rayleigh", "[model.damping]\nkind = \"rayleigh\"\nalpha = 1.0\nbeta = 1e-6\n"),
    ] {
        texts.push((name.into(), text.into()));
    }
    assert!(texts.len() > 10);
    for (name, text) in texts {
        let case = Case::from_toml(&text, Path::new(&name)).unwrap();
        let json = serde_json::to_value(&case).unwrap();
        let back: Case = serde_json::from_value(json).unwrap_or_else(|e| panic!("{name}: {e}"));
        assert_eq!(back, case, "{name}");
    }
}

#[test]
fn the_spectrum_of_a_point_uses_the_runs_hill_truncation_by_default() {
    // `cyclorub run` checks with `[stability] harmonics`; `cyclorub
    // stability` of the same folder must give the same exponents.
    let dir = scratch("truncation");
    let case = dir.join("tiny.toml");
    std::fs::write(&case, format!("{TINY}\n[stability]\nharmonics = 5\n")).unwrap();
    let out = dir.join("results");
    let run = cyclorub(&[
        "run",
        case.to_str().unwrap(),
        "--output",
        out.to_str().unwrap(),
        "--at-hz",
        FREQUENCIES,
        "--no-stability",
    ]);
    assert!(run.status.success(), "{}", text(&run));
    let spectrum = |extra: &[&str]| {
        let mut args = vec!["stability", out.to_str().unwrap(), "--json"];
        args.extend_from_slice(extra);
        let output = cyclorub(&args);
        assert!(output.status.success(), "{}", text(&output));
        serde_json::from_slice::<serde_json::Value>(&output.stdout).unwrap()
    };
    assert_eq!(spectrum(&[])["harmonics"], 5);
    assert_eq!(spectrum(&["--harmonics", "4"])["harmonics"], 4);
}
