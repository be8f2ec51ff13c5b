//! Results a person uses, against independent computations: recovery from
//! a reduced basis against the physical full model, cyclic components of
//! known waves, the HDF5 round trip (Rust and h5py), and the figures.

use crate::common::h5py::read_with_h5py;
use cyclorub::basis::SpectralBasis;
use cyclorub::case::{BasisChoice, Case};
use cyclorub::contact::{ContactModel, DynamicLagrangian};
use cyclorub::continuation::{solve_at_frequencies, NewtonSettings, Point};
use cyclorub::cyclic::ExcitationPattern;
use cyclorub::forced_response::ForcedResponse;
use cyclorub::hbm::{Casing, Forcing, Formulation, HarmonicBalance, ProblemSpec};
use cyclorub::model::SectorModel;
use cyclorub::plot::{write_figures, FigureOptions, Reference};
use cyclorub::results::components::CyclicComponents;
use cyclorub::results::data::ResultsData;
use cyclorub::results::folder::BranchTable;
use cyclorub::results::hdf5;
use cyclorub::results::recovery::{contact_history, dof_histories, DofHistory};
use cyclorub::run::{prepare, Prepared};
use std::f64::consts::PI;
use std::path::{Path, PathBuf};

fn case(text: &str) -> Case {
    Case::from_toml(text, Path::new("test.toml")).expect("test case")
}

/// A standing wave on 8 sectors: every sector responds differently.
const STANDING: &str = r#"
[model]
sectors = 8
[excitation]
kind = "standing"
engine_order = 1
amplitude = 3.0
[harmonic_balance]
harmonics = 4
time_samples = 64
[output]
peak_histories = true
"#;

/// Solves `case` on `basis` at `factors` times the first resonance of
/// nodal diameter `diameter`, in order (natural continuation), and returns
/// the prepared problem and the points.
fn solve(
    case: &Case,
    basis: BasisChoice,
    diameter: usize,
    factors: &[f64],
) -> (Prepared, Vec<Point>) {
    let mut prepared = prepare(case, Path::new("."), basis).expect("prepare");
    let f = prepared.model.natural_frequencies().expect("modes")[diameter].1[0];
    let points = solve_problem(&mut prepared.problem, f, factors);
    (prepared, points)
}

fn solve_problem(problem: &mut HarmonicBalance, resonance_hz: f64, factors: &[f64]) -> Vec<Point> {
    let omegas: Vec<f64> = factors
        .iter()
        .map(|x| 2.0 * PI * resonance_hz * x)
        .collect();
    let start = problem.linear_solution(omegas[0]).expect("linear");
    let settings = NewtonSettings {
        tolerance: 1e-11,
        max_iterations: 60,
        ..Default::default()
    };
    let branch = solve_at_frequencies(problem, start, &omegas, &settings, |_, _| {});
    for p in &branch.points {
        assert!(p.converged, "not converged at {} Hz", p.omega / 2.0 / PI);
    }
    branch.points
}

fn max_difference(a: &[f64], b: &[f64]) -> f64 {
    a.iter()
        .zip(b)
        .fold(0.0_f64, |m, (x, y)| m.max((x - y).abs()))
}

/// Recovery from `small` (a reduced basis) against `full` (the physical
/// model) at their last points: every dof, every sector, displacement,
/// velocity, contact force and contact time.
fn compare_recovery(
    (small, q): (&HarmonicBalance, &Point),
    (full, p): (&HarmonicBalance, &Point),
    dofs: usize,
    time_samples: usize,
) {
    assert!(small.layout().unknowns < full.layout().unknowns);
    let n = full.layout().sectors;
    let all: Vec<usize> = (0..n).collect();
    let nt = time_samples;
    // Every dof of the sector: the contact dof and the recovered ones.
    for dof in 0..dofs {
        let a = dof_histories(small, &q.unknowns, q.omega, dof, &all, nt).unwrap();
        let b = dof_histories(full, &p.unknowns, p.omega, dof, &all, nt).unwrap();
        // Relative to the dof's largest value over all sectors (a sector on
        // a node of the standing wave barely moves).
        let scale = |f: &dyn Fn(&DofHistory) -> &Vec<f64>| {
            b.iter()
                .flat_map(|h| f(h).iter())
                .fold(0.0_f64, |m, v| m.max(v.abs()))
        };
        let (u, v) = (scale(&|h| &h.displacement), scale(&|h| &h.velocity));
        assert!(u > 0.0 && v > 0.0);
        for (x, y) in a.iter().zip(&b) {
            assert_eq!(x.sector, y.sector);
            let d = max_difference(&x.displacement, &y.displacement) / u;
            assert!(
                d < 1e-9,
                "dof {dof} sector {}: displacement differs by {d:e}",
                x.sector + 1
            );
            let w = max_difference(&x.velocity, &y.velocity) / v;
            assert!(
                w < 1e-9,
                "dof {dof} sector {}: velocity differs by {w:e}",
                x.sector + 1
            );
        }
    }
    let a = contact_history(small, &q.unknowns, q.omega, &all, nt).unwrap();
    let b = contact_history(full, &p.unknowns, p.omega, &all, nt).unwrap();
    let scale = b.signals.iter().map(|s| s.peak_force()).fold(0.0, f64::max);
    assert!(scale > 0.0);
    for (x, y) in a.signals.iter().zip(&b.signals) {
        let f = x
            .force
            .iter()
            .zip(&y.force)
            .fold(0.0_f64, |m, (u, v)| m.max((u - v).abs()))
            / scale;
        assert!(
            f < 1e-7,
            "sector {}: contact force differs by {f:e}",
            x.sector + 1
        );
        assert!((x.fraction_in_contact() - y.fraction_in_contact()).abs() <= 1.0 / nt as f64);
    }
    // One contact dof: a sector's time in contact is its dof's.
    for ((sector, fraction), signal) in b.fraction_per_sector().iter().zip(&b.signals) {
        assert_eq!(*sector, signal.sector);
        assert!((fraction - signal.fraction_in_contact()).abs() < 1e-15);
    }
    let touching = b.sectors_in_contact();
    assert_eq!(a.sectors_in_contact(), touching);
    assert!(
        !touching.is_empty() && touching.len() < n,
        "the test point should touch the casing on some sectors only: {touching:?}"
    );
}

#[test]
fn recovery_from_a_reduced_basis_equals_the_full_model_on_every_sector() {
    // The standing wave touches the casing near its antinodes only.
    let standing = case(STANDING);
    let factors = [0.97, 0.985, 0.995, 1.0];
    let (full, full_points) = solve(&standing, BasisChoice::Physical, 1, &factors);
    let (small, small_points) = solve(&standing, BasisChoice::Symmetry, 1, &factors);
    compare_recovery(
        (&small.problem, small_points.last().unwrap()),
        (&full.problem, full_points.last().unwrap()),
        full.model.dofs_per_sector(),
        standing.harmonic_balance.time_samples,
    );
}

#[test]
fn dlft_contact_forces_from_a_reduced_basis_equal_the_full_model() {
    // DLFT-HBM with the paper's flexible wall, built directly.
    let model = SectorModel::academic(8).unwrap();
    let forcing = Forcing {
        pattern: ExcitationPattern::Standing { engine_order: 1 },
        amplitude: 3.0,
        dofs: vec![0],
        static_force: 0.0,
    };
    let casing = Casing {
        gaps: vec![1e-3],
        order: 0,
        amplitudes: vec![0.0],
    };
    let spec = ProblemSpec {
        model: &model,
        contact_dofs: &[0],
        forcing: Some(&forcing),
        casing: &casing,
        contact: ContactModel::Lagrangian(DynamicLagrangian::new(1e9, Some(1e8)).unwrap()),
        friction: None,
        preload: None,
        harmonics: 4,
        time_samples: 64,
    };
    let basis = SpectralBasis::symmetry(&spec.load_case(), 4).unwrap();
    let mut small = spec.build(&Formulation::Cyclic(basis)).unwrap();
    let mut full = spec.build(&Formulation::Physical).unwrap();
    let f = model.natural_frequencies().unwrap()[1].1[0];
    let factors = [0.97, 0.985, 0.995, 1.0];
    let small_points = solve_problem(&mut small, f, &factors);
    let full_points = solve_problem(&mut full, f, &factors);
    compare_recovery(
        (&small, small_points.last().unwrap()),
        (&full, full_points.last().unwrap()),
        model.dofs_per_sector(),
        64,
    );
}

/// Coordinates on `n` sectors of `Σ A cos(kωt − sαj + φ)` over `list` of
/// `(A, s, k, φ)`, sector `j` 0-based.
fn waves(n: usize, harmonics: usize, list: &[(f64, i64, usize, f64)]) -> Vec<Vec<f64>> {
    let alpha = 2.0 * PI / n as f64;
    (0..n)
        .map(|j| {
            let mut c = vec![0.0; 2 * harmonics + 1];
            for &(a, s, k, phi) in list {
                let angle = phi - s as f64 * alpha * j as f64;
                if k == 0 {
                    c[0] += a * angle.cos();
                } else {
                    c[2 * k - 1] += 0.5 * a * angle.cos();
                    c[2 * k] += 0.5 * a * angle.sin();
                }
            }
            c
        })
        .collect()
}

#[test]
fn a_traveling_wave_has_only_its_signed_pair_on_each_harmonic() {
    for n in [7, 8, 24, 45] {
        let harmonics = 6;
        // The zig-zag of engine order 2, backward: (−2k mod N, k), plus a
        // forward wave (+3, 1) and a mean.
        let mut list: Vec<(f64, i64, usize, f64)> = (1..=harmonics)
            .map(|k| (1.0 / k as f64, -2 * k as i64, k, 0.3 * k as f64))
            .collect();
        list.push((0.2, 0, 0, 0.0));
        let c = CyclicComponents::from_sector_coordinates(&waves(n, harmonics, &list)).unwrap();
        let m = n / 2;
        for k in 1..=harmonics {
            let s = (-2 * k as i64).rem_euclid(n as i64);
            let (d, forward) = if s == 0 || 2 * s == n as i64 {
                (s as usize, None)
            } else if 2 * s < n as i64 {
                (s as usize, Some(true))
            } else {
                ((n as i64 - s) as usize, Some(false))
            };
            let amplitude = 1.0 / k as f64;
            let (expected, other) = match forward {
                Some(true) => (c.forward[k][d], c.backward[k][d]),
                Some(false) => (c.backward[k][d], c.forward[k][d]),
                None => (c.forward[k][d] + c.backward[k][d], 0.0),
            };
            assert!(
                (expected - amplitude).abs() < 1e-13,
                "N={n} k={k}: {expected} vs {amplitude}"
            );
            assert!(
                other < 1e-12 * amplitude,
                "N={n} k={k}: other direction {other:e}"
            );
            for e in 0..=m {
                if e != d {
                    let rest = c.forward[k][e].max(c.backward[k][e]);
                    assert!(rest < 1e-12 * amplitude, "N={n} k={k} d={e}: {rest:e}");
                }
            }
        }
        assert!((c.forward[0][0] + c.backward[0][0] - 0.2).abs() < 1e-14);
    }
}

#[test]
fn a_standing_wave_is_equal_forward_and_backward() {
    for n in [8, 9, 24] {
        // A cos(dαj) cos(kωt) = A/2 cos(kωt − dαj) + A/2 cos(kωt + dαj).
        let (a, d, k) = (2.0, 3_i64, 2);
        let c = CyclicComponents::from_sector_coordinates(&waves(
            n,
            3,
            &[(a / 2.0, d, k, 0.4), (a / 2.0, -d, k, 0.4)],
        ))
        .unwrap();
        let (f, b) = (c.forward[k][d as usize], c.backward[k][d as usize]);
        assert!(
            (f - a / 2.0).abs() < 1e-14 && (b - a / 2.0).abs() < 1e-14,
            "N={n}: {f} {b}"
        );
        assert!((f - b).abs() < 1e-14 * a);
        // Diameter N/2 (even N) and 0 are standing by nature: half and half.
        if n % 2 == 0 {
            let c = CyclicComponents::from_sector_coordinates(&waves(
                n,
                1,
                &[(1.0, n as i64 / 2, 1, 0.0)],
            ))
            .unwrap();
            assert!(
                (c.forward[1][n / 2] - 0.5).abs() < 1e-14
                    && (c.backward[1][n / 2] - 0.5).abs() < 1e-14
            );
        }
    }
}

#[test]
fn a_solved_traveling_wave_shows_the_zigzag_pairs_only() {
    // The paper's Fig. 6 on the reduced run: (−k, k) on each harmonic.
    let traveling = case(
        r#"
[harmonic_balance]
harmonics = 5
time_samples = 240
"#,
    );
    let (prepared, points) = solve(&traveling, BasisChoice::Symmetry, 1, &[0.98, 0.99, 1.0]);
    let q = points.last().unwrap();
    let all: Vec<usize> = (0..24).collect();
    let h = dof_histories(&prepared.problem, &q.unknowns, q.omega, 0, &all, 240).unwrap();
    let coordinates: Vec<Vec<f64>> = h.iter().map(|h| h.coordinates.clone()).collect();
    let c = CyclicComponents::from_sector_coordinates(&coordinates).unwrap();
    for k in 1..=5 {
        let pair = c.backward[k][k];
        let rest = (0..=12)
            .flat_map(|d| [c.forward[k][d], if d == k { 0.0 } else { c.backward[k][d] }])
            .fold(0.0, f64::max);
        assert!(
            pair > 0.0 && rest < 1e-12 * pair,
            "k={k}: pair {pair:e}, rest {rest:e}"
        );
    }
}

fn scratch(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("cyclorub-results-{}-{name}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

/// The results data of a short standing-wave run at fixed frequencies,
/// through the library's front door.
fn standing_data() -> ResultsData {
    let mut standing = case(STANDING);
    standing.continuation.tolerance = 1e-11;
    standing.continuation.max_iterations = 60;
    let prepared = prepare(&standing, Path::new("."), BasisChoice::Symmetry).expect("prepare");
    let f = prepared.model.natural_frequencies().expect("modes")[1].1[0];
    let solution = ForcedResponse::from_case(&standing)
        .expect("case")
        .basis(BasisChoice::Symmetry)
        .at_frequencies_hz([0.97, 0.985, 0.995, 1.0].iter().map(|x| x * f).collect())
        .build()
        .expect("build")
        .run(&mut [])
        .expect("run");
    for p in &solution.branch.points {
        assert!(p.converged, "not converged at {} Hz", p.omega / 2.0 / PI);
    }
    solution.results_data().expect("results data")
}

#[test]
fn hdf5_round_trip_in_rust_and_with_h5py() {
    let data = standing_data();
    assert_eq!(data.points.len(), 4);
    assert!(data.histories.is_some());
    assert!(data.points.iter().any(|p| p.sectors_in_contact > 0));
    let dir = scratch("hdf5");
    let path = dir.join(hdf5::FILE_NAME);
    hdf5::write(&path, &data).unwrap();
    let back = hdf5::read(&path).unwrap();
    assert_eq!(back, data);
    // A branch with a gap keeps it.
    let gapped = ResultsData {
        gap_after: Some(1),
        ..data.clone()
    };
    let gapped_path = dir.join("gapped.h5");
    hdf5::write(&gapped_path, &gapped).unwrap();
    assert_eq!(hdf5::read(&gapped_path).unwrap().gap_after, Some(1));
    assert_eq!(gapped.converged_breaks(), vec![2]);
    branches_round_trip(&gapped_path, &gapped);
    // The same file read by h5py (the HDF5 C library), when Python has it.
    let script = r#"
import sys, json, h5py
f = h5py.File(sys.argv[1], "r")
assert f.attrs["format"] == "cyclorub results", f.attrs["format"]
case = json.loads(f.attrs["case_json"])
p = f["branch/frequency_hz"].shape[0]
n = int(f.attrs["sectors"])
print(json.dumps({
    "sectors": case["model"]["sectors"],
    "points": p,
    "amplitude": f["branch/observed/amplitude"][()].tolist(),
    "coordinates_shape": list(f["branch/observed/coordinates"][()].shape),
    "compression": f["branch/observed/coordinates"].compression,
    "status": f.attrs["status"],
    "unknowns": f["branch/unknowns"][()].tolist(),
    "unit": f["branch/observed/amplitude"].attrs["unit"],
    "peak_point": int(f["peak"].attrs["point"]),
    "force_shape": list(f["peak/contact_force"].shape),
}))
"#;
    let Some(v) = read_with_h5py(script, &path) else {
        return;
    };
    assert_eq!(v["sectors"], 8);
    assert_eq!(v["points"], 4);
    assert_eq!(v["unit"], "m");
    assert_eq!(v["coordinates_shape"], serde_json::json!([4, 8, 9]));
    assert_eq!(v["compression"], "gzip");
    assert_eq!(v["status"], "complete");
    for (i, p) in data.points.iter().enumerate() {
        for (j, x) in p.unknowns.iter().enumerate() {
            let read = v["unknowns"][i][j].as_f64().unwrap();
            assert!(
                (read - x).abs() <= 4.0 * f64::EPSILON * x.abs(),
                "unknown {i} {j}"
            );
        }
    }
    assert_eq!(v["force_shape"], serde_json::json!([8, 1, 64]));
    assert_eq!(
        v["peak_point"].as_u64().unwrap() as usize,
        data.peak_point().unwrap()
    );
    for (i, p) in data.points.iter().enumerate() {
        for (j, a) in p.amplitude.iter().enumerate() {
            let read = v["amplitude"][i][j].as_f64().unwrap();
            // JSON text parsed back: equal to the last bits or so.
            assert!(
                (read - a).abs() <= 4.0 * f64::EPSILON * a.abs(),
                "point {i} sector {j}: {read} vs {a}"
            );
        }
    }
}

#[test]
fn hdf5_round_trip_of_a_run_without_points() {
    let mut data = standing_data();
    data.points.clear();
    data.linear = Default::default();
    data.histories = None;
    let dir = scratch("hdf5-empty");
    let path = dir.join(hdf5::FILE_NAME);
    hdf5::write(&path, &data).unwrap();
    assert_eq!(hdf5::read(&path).unwrap(), data);
    // The figures that have something to show are drawn; the others skipped.
    let written = write_figures(&dir.join("plots"), &data, &FigureOptions::default()).unwrap();
    assert_eq!(written.len(), 1, "{written:?}");
}

/// The results file of a killed run (status `running`: points appended,
/// never written whole) gets its branches and stays `running`, its points
/// as the run appended them.
#[test]
fn branches_of_a_killed_run_keep_its_running_status() {
    let data = standing_data();
    let header = ResultsData {
        points: Vec::new(),
        linear: Default::default(),
        histories: None,
        ..data.clone()
    };
    let path = scratch("hdf5-killed").join(hdf5::FILE_NAME);
    let unknowns = data.points[0].unknowns.len();
    let mut appender =
        hdf5::Appender::create(&path, &header, unknowns, hdf5::Contents::ALL).unwrap();
    for point in &data.points[..3] {
        appender.push(point.clone());
    }
    appender.close().unwrap();
    assert_eq!(hdf5::status(&path).unwrap().as_deref(), Some("running"));
    let killed = ResultsData {
        points: data.points[..3].to_vec(),
        ..header
    };
    branches_round_trip(&path, &killed);
    assert_eq!(hdf5::status(&path).unwrap().as_deref(), Some("running"));
}

/// The legend and axis texts of an SVG file, after checking it parses.
fn svg_texts(path: &Path) -> Vec<String> {
    let text = std::fs::read_to_string(path).unwrap();
    let document = roxmltree::Document::parse(&text)
        .unwrap_or_else(|e| panic!("{} is not valid XML: {e}", path.display()));
    assert_eq!(document.root_element().tag_name().name(), "svg");
    document
        .descendants()
        .filter(|n| n.has_tag_name("text"))
        .filter_map(|n| n.text().map(|t| t.trim().to_string()))
        .collect()
}

fn count_tag(path: &Path, tag: &str) -> usize {
    let text = std::fs::read_to_string(path).unwrap();
    let document = roxmltree::Document::parse(&text).unwrap();
    document
        .descendants()
        .filter(|n| n.has_tag_name(tag))
        .count()
}

#[test]
fn figures_are_valid_svg_with_the_expected_series() {
    let data = standing_data();
    let dir = scratch("figures");
    // A reference branch.csv: the same curve on sectors 1 and 2.
    let mut csv = String::from("point,frequency_hz,amplitude_sector_1,amplitude_sector_2,iterations,residual_norm,converged\n");
    for (i, p) in data.points.iter().enumerate() {
        csv.push_str(&format!(
            "{i},{},{},{},3,1e-12,true\n",
            p.frequency_hz, p.amplitude[0], p.amplitude[1]
        ));
    }
    std::fs::write(dir.join("branch.csv"), csv).unwrap();
    let options = FigureOptions {
        sectors: Some(vec![1, 2]),
        point: Some(3),
        reference: Some(Reference {
            label: "reference (physical)".into(),
            branch: BranchTable::read(&dir.join("branch.csv")).unwrap(),
        }),
        relative_floor: 0.0,
        png: false,
        sizes: None,
    };
    let written = write_figures(&dir.join("plots"), &data, &options).unwrap();
    let names: Vec<String> = written
        .iter()
        .map(|p| p.file_name().unwrap().to_string_lossy().into_owned())
        .collect();
    for expected in [
        "forced_response.svg",
        "cyclic_components.svg",
        "first_harmonic_components.svg",
        "frequency_vs_nodal_diameter.svg",
    ] {
        assert!(
            names.contains(&expected.to_string()),
            "{expected} missing from {names:?}"
        );
        assert!(dir.join("plots").join(expected).is_file());
    }
    let texts = svg_texts(&dir.join("plots/forced_response.svg"));
    for label in [
        "sector 1",
        "sector 2",
        "linear, sector 1",
        "linear, sector 2",
        "reference (physical), sector 1",
        "reference (physical), sector 2",
        "frequency (Hz)",
        "amplitude of m1, the blade tip (m)",
    ] {
        assert!(
            texts.iter().any(|t| t == label),
            "{label:?} not in {texts:?}"
        );
    }
    // Two solid curves and the dashes of the reference.
    assert!(count_tag(&dir.join("plots/forced_response.svg"), "polyline") > 4);
    // Standing wave of order 1: diameters 1 (harmonic 1) and its couplings.
    let texts = svg_texts(&dir.join("plots/cyclic_components.svg"));
    assert!(texts.iter().any(|t| t == "ND 1"), "{texts:?}");
    assert!(texts.iter().any(|t| t.starts_with("forward components")));
    assert!(texts.iter().any(|t| t.starts_with("backward components")));
    assert!(texts.iter().any(|t| t == "harmonic k"));
    assert!(count_tag(&dir.join("plots/cyclic_components.svg"), "rect") > 4);
    let texts = svg_texts(&dir.join("plots/first_harmonic_components.svg"));
    assert!(
        texts.iter().any(|t| t == "ND 1 forward") && texts.iter().any(|t| t == "ND 1 backward"),
        "{texts:?}"
    );
    let texts = svg_texts(&dir.join("plots/frequency_vs_nodal_diameter.svg"));
    assert!(texts.iter().any(|t| t == "mode 1"));
    // A sector that does not exist is refused.
    let bad = FigureOptions {
        sectors: Some(vec![9]),
        ..FigureOptions::default()
    };
    assert!(write_figures(&dir.join("bad"), &data, &bad).is_err());
}

/// The `/branches` group round trip, its edge cases included: a side
/// without points (no first point off the branch point), verdicts partly
/// checked, a branch point not switched at (no marker: found by
/// `--class`); added to the file at `path` (holding `data`) by
/// `replace_branches`, the rest of the file kept.
fn branches_round_trip(path: &Path, data: &ResultsData) {
    use cyclorub::results::bifurcated::{BifurcatedBranchData, BifurcatedSide};
    let n = data.sectors;
    let side = |direction: f64, points: usize| BifurcatedSide {
        direction,
        frequency_hz: (0..points).map(|i| 211.25 + 0.01 * i as f64).collect(),
        stable: (0..points).map(|i| (i > 0).then_some(i == 2)).collect(),
        sector_amplitudes_m: (0..points)
            .map(|i| (0..n).map(|j| 1e-3 + 1e-6 * (i * n + j) as f64).collect())
            .collect(),
        stop: serde_json::json!({"reason": "no_first_point", "distance": 1e-4}),
        stop_reason: "in words".into(),
    };
    let switched = BifurcatedBranchData {
        marker: Some(1),
        marker_hz: 211.2469,
        class: 3,
        parent_point: 2,
        branch_point_hz: Some(211.2471),
        basis_unknowns: Some(42),
        full_unknowns: Some(126),
        sides: vec![side(1.0, 3), side(-1.0, 0)],
        file: Some("branches/class3_211.2471Hz.csv".into()),
        not_switched: None,
    };
    let refused = BifurcatedBranchData {
        marker: None,
        marker_hz: 211.6,
        class: 2,
        parent_point: 0,
        branch_point_hz: None,
        basis_unknowns: None,
        full_unknowns: None,
        sides: Vec::new(),
        file: None,
        not_switched: Some("no real multiplier crosses +1".into()),
    };
    let branches = vec![refused, switched];
    let status = hdf5::status(path).unwrap();
    hdf5::replace_branches(path, &branches).unwrap();
    // The file's own status is kept (a killed run's file stays `running`).
    assert_eq!(hdf5::status(path).unwrap(), status);
    let back = hdf5::read(path).unwrap();
    assert_eq!(back.branches, branches);
    assert_eq!(back.points, data.points);
    assert_eq!(back.histories, data.histories);
    assert_eq!(back.gap_after, data.gap_after);
    // Replaced, not added to.
    hdf5::replace_branches(path, &branches[1..]).unwrap();
    assert_eq!(hdf5::read(path).unwrap().branches, branches[1..]);
}
