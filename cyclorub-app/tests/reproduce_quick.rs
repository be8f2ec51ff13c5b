//! The quick reproduction of the paper's academic studies (CI): every
//! reduced run, carried over to the full wheel, is a full solution to the
//! harmonic balance core's tolerance, and the independent full branch lies
//! in the reduced basis (energy outside below 1e-10) and on the same curve.
//!
//! The mixed case with DLFT-HBM was once pinned here as a full branch
//! leaving the symmetric solutions at 211 Hz: it was the continuation
//! jumping onto another sheet at a pair of nearly coincident folds, gone
//! since long steps keep tight turn limits on piecewise residuals.

use cyclorub::case::LawKind;
use cyclorub::forced_response::StabilityStatus;
use cyclorub_app::reproduce::{
    reproduce, Report, ReproduceOptions, Study, ENERGY_TOLERANCE, QUICK_CASES, TOLERANCE,
};
use std::path::{Path, PathBuf};

fn examples() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../examples")
}

/// `case` with `law` reproduced alone in quick mode, into a folder of its
/// own (`tag` names it), with or without the stability column.
fn reproduced(case: &str, law: LawKind, tag: &str, stability: bool) -> (Report, PathBuf) {
    let output = Path::new(env!("CARGO_TARGET_TMPDIR"))
        .join("reproduce-quick")
        .join(format!("{case}-{tag}"));
    let _ = std::fs::remove_dir_all(&output);
    let options = ReproduceOptions {
        folder: examples(),
        output: output.clone(),
        quick: true,
        cases: vec![case.to_string()],
        laws: vec![law],
        stability,
    };
    let report = reproduce(&options, |_| {}).expect("the quick reproduction runs");
    (report, output)
}

/// One quick study (a case with one law), reproduced alone: one test per
/// study, so that the test harness spreads them over the cores (the
/// reproduction runs its studies one after the other).
fn quick_study(case: &str, law: LawKind) -> (Report, PathBuf) {
    // The stability column is tested on a small study (the CLI's tests):
    // here it would take several times the runs' time.
    let (report, output) = reproduced(case, law, law.name(), false);
    assert_eq!(report.studies.len(), 1, "{case} with {law:?}");
    check_study(&report.studies[0], &output);
    // The report: Markdown with the study, JSON a program reads, run folders.
    let markdown = std::fs::read_to_string(output.join("report.md")).unwrap();
    assert!(markdown.contains("**1 of 1 studies exact.**"), "{markdown}");
    assert!(markdown.contains(&format!("## {case}")), "{markdown}");
    assert!(!markdown.contains("leaves this basis"), "{markdown}");
    let json: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(output.join("report.json")).unwrap())
            .unwrap();
    assert_eq!(json["studies"].as_array().map(Vec::len), Some(1));
    let folder = study_folder(&output, &report.studies[0].runs[2]);
    assert!(folder.join("branch.csv").is_file() && folder.join("run.json").is_file());
    (report, output)
}

/// Every run of `study` succeeded, the reduced ones are exact against the
/// full wheel, and its figures are valid SVG.
fn check_study(study: &Study, output: &Path) {
    let name = format!("{} with {:?}", study.case, study.law);
    assert_eq!(study.runs.len(), 3, "{name}: symmetry, paper, physical");
    for run in &study.runs {
        assert!(
            run.error.is_none(),
            "{name}: {} failed: {:?}",
            run.basis,
            run.error
        );
        assert!(
            run.points >= 10,
            "{name}: {} has {} points",
            run.basis,
            run.points
        );
    }
    let physical = &study.runs[2];
    assert_eq!(physical.unknowns, physical.full_unknowns, "{name}");
    assert!(
        study.runs[0].unknowns < physical.unknowns,
        "{name}: a reduction"
    );
    assert!(!study.comparisons.is_empty(), "{name}: compared");
    assert!(study.exact(), "{name}: not exact: {:?}", study.comparisons);
    for c in &study.comparisons {
        let p = c.point_by_point.as_ref().unwrap();
        assert!(p.points >= 10 && p.not_converged == 0, "{name}: {p:?}");
        assert!(p.largest_unknowns_difference <= TOLERANCE, "{name}: {p:?}");
        assert!(
            p.largest_displacement_difference <= TOLERANCE,
            "{name}: {p:?}"
        );
        // A reduced point is a full solution to round-off, not merely to
        // the continuation's tolerance.
        assert!(p.largest_full_residual < 1e-9, "{name}: {p:?}");
        let energy = c.energy_outside.as_ref().unwrap();
        assert!(
            energy.at_resonance <= ENERGY_TOLERANCE,
            "{name}: {energy:?}"
        );
        assert!(energy.largest <= ENERGY_TOLERANCE, "{name}: {energy:?}");
        assert!(
            c.same_curve(),
            "{name}: curve distance {:?}",
            c.curve_distance
        );
    }
    assert!(study.resonance_hz.is_some(), "{name}");
    assert_eq!(study.figures.len(), 2, "{name}: {:?}", study.figures);
    for figure in &study.figures {
        let text = std::fs::read_to_string(output.join(figure)).unwrap();
        let svg = roxmltree::Document::parse(&text).expect("valid SVG");
        assert_eq!(svg.root_element().tag_name().name(), "svg");
    }
}

#[test]
fn the_quick_cases_are_the_three_studied_here() {
    assert_eq!(
        QUICK_CASES,
        [
            "n24-traveling-h1",
            "n24-standing-h4",
            "n24-mixed-h6-casing-h8"
        ]
    );
}

#[test]
fn traveling_wave_with_r_hbm_is_exact() {
    quick_study("n24-traveling-h1", LawKind::Regularized);
}

/// The longest of these studies: its name sorts first, so that the test
/// harness (which starts tests in name order) starts it first.
#[test]
fn dlft_hbm_on_the_traveling_wave_is_exact() {
    quick_study("n24-traveling-h1", LawKind::Dlft);
}

#[test]
fn standing_wave_with_r_hbm_is_exact() {
    quick_study("n24-standing-h4", LawKind::Regularized);
}

#[test]
fn standing_wave_with_dlft_hbm_is_exact() {
    quick_study("n24-standing-h4", LawKind::Dlft);
}

#[test]
fn mixed_case_with_r_hbm_is_exact() {
    mixed_case(LawKind::Regularized);
}

#[test]
fn mixed_case_with_dlft_hbm_is_exact() {
    mixed_case(LawKind::Dlft);
}

/// The mixed case: the symmetry basis is the smaller one (63 unknowns per
/// contact dof with N_h = 10; 33 with the quick N_h = 5), and the paper's
/// basis differs from it.
fn mixed_case(law: LawKind) {
    let (report, _) = quick_study("n24-mixed-h6-casing-h8", law);
    let mixed = &report.studies[0];
    assert_eq!(
        (
            mixed.runs[0].unknowns,
            mixed.runs[1].unknowns,
            mixed.runs[2].unknowns
        ),
        (33, 132, 264)
    );
    assert!(
        mixed.runs[1].same_as.is_none(),
        "the paper's basis differs here"
    );
}

fn study_folder(output: &Path, run: &cyclorub_app::reproduce::RunSummary) -> PathBuf {
    output.join(run.folder.as_ref().expect("a run folder"))
}

/// The open fan (friction at its tip nodes) gets its stability column like
/// the academic studies: the condensed Hill solver holds friction's
/// velocity terms, so the symmetry run is checked point by point; the full
/// wheel's check is refused for its size, saying so. Traveling h = 4 (its
/// contact within the quick window, unlike h = 1's `quick_case` measure):
/// 19 s in release, 37 s in the test profile with a build beside it.
#[test]
fn the_open_fan_with_friction_is_checked_for_stability() {
    let case = "fan16-traveling-h4";
    let (report, output) = reproduced(case, LawKind::Dlft, "stability", true);
    let study = &report.studies[0];
    check_study(study, &output);
    let symmetry = study.runs[0]
        .stability
        .as_ref()
        .expect("a stability column");
    assert_eq!(symmetry.status, StabilityStatus::Computed, "{symmetry:?}");
    assert_eq!(symmetry.points, study.runs[0].points, "{symmetry:?}");
    assert!(symmetry.points_by_hill > 0, "in contact: {symmetry:?}");
    let physical = study.runs[2]
        .stability
        .as_ref()
        .expect("a stability column");
    assert_eq!(
        physical.status,
        StabilityStatus::NotComputed,
        "{physical:?}"
    );
    assert!(
        physical
            .reason
            .as_deref()
            .is_some_and(|r| r.contains("above the limit")),
        "{physical:?}"
    );
}
