//! The quick reproduction of the paper's academic studies (CI): every
//! reduced run, carried over to the full wheel, is a full solution to the
//! harmonic balance core's tolerance, and the independent full branch lies
//! in the reduced basis (energy outside below 1e-10) and on the same curve.
//!
//! The mixed case with DLFT-HBM was once pinned here as a full branch
//! leaving the symmetric solutions at 211 Hz: it was the continuation
//! jumping onto another sheet at a pair of nearly coincident folds, gone
//! since long steps keep tight turn limits on piecewise residuals.

use cyclorub_app::reproduce::{reproduce, ReproduceOptions, ENERGY_TOLERANCE, TOLERANCE};
use std::path::{Path, PathBuf};

fn examples() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../examples")
}

#[test]
fn quick_reproduction_is_exact_and_reports_it() {
    let output = Path::new(env!("CARGO_TARGET_TMPDIR")).join("reproduce-quick");
    let _ = std::fs::remove_dir_all(&output);
    let options = ReproduceOptions {
        folder: examples(),
        output: output.clone(),
        quick: true,
        cases: Vec::new(),
        laws: Vec::new(),
        // The stability column is tested on a small study (the CLI's
        // tests): here it would take several times the runs' time.
        stability: false,
    };
    let report = reproduce(&options, |_| {}).expect("the quick reproduction runs");
    assert_eq!(report.studies.len(), 6, "3 quick cases × 2 laws");
    for study in &report.studies {
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
    // The mixed case: the symmetry basis is the smaller one (63 unknowns
    // per contact dof with N_h = 10; 33 with the quick N_h = 5).
    let mixed = &report.studies[4];
    assert_eq!(mixed.case, "n24-mixed-h6-casing-h8");
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
    // The report: Markdown with every study, JSON a program reads, run folders.
    let markdown = std::fs::read_to_string(output.join("report.md")).unwrap();
    assert!(markdown.contains("**6 of 6 studies exact.**"), "{markdown}");
    for study in &report.studies {
        assert!(markdown.contains(&format!("## {}", study.case)));
    }
    assert!(!markdown.contains("leaves this basis"), "{markdown}");
    let json: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(output.join("report.json")).unwrap())
            .unwrap();
    assert_eq!(json["studies"].as_array().map(Vec::len), Some(6));
    let folder = study_folder(&output, &report.studies[0].runs[2]);
    assert!(folder.join("branch.csv").is_file() && folder.join("run.json").is_file());
}

fn study_folder(output: &Path, run: &cyclorub_app::reproduce::RunSummary) -> PathBuf {
    output.join(run.folder.as_ref().expect("a run folder"))
}
