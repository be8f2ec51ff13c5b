//! The `[model]` table and Matrix Market import: valid cases, and each
//! validation error triggered by a fixture with its message checked.

use cyclorub::model::{ModelError, ModelSpec, SectorModel};
use std::path::{Path, PathBuf};

fn fixtures() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/fixtures/model")
}

fn build(case: &Path) -> Result<SectorModel, ModelError> {
    let spec = ModelSpec::from_case_file(case)?;
    spec.build(case.parent().expect("case dir"))
}

fn error_of(name: &str) -> String {
    let case = fixtures().join("errors").join(format!("{name}.toml"));
    match build(&case) {
        Ok(_) => panic!("{name}: expected an error"),
        Err(e) => e.to_string(),
    }
}

fn assert_contains(message: &str, parts: &[&str]) {
    for part in parts {
        assert!(message.contains(part), "message {message:?} lacks {part:?}");
    }
}

fn assert_same_frequencies(a: &SectorModel, b: &SectorModel, tolerance: f64) {
    let fa = a.natural_frequencies().expect("frequencies");
    let fb = b.natural_frequencies().expect("frequencies");
    assert_eq!(fa.len(), fb.len());
    for ((da, va), (db, vb)) in fa.iter().zip(&fb) {
        assert_eq!(da, db);
        assert_eq!(va.len(), vb.len());
        for (x, y) in va.iter().zip(vb) {
            assert!((x - y).abs() <= tolerance * y, "nd {da}: {x} vs {y}");
        }
    }
}

#[test]
fn minimal_academic_case_is_the_default() {
    let spec = ModelSpec::from_case_file(&fixtures().join("academic.toml")).expect("spec");
    assert_eq!(spec, ModelSpec::default());
    assert_eq!(spec.sectors(), 24);
    let model = spec.build(&fixtures()).expect("model");
    assert_eq!(model.sectors(), 24);
    assert_eq!(model.dofs_per_sector(), 5);
    assert_eq!(model.dof_label(0), "m1");
    assert_same_frequencies(&model, &SectorModel::academic(24).expect("academic"), 1e-14);
    // No [model] table at all: the default too.
    assert_eq!(
        ModelSpec::from_case_toml("[excitation]\nh = 1\n").expect("spec"),
        ModelSpec::default()
    );
}

#[test]
fn default_round_trips_through_toml() {
    let text = toml::to_string(&ModelSpec::default()).expect("serialize");
    let back: ModelSpec = toml::from_str(&text).expect("parse");
    assert_eq!(back, ModelSpec::default());
}

#[test]
fn matrix_market_chain_equals_lumped_chain() {
    let fe = build(&fixtures().join("chain.toml")).expect("fe chain");
    assert_eq!(fe.sectors(), 12);
    assert_eq!(fe.dofs_per_sector(), 4);
    assert_eq!(fe.dof_label(3), "dof 5");
    let lumped = build(&fixtures().join("chain_lumped.toml")).expect("lumped chain");
    assert_same_frequencies(&fe, &lumped, 1e-12);
    // The general-format stiffness gives the same model.
    let text = std::fs::read_to_string(fixtures().join("chain.toml"))
        .expect("read")
        .replace("chain_K.mtx", "chain_K_general.mtx");
    let general = ModelSpec::from_case_toml(&text)
        .expect("spec")
        .build(&fixtures())
        .expect("model");
    assert_same_frequencies(&fe, &general, 1e-14);
}

#[test]
fn inline_fe_sector_equals_matrix_market() {
    let text = r#"
[model]
kind = "matrices"
sectors = 12
mass = [
  [1.0, 0.0, 0.0, 0.0, 0.0],
  [0.0, 1.0, 0.0, 0.0, 0.0],
  [0.0, 0.0, 0.8, 0.0, 0.0],
  [0.0, 0.0, 0.0, 1.0, 0.0],
  [0.0, 0.0, 0.0, 0.0, 0.2],
]
stiffness = [
  [ 1.0e5, -1.0e5,     0.0,     0.0,     0.0],
  [-1.0e5, 2.55e5, -1.5e5,      0.0,     0.0],
  [   0.0, -1.5e5,  3.0e5,  -1.2e5,  -3.0e4],
  [   0.0,    0.0, -1.2e5,   1.2e5,     0.0],
  [   0.0,    0.0, -3.0e4,     0.0,   3.0e4],
]
left_boundary = [1]
right_boundary = [4]
"#;
    let inline = ModelSpec::from_case_toml(text)
        .expect("spec")
        .build(&fixtures())
        .expect("model");
    let imported = build(&fixtures().join("chain.toml")).expect("imported");
    assert_same_frequencies(&inline, &imported, 1e-14);
    assert_eq!(inline.dof_by_label("dof 5"), Some(3));
    assert_eq!(inline.dof_by_label("dof 4"), None);
}

#[test]
fn one_dof_oscillator_inline() {
    let model = build(&fixtures().join("oscillator.toml")).expect("oscillator");
    let freqs = model.natural_frequencies().expect("frequencies");
    let expected = 40.0_f64.sqrt() / (2.0 * std::f64::consts::PI);
    assert_eq!(freqs.len(), 1);
    assert!((freqs[0].1[0] - expected).abs() <= 1e-14 * expected);
}

#[test]
fn not_square() {
    assert_contains(
        &error_of("not_square"),
        &[
            "model.stiffness_file",
            "not_square.mtx",
            "not square",
            "3 rows, 4 columns",
        ],
    );
}

#[test]
fn not_symmetric() {
    assert_contains(
        &error_of("nonsymmetric"),
        &[
            "model.stiffness_file",
            "nonsymmetric.mtx",
            "not symmetric",
            "(2, 1)",
            "(1, 2)",
        ],
    );
}

#[test]
fn mass_not_positive_definite() {
    assert_contains(
        &error_of("mass_not_pd"),
        &[
            "model.mass_file",
            "mass_not_pd.mtx",
            "not positive definite",
        ],
    );
}

#[test]
fn size_mismatch() {
    assert_contains(
        &error_of("size_mismatch"),
        &["model.mass_file", "4×4", "model.stiffness_file", "5×5"],
    );
}

#[test]
fn boundary_lists_of_unequal_length() {
    assert_contains(
        &error_of("boundary_unequal"),
        &[
            "model.left_boundary",
            "model.right_boundary",
            "unequal lengths",
            "2 left",
            "1 right",
        ],
    );
}

#[test]
fn boundary_dof_out_of_range() {
    assert_contains(
        &error_of("boundary_out_of_range"),
        &["model.right_boundary[1]", "dof 9", "out of range", "1..=5"],
    );
    assert_contains(
        &error_of("boundary_zero"),
        &["model.left_boundary[1]", "dof 0", "numbered from 1"],
    );
    assert_contains(
        &error_of("boundary_repeated"),
        &["model.right_boundary[1]", "dof 1", "model.left_boundary[1]"],
    );
}

#[test]
fn malformed_matrix_market_files() {
    assert_contains(
        &error_of("bad_header"),
        &["bad_header.mtx:1", "array", "allowed: coordinate"],
    );
    assert_contains(
        &error_of("entry_out_of_range"),
        &["entry_out_of_range.mtx:4", "row 3", "out of range 1..=2"],
    );
    assert_contains(
        &error_of("missing_file"),
        &["model.mass_file", "does_not_exist.mtx", "cannot read"],
    );
}

#[test]
fn unknown_and_misplaced_keys() {
    let message = error_of("unknown_key");
    assert_contains(
        &message,
        &[
            "unknown_key.toml",
            "line 4",
            "stifness",
            "expected one of",
            "stiffness",
        ],
    );
    assert_contains(
        &error_of("key_not_for_kind"),
        &["model.mass_file", "kind = \"academic\"", "masses, springs"],
    );
}

#[test]
fn semantic_errors_name_the_key() {
    let cases: &[(&str, &[&str])] = &[
        ("[model]\nsectors = 0\n", &["model.sectors", "at least 1"]),
        (
            "[model]\nmasses = [1.0, 2.0]\n",
            &["model.springs", "required"],
        ),
        (
            "[model]\nmasses = [0.2, 0.3, -0.4, 1.2, 1.2]\n",
            &["model.masses[3]", "-0.4"],
        ),
        (
            "[model]\nmasses = [1.0]\nsprings = [{ dofs = [1, 2], stiffness = 1.0 }]\n",
            &["model.springs[1].dofs", "dof 2", "out of range"],
        ),
        (
            "[model]\nmasses = [1.0]\nsprings = [{ dofs = [1], stiffness = 1.0 }]\n",
            &["model.springs[1].dofs", "two dofs"],
        ),
        (
            "[model.damping]\nkind = \"modal\"\nratios = [1e-3]\n",
            &["model.damping.others", "required", "5 modes"],
        ),
        (
            "[model.damping]\nkind = \"rayleigh\"\nratio = 1e-3\n",
            &["model.damping.ratio", "not used", "alpha, beta"],
        ),
        (
            "[model.damping]\nothers = 3e-3\n",
            &["model.damping.others", "only used with ratios"],
        ),
        (
            "[model.damping]\nkind = \"modal\"\nratio = -1.0\n",
            &["model.damping.ratio", "-1"],
        ),
        (
            "[model]\nkind = \"matrices\"\nmass = [[1.0]]\n",
            &["model.stiffness", "required"],
        ),
        (
            "[model]\nkind = \"matrices\"\nmass = [[1.0, 0.0], [0.0]]\nstiffness = [[1.0]]\n",
            &["model.mass", "row 2"],
        ),
        (
            "[model]\nkind = \"matrices\"\nsectors = 1\nmass = [[1.0]]\nstiffness = [[1.0, 2.0]]\n",
            &["model.stiffness", "not square"],
        ),
    ];
    for (text, parts) in cases {
        let spec = ModelSpec::from_case_toml(text).expect("parses");
        match spec.build(&fixtures()) {
            Ok(_) => panic!("expected an error for {text:?}"),
            Err(e) => assert_contains(&e.to_string(), parts),
        }
    }
}

#[test]
fn damping_kinds_from_toml() {
    for text in [
        "[model.damping]\nkind = \"none\"\n",
        "[model.damping]\nkind = \"rayleigh\"\nalpha = 1.0\nbeta = 1e-6\n",
        "[model.damping]\nkind = \"modal\"\nratios = [1e-3, 1e-3, 1e-3, 1e-3, 1e-3]\n",
        "[model.damping]\nkind = \"matrix\"\nmatrix = [[1,0,0,0,0],[0,1,0,0,0],[0,0,1,0,0],[0,0,0,1,0],[0,0,0,0,1]]\n",
    ] {
        let spec = ModelSpec::from_case_toml(text).expect("parses");
        let model = spec.build(&fixtures()).expect("builds");
        assert_eq!(model.is_damped(), !text.contains("none"));
    }
}

#[test]
fn every_error_fixture_is_refused_with_a_message() {
    // A fixture added under errors/ that builds by mistake fails here, and
    // every refusal says something (run with --nocapture to review them).
    let mut count = 0;
    for entry in std::fs::read_dir(fixtures().join("errors")).expect("dir") {
        let path = entry.expect("entry").path();
        if path.extension().is_some_and(|e| e == "toml") {
            let message = match build(&path) {
                Err(e) => e.to_string(),
                Ok(_) => panic!("{} builds, but it is an error fixture", path.display()),
            };
            assert!(message.len() > 20, "{}: {message:?}", path.display());
            println!("{}: {message}", path.display());
            count += 1;
        }
    }
    assert!(count >= 5, "{count} error fixtures");
}

#[test]
fn the_model_layer_names_matrices_and_the_caller_names_keys() {
    use cyclorub::model::{BlockCirculantSector, Damping, SectorInput};
    use faer::Mat;
    // A 2×2 mass coupling beside a 3×3 stiffness: the model layer says
    // which matrix, in its own words.
    let sector = BlockCirculantSector {
        mass: Mat::identity(3, 3),
        stiffness: Mat::identity(3, 3),
        mass_coupling: Some(Mat::zeros(2, 2)),
        stiffness_coupling: None,
    };
    let error = SectorModel::block_circulant(6, sector, Damping::None).expect_err("mismatch");
    assert_eq!(
        error.to_string(),
        "mass coupling: size 2×2 does not match stiffness (3×3)"
    );
    // The caller attaches its keys, to the matrix and to its reference.
    let named = error.named(|input| match input {
        SectorInput::MassCoupling => "table.m1".into(),
        SectorInput::Stiffness => "table.k0".into(),
        other => other.name().into(),
    });
    assert_eq!(
        named.to_string(),
        "table.m1: size 2×2 does not match table.k0 (3×3)"
    );
    // A case file names both by their keys.
    let text = "[model]\nkind = \"matrices\"\nsectors = 6\nmass = [[1.0, 0.0], [0.0, 1.0]]\n\
                stiffness = [[1.0, 0.0], [0.0, 1.0]]\nstiffness_coupling = [[1.0]]\n";
    let spec = ModelSpec::from_case_toml(text).expect("parses");
    let message = spec.build(&fixtures()).expect_err("mismatch").to_string();
    assert_eq!(
        message,
        "model.stiffness_coupling: size 1×1 does not match model.stiffness (2×2)"
    );
}
