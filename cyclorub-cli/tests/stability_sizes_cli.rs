//! A run with unstable points converges its sizes at its fastest growth
//! (2, 4, 8 times Hill's truncation) and says how far the run's were.

use crate::common::{cyclorub, text};
use crate::stability_cli::{scratch, FREQUENCIES, TINY};
use std::path::PathBuf;

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
