//! The templates parse back to their cases, the examples hold the paper's
//! parameters, and every key the key table lists is rendered.

use super::render::{automatic_range, example};
use super::*;
use cyclorub::case::keys::TABLES;
use cyclorub::case::text::lookup;
use cyclorub::case::CaseError;
use cyclorub::model::ModelKind;
use std::collections::BTreeSet;
use std::num::FpCategory;
use std::path::PathBuf;

fn parse(text: &str) -> Result<Case, CaseError> {
    Case::from_toml(text, Path::new("template.toml"))
}

#[test]
fn the_default_template_parses_to_the_default_case() {
    let text = default_template();
    let case = parse(&text).unwrap_or_else(|e| panic!("{e}\n{text}"));
    assert_eq!(case, Case::default());
    case.validate().unwrap();
}

#[test]
fn every_example_parses_to_its_case_and_validates() {
    for example in &EXAMPLES {
        let text = example.template();
        let case = parse(&text).unwrap_or_else(|e| panic!("{}: {e}", example.name));
        assert_eq!(case, example.case(), "{}", example.name);
        case.validate()
            .unwrap_or_else(|e| panic!("{}: {e}", example.name));
        case.model
            .build(Path::new("."))
            .unwrap_or_else(|e| panic!("{}: {e}", example.name));
        assert_eq!(example_template(example.name), Some(text));
    }
    assert_eq!(example_template("no-such-case"), None);
}

#[test]
fn examples_have_the_papers_parameters() {
    let names = Example::names();
    assert_eq!(names.len(), 10);
    assert_eq!(names.iter().collect::<BTreeSet<_>>().len(), 10);
    for example in &EXAMPLES {
        let case = example.case();
        assert_eq!(case.harmonic_balance.harmonics, 10);
        assert_eq!(case.harmonic_balance.time_samples, 10000);
        let mut contact = Case::default().contact;
        contact.wall_stiffness = Some(1e8);
        assert_eq!(case.contact, contact);
        assert_eq!(case.continuation.start_hz, None);
        let p = match &case.casing.amplitude {
            PerContactDof::One(p) => *p,
            PerContactDof::Each(_) => panic!("one value"),
        };
        if example.casing_order > 0 {
            assert!((p - 0.05 * PAPER_GAP).abs() < 1e-18);
        } else {
            assert_eq!(p.classify(), FpCategory::Zero);
        }
    }
    let h17 = Example::find("n45-traveling-h17").unwrap();
    assert_eq!((h17.sectors, h17.engine_order), (45, 17));
    assert!((h17.amplitude - 4.0).abs() < 1e-15);
}

#[test]
fn every_fan_example_parses_to_its_case_and_validates() {
    for example in &FAN_EXAMPLES {
        let text = example.template();
        let case = parse(&text).unwrap_or_else(|e| panic!("{}: {e}", example.name));
        assert_eq!(case, example.case(), "{}", example.name);
        case.validate()
            .unwrap_or_else(|e| panic!("{}: {e}", example.name));
        assert_eq!(example_template(example.name), Some(text.clone()));
        assert!(
            text.contains("cyclorub mesh fan --output examples/fan16"),
            "{}",
            example.name
        );
        assert!(text.contains(&example.gap_note()), "{}", example.name);
    }
    assert_eq!(example_names().len(), EXAMPLES.len() + FAN_EXAMPLES.len());
}

/// The fan examples are the case that `cyclorub mesh fan` writes, with
/// only their own excitation, gap, results folder and the model files
/// in `fan16/`.
#[test]
fn the_fan_examples_are_the_mesh_commands_case() {
    let dir = std::env::temp_dir().join(format!("cyclorub-fan-template-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    let fan = cyclorub::mesh::fan(FAN_SECTORS, 1, &cyclorub::mesh::FanGeometry::default()).unwrap();
    let matrices = cyclorub::mesh::assemble(&fan.mesh).unwrap();
    cyclorub::mesh::write_fan(&fan, &matrices, &dir, false).unwrap();
    let written = Case::from_file_checked(&dir.join("fan16.toml")).unwrap();
    let _ = std::fs::remove_dir_all(&dir);
    for example in &FAN_EXAMPLES {
        let mut expected = written.clone();
        let m = &mut expected.model;
        for file in [
            &mut m.mass_file,
            &mut m.stiffness_file,
            &mut m.coordinates_file,
            &mut m.node_sets_file,
        ] {
            *file = file.as_ref().map(|f| Path::new(FAN_FOLDER).join(f));
        }
        let e = &mut expected.excitation;
        e.kind = example.excitation;
        e.engine_order = example.engine_order;
        e.amplitude = example.amplitude;
        expected.casing.gap = PerContactDof::One(example.gap);
        expected.output.directory = Path::new("results").join(example.name);
        assert_eq!(example.case(), expected, "{}", example.name);
    }
    // The paper's Sec. 5 settings.
    let h7 = FanExample::find("fan16-partly-standing-h7").unwrap().case();
    assert_eq!(h7.excitation.kind, ExcitationKind::Mixed);
    assert!((h7.excitation.backward_weight - 0.9).abs() < 1e-15);
    assert!((h7.excitation.forward_weight - 0.1).abs() < 1e-15);
    assert!(h7
        .contact
        .friction
        .is_some_and(|mu| (mu - 0.15).abs() < 1e-15));
    assert_eq!(h7.contact.law, cyclorub::case::LawKind::Dlft);
    assert_eq!(h7.harmonic_balance.time_samples % FAN_SECTORS, 0);
    for (key, file) in FAN_MODEL_FILES {
        let text = h7.to_value().unwrap();
        let value = lookup(&text, &format!("model.{key}")).unwrap();
        assert_eq!(
            value.as_str(),
            Some(format!("{FAN_FOLDER}/{file}").as_str())
        );
    }
}

/// Any case, with every optional key set, renders and parses back.
#[test]
fn a_case_with_every_optional_key_round_trips() {
    let mut case = Case::default();
    case.model.kind = ModelKind::Matrices;
    case.model.symmetry_tolerance = Some(1e-6);
    case.model.mass = Some(vec![vec![1.0, 0.0], vec![0.0, 2.0]]);
    case.model.stiffness = Some(vec![vec![3e6, -1e6], vec![-1e6, 2.5e6]]);
    case.model.left_boundary = Some(vec![1]);
    case.model.right_boundary = Some(vec![2]);
    case.model.mass_file = Some(PathBuf::from("dir/m \"x\".mtx"));
    case.model.springs = Some(vec![cyclorub::model::SpringSpec {
        dofs: vec![1, 2],
        stiffness: 2e6,
        link: cyclorub::model::SpringLinkSpec::NextSector,
    }]);
    case.model.damping.ratios = Some(vec![1e-3, 2e-3]);
    case.model.damping.others = Some(0.01);
    case.excitation.kind = ExcitationKind::PerSector;
    case.excitation.amplitudes = vec![1.0; 24];
    case.excitation.phases = vec![0.123_456_789; 24];
    case.excitation.static_force = -12.5;
    case.casing.gap = PerContactDof::Each(vec![1e-3, 2.5e-4]);
    case.contact.dofs = vec![1, 2];
    case.contact.law = cyclorub::case::LawKind::Dlft;
    case.contact.wall_stiffness = Some(5e7);
    case.continuation.start_hz = Some(150.0);
    case.continuation.end_hz = Some(120.5);
    case.output.sectors = vec![1, 4];
    let text = render(&case, &["a test".to_string()]).unwrap();
    assert_eq!(parse(&text).unwrap_or_else(|e| panic!("{e}\n{text}")), case);
}

/// Every key shown commented out parses once uncommented, and every
/// key's comment is the key table's.
#[test]
fn every_commented_out_key_parses_once_uncommented() {
    let text = default_template();
    let root = Case::default().to_value().unwrap();
    let range = automatic_range(&Case::default());
    let mut count = 0;
    for table in TABLES {
        for key in table.keys {
            assert!(
                text.contains(&format!("# {}", key.meaning())),
                "{}",
                key.name
            );
            if lookup(&root, &table.path(key)).is_some() {
                continue;
            }
            let value = example(table, key, range);
            let uncommented = format!("[{}]\n{} = {value}\n", table.name, key.name);
            parse(&uncommented).unwrap_or_else(|e| panic!("{e}\n{uncommented}"));
            count += 1;
        }
    }
    assert!(count >= 15, "{count}");
}

/// Sets the examples of `keys` in a `[model]` table of `kind`.
fn model_with_examples(kind: &str, keys: &[&str]) -> Case {
    let table = TABLES.iter().find(|t| t.name == "model").unwrap();
    let mut text = format!("[model]\nkind = \"{kind}\"\n");
    for key in table.keys.iter().filter(|k| keys.contains(&k.name)) {
        text.push_str(&format!("{} = {}\n", key.name, example(table, key, None)));
    }
    parse(&text).unwrap()
}

/// The springs and masses shown commented out are the defaults: set
/// them and the model is the same.
#[test]
fn the_commented_academic_model_is_the_default_one() {
    let case = model_with_examples("academic", &["masses", "springs", "symmetry_tolerance"]);
    assert!(case.model.springs.is_some());
    let explicit = case.model.build(Path::new(".")).unwrap();
    let default = Case::default().model.build(Path::new(".")).unwrap();
    assert_eq!(
        explicit.natural_frequencies().unwrap(),
        default.natural_frequencies().unwrap()
    );
}

/// The inline-matrix model shown commented out builds.
#[test]
fn the_commented_matrices_model_builds() {
    let keys = ["mass", "stiffness", "mass_coupling", "stiffness_coupling"];
    let case = model_with_examples("matrices", &keys);
    case.model.build(Path::new(".")).unwrap();
}

/// The frequencies shown for the automatic range are the run's.
#[test]
fn the_automatic_range_shown_is_the_runs() {
    for case in [Case::default(), EXAMPLES[9].case()] {
        let (start, end) = automatic_range(&case).unwrap();
        let prepared = cyclorub::run::prepare(&case, Path::new("."), case.basis.kind).unwrap();
        let k = prepared.case.continuation;
        assert!((k.start_hz.unwrap() - start).abs() < 1e-9 * start);
        assert!((k.end_hz.unwrap() - end).abs() < 1e-9 * end);
    }
    let text = default_template();
    assert!(text.contains("# start_hz = 121.31\n"), "{text}");
    assert!(text.contains(", here 121.31 Hz)"), "{text}");
}

#[test]
fn the_default_case_and_every_example_run_without_a_warning_of_unused_keys() {
    // `cyclorub init` writes every key at its default, the examples too:
    // a new user's first run must not open with warnings about keys they
    // never touched (each example once warned of 4 to 6: the other law's
    // epsilon and wall stiffness, the other excitations' lists).
    let mut texts = vec![("default".to_string(), default_template())];
    for name in example_names() {
        if let Some(text) = example_template(name) {
            texts.push((name.to_string(), text));
        }
    }
    for (name, text) in texts {
        let case = parse(&text).unwrap_or_else(|e| panic!("{name}: {e}"));
        let unused = case.unused_keys_in(&text);
        assert!(unused.is_empty(), "{name}: {unused:?}");
    }
}
