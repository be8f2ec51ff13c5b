//! Issue 45, the misleading messages: each refusal names the real cause
//! (the key or file, the value, the rule), not a key it led to.

use cyclorub::model::{ModelError, ModelSpec};
use std::path::{Path, PathBuf};

fn build(text: &str, dir: &Path) -> ModelError {
    ModelSpec::from_case_toml(text)
        .unwrap()
        .build(dir)
        .unwrap_err()
}

/// Item 10: `masses = []` was blamed on model.springs.
#[test]
fn empty_masses_are_named() {
    let error = build("[model]\nmasses = []\n", Path::new("."));
    let message = error.to_string();
    assert!(matches!(error, ModelError::Invalid { .. }), "{error:?}");
    assert!(
        message.starts_with("model.masses: [] is not allowed"),
        "{message}"
    );
}

/// Item 11: a negative ratio was blamed on model.damping.others.
#[test]
fn a_negative_modal_ratio_is_named() {
    let error = build(
        "[model]\n[model.damping]\nkind = \"modal\"\nratios = [1e-3, -1e-3]\n",
        Path::new("."),
    );
    let message = error.to_string();
    assert!(matches!(error, ModelError::Invalid { .. }), "{error:?}");
    assert!(
        message.starts_with("model.damping.ratios: entry 2 = -0.001 is not allowed")
            && message.contains("finite and ≥ 0"),
        "{message}"
    );
}

/// Item 12: a Matrix Market file with fewer entries than announced was
/// reported at "line 0": now at its last line, naming the announced count.
#[test]
fn a_matrix_market_file_short_of_entries_names_its_last_line() {
    let fixtures = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/fixtures/model");
    let dir: PathBuf =
        std::env::temp_dir().join(format!("cyclorub-short-mtx-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    std::fs::copy(fixtures.join("chain_M.mtx"), dir.join("chain_M.mtx")).unwrap();
    let stiffness = std::fs::read_to_string(fixtures.join("chain_K.mtx")).unwrap();
    let short: Vec<&str> = stiffness.lines().collect();
    let kept = &short[..short.len() - 1];
    std::fs::write(dir.join("chain_K.mtx"), kept.join("\n") + "\n").unwrap();
    let case = std::fs::read_to_string(fixtures.join("chain.toml")).unwrap();
    let error = build(&case, &dir);
    let message = error.to_string();
    assert!(
        matches!(error, ModelError::MatrixMarket { line, .. } if line == kept.len()),
        "{error:?}"
    );
    assert!(
        message.contains(&format!("chain_K.mtx:{}: ", kept.len()))
            && message.contains("after 8 entries but 9 are announced on line 5"),
        "{message}"
    );
    let _ = std::fs::remove_dir_all(&dir);
}

/// Item 13: `gap = "1e-3"` (a string) said "data did not match any variant
/// of untagged enum PerContactDof": now what is allowed.
#[test]
fn a_gap_given_as_a_string_says_what_is_allowed() {
    use cyclorub::case::{Case, CaseError};
    let error = Case::from_toml("[casing]\ngap = \"1e-3\"\n", Path::new("case.toml")).unwrap_err();
    let message = error.to_string();
    assert!(matches!(error, CaseError::Parse { .. }), "{error:?}");
    assert!(
        message.contains("gap")
            && message.contains("a number, or a list of numbers, one per contact dof")
            && !message.contains("untagged"),
        "{message}"
    );
    // Numbers, integers and lists still read.
    for text in ["gap = 1e-3", "gap = 1", "gap = [1e-3]"] {
        Case::from_toml(&format!("[casing]\n{text}\n"), Path::new("case.toml")).unwrap();
    }
}
