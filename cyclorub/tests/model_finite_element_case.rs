//! `kind = "finite_element"` on the coarse open fan written by the mesh
//! module: the reduced model's first family against the frequencies
//! measured on the full sector (mesh/readme.rs, refine 1), the cache of a
//! second build, the full sector's own frequencies and their cache, and one
//! fixture per import error class, each naming the file and, where there is
//! one, the line.

use cyclorub::mesh::{assemble, fan, write_fan, FanGeometry, MEASURED_FIRST_FAMILY};
use cyclorub::model::{ModelError, ModelSpec};
use std::path::{Path, PathBuf};

/// A fresh folder holding the coarse 16-sector fan.
fn fan_folder(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("cyclorub-fe-{name}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    let fan = fan(16, 1, &FanGeometry::default()).unwrap();
    let matrices = assemble(&fan.mesh).unwrap();
    write_fan(&fan, &matrices, &dir, false).unwrap();
    dir
}

const MODEL: &str = r#"
[model]
kind = "finite_element"
sectors = 16
mass_file = "sector_mass.mtx"
stiffness_file = "sector_stiffness.mtx"
coordinates_file = "nodes.csv"
dofs_per_node = 3
axis = "z"
boundary_frame = "cartesian"
node_sets_file = "node_sets.toml"

[model.reduction]
internal_modes = 20

[model.damping]
kind = "modal"
ratios = [1e-3, 1e-3, 1e-3, 1e-3, 1e-3]
others = 5e-3
"#;

fn build(dir: &Path, text: &str) -> Result<cyclorub::model::SectorModel, ModelError> {
    ModelSpec::from_case_toml(text).unwrap().build(dir)
}

#[test]
fn the_fan_case_builds_the_reduced_first_family_and_a_second_build_reads_the_cache() {
    let dir = fan_folder("family");
    let started = std::time::Instant::now();
    let model = build(&dir, MODEL).unwrap();
    let first = started.elapsed();
    assert_eq!(model.dofs_per_sector(), 11 * 3 + 20);
    assert_eq!(model.dof_label(33), "mode 1");
    let frequencies = model.natural_frequencies().unwrap();
    let measured = MEASURED_FIRST_FAMILY[0].1;
    for (d, f) in &frequencies {
        // The table is rounded to 0.01 Hz; Craig–Bampton adds < 1e-5.
        assert!(
            (f[0] - measured[*d]).abs() <= 0.007,
            "ND {d}: {} vs {} Hz",
            f[0],
            measured[*d]
        );
    }
    let cached: Vec<_> = std::fs::read_dir(dir.join(".cyclorub-cache"))
        .unwrap()
        .collect();
    assert_eq!(cached.len(), 1);
    let started = std::time::Instant::now();
    let again = build(&dir, MODEL).unwrap();
    let second = started.elapsed();
    println!("first build {first:.2?}, cached {second:.2?}");
    for s in [0i64, 3, -5, 8] {
        let (a, b) = (
            model.nodal_diameter_matrices(s).unwrap(),
            again.nodal_diameter_matrices(s).unwrap(),
        );
        assert_eq!(a.stiffness, b.stiffness);
        assert_eq!(a.mass, b.mass);
    }
    // A changed setting is another reduction, not the cached one.
    let fewer = MODEL.replace("internal_modes = 20", "internal_modes = 4");
    assert_eq!(build(&dir, &fewer).unwrap().dofs_per_sector(), 33 + 4);
    let _ = std::fs::remove_dir_all(&dir);
}

/// The files of `dir`'s cache whose names start with `prefix`.
fn cache_files(dir: &Path, prefix: &str) -> Vec<PathBuf> {
    std::fs::read_dir(dir.join(".cyclorub-cache"))
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| {
            p.file_name()
                .and_then(|n| n.to_str())
                .is_some_and(|n| n.starts_with(prefix))
        })
        .collect()
}

/// The full sector's frequencies of a finite-element table: the first
/// family is the one measured on the full sector (mesh/readme.rs), and they
/// are cached beside the Craig–Bampton models: fewer frequencies, or
/// another `[model.reduction]`, read the file (untouched, the same values to
/// the bit); more frequencies or a corrupt file are computed again. Another
/// kind is refused naming `model.kind`.
#[test]
fn the_full_sector_frequencies_are_the_measured_ones_and_are_cached() {
    let dir = fan_folder("full");
    let spec = ModelSpec::from_case_toml(MODEL).unwrap();
    let first = spec.full_sector_frequencies(&dir, 3).unwrap();
    let measured = MEASURED_FIRST_FAMILY[0].1;
    assert_eq!(first.len(), 9);
    for (d, f) in &first {
        assert_eq!(f.len(), 3);
        assert!(f.windows(2).all(|w| w[0] < w[1]), "ND {d}: {f:?}");
        // The table is rounded to 0.01 Hz.
        assert!(
            (f[0] - measured[*d]).abs() <= 0.0051,
            "ND {d}: {} vs {} Hz",
            f[0],
            measured[*d]
        );
    }
    let files = cache_files(&dir, "full-sector-");
    assert_eq!(files.len(), 1, "{files:?}");
    let file = &files[0];
    let stamp = || std::fs::metadata(file).unwrap().modified().unwrap();
    let (written, bytes) = (stamp(), std::fs::read(file).unwrap());

    let fewer = spec.full_sector_frequencies(&dir, 2).unwrap();
    let other =
        ModelSpec::from_case_toml(&MODEL.replace("internal_modes = 20", "internal_modes = 4"))
            .unwrap()
            .full_sector_frequencies(&dir, 3)
            .unwrap();
    assert_eq!(other, first);
    for ((_, a), (_, b)) in fewer.iter().zip(&first) {
        assert_eq!(a[..], b[..2]);
    }
    assert_eq!(stamp(), written, "the cache file was rewritten");
    assert_eq!(std::fs::read(file).unwrap(), bytes);
    assert_eq!(cache_files(&dir, "full-sector-").len(), 1);

    let more = spec.full_sector_frequencies(&dir, 5).unwrap();
    for ((_, a), (_, b)) in more.iter().zip(&first) {
        assert_eq!(a.len(), 5);
        for (x, y) in a.iter().zip(b) {
            assert!((x - y).abs() <= 1e-10 * y, "{x} vs {y} Hz");
        }
    }
    assert_ne!(std::fs::read(file).unwrap(), bytes, "5 frequencies stored");
    let stored = std::fs::read(file).unwrap();
    std::fs::write(file, &stored[..stored.len() / 2]).unwrap();
    assert_eq!(spec.full_sector_frequencies(&dir, 5).unwrap(), more);
    assert_eq!(
        std::fs::read(file).unwrap(),
        stored,
        "the corrupt file is rewritten"
    );

    let error = ModelSpec::default()
        .full_sector_frequencies(&dir, 3)
        .unwrap_err()
        .to_string();
    assert!(error.starts_with("model.kind: \"academic\""), "{error}");
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn boundary_pairs_given_out_of_order_are_matched_by_coordinates() {
    let dir = fan_folder("pairs");
    let reference = build(&dir, MODEL).unwrap().natural_frequencies().unwrap();
    let sets = dir.join("node_sets.toml");
    let text = std::fs::read_to_string(&sets).unwrap();
    // Reverse the right boundary list.
    let start = text.find("right_boundary = [").unwrap();
    let end = start + text[start..].find(']').unwrap();
    let nodes: Vec<&str> = text[start + 18..end]
        .split(|c: char| !c.is_ascii_digit())
        .filter(|t| !t.is_empty())
        .collect();
    let reversed: Vec<&str> = nodes.iter().rev().cloned().collect();
    let text = format!(
        "{}right_boundary = [{}]{}",
        &text[..start],
        reversed.join(", "),
        &text[end + 1..]
    );
    std::fs::write(&sets, text).unwrap();
    let _ = std::fs::remove_dir_all(dir.join(".cyclorub-cache"));
    let model = build(&dir, MODEL).unwrap();
    for ((_, a), (_, b)) in model.natural_frequencies().unwrap().iter().zip(&reference) {
        assert!((a[0] - b[0]).abs() <= 1e-9 * b[0], "{} vs {}", a[0], b[0]);
    }
    let _ = std::fs::remove_dir_all(&dir);
}

/// Rewrites `file` of `dir` by `edit`, builds, and returns the error text.
fn error_after(dir: &Path, file: &str, edit: impl Fn(&str) -> String) -> String {
    let path = dir.join(file);
    let original = std::fs::read_to_string(&path).unwrap();
    std::fs::write(&path, edit(&original)).unwrap();
    let _ = std::fs::remove_dir_all(dir.join(".cyclorub-cache"));
    let error = build(dir, MODEL).unwrap_err();
    std::fs::write(&path, original).unwrap();
    error.to_string()
}

#[test]
fn import_errors_name_the_file_and_the_line() {
    let dir = fan_folder("errors");
    // Unmatched boundary: one right-face node moved by 1 mm in z.
    let sets = std::fs::read_to_string(dir.join("node_sets.toml")).unwrap();
    let right_start = sets.find("right_boundary = [").unwrap() + 18;
    let first_right: usize = sets[right_start..]
        .trim_start()
        .split(|c: char| !c.is_ascii_digit())
        .next()
        .unwrap()
        .parse()
        .unwrap();
    let message = error_after(&dir, "nodes.csv", |text| {
        text.lines()
            .map(|l| {
                let fields: Vec<&str> = l.split(',').collect();
                if fields[0] == first_right.to_string() {
                    let z: f64 = fields[3].parse().unwrap();
                    format!("{},{},{},{:e}\n", fields[0], fields[1], fields[2], z + 1e-3)
                } else {
                    format!("{l}\n")
                }
            })
            .collect()
    });
    println!("{message}");
    assert!(
        message.contains("node_sets.toml:") && message.contains("no right_boundary node"),
        "{message}"
    );
    // A node set naming a node the coordinates file lacks.
    let message = error_after(&dir, "node_sets.toml", |text| {
        text.replacen("contact = [\n    ", "contact = [\n    999999, ", 1)
    });
    println!("{message}");
    let line = sets.lines().position(|l| l.starts_with("contact")).unwrap() + 2;
    assert!(
        message.contains(&format!("node_sets.toml:{line}")) && message.contains("node 999999"),
        "{message}"
    );
    // A missing node in the coordinates file.
    let message = error_after(&dir, "nodes.csv", |text| {
        text.lines()
            .filter(|l| !l.starts_with("7,"))
            .map(|l| format!("{l}\n"))
            .collect()
    });
    println!("{message}");
    assert!(
        message.contains("nodes.csv") && message.contains("node 7 is missing"),
        "{message}"
    );
    // A non-symmetric stiffness: a general file with one entry changed.
    // (lines: header, comment, size, then the lower triangle's entries)
    let message = error_after(&dir, "sector_stiffness.mtx", |text| {
        let lines: Vec<&str> = text.lines().collect();
        let mut body = Vec::new();
        for (k, e) in lines[3..].iter().enumerate() {
            let f: Vec<&str> = e.split_whitespace().collect();
            body.push(e.to_string());
            if f[0] != f[1] {
                let v: f64 = f[2].parse().unwrap();
                let v = if k == 5 { v * 1.01 } else { v };
                body.push(format!("{} {} {v:e}", f[1], f[0]));
            }
        }
        let size: Vec<&str> = lines[2].split_whitespace().collect();
        let header = "%%MatrixMarket matrix coordinate real general".to_string();
        let mut out = vec![header, format!("{} {} {}", size[0], size[1], body.len())];
        out.extend(body);
        out.join("\n") + "\n"
    });
    println!("{message}");
    assert!(
        message.contains("sector_stiffness.mtx:") && message.contains("not symmetric"),
        "{message}"
    );
    // An indefinite stiffness.
    let message = error_after(&dir, "sector_stiffness.mtx", |text| {
        text.lines()
            .enumerate()
            .map(|(i, l)| {
                let f: Vec<&str> = l.split_whitespace().collect();
                if i < 3 {
                    format!("{l}\n")
                } else {
                    let v: f64 = f[2].parse().unwrap();
                    format!("{} {} {:e}\n", f[0], f[1], -v)
                }
            })
            .collect()
    });
    println!("{message}");
    assert!(
        message.contains("sector_stiffness.mtx") && message.contains("not positive definite"),
        "{message}"
    );
    let _ = std::fs::remove_dir_all(&dir);
}

/// The case file `cyclorub mesh fan` writes is valid, builds, and its dof
/// numbers name the dofs it says: the contact nodes' radial dofs (and their
/// circumferential and axial ones for friction, with radii from the
/// coordinates), the y dof of the excitation node and of the observation
/// node.
#[test]
fn the_written_fan_case_is_valid_and_its_dofs_are_the_named_ones() {
    let dir = fan_folder("case");
    let fan = fan(16, 1, &FanGeometry::default()).unwrap();
    let case = cyclorub::case::Case::from_file_checked(&dir.join("fan16.toml")).unwrap();
    let model = case.model.build(&dir).unwrap();
    case.check_model(&model).unwrap();
    let contact: Vec<String> = case
        .contact_dofs()
        .iter()
        .map(|&d| model.dof_label(d))
        .collect();
    let expected: Vec<String> = fan
        .sets
        .contact
        .iter()
        .map(|n| format!("node {} r", n + 1))
        .collect();
    assert_eq!(contact, expected);
    let friction = case
        .friction(&model)
        .unwrap()
        .expect("the fan rubs with friction");
    assert_eq!(friction.coefficient(), 0.15);
    for (node, n) in friction.nodes().iter().zip(&fan.sets.contact) {
        assert_eq!(
            model.dof_label(node.circumferential),
            format!("node {} θ", n + 1)
        );
        assert_eq!(model.dof_label(node.axial), format!("node {} z", n + 1));
        let [x, y, _] = fan.mesh.nodes[*n];
        assert!((node.radius - x.hypot(y)).abs() < 1e-12 * node.radius);
    }
    let forcing = case.forcing().unwrap();
    assert_eq!(
        forcing
            .dofs
            .iter()
            .map(|&d| model.dof_label(d))
            .collect::<Vec<_>>(),
        vec![format!("node {} y", fan.sets.excitation + 1)]
    );
    assert_eq!(
        model.dof_label(case.output.observed_dof - 1),
        format!("node {} y", fan.sets.observation + 1)
    );
    let _ = std::fs::remove_dir_all(&dir);
}

/// `contact_frame = "cylindrical"` turns each contact node's dofs into its
/// radial, circumferential and axial directions: the per-diameter matrices
/// are `T A Tᵀ` of the Cartesian ones (checked entry by entry on every
/// contact node's radial direction, from the coordinates) and the
/// frequencies do not change.
#[test]
fn the_cylindrical_contact_frame_turns_the_contact_dofs_and_keeps_the_frequencies() {
    let dir = fan_folder("frame");
    let fan = fan(16, 1, &FanGeometry::default()).unwrap();
    let cartesian = build(&dir, MODEL).unwrap();
    let cylindrical_text = MODEL.replace(
        "node_sets_file = \"node_sets.toml\"",
        "node_sets_file = \"node_sets.toml\"\ncontact_frame = \"cylindrical\"",
    );
    let cylindrical = build(&dir, &cylindrical_text).unwrap();
    let (a, b) = (
        cartesian.natural_frequencies().unwrap(),
        cylindrical.natural_frequencies().unwrap(),
    );
    for ((d, f), (_, g)) in a.iter().zip(&b) {
        for (x, y) in f.iter().zip(g) {
            assert!((x - y).abs() < 1e-9 * x, "ND {d}: {x} vs {y} Hz");
        }
    }
    for s in [0, 3] {
        let k = cartesian.nodal_diameter_matrices(s).unwrap().stiffness;
        let l = cylindrical.nodal_diameter_matrices(s).unwrap().stiffness;
        let scale = k[(0, 0)].norm();
        for (i, &n) in fan.sets.contact.iter().enumerate() {
            let [x, y, _] = fan.mesh.nodes[n];
            let r = [x / x.hypot(y), y / x.hypot(y), 0.0];
            let mut radial = faer::c64::new(0.0, 0.0);
            for p in 0..3 {
                for q in 0..3 {
                    radial += k[(3 * i + p, 3 * i + q)] * r[p] * r[q];
                }
            }
            let direct = l[(3 * i, 3 * i)];
            assert!(
                (radial - direct).norm() < 1e-12 * scale,
                "ND {s}, contact node {}: {radial} vs {direct}",
                n + 1
            );
            assert_eq!(cylindrical.dof_label(3 * i), format!("node {} r", n + 1));
        }
        // The other retained nodes and the modes are untouched.
        let last = k.nrows() - 1;
        assert_eq!(k[(last, last)], l[(last, last)]);
    }
    let _ = std::fs::remove_dir_all(&dir);
}

/// The node sets' rules: a node listed twice in a set, or in two of the
/// retained sets, or retained and clamped, would shift every dof number
/// after it (the case's `contact.dofs`, `excitation.dofs` then name other
/// nodes than meant): refused naming the file, its line, the set, the
/// entry and the node.
#[test]
fn overlapping_node_sets_are_refused_naming_the_set_and_the_node() {
    let dir = fan_folder("overlap");
    let fan = fan(16, 1, &FanGeometry::default()).unwrap();
    let first = fan.sets.contact[0] + 1;
    let excitation = fan.sets.excitation + 1;
    let clamped = fan.sets.clamped[0] + 1;
    // Item 1: `contact = [407, 408, …, 407]`.
    let path = dir.join("node_sets.toml");
    let original = std::fs::read_to_string(&path).unwrap();
    let repeated = original.replacen("contact = [\n", &format!("contact = [\n    {first}, "), 1);
    std::fs::write(&path, &repeated).unwrap();
    let error = build(&dir, MODEL).unwrap_err();
    std::fs::write(&path, &original).unwrap();
    let contact_line = original
        .lines()
        .position(|l| l.starts_with("contact"))
        .unwrap()
        + 2;
    assert!(
        matches!(&error, ModelError::InputFile { key, line, .. }
            if key.starts_with("model.node_sets_file") && *line == contact_line),
        "{error:?}"
    );
    let message = error.to_string();
    println!("{message}");
    assert!(
        message.contains("node_sets.toml:")
            && message.contains(&format!("contact[2]: node {first} is already contact[1]"))
            && message.contains("list each node once"),
        "{message}"
    );
    // Item 2: `excitation = [407]`, a contact node.
    let message = error_after(&dir, "node_sets.toml", |text| {
        text.replace(
            &format!("excitation = [{excitation}]"),
            &format!("excitation = [{first}]"),
        )
    });
    println!("{message}");
    assert!(
        message.contains("node_sets.toml:")
            && message.contains(&format!(
                "excitation[1]: node {first} is already contact[1]"
            ))
            && message.contains("a node belongs to one of contact, excitation and observation"),
        "{message}"
    );
    // A retained node that is clamped.
    let message = error_after(&dir, "node_sets.toml", |text| {
        text.replace(
            &format!("excitation = [{excitation}]"),
            &format!("excitation = [{clamped}]"),
        )
    });
    println!("{message}");
    assert!(
        message.contains(&format!("excitation[1]: node {clamped} is also clamped[1]")),
        "{message}"
    );
    // A left boundary node listed twice.
    let left = fan.sets.left_boundary[0] + 1;
    let message = error_after(&dir, "node_sets.toml", |text| {
        text.replacen(
            "left_boundary = [\n",
            &format!("left_boundary = [\n    {left}, "),
            1,
        )
    });
    println!("{message}");
    assert!(
        message.contains(&format!(
            "left_boundary[2]: node {left} is already left_boundary[1]"
        )),
        "{message}"
    );
    let _ = std::fs::remove_dir_all(&dir);
}

/// Issue 45 item 14: `contact = []` shifted every dof number onto the
/// excitation and observation nodes, and was blamed on
/// `output.observed_dof`: the empty set is named, at its line.
#[test]
fn an_empty_contact_set_is_named() {
    let dir = fan_folder("empty-contact");
    let path = dir.join("node_sets.toml");
    let original = std::fs::read_to_string(&path).unwrap();
    let start = original.find("contact = [").unwrap();
    let end = start + original[start..].find(']').unwrap() + 1;
    let edited = format!("{}contact = []{}", &original[..start], &original[end..]);
    std::fs::write(&path, &edited).unwrap();
    let error = build(&dir, MODEL).unwrap_err();
    let line = edited[..start].lines().count() + 1;
    assert!(
        matches!(&error, ModelError::InputFile { key, line: l, .. }
            if key.starts_with("model.node_sets_file") && *l == line),
        "{error:?}"
    );
    let message = error.to_string();
    println!("{message}");
    assert!(
        message.contains("contact = []: the contact set is empty")
            && message.contains("at least one")
            && !message.contains("observed_dof"),
        "{message}"
    );
    // Without the key at all.
    std::fs::write(&path, format!("{}{}", &original[..start], &original[end..])).unwrap();
    let message = build(&dir, MODEL).unwrap_err().to_string();
    assert!(message.contains("no contact set"), "{message}");
    let _ = std::fs::remove_dir_all(&dir);
}

/// Item 3: on a finite-element case the nodes are known: a contact dof's
/// circumferential and axial dofs must be its own node's, not (here) the
/// excitation node's x dof.
#[test]
fn friction_dofs_of_another_node_are_refused_naming_both_nodes() {
    use cyclorub::case::{Case, CaseError};
    let dir = fan_folder("friction-node");
    let fan = fan(16, 1, &FanGeometry::default()).unwrap();
    let path = dir.join("fan16.toml");
    let text = std::fs::read_to_string(&path).unwrap();
    // The coarse fan keeps 9 contact nodes (dofs 1..=27), then the
    // excitation node (28, 29, 30): 28 is its x dof.
    let start = text.find("circumferential_dofs = [").unwrap() + 24;
    let comma = start + text[start..].find(',').unwrap();
    let edited = format!("{}28{}", &text[..start], &text[comma..]);
    std::fs::write(&path, &edited).unwrap();
    let case = Case::from_file_checked(&path).unwrap();
    let model = case.model.build(&dir).unwrap();
    let error = case.friction(&model).unwrap_err();
    let message = error.to_string();
    println!("{message}");
    assert!(
        matches!(&error, CaseError::Invalid { key, .. } if key == "contact.circumferential_dofs"),
        "{error:?}"
    );
    let contact = fan.sets.contact[0] + 1;
    let excitation = fan.sets.excitation + 1;
    assert!(
        message.starts_with("contact.circumferential_dofs = [28, ")
            && message.contains(&format!("entry 1 is dof 28 (node {excitation} x)"))
            && message.contains(&format!("is on node {contact}"))
            && message.contains("must be its own node's"),
        "{message}"
    );
    let _ = std::fs::remove_dir_all(&dir);
}
