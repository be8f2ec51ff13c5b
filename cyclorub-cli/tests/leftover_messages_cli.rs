//! Messages a hostile run found unclear (the leftovers of its last
//! report): each names the option or key the user gave, its value and
//! what is allowed, and a request that cannot be met exits with 2.

use crate::common::{cyclorub, text};
use std::path::{Path, PathBuf};

fn scratch(name: &str) -> crate::common::Scratch {
    crate::common::scratch("leftovers", name)
}

/// The academic wheel of 6 sectors, 3 harmonics, a gap of 0.2 mm (in
/// contact near 200 Hz), with `extra` appended; written to `dir/name.toml`.
fn case(dir: &Path, name: &str, extra: &str) -> PathBuf {
    let path = dir.join(format!("{name}.toml"));
    std::fs::write(
        &path,
        format!(
            "[model]\nsectors = 6\n[harmonic_balance]\nharmonics = 3\ntime_samples = 64\n\
             [casing]\ngap = 2e-4\n[output]\nfigures = [\"svg\"]\n{extra}"
        ),
    )
    .unwrap();
    path
}

/// Hill's truncation too large for memory is refused naming
/// `--stability-harmonics` and the most that fit, not `stability.enabled`.
#[test]
fn too_many_stability_harmonics_are_refused_by_name_with_the_most_that_fit() {
    let dir = scratch("harmonics");
    let path = case(&dir, "case", "");
    let out = cyclorub(&[
        "run",
        path.to_str().unwrap(),
        "--output",
        dir.join("out").to_str().unwrap(),
        "--at-hz",
        "200",
        "--stability-harmonics",
        "100000",
    ]);
    let said = text(&out);
    assert_eq!(out.status.code(), Some(2), "{said}");
    assert!(
        said.contains("error: --stability-harmonics 100000: Hill's truncation is too large"),
        "{said}"
    );
    let most: usize = said
        .split("at most ")
        .nth(1)
        .and_then(|rest| rest.split(' ').next())
        .and_then(|h| h.parse().ok())
        .unwrap_or_else(|| panic!("no limit in {said}"));
    assert!((1..100000).contains(&most), "{said}");
    let _ = std::fs::remove_dir_all(&dir);
}

/// `cyclorub run` of `case` at `at_hz` into `dir/out`, which it returns.
fn run_at(dir: &Path, name: &str, case: &Path, at_hz: &str) -> PathBuf {
    let out = dir.join(name);
    let ran = cyclorub(&[
        "run",
        case.to_str().unwrap(),
        "--output",
        out.to_str().unwrap(),
        "--at-hz",
        at_hz,
        "--no-stability",
    ]);
    assert!(ran.status.success(), "{}", text(&ran));
    out
}

/// `--largest-eigenproblem 0` is refused as such (before any folder is
/// read), not met with advice on the harmonics.
#[test]
fn a_largest_eigenproblem_of_0_is_refused_as_such() {
    let out = cyclorub(&["stability", "nowhere", "--largest-eigenproblem", "0"]);
    let said = text(&out);
    assert_eq!(out.status.code(), Some(2), "{said}");
    assert!(
        said.contains("--largest-eigenproblem 0: give a size ≥ 1")
            && said.contains("0 would refuse every class"),
        "{said}"
    );
}

/// `--at-hz` beyond the branch is refused with its range; within it, the
/// point taken and how far it is are said.
#[test]
fn a_frequency_beyond_the_branch_is_refused_with_its_range() {
    let dir = scratch("at-hz");
    let path = case(&dir, "case", "[stability]\nenabled = false\n");
    let out = run_at(&dir, "out", &path, "195,200,205");
    let folder = out.to_str().unwrap();
    for args in [
        vec!["stability", folder, "--at-hz", "1e9"],
        vec!["recover", folder, "--at-hz", "1e9", "--dof", "1"],
        vec!["plot", folder, "--at-hz", "1e9"],
    ] {
        let command = args[0];
        let beyond = cyclorub(&args);
        let said = text(&beyond);
        assert_eq!(beyond.status.code(), Some(2), "{command}: {said}");
        assert!(
            said.contains(
                "--at-hz 1000000000: beyond the branch, which spans 195.000000 to 205.000000 Hz \
                 (3 points)"
            ),
            "{command}: {said}"
        );
    }
    let within = cyclorub(&[
        "stability",
        out.to_str().unwrap(),
        "--at-hz",
        "201",
        "--no-refine",
    ]);
    let said = text(&within);
    assert!(within.status.success(), "{said}");
    assert!(
        said.contains("(the nearest to --at-hz 201, 1.0000e0 Hz away)"),
        "{said}"
    );
    let _ = std::fs::remove_dir_all(&dir);
}

/// A mistuned run's curves are drawn against the tuned wheel's (the same
/// case without `[mistuning]`); the reverse is refused saying why.
#[test]
fn a_mistuned_run_is_drawn_against_the_tuned_wheel() {
    let dir = scratch("tuned-reference");
    let common = "[basis]\nkind = \"physical\"\n[stability]\nenabled = false\n";
    let mistuned = case(
        &dir,
        "mistuned",
        &format!("{common}[mistuning]\nstandard_deviation = 0.01\nseed = 1\n"),
    );
    let tuned = case(&dir, "tuned", common);
    let frequencies = "195,200,205";
    let (m, t) = (
        run_at(&dir, "m", &mistuned, frequencies),
        run_at(&dir, "t", &tuned, frequencies),
    );
    let plotted = cyclorub(&[
        "plot",
        m.to_str().unwrap(),
        "--reference",
        t.to_str().unwrap(),
    ]);
    let said = text(&plotted);
    assert!(plotted.status.success(), "{said}");
    assert!(
        said.contains("the tuned wheel (the same case without [mistuning]), drawn dashed"),
        "{said}"
    );
    let svg = std::fs::read_to_string(m.join("plots").join("forced_response.svg")).unwrap();
    assert!(svg.contains("tuned wheel (physical)"), "no legend");
    let reverse = cyclorub(&[
        "plot",
        t.to_str().unwrap(),
        "--reference",
        m.to_str().unwrap(),
    ]);
    let said = text(&reverse);
    assert_eq!(reverse.status.code(), Some(2), "{said}");
    assert!(said.contains("the reference is a mistuned wheel"), "{said}");
    let _ = std::fs::remove_dir_all(&dir);
}

/// `cyclorub modes --help` says a case's `[mistuning]` is applied.
#[test]
fn modes_help_says_the_mistuning_is_applied() {
    let out = cyclorub(&["modes", "--help"]);
    let said = text(&out);
    assert!(out.status.success(), "{said}");
    assert!(said.contains("[mistuning]"), "{said}");
}

/// A run.json whose number of sectors was edited is refused naming both
/// files' numbers, not believed.
#[test]
fn an_edited_number_of_sectors_in_run_json_is_refused() {
    let dir = scratch("sectors");
    let path = case(&dir, "case", "[stability]\nenabled = false\n");
    let out = run_at(&dir, "out", &path, "200");
    let json = out.join("run.json");
    let mut run: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(&json).unwrap()).unwrap();
    run["case"]["model"]["sectors"] = serde_json::json!(12);
    std::fs::write(&json, run.to_string()).unwrap();
    for args in [
        vec!["stability", out.to_str().unwrap(), "--no-refine"],
        vec!["compare", out.to_str().unwrap(), out.to_str().unwrap()],
    ] {
        let refused = cyclorub(&args);
        let said = text(&refused);
        assert_eq!(refused.status.code(), Some(2), "{args:?}: {said}");
        assert!(
            said.contains("says case.model.sectors = 12, but")
                && said.contains("results.h5 holds 6 sectors"),
            "{args:?}: {said}"
        );
    }
    let _ = std::fs::remove_dir_all(&dir);
}

/// `[stability] harmonics` with `enabled = false` is said, naming the key.
#[test]
fn stability_harmonics_without_the_check_are_warned_of() {
    let dir = scratch("unused");
    let path = case(
        &dir,
        "case",
        "[stability]\nenabled = false\nharmonics = 5\n",
    );
    let out = cyclorub(&[
        "run",
        path.to_str().unwrap(),
        "--output",
        dir.join("out").to_str().unwrap(),
        "--at-hz",
        "200",
    ]);
    let said = text(&out);
    assert!(out.status.success(), "{said}");
    assert!(
        said.contains("stability.harmonics = 5 is not used by the run: stability.enabled = false"),
        "{said}"
    );
    let _ = std::fs::remove_dir_all(&dir);
}

/// Each sector's "largest displacement" `recover` prints, from sector
/// 1's line.
fn first_crest(said: &str) -> f64 {
    said.split("largest displacement ")
        .nth(1)
        .and_then(|rest| rest.split(' ').next())
        .and_then(|v| v.parse().ok())
        .unwrap_or_else(|| panic!("no crest in {said}"))
}

/// `recover --time-samples 8` prints the crest of the harmonic series, not
/// the largest of its 8 samples: the same as with 4096 samples, and above
/// every row of its own CSV.
#[test]
fn recover_prints_the_crest_whatever_the_samples() {
    let dir = scratch("crest");
    let path = case(&dir, "case", "[stability]\nenabled = false\n");
    let out = run_at(&dir, "out", &path, "200");
    let folder = out.to_str().unwrap();
    let mut crests = Vec::new();
    for samples in ["8", "4096"] {
        let csv = dir.join(format!("recovered{samples}.csv"));
        let recovered = cyclorub(&[
            "recover",
            folder,
            "--dof",
            "1",
            "--sector",
            "1",
            "--time-samples",
            samples,
            "--output",
            csv.to_str().unwrap(),
        ]);
        let said = text(&recovered);
        assert!(recovered.status.success(), "{said}");
        let crest = first_crest(&said);
        let rows = std::fs::read_to_string(&csv).unwrap();
        let largest = rows
            .lines()
            .skip(1)
            .filter_map(|line| line.split(',').nth(1)?.parse::<f64>().ok())
            .fold(f64::NEG_INFINITY, f64::max);
        assert!(
            largest <= crest * (1.0 + 1e-6),
            "{samples}: {largest} > {crest}"
        );
        crests.push((crest, largest));
    }
    // Printed to 7 digits: the two crests agree to them; 8 samples of
    // three harmonics fall visibly short of it.
    assert!(
        (crests[0].0 - crests[1].0).abs() <= 1e-6 * crests[1].0.abs(),
        "{crests:?}"
    );
    assert!(crests[0].1 < crests[0].0 * (1.0 - 1e-4), "{crests:?}");
}

/// A run held by its cap on points says so, names the key, and exits 1 (the
/// curve asked for is not whole), keeping its points.
#[test]
fn a_run_held_by_its_point_cap_says_so() {
    let dir = scratch("cap");
    let path = case(
        &dir,
        "case",
        "[stability]\nenabled = false\n[continuation]\nstart_hz = 190\nend_hz = 210\nmax_points = 3\n",
    );
    let out = dir.join("out");
    let ran = cyclorub(&[
        "run",
        path.to_str().unwrap(),
        "--output",
        out.to_str().unwrap(),
    ]);
    let said = text(&ran);
    assert_eq!(ran.status.code(), Some(1), "{said}");
    assert!(
        said.contains("the run stopped at its cap of 3 points before the end of its range")
            && said.contains("continuation.max_points")
            && !said.contains("did not converge"),
        "{said}"
    );
    assert!(out.join("branch.csv").exists());
}
