//! The case's checks: values refused with their key, unused keys named.

use super::*;
use crate::case::tests::parse;
use crate::case::BasisChoice;
use std::path::Path;

/// The message of a case refused before any work: by its validation,
/// or while its model and problem are built.
fn refusal(text: &str) -> String {
    let case = match parse(text) {
        Ok(case) => case,
        Err(error) => return error.to_string(),
    };
    match crate::run::prepare(&case, Path::new("."), BasisChoice::Symmetry) {
        Ok(_) => panic!("{text:?} was accepted"),
        Err(error) => error.to_string(),
    }
}

#[test]
fn stability_harmonics_without_the_check_are_named_as_unused() {
    let case = parse("[stability]\nenabled = false\nharmonics = 5").unwrap();
    let unused = case.unused_keys();
    assert_eq!(unused.len(), 1, "{unused:?}");
    assert!(
        unused[0].starts_with("stability.harmonics = 5 is not used by the run"),
        "{unused:?}"
    );
    for used in ["[stability]\nharmonics = 5", "[stability]\nenabled = false"] {
        assert!(parse(used).unwrap().unused_keys().is_empty(), "{used}");
    }
}

#[test]
fn a_friction_coefficient_of_zero_is_frictionless() {
    // μ = 0 needs no tangential dofs nor rotation (a study over μ starts
    // there); any other μ still does.
    let zero = parse("[contact]\nfriction = 0.0").unwrap();
    let prepared = crate::run::prepare(&zero, Path::new("."), BasisChoice::Symmetry);
    assert!(
        prepared.is_ok(),
        "{:?}",
        prepared.err().map(|e| e.to_string())
    );
    assert!(refusal("[contact]\nfriction = 0.1").contains("contact.circumferential_dofs"));
}

#[test]
fn keys_of_the_other_contact_law_are_named_as_unused() {
    // A hostile run's finding: with the regularized law, `epsilon = nan`
    // and `wall_stiffness = 0` were accepted without a word.
    let text = "[contact]\nlaw = \"regularized\"\nepsilon = nan\nwall_stiffness = 0.0";
    let case = parse(text).unwrap();
    let unused = keys_not_in_use(&case, text);
    assert_eq!(unused.len(), 2, "{unused:?}");
    assert!(
        unused[0]
            .message
            .starts_with("contact.epsilon = nan is not used")
            && unused[0].message.contains("contact.law = \"dlft\""),
        "{unused:?}"
    );
    // Checked as if in use: both values would be refused.
    assert!(unused.iter().all(|u| u.refused.is_some()), "{unused:?}");
    // A valid value of the other law is named, not refused.
    let valid = "[contact]\nlaw = \"regularized\"\nepsilon = 3e7";
    let unused = keys_not_in_use(&parse(valid).unwrap(), valid);
    assert_eq!(unused.len(), 1, "{unused:?}");
    assert_eq!(unused[0].refused, None);
    // The same keys with their law: in use, and checked.
    let used = "[contact]\nlaw = \"dlft\"\nepsilon = 1e9";
    assert!(keys_not_in_use(&parse(used).unwrap(), used).is_empty());
}

#[test]
fn bad_values_name_their_key() {
    let cases = [
        ("[casing]\ngap = -1e-3", "casing.gap = -0.001"),
        ("[contact]\nstiffness = -5.0", "contact.stiffness = -5"),
        (
            "[continuation]\nstart_hz = 100.0\nend_hz = 100.0",
            "frequency range is empty",
        ),
        (
            "[excitation]\nengine_order = 24",
            "excitation.engine_order = 24",
        ),
        (
            "[model]\nsectors = 0",
            "model.sectors = 0: must be at least 1",
        ),
        (
            "[excitation]\ndofs = [0, 2]",
            "excitation.dofs = [0, 2]: dofs are numbered from 1",
        ),
        (
            "[contact]\ndofs = []",
            "contact.dofs = []: give at least one dof",
        ),
        (
            "[excitation]\nkind = \"per_sector\"\namplitudes = [1.0]",
            "excitation.amplitudes = 1 values",
        ),
        (
            "[continuation]\nmin_step = 0.5",
            "continuation.min_step = 0.5: must not exceed continuation.max_step = 0.1",
        ),
        (
            "[output]\nsectors = [25]",
            "output.sectors = 25: must be in 1..=24",
        ),
        ("[basis]\nkind = \"magic\"", "unknown variant `magic`"),
        ("[casing]\ngapp = 1.0", "unknown field `gapp`"),
    ];
    for (text, expected) in cases {
        let message = parse(text).unwrap_err().to_string();
        assert!(message.contains(expected), "{text:?} gave {message:?}");
    }
    // Not excited: the excitation's keys are not used, nor checked.
    assert!(parse("[excitation]\nkind = \"none\"\nengine_order = 24\ndofs = []").is_ok());
}

/// A value that breaks `rule`, and the keys it needs set beside it.
fn breaking(rule: Rule) -> Option<(&'static str, &'static str)> {
    Some(match rule {
        Rule::Finite => ("nan", ""),
        Rule::NonNegative | Rule::Positive => ("-1.0", ""),
        Rule::AtLeast(_) | Rule::AboveTwice(_) => ("0", ""),
        Rule::Dofs => ("[0]", ""),
        Rule::Below(_) | Rule::BelowHalf(..) => ("100000", ""),
        Rule::OneTo(_) => ("[100000]", ""),
        Rule::CountOf(_) => ("[1.0]", ""),
        Rule::AtMost(_) => ("1e9", ""),
        Rule::NoMoreThan(_) => ("1e300", ""),
        Rule::Differs(..) => ("100.0", "start_hz = 100.0\n"),
        Rule::OneOf(_) | Rule::CheckedBy(_) => return None,
    })
}

/// Every machine rule of the key table refuses a value that breaks it,
/// naming the key and the value.
#[test]
fn every_rule_of_the_key_table_refuses_a_bad_value() {
    let mut count = 0;
    for table in TABLES {
        for key in table.keys {
            for &rule in key.rules {
                let Some((bad, beside)) = breaking(rule) else {
                    continue;
                };
                let use_it = match key.when {
                    When::Is(k, v) => format!("{} = \"{v}\"\n", k.rsplit('.').next().unwrap()),
                    _ => String::new(),
                };
                let text = format!("[{}]\n{use_it}{beside}{} = {bad}\n", table.name, key.name);
                let case = Case::from_toml(&text, Path::new("case.toml")).unwrap();
                let root = case.to_value().unwrap();
                let message = check_key(&root, table, key).unwrap_err().to_string();
                let path = table.path(key);
                assert!(
                    message.starts_with(&format!("{path} = ")),
                    "{text}: {message}"
                );
                assert!(parse(&text).is_err(), "{text}");
                count += 1;
            }
        }
    }
    assert!(count >= 20, "{count}");
}

/// A bad value of each key that the code consuming it checks.
const CONSUMED: &[(&str, &str)] = &[
    ("model.symmetry_tolerance", "[model]\nsymmetry_tolerance = -1.0"),
    ("model.masses", "[model]\nmasses = [1.0, 1.0, -1.0, 1.0, 1.0]"),
    ("model.springs", "[model]\nsprings = [{ dofs = [0, 1], stiffness = 1.0 }]"),
    ("model.mass", "[model]\nkind = \"matrices\"\nmass = [[-1.0]]\nstiffness = [[1.0]]"),
    ("model.stiffness", "[model]\nkind = \"matrices\"\nmass = [[1.0]]"),
    (
        "model.mass_coupling",
        "[model]\nkind = \"matrices\"\nmass = [[1.0]]\nstiffness = [[1.0]]\nmass_coupling = [[1.0, 2.0]]",
    ),
    (
        "model.stiffness_coupling",
        "[model]\nkind = \"matrices\"\nmass = [[1.0]]\nstiffness = [[1.0]]\nstiffness_coupling = [[1.0, 2.0]]",
    ),
    ("model.mass_file", "[model]\nkind = \"matrix_market\"\nstiffness_file = \"k.mtx\""),
    ("model.stiffness_file", "[model]\nkind = \"matrix_market\"\nmass_file = \"m.mtx\""),
    ("model.coordinates_file", "[model]\nkind = \"finite_element\""),
    ("model.dofs_per_node", "[model]\nkind = \"finite_element\"\ndofs_per_node = 6"),
    (
        "model.node_sets_file",
        "[model]\nkind = \"finite_element\"\ncoordinates_file = \"nodes.csv\"",
    ),
    (
        "model.left_boundary",
        "[model]\nkind = \"matrices\"\nmass = [[1.0, 0.0], [0.0, 1.0]]\nstiffness = [[2.0, -1.0], [-1.0, 2.0]]\nleft_boundary = [0]\nright_boundary = [2]",
    ),
    (
        "model.right_boundary",
        "[model]\nkind = \"matrices\"\nmass = [[1.0, 0.0], [0.0, 1.0]]\nstiffness = [[2.0, -1.0], [-1.0, 2.0]]\nleft_boundary = [1]\nright_boundary = []",
    ),
    (
        "model.reduction.internal_modes",
        "[model]\nkind = \"finite_element\"\n[model.reduction]\ninternal_modes = 100000",
    ),
    ("model.damping.ratio", "[model.damping]\nratio = -1.0"),
    ("model.damping.ratios", "[model.damping]\nratios = [-1.0, 0.0, 0.0, 0.0, 0.0]"),
    ("model.damping.others", "[model.damping]\nratios = [1e-3]\nothers = -1.0"),
    ("model.damping.alpha", "[model.damping]\nkind = \"rayleigh\"\nalpha = -1.0"),
    ("model.damping.beta", "[model.damping]\nkind = \"rayleigh\"\nbeta = -1.0"),
    ("model.damping.matrix", "[model.damping]\nkind = \"matrix\"\nmatrix = [[1.0]]"),
    (
        "model.damping.coupling",
        "[model.damping]\nkind = \"matrix\"\nmatrix = [[1.0, 0.0, 0.0, 0.0, 0.0], [0.0, 1.0, 0.0, 0.0, 0.0], [0.0, 0.0, 1.0, 0.0, 0.0], [0.0, 0.0, 0.0, 1.0, 0.0], [0.0, 0.0, 0.0, 0.0, 1.0]]\ncoupling = [[1.0]]",
    ),
    ("model.damping.file", "[model.damping]\nkind = \"matrix\"\nfile = \"no_such_file.mtx\""),
    ("casing.gap", "[casing]\ngap = [1e-3, 1e-3]"),
    ("casing.amplitude", "[casing]\namplitude = [0.0, 0.0]"),
    ("contact.stiffness", "[contact]\nstiffness = -5.0"),
    ("contact.regularization", "[contact]\nregularization = nan"),
    ("contact.epsilon", "[contact]\nlaw = \"dlft\"\nepsilon = 0.0"),
    ("contact.wall_stiffness", "[contact]\nlaw = \"dlft\"\nwall_stiffness = -1.0"),
    (
        "contact.circumferential_dofs",
        "[contact]\nfriction = 0.1\ncircumferential_dofs = [2, 3]\naxial_dofs = [4]\n[rotation]\nspeed = 10.0",
    ),
    (
        "contact.axial_dofs",
        "[contact]\nfriction = 0.1\ncircumferential_dofs = [2]\naxial_dofs = [0]\n[rotation]\nspeed = 10.0",
    ),
    (
        "contact.radius",
        "[contact]\nfriction = 0.1\ncircumferential_dofs = [2]\naxial_dofs = [3]\n[rotation]\nspeed = 10.0",
    ),
    (
        "rotation.speed",
        "[contact]\nfriction = 0.1\ncircumferential_dofs = [2]\naxial_dofs = [3]\nradius = 0.3",
    ),
    ("preload.speed", "[preload]\ncentrifugal = true"),
    ("preload.static_forces", "[preload]\nstatic_forces = [1.0, 2.0]"),
    ("output.observed_dof", "[output]\nobserved_dof = 6"),
];

/// Every key checked where its value is consumed has a bad value here,
/// refused before any work with the key named.
#[test]
fn values_checked_where_consumed_are_refused_with_their_key() {
    let mut listed: Vec<String> = Vec::new();
    for table in TABLES {
        for key in table.keys {
            if key.rules.iter().any(|r| matches!(r, Rule::CheckedBy(_))) {
                listed.push(table.path(key));
            }
        }
    }
    let sampled: Vec<String> = CONSUMED.iter().map(|(k, _)| k.to_string()).collect();
    assert_eq!(sampled, listed);
    for (key, text) in CONSUMED {
        let message = refusal(text);
        assert!(message.contains(key), "{text:?} gave {message:?}");
    }
    assert!(
        refusal("[harmonic_balance]\nharmonics = 10\ntime_samples = 20")
            .contains("harmonic_balance.time_samples = 20")
    );
    assert!(refusal("[output]\nobserved_dof = 0")
        .starts_with("output.observed_dof = 0: a sector has dofs 1..=5"));
    assert!(refusal("[contact]\nstiffness = -5.0").contains(
        "contact.stiffness = -5: the contact stiffness κ must be a finite number > 0 (N/m)"
    ));
}

#[test]
fn a_casing_order_the_time_samples_cannot_resolve_is_refused() {
    let message =
        parse("[casing]\norder = 24\n[harmonic_balance]\nharmonics = 3\ntime_samples = 48\n")
            .unwrap_err()
            .to_string();
    assert!(message.starts_with("casing.order = 24"), "{message}");
    assert!(message.contains("aliasing"), "{message}");
    assert!(
        parse("[casing]\norder = 23\n[harmonic_balance]\nharmonics = 3\ntime_samples = 48\n")
            .is_ok()
    );
}

#[test]
fn huge_and_tiny_numbers_are_shown_in_scientific_notation() {
    use crate::case::error::number_text;
    assert_eq!(number_text(1e300), "1e300");
    assert_eq!(number_text(-2.5e-9), "-2.5e-9");
    assert_eq!(number_text(0.001), "0.001");
    assert_eq!(number_text(123456.0), "123456");
    assert_eq!(number_text(0.0), "0");
    assert_eq!(number_text(f64::NAN), "NaN");
    // A refused key shows its value so.
    let error = parse("[casing]\ngap = -1e300").unwrap_err();
    assert!(error.to_string().contains("casing.gap = -1e300"), "{error}");
}
