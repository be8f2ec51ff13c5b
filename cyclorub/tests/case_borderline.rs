//! Issue 45 item 8, the borderline values now refused, each naming its key,
//! the value and the rule: a symmetry tolerance that would accept any
//! matrix, a casing shape deeper than the gap, and a first step above the
//! largest.

use cyclorub::case::{Case, CaseError};
use cyclorub::model::{ModelError, ModelSpec};
use std::path::Path;

/// The refusal of a case text by [`Case::validate`].
fn refused(text: &str) -> (String, String) {
    let case = Case::from_toml(text, Path::new("case.toml")).unwrap();
    match case.validate() {
        Err(CaseError::Invalid {
            key,
            value,
            allowed,
        }) => (key, format!("{value}: {allowed}")),
        other => panic!("{text:?}: {other:?}"),
    }
}

#[test]
fn a_symmetry_tolerance_above_1e_3_is_refused() {
    let text = |tolerance: &str| {
        format!(
            "[model]\nkind = \"matrices\"\nsectors = 6\nsymmetry_tolerance = {tolerance}\n\
             mass = [[1.0, 0.0], [0.0, 1.0]]\n\
             stiffness = [[1e5, 2e5], [0.0, 1e5]]\n"
        )
    };
    let error = ModelSpec::from_case_toml(&text("10.0"))
        .unwrap()
        .build(Path::new("."))
        .unwrap_err();
    let message = error.to_string();
    assert!(matches!(error, ModelError::Invalid { .. }), "{error:?}");
    assert!(
        message.starts_with("model.symmetry_tolerance: 10 is not allowed: at most 1e-3"),
        "{message}"
    );
    // Within the bound, the matrix itself is refused as not symmetric.
    let message = ModelSpec::from_case_toml(&text("1e-3"))
        .unwrap()
        .build(Path::new("."))
        .unwrap_err()
        .to_string();
    assert!(message.contains("not symmetric"), "{message}");
}

#[test]
fn a_casing_shape_deeper_than_the_gap_is_refused_naming_both_keys() {
    let (key, message) = refused("[casing]\ngap = 1e-4\norder = 2\namplitude = 2e-4\n");
    assert_eq!(key, "casing.amplitude");
    assert!(
        message.starts_with("0.0002: deeper than casing.gap = 0.0001 with casing.order = 2")
            && message.contains("cuts into the blade at rest"),
        "{message}"
    );
    // Per contact dof: the entry is named.
    let (key, message) = refused(
        "[contact]\ndofs = [1, 2]\n[casing]\ngap = [1e-3, 1e-4]\norder = 3\namplitude = 2e-4\n",
    );
    assert_eq!(key, "casing.amplitude");
    assert!(message.contains("at contact dof 2 (entry 2)"), "{message}");
    // A circular casing (order 0) only adds the amplitude to the gap, and
    // a shape that just touches is allowed.
    for text in [
        "[casing]\ngap = 1e-4\norder = 0\namplitude = 2e-4\n",
        "[casing]\ngap = 1e-4\norder = 2\namplitude = 1e-4\n",
    ] {
        Case::from_toml(text, Path::new("case.toml"))
            .unwrap()
            .validate()
            .unwrap();
    }
}

#[test]
fn a_first_step_above_the_largest_is_refused_naming_both() {
    let (key, message) = refused("[continuation]\ninitial_step = 5.0\nmax_step = 0.1\n");
    assert_eq!(key, "continuation.initial_step");
    assert_eq!(message, "5: must not exceed continuation.max_step = 0.1");
}
