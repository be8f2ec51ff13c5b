//! The written folder read back: the matrices through the crate's own Matrix
//! Market reader (bit for bit), the coordinates and node sets, and the same
//! bytes on every run.

use super::super::{assemble, fan, write_fan, FanGeometry, MeshError, FAN_FILES};
use super::dense;
use crate::model::parse_matrix_market;
use std::path::{Path, PathBuf};

fn scratch(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("cyclorub-mesh-{}-{name}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    dir
}

fn read(path: &Path) -> String {
    std::fs::read_to_string(path).unwrap()
}

#[test]
fn the_written_matrices_read_back_bit_for_bit_and_every_run_writes_the_same_bytes() {
    let fan = fan(16, 1, &FanGeometry::default()).unwrap();
    let matrices = assemble(&fan.mesh).unwrap();
    let (first, second) = (scratch("first"), scratch("second"));
    let output = write_fan(&fan, &matrices, &first, false).unwrap();
    assert_eq!(output.files.len(), FAN_FILES.len() + 1);
    // A second, independent build and write.
    let again = super::super::fan(16, 1, &FanGeometry::default()).unwrap();
    write_fan(&again, &assemble(&again.mesh).unwrap(), &second, false).unwrap();
    for (path, size) in &output.files {
        let name = path.file_name().unwrap();
        let (a, b) = (
            std::fs::read(path).unwrap(),
            std::fs::read(second.join(name)).unwrap(),
        );
        assert_eq!(a.len() as u64, *size);
        assert!(a == b, "{name:?} differs between two runs");
    }
    for (file, matrix) in [
        ("sector_mass.mtx", &matrices.mass),
        ("sector_stiffness.mtx", &matrices.stiffness),
    ] {
        let path = first.join(file);
        let back = parse_matrix_market(&read(&path), &path).unwrap();
        let expected = dense(matrix);
        assert_eq!((back.nrows(), back.ncols()), (fan.dofs(), fan.dofs()));
        for i in 0..back.nrows() {
            for j in 0..back.ncols() {
                assert_eq!(
                    back[(i, j)].to_bits(),
                    expected[(i, j)].to_bits(),
                    "{file} ({i}, {j})"
                );
            }
        }
    }
    // nodes.csv: header, 1-based numbers, the same f64 coordinates.
    let nodes = read(&first.join("nodes.csv"));
    let mut lines = nodes.lines();
    assert_eq!(lines.next(), Some("node,x,y,z"));
    for (n, line) in lines.enumerate() {
        let fields: Vec<&str> = line.split(',').collect();
        assert_eq!(fields[0].parse::<usize>().unwrap(), n + 1);
        for d in 0..3 {
            let v: f64 = fields[d + 1].parse().unwrap();
            assert_eq!(v.to_bits(), fan.mesh.nodes[n][d].to_bits());
        }
    }
    // node_sets.toml: every set, 1-based.
    let sets: toml::Table = toml::from_str(&read(&first.join("node_sets.toml"))).unwrap();
    let list = |key: &str| -> Vec<usize> {
        sets[key]
            .as_array()
            .unwrap()
            .iter()
            .map(|v| v.as_integer().unwrap() as usize - 1)
            .collect()
    };
    let s = &fan.sets;
    assert_eq!(list("clamped"), s.clamped);
    assert_eq!(list("left_boundary"), s.left_boundary);
    assert_eq!(list("right_boundary"), s.right_boundary);
    assert_eq!(list("contact"), s.contact);
    assert_eq!(list("excitation"), vec![s.excitation]);
    assert_eq!(list("observation"), vec![s.observation]);
    assert_eq!(list("blade"), s.blade);
    // The case file is TOML with the finite-element [model] table (built as
    // a case in tests/model_finite_element_case.rs).
    let case: toml::Table = toml::from_str(&read(&first.join("fan16.toml"))).unwrap();
    let model = case["model"].as_table().unwrap();
    assert_eq!(model["kind"].as_str(), Some("finite_element"));
    assert_eq!(model["sectors"].as_integer(), Some(16));
    assert_eq!(model["node_sets_file"].as_str(), Some("node_sets.toml"));
    assert_eq!(model["reduction"]["internal_modes"].as_integer(), Some(20));
    assert!(read(&first.join("README.md")).contains(&format!("{} dofs", fan.dofs())));
    for dir in [first, second] {
        std::fs::remove_dir_all(dir).unwrap();
    }
}

#[test]
fn an_existing_folder_is_refused_without_overwrite_and_replaced_with_it() {
    let fan = fan(16, 1, &FanGeometry::default()).unwrap();
    let matrices = assemble(&fan.mesh).unwrap();
    let dir = scratch("overwrite");
    std::fs::create_dir_all(&dir).unwrap();
    std::fs::write(dir.join("other.txt"), "keep me").unwrap();
    let error = write_fan(&fan, &matrices, &dir, false).unwrap_err();
    assert!(matches!(error, MeshError::Output { .. }) && error.is_input_error());
    assert!(error.to_string().contains("--overwrite"), "{error}");
    write_fan(&fan, &matrices, &dir, true).unwrap();
    assert_eq!(read(&dir.join("other.txt")), "keep me");
    assert!(dir.join("sector_mass.mtx").exists());
    // A file where the folder should be.
    let file = dir.join("other.txt");
    assert!(write_fan(&fan, &matrices, &file, true).is_err());
    std::fs::remove_dir_all(dir).unwrap();
}
