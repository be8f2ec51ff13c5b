//! The static preload (`[preload]`): a load on every sector alike, solved on
//! harmonic 0.
//! - The centrifugal force of the coarse open fan, solved on the full
//!   sector, against a dense solve written here that holds the cyclic
//!   boundary and the clamp by Lagrange multipliers instead of eliminating
//!   them.
//! - With the gap measured after the preload (the paper's), the solution is
//!   the unloaded one plus the static displacement on harmonic 0; measured
//!   at rest, it is the unloaded one with the gap closed by that growth,
//!   plus the displacement. Both exact for a linear structure, checked on
//!   the reduced basis and on the physical full wheel.

use cyclorub::case::{BasisChoice, Case};
use cyclorub::continuation::{solve_at_frequencies, NewtonSettings};
use cyclorub::hbm::HarmonicBalance;
use cyclorub::mesh::{assemble, fan, write_fan, FanGeometry};
use cyclorub::run::prepare;
use faer::linalg::solvers::Solve;
use faer::Mat;
use std::f64::consts::PI;
use std::path::Path;

/// The unknowns at `omegas`, each point converged.
fn solve(problem: &mut HarmonicBalance, omegas: &[f64]) -> Vec<Vec<f64>> {
    let start = problem.linear_solution(omegas[0]).unwrap();
    let settings = NewtonSettings {
        tolerance: 1e-11,
        max_iterations: 60,
        ..Default::default()
    };
    solve_at_frequencies(problem, start, omegas, &settings, |_, _| {})
        .points
        .into_iter()
        .map(|p| {
            assert!(p.converged, "no convergence at {} Hz", p.omega / 2.0 / PI);
            p.unknowns
        })
        .collect()
}

/// For each unknown, the sector dof it belongs to when it is a harmonic-0
/// coefficient of nodal diameter 0 (or of any sector, on the physical full
/// wheel), divided by the weight that turns a sector displacement into it.
fn static_slots(problem: &HarmonicBalance) -> Vec<Option<(usize, f64)>> {
    let layout = problem.layout();
    let mut slots = vec![None; layout.unknowns];
    for block in layout.blocks.iter().filter(|b| b.harmonic == 0) {
        if let cyclorub::hbm::layout::BlockKind::Pair { nodal_diameter } = block.kind {
            if nodal_diameter != 0 {
                continue;
            }
        }
        for (i, slot) in block.slots.iter().enumerate() {
            slots[slot.re] = Some((i % layout.contact_dofs, 1.0));
        }
    }
    slots
}

/// The largest difference between `with` and `without` shifted by the
/// static displacement `shift` (per condensed dof) on the harmonic-0 slots,
/// relative to the largest unknown.
fn shifted_difference(
    problem: &HarmonicBalance,
    with: &[Vec<f64>],
    without: &[Vec<f64>],
    shift: &[f64],
) -> f64 {
    let slots = static_slots(problem);
    let mut worst = 0.0_f64;
    let mut scale = 0.0_f64;
    for (a, b) in with.iter().zip(without) {
        for (i, (x, y)) in a.iter().zip(b).enumerate() {
            let expected = y + slots[i].map_or(0.0, |(d, w)| w * shift[d]);
            worst = worst.max((x - expected).abs());
            scale = scale.max(x.abs());
        }
    }
    worst / scale
}

/// The academic chain (N = 6), traveling wave h = 1, R-HBM, a static force
/// on every dof that moves the blade tip toward the casing.
fn academic() -> Case {
    let mut case = Case::default();
    case.model.sectors = 6;
    case.harmonic_balance.harmonics = 4;
    case.harmonic_balance.time_samples = 48;
    case.casing.gap = cyclorub::case::PerContactDof::One(4e-4);
    case
}

#[test]
fn a_preload_measured_after_shifts_the_solution_on_harmonic_0_only() {
    let dir = Path::new(".");
    let base = academic();
    let mut loaded = base.clone();
    let dofs = prepare(&base, dir, BasisChoice::Symmetry)
        .unwrap()
        .model
        .dofs_per_sector();
    loaded.preload.static_forces = (0..dofs).map(|d| 30.0 + 5.0 * d as f64).collect();
    let model = prepare(&loaded, dir, BasisChoice::Symmetry).unwrap().model;
    let growth = model
        .static_response(&loaded.preload.static_forces, "preload")
        .unwrap();
    let contact = base.contact_dofs()[0];
    assert!(growth[contact] > 1e-5, "tip growth {:e}", growth[contact]);
    let first = prepare(&base, dir, BasisChoice::Symmetry)
        .unwrap()
        .case
        .continuation
        .start_hz
        .unwrap()
        / 0.95;
    let omegas: Vec<f64> = [0.97, 0.99, 1.0, 1.01, 1.02]
        .iter()
        .map(|f| 2.0 * PI * first * f)
        .collect();
    for basis in [BasisChoice::Symmetry, BasisChoice::Physical] {
        let mut without = prepare(&base, dir, basis).unwrap().problem;
        let mut with = prepare(&loaded, dir, basis).unwrap().problem;
        let (a, b) = (solve(&mut with, &omegas), solve(&mut without, &omegas));
        let touching = b
            .iter()
            .zip(&omegas)
            .filter(|(x, w)| {
                without
                    .contact_samples(x, **w)
                    .unwrap()
                    .penetration
                    .iter()
                    .flatten()
                    .any(|&p| p > 0.0)
            })
            .count();
        assert!(touching >= 2, "{basis:?}: only {touching} points touch");
        let difference = shifted_difference(&with, &a, &b, &[growth[contact]]);
        println!("{basis:?}: measured after the preload, difference {difference:e}");
        assert!(difference < 1e-9, "{basis:?}: {difference:e}");
    }
}

#[test]
fn a_preload_measured_at_rest_closes_the_gap_by_the_tip_growth() {
    let dir = Path::new(".");
    let mut cold = academic();
    let dofs = prepare(&cold, dir, BasisChoice::Symmetry)
        .unwrap()
        .model
        .dofs_per_sector();
    cold.preload.static_forces = vec![20.0; dofs];
    cold.casing.gap_after_preload = false;
    let prepared = prepare(&cold, dir, BasisChoice::Symmetry).unwrap();
    let growth = prepared
        .model
        .static_response(&cold.preload.static_forces, "preload")
        .unwrap()[cold.contact_dofs()[0]];
    let mut closed = academic();
    closed.casing.gap = cyclorub::case::PerContactDof::One(4e-4 - growth);
    assert!(growth > 1e-5 && growth < 4e-4, "tip growth {growth:e}");
    let first = prepared.case.continuation.start_hz.unwrap() / 0.95;
    let omegas: Vec<f64> = [0.98, 1.0, 1.02]
        .iter()
        .map(|f| 2.0 * PI * first * f)
        .collect();
    let mut with = prepared.problem;
    let mut without = prepare(&closed, dir, BasisChoice::Symmetry)
        .unwrap()
        .problem;
    let (a, b) = (solve(&mut with, &omegas), solve(&mut without, &omegas));
    let difference = shifted_difference(&with, &a, &b, &[growth]);
    println!("measured at rest: difference {difference:e}");
    assert!(difference < 1e-9, "{difference:e}");
}

#[test]
fn a_wrong_preload_is_refused_with_its_key() {
    let dir = Path::new(".");
    let mut case = academic();
    case.preload.static_forces = vec![1.0; 2];
    let error = prepare(&case, dir, BasisChoice::Symmetry).err().unwrap();
    assert!(
        error.to_string().contains("preload.static_forces"),
        "{error}"
    );
    let mut case = academic();
    case.preload.centrifugal = true;
    case.rotation.speed = Some(100.0);
    let error = prepare(&case, dir, BasisChoice::Symmetry).err().unwrap();
    assert!(
        error.to_string().contains("preload.centrifugal")
            && error.to_string().contains("finite_element"),
        "{error}"
    );
    let mut case = academic();
    case.preload.centrifugal = true;
    let error = prepare(&case, dir, BasisChoice::Symmetry).err().unwrap();
    assert!(error.to_string().contains("preload.speed"), "{error}");
}

/// The coarse fan's centrifugal preload at the paper's 1151.9 rad/s, by a
/// dense solve with Lagrange multipliers: `[K Cᵀ; C 0] [u; λ] = [f; 0]`,
/// `C` holding the clamped dofs at 0 and each right boundary node at the
/// rotation `R(α)` of its left twin (nodal diameter 0), `f = Ω² M r⊥`
/// from the mesh's own coordinates.
#[test]
fn the_centrifugal_preload_is_the_full_sectors_static_response() {
    let dir = std::env::temp_dir().join(format!("cyclorub-preload-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    let mesh = fan(16, 1, &FanGeometry::default()).unwrap();
    let matrices = assemble(&mesh.mesh).unwrap();
    write_fan(&mesh, &matrices, &dir, false).unwrap();
    let case = Case::from_file_checked(&dir.join("fan16.toml")).unwrap();
    let speed = 1151.9;
    let model = case.model.build(&dir).unwrap();
    let preload = case.model.centrifugal_preload(&dir, &model, speed).unwrap();
    // Kept next to the case, per unit speed: read back at once, and the
    // same bits; at another speed scaled by Ω²; a damaged file is
    // recomputed.
    let cached: Vec<_> = std::fs::read_dir(dir.join(".cyclorub-cache"))
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| p.to_string_lossy().contains("centrifugal-"))
        .collect();
    assert_eq!(cached.len(), 1, "{cached:?}");
    assert_eq!(
        case.model.centrifugal_preload(&dir, &model, speed).unwrap(),
        preload
    );
    let half = case
        .model
        .centrifugal_preload(&dir, &model, speed / 2.0)
        .unwrap();
    for (a, b) in half.displacements.iter().zip(&preload.displacements) {
        assert!(
            (4.0 * a - b).abs() <= 1e-14 * b.abs().max(1e-12),
            "{a:e} {b:e}"
        );
    }
    let mut bytes = std::fs::read(&cached[0]).unwrap();
    let middle = bytes.len() / 2;
    bytes[middle] ^= 1;
    std::fs::write(&cached[0], bytes).unwrap();
    assert_eq!(
        case.model.centrifugal_preload(&dir, &model, speed).unwrap(),
        preload
    );

    let nodes = &mesh.mesh.nodes;
    let n = 3 * nodes.len();
    let dense = |m: &cyclorub::mesh::SymmetricMatrix| {
        let mut a = Mat::<f64>::zeros(n, n);
        for j in 0..n {
            for p in m.starts[j]..m.starts[j + 1] {
                a[(m.rows[p], j)] = m.values[p];
                a[(j, m.rows[p])] = m.values[p];
            }
        }
        a
    };
    let (k, m) = (dense(&matrices.stiffness), dense(&matrices.mass));
    let away: Vec<f64> = nodes.iter().flat_map(|p| [p[0], p[1], 0.0]).collect();
    let force: Vec<f64> = (0..n)
        .map(|r| speed * speed * (0..n).map(|c| m[(r, c)] * away[c]).sum::<f64>())
        .collect();
    let sets = &mesh.sets;
    let mut rows: Vec<Vec<(usize, f64)>> = Vec::new();
    let clamped: Vec<usize> = sets
        .clamped
        .iter()
        .flat_map(|&c| [3 * c, 3 * c + 1, 3 * c + 2])
        .collect();
    for &d in &clamped {
        rows.push(vec![(d, 1.0)]);
    }
    let (s, c) = (2.0 * PI / 16.0).sin_cos();
    let rotation = [[c, -s, 0.0], [s, c, 0.0], [0.0, 0.0, 1.0]];
    for (&l, &r) in sets.left_boundary.iter().zip(&sets.right_boundary) {
        for (i, row) in rotation.iter().enumerate() {
            if clamped.contains(&(3 * r + i)) {
                continue;
            }
            let mut entries = vec![(3 * r + i, 1.0)];
            entries.extend((0..3).map(|e| (3 * l + e, -row[e])));
            rows.push(entries);
        }
    }
    let size = n + rows.len();
    let mut system = Mat::<f64>::zeros(size, size);
    for i in 0..n {
        for j in 0..n {
            system[(i, j)] = k[(i, j)];
        }
    }
    for (q, entries) in rows.iter().enumerate() {
        for &(d, v) in entries {
            system[(n + q, d)] = v;
            system[(d, n + q)] = v;
        }
    }
    let rhs = Mat::from_fn(size, 1, |r, _| if r < n { force[r] } else { 0.0 });
    let u = system.partial_piv_lu().solve(&rhs);

    // The retained dofs as the model labels them: "node N x|y|z", or the
    // contact nodes' "node N r|θ|z" in their cylindrical frames.
    let mut worst = 0.0_f64;
    let mut largest = 0.0_f64;
    let mut compared = 0;
    for dof in 0..model.dofs_per_sector() {
        let label = model.dof_label(dof);
        let Some(rest) = label.strip_prefix("node ") else {
            assert_eq!(preload.displacements[dof], 0.0, "{label}");
            continue;
        };
        let (node, direction) = rest.split_once(' ').unwrap();
        let node: usize = node.parse::<usize>().unwrap() - 1;
        let v = [u[(3 * node, 0)], u[(3 * node + 1, 0)], u[(3 * node + 2, 0)]];
        let [x, y, _] = nodes[node];
        let radius = x.hypot(y);
        let expected = match direction {
            "x" => v[0],
            "y" => v[1],
            "z" => v[2],
            "r" => (x * v[0] + y * v[1]) / radius,
            "θ" => (-y * v[0] + x * v[1]) / radius,
            other => panic!("unknown direction {other}"),
        };
        worst = worst.max((preload.displacements[dof] - expected).abs());
        largest = largest.max(expected.abs());
        compared += 1;
    }
    println!(
        "centrifugal preload: {compared} retained dofs, largest static displacement {largest:e} m, \
         difference {:e}",
        worst / largest
    );
    assert!(
        largest > 1e-6,
        "the preload barely moves the fan: {largest:e} m"
    );
    assert!(worst < 1e-9 * largest, "difference {:e}", worst / largest);
    // The force given to the reduced model gives it that static response.
    let back = model.static_response(&preload.forces, "preload").unwrap();
    for (a, b) in back.iter().zip(&preload.displacements) {
        assert!((a - b).abs() < 1e-9 * largest, "{a:e} against {b:e}");
    }
    let _ = std::fs::remove_dir_all(&dir);
}

/// The continuation follows the same branch, point for point, with a
/// preload measured after it: its steps are scaled by the clearance, not by
/// the gap from rest that the problem holds.
#[test]
fn a_preload_measured_after_leaves_the_continuation_unchanged() {
    let mut base = academic();
    base.continuation.max_points = 60;
    let mut loaded = base.clone();
    loaded.preload.static_forces = vec![25.0; 5];
    let run = |case: &Case| {
        cyclorub::forced_response::ForcedResponse::from_case(case)
            .unwrap()
            .build()
            .unwrap()
            .run(&mut [])
            .unwrap()
            .branch
    };
    let (a, b) = (run(&base), run(&loaded));
    assert_eq!(a.points.len(), b.points.len());
    let worst = a
        .points
        .iter()
        .zip(&b.points)
        .map(|(p, q)| ((p.omega - q.omega) / p.omega).abs())
        .fold(0.0, f64::max);
    println!("{} points, frequencies within {worst:e}", a.points.len());
    assert!(worst < 1e-9, "{worst:e}");
}
