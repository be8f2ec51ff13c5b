//! `cyclorub stability RESULTS`: the exponents of one point of a results
//! folder, per symmetry class, are the library's for that point; bad
//! folders and points are refused with exit code 2, naming what is wrong.
//! `cyclorub recover RESULTS`: any dof of any sector of a stored point is
//! the recovery the run did.

use crate::common::{cyclorub, text};
use cyclorub::case::Case;
use cyclorub::forced_response::prepare;
use cyclorub::results::hdf5;
use cyclorub::stability::{Stability, StabilitySettings};
use std::path::{Path, PathBuf};

fn scratch(name: &str) -> crate::common::Scratch {
    crate::common::scratch("stability-cli", name)
}

/// The default wheel cut to 6 sectors, with few harmonics.
const TINY: &str = r#"
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
const FREQUENCIES: &str = "206,208,209,210,212";

fn run_tiny(dir: &Path) -> (PathBuf, PathBuf) {
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

/// Reads the CSV of `cyclorub recover`: its header and its columns.
fn read_csv(path: &Path) -> (Vec<String>, Vec<Vec<f64>>) {
    let text = std::fs::read_to_string(path).unwrap();
    let mut lines = text.lines();
    let header: Vec<String> = lines.next().unwrap().split(',').map(String::from).collect();
    let mut columns = vec![Vec::new(); header.len()];
    for line in lines {
        for (column, value) in columns.iter_mut().zip(line.split(',')) {
            column.push(value.parse::<f64>().unwrap());
        }
    }
    (header, columns)
}

#[test]
fn recover_gives_the_histories_the_run_stored_and_any_other_dof() {
    let dir = scratch("recover");
    let (case_path, out) = run_tiny(&dir);
    let data = hdf5::read(&out.join(hdf5::FILE_NAME)).unwrap();
    let stored = data.histories.as_ref().expect("the peak point's histories");
    let p = stored.point;

    // The observed dof (1) on every sector, at the peak point: the run's
    // own histories, to 1e-12.
    let csv = dir.join("observed.csv");
    let output = cyclorub(&[
        "recover",
        out.to_str().unwrap(),
        "--dof",
        "1",
        "--point",
        &p.to_string(),
        "--output",
        csv.to_str().unwrap(),
    ]);
    assert!(output.status.success(), "{}", text(&output));
    let (header, columns) = read_csv(&csv);
    assert_eq!(header.len(), 1 + 2 * 6, "{header:?}");
    let scale = stored
        .displacement
        .iter()
        .flatten()
        .fold(0.0_f64, |m, x| m.max(x.abs()));
    let velocity_scale = stored
        .velocity
        .iter()
        .flatten()
        .fold(0.0_f64, |m, x| m.max(x.abs()));
    for sector in 0..6 {
        assert_eq!(
            header[1 + 2 * sector],
            format!("displacement_sector{}_m", sector + 1)
        );
        for (n, (&got, &want)) in columns[1 + 2 * sector]
            .iter()
            .zip(&stored.displacement[sector])
            .enumerate()
        {
            assert!(
                (got - want).abs() <= 1e-12 * scale,
                "sector {sector}, sample {n}: {got} {want}"
            );
        }
        for (&got, &want) in columns[2 + 2 * sector].iter().zip(&stored.velocity[sector]) {
            assert!((got - want).abs() <= 1e-12 * velocity_scale, "{got} {want}");
        }
    }
    for (got, want) in columns[0].iter().zip(&stored.time_s) {
        assert!(
            (got - want).abs() <= 1e-12 * want.abs().max(1e-3),
            "{got} {want}"
        );
    }

    // Another dof on two sectors at another point, against the library's
    // recovery from the case file itself.
    let csv = dir.join("other.csv");
    let output = cyclorub(&[
        "recover",
        out.to_str().unwrap(),
        "--dof",
        "3",
        "--sector",
        "2",
        "--sector",
        "5",
        "--point",
        "1",
        "--time-samples",
        "32",
        "--output",
        csv.to_str().unwrap(),
    ]);
    assert!(output.status.success(), "{}", text(&output));
    let (header, columns) = read_csv(&csv);
    assert_eq!(header.len(), 5, "{header:?}");
    assert_eq!(columns[0].len(), 32);
    let case = Case::from_file_checked(&case_path).unwrap();
    let prepared = prepare(&case, &dir, case.basis.kind).unwrap();
    let point = &data.points[1];
    let omega = 2.0 * std::f64::consts::PI * point.frequency_hz;
    let expected = cyclorub::results::recovery::dof_histories(
        &prepared.problem,
        &point.unknowns,
        omega,
        2,
        &[1, 4],
        32,
    )
    .unwrap();
    for (k, history) in expected.iter().enumerate() {
        let scale = history
            .displacement
            .iter()
            .fold(0.0_f64, |m, x| m.max(x.abs()));
        assert!(scale > 0.0);
        for (&got, &want) in columns[1 + 2 * k].iter().zip(&history.displacement) {
            assert!((got - want).abs() <= 1e-12 * scale, "{got} {want}");
        }
    }

    // Bad dofs and sectors: exit 2, naming the flag and the range.
    for (flag, value, range) in [
        ("--dof", "0", "1..=5"),
        ("--dof", "6", "1..=5"),
        ("--sector", "7", "1..=6"),
    ] {
        let mut args = vec!["recover", out.to_str().unwrap(), "--dof", "1"];
        if flag == "--dof" {
            args[3] = value;
        } else {
            args.extend([flag, value]);
        }
        let output = cyclorub(&args);
        assert_eq!(output.status.code(), Some(2), "{}", text(&output));
        let message = String::from_utf8_lossy(&output.stderr);
        assert!(message.contains(&format!("{flag} {value}")), "{message}");
        assert!(message.contains(range), "{message}");
    }
    let _ = std::fs::remove_dir_all(&dir);
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

/// The tiny case run at [`FREQUENCIES`] with `extra` arguments in a scratch
/// folder `name`: its results folder, its standard output and its run.json.
/// Its scratch guard comes back first: the results folder lives as long as it.
fn run_tiny_with_sizes(
    name: &str,
    extra: &[&str],
) -> (crate::common::Scratch, PathBuf, String, serde_json::Value) {
    let dir = scratch(name);
    let case = dir.join("tiny.toml");
    std::fs::write(&case, TINY).unwrap();
    let out = dir.join("results");
    let mut args = vec![
        "run",
        case.to_str().unwrap(),
        "--output",
        out.to_str().unwrap(),
        "--at-hz",
        FREQUENCIES,
    ];
    args.extend_from_slice(extra);
    let run = cyclorub(&args);
    assert!(run.status.success(), "{}", text(&run));
    let record =
        serde_json::from_str(&std::fs::read_to_string(out.join("run.json")).unwrap()).unwrap();
    (
        dir,
        out,
        String::from_utf8_lossy(&run.stdout).to_string(),
        record,
    )
}

#[test]
fn a_run_with_unstable_points_says_how_far_its_sizes_are_from_converged() {
    // The run refines its fastest growth until the leading real part
    // settles within 5 % (at most 8 times the harmonics) and records the
    // refinements in run.json; `cyclorub stability --point P` of that
    // point gives the same refinements.
    let (_dir, out, stdout, record) = run_tiny_with_sizes("sizes", &[]);
    let line = stdout
        .lines()
        .find(|l| l.starts_with("sizes: at "))
        .unwrap_or_else(|| panic!("no sizes line:\n{stdout}"));
    let point: usize = line
        .split("(point ")
        .nth(1)
        .and_then(|s| s.split(',').next())
        .and_then(|s| s.parse().ok())
        .unwrap_or_else(|| panic!("{line}"));
    let sizes = &record["stability"]["sizes"];
    assert_eq!(sizes["point"].as_u64(), Some(point as u64), "{sizes}");
    let run_harmonics: Vec<u64> = sizes["harmonics"]
        .as_array()
        .unwrap()
        .iter()
        .map(|h| h.as_u64().unwrap())
        .collect();
    assert_eq!(run_harmonics[0], 3, "{sizes}");
    let run_leading: Vec<f64> = sizes["leading_re"]
        .as_array()
        .unwrap()
        .iter()
        .map(|l| l.as_f64().unwrap())
        .collect();
    let run_changes: Vec<f64> = sizes["changes"]
        .as_array()
        .unwrap()
        .iter()
        .map(|c| c.as_f64().unwrap())
        .collect();
    // Settled at the first change under 5 %, or refined to 8 times.
    let settled = run_changes.iter().position(|c| *c < 0.05);
    assert_eq!(
        run_changes.len(),
        settled.map_or(3, |i| i + 1),
        "stops at the first change below 5 %: {sizes}"
    );
    assert_eq!(sizes["converged"].as_bool(), Some(settled.is_some()));
    assert!(
        line.contains(&format!("H = {}", run_harmonics.last().unwrap())),
        "{line}"
    );
    let classes = sizes["classes"].as_array().unwrap();
    let finest_leading = classes
        .iter()
        .map(|c| c["finest_re"].as_f64().unwrap())
        .fold(f64::NEG_INFINITY, f64::max);
    assert_eq!(finest_leading, *run_leading.last().unwrap(), "{sizes}");
    // The stability figure, drawn again, shows them: one circle per class
    // σ ≥ 0 at the point, and its legend line.
    let figure = std::fs::read_to_string(out.join("plots/stability_exponents.svg")).unwrap();
    let legend = format!(
        "converged at point {point} (H = {}; the curves: H = 3)",
        run_harmonics.last().unwrap()
    );
    assert!(figure.contains(&legend), "no `{legend}` in the figure");
    let drawn = classes
        .iter()
        .filter(|c| c["class"].as_i64().unwrap() >= 0)
        .count();
    assert!(
        figure.matches("<circle").count() > drawn,
        "{} circles for {drawn} classes and the legend",
        figure.matches("<circle").count()
    );
    let output = cyclorub(&[
        "stability",
        out.to_str().unwrap(),
        "--point",
        &point.to_string(),
        "--json",
    ]);
    assert!(output.status.success(), "{}", text(&output));
    let json: serde_json::Value = serde_json::from_slice(&output.stdout).unwrap();
    let estimate = json["refined"]["estimate"].as_f64().unwrap();
    assert!(
        (estimate - run_changes[0]).abs() <= 1e-12,
        "{sizes}: the stability command says {estimate}"
    );
    // The refinements double the harmonics (6, 12, 24 for H = 3) until
    // the leading real part moves by less than --converge-within; the
    // first is the run's estimate, each change is its leading real part's
    // from the one before, and the last is the estimate of the sizes.
    let convergence = &json["convergence"];
    let harmonics: Vec<u64> = convergence["harmonics"]
        .as_array()
        .unwrap()
        .iter()
        .map(|h| h.as_u64().unwrap())
        .collect();
    let run = json["harmonics"].as_u64().unwrap();
    for (i, h) in harmonics.iter().enumerate() {
        assert_eq!(*h, run << (i + 1), "{convergence}");
    }
    let leading: Vec<f64> = convergence["leading"]
        .as_array()
        .unwrap()
        .iter()
        .map(|l| l[1].as_f64().unwrap())
        .collect();
    let changes: Vec<f64> = convergence["changes"]
        .as_array()
        .unwrap()
        .iter()
        .map(|c| c.as_f64().unwrap())
        .collect();
    assert!((changes[0] - estimate).abs() <= 1e-12, "{convergence}");
    // The same refinements as the run's, as far as both went.
    for (i, (a, b)) in leading.iter().zip(&run_leading[1..]).enumerate() {
        assert!(
            (a - b).abs() <= 1e-9 * b.abs(),
            "refinement {i}: {convergence} against {sizes}"
        );
    }
    for i in 1..leading.len() {
        let change = (leading[i] - leading[i - 1]).abs() / leading[i].abs();
        assert!((changes[i] - change).abs() <= 1e-12, "{convergence}");
    }
    let last = *changes.last().unwrap();
    assert_eq!(convergence["estimate"].as_f64().unwrap(), last);
    assert_eq!(convergence["converged"].as_bool().unwrap(), last < 0.01);
    assert_eq!(
        harmonics.len() < 3,
        last < 0.01,
        "stops at the first change below 1 %: {convergence}"
    );
}

#[test]
fn a_hill_truncation_below_the_orbits_is_refined_to_the_orbits_at_least() {
    // With Hill's H = 1 on an orbit of 3 harmonics, the refinements check
    // at least the refined orbit's harmonics (6, 12, 24), not 2, 4, 8: two
    // truncations below the orbit's could agree and pass for converged
    // while both miss the growth (a hostile run's finding: "settles at
    // −0.44 1/s within 3 %, the verdict holds" where H = 24 says +226 1/s).
    let (_dir, _, stdout, record) =
        run_tiny_with_sizes("sizes-below", &["--stability-harmonics", "1"]);
    let sizes = &record["stability"]["sizes"];
    let harmonics: Vec<u64> = sizes["harmonics"]
        .as_array()
        .unwrap_or_else(|| panic!("no sizes in run.json: {stdout}"))
        .iter()
        .map(|h| h.as_u64().unwrap())
        .collect();
    assert_eq!(harmonics[0], 1, "{sizes}");
    for (i, h) in harmonics.iter().enumerate().skip(1) {
        assert_eq!(*h, 3 << i, "{sizes}");
    }
    // Every check's verdict is recorded, and `verdict_holds` says whether
    // they all give the run's.
    let stable: Vec<bool> = sizes["stable"]
        .as_array()
        .unwrap()
        .iter()
        .map(|s| s.as_bool().unwrap())
        .collect();
    assert_eq!(stable.len(), harmonics.len(), "{sizes}");
    assert_eq!(
        sizes["verdict_holds"].as_bool().unwrap(),
        stable.iter().all(|&s| s == stable[0]),
        "{sizes}"
    );
}
