//! Craig–Bampton per nodal diameter on the coarse open fan (`refine 1`)
//! against the full sector, solved densely: the per-diameter matrices
//! built here independently (`T(s)ᴴ K T(s)` with `u_R = e^{−iαs} R(α) u_L`,
//! the sign convention of `model/mod.rs`), the static response at the
//! retained dofs, and the first bending frequency of every diameter; the
//! reduced sector as a sector model (modal damping by mode index, the full
//! wheel), the cache of reduced models, and the full sector's sparse
//! frequencies (the reference `cyclorub modes` shows) against the dense ones.

use cyclorub::mesh::{assemble, fan, FanGeometry, FanMesh, SymmetricMatrix};
use cyclorub::model::craig_bampton::{
    craig_bampton, craig_bampton_cached, craig_bampton_nodal_diameter, full_sector_frequencies,
    reduced_sector_model, CacheOutcome, CraigBamptonSettings, InputDigest, ReductionCache,
    ReductionError, SparseSector,
};
use cyclorub::model::{Axis, BoundaryFrame, Damping, ModalDamping};
use faer::linalg::solvers::Solve;
use faer::sparse::{SparseColMat, Triplet};
use faer::{c64, Mat, Side};

const SECTORS: usize = 16;

/// A real symmetric matrix stored by its lower triangle, as faer's sparse
/// matrix with both triangles.
fn full_storage(a: &SymmetricMatrix) -> SparseColMat<usize, f64> {
    let triplets: Vec<Triplet<usize, usize, f64>> = a
        .entries()
        .flat_map(|(i, j, v)| {
            let mirror = (i != j).then(|| Triplet::new(j, i, v));
            std::iter::once(Triplet::new(i, j, v)).chain(mirror)
        })
        .collect();
    SparseColMat::try_new_from_triplets(a.size, a.size, &triplets).unwrap()
}

/// The 3 dofs of each node.
fn node_dofs(nodes: &[usize]) -> Vec<usize> {
    nodes
        .iter()
        .flat_map(|&n| (0..3).map(move |d| 3 * n + d))
        .collect()
}

struct Case {
    fan: FanMesh,
    mass: SymmetricMatrix,
    stiffness: SymmetricMatrix,
    sector: SparseSector,
    retained: Vec<usize>,
}

/// The coarse fan with its contact, excitation and observation nodes
/// retained (33 dofs).
fn case() -> Case {
    let fan = fan(SECTORS, 1, &FanGeometry::default()).unwrap();
    let matrices = assemble(&fan.mesh).unwrap();
    let mut retained_nodes = fan.sets.contact.clone();
    retained_nodes.push(fan.sets.excitation);
    retained_nodes.push(fan.sets.observation);
    let sector = SparseSector {
        mass: full_storage(&matrices.mass),
        stiffness: full_storage(&matrices.stiffness),
        clamped: node_dofs(&fan.sets.clamped),
        left_boundary: node_dofs(&fan.sets.left_boundary),
        right_boundary: node_dofs(&fan.sets.right_boundary),
        boundary_frame: BoundaryFrame::Cartesian { axis: Axis::Z },
        sectors: SECTORS,
        symmetry_tolerance: 1e-10,
    };
    Case {
        retained: node_dofs(&retained_nodes),
        fan,
        mass: matrices.mass,
        stiffness: matrices.stiffness,
        sector,
    }
}

/// The oracle: dense `K(s)`, `M(s)` on the kept dofs in ascending order
/// (not clamped, not on the right face), and the row of each sector dof.
fn dense_full_sector(case: &Case, s: i64) -> (Mat<c64>, Mat<c64>, Vec<usize>) {
    let fan = &case.fan;
    let nodes = fan.mesh.nodes.len();
    let mut clamped = vec![false; nodes];
    for &n in &fan.sets.clamped {
        clamped[n] = true;
    }
    let mut twin = vec![None; nodes];
    for (&l, &r) in fan.sets.left_boundary.iter().zip(&fan.sets.right_boundary) {
        twin[r] = Some(l);
    }
    let mut row = vec![usize::MAX; 3 * nodes];
    let mut size = 0;
    for n in (0..nodes).filter(|&n| !clamped[n] && twin[n].is_none()) {
        for d in 0..3 {
            row[3 * n + d] = size;
            size += 1;
        }
    }
    let alpha = 2.0 * std::f64::consts::PI / SECTORS as f64;
    let (sa, ca) = alpha.sin_cos();
    let rotation = [[ca, -sa, 0.0], [sa, ca, 0.0], [0.0, 0.0, 1.0]];
    let phase = c64::new((alpha * s as f64).cos(), -(alpha * s as f64).sin());
    let map: Vec<Vec<(usize, c64)>> = (0..3 * nodes)
        .map(|dof| {
            let (n, d) = (dof / 3, dof % 3);
            match (clamped[n], twin[n]) {
                (true, _) => vec![],
                (false, None) => vec![(row[dof], c64::new(1.0, 0.0))],
                (false, Some(l)) => (0..3)
                    .filter(|&e| !clamped[l] && rotation[d][e] != 0.0)
                    .map(|e| (row[3 * l + e], phase * rotation[d][e]))
                    .collect(),
            }
        })
        .collect();
    let reduce = |a: &SymmetricMatrix| {
        let mut out = Mat::<c64>::zeros(size, size);
        let mut add = |i: usize, j: usize, v: f64| {
            for &(p, tp) in &map[i] {
                for &(q, tq) in &map[j] {
                    out[(p, q)] += tp.conj() * tq * v;
                }
            }
        };
        for (i, j, v) in a.entries() {
            add(i, j, v);
            if i != j {
                add(j, i, v);
            }
        }
        out
    };
    (reduce(&case.stiffness), reduce(&case.mass), row)
}

/// The eigenvalues of the dense pencil `(K, M)`, ascending.
fn dense_eigenvalues(k: &Mat<c64>, m: &Mat<c64>) -> Vec<f64> {
    let n = k.nrows();
    let l = m.llt(Side::Lower).unwrap();
    let l = l.L();
    let mut y = k.clone();
    l.solve_lower_triangular_in_place(y.as_mut());
    let mut a: Mat<c64> = y.adjoint().to_owned();
    l.solve_lower_triangular_in_place(a.as_mut());
    let a = Mat::from_fn(n, n, |i, j| (a[(i, j)] + a[(j, i)].conj()) * 0.5);
    let mut values = a.self_adjoint_eigenvalues(Side::Lower).unwrap();
    values.sort_by(f64::total_cmp);
    values
}

/// The lowest eigenvalue of the dense pencil `(K, M)`.
fn lowest_eigenvalue(k: &Mat<c64>, m: &Mat<c64>) -> f64 {
    dense_eigenvalues(k, m)[0]
}

fn hertz(eigenvalue: f64) -> f64 {
    eigenvalue.sqrt() / (2.0 * std::f64::consts::PI)
}

/// A load on every retained dof, different from dof to dof.
fn boundary_load(b: usize) -> Mat<c64> {
    Mat::from_fn(b, 1, |i, _| {
        c64::new(1.0 + (i % 7) as f64, 0.5 * ((i % 3) as f64 - 1.0))
    })
}

#[test]
fn the_static_response_at_the_retained_dofs_is_the_full_sectors_on_every_diameter() {
    let case = case();
    let settings = CraigBamptonSettings {
        retained: case.retained.clone(),
        internal_modes: 5,
    };
    let b = case.retained.len();
    let load = boundary_load(b);
    let reduced = craig_bampton(&case.sector, &settings).unwrap();
    assert_eq!(reduced.len(), SECTORS / 2 + 1);
    let mut worst = 0.0_f64;
    for r in &reduced {
        let s = r.nodal_diameter;
        let (k, _, row) = dense_full_sector(&case, s);
        let mut full_load = Mat::<c64>::zeros(k.nrows(), 1);
        for (i, &dof) in case.retained.iter().enumerate() {
            full_load[(row[dof], 0)] = load[(i, 0)];
        }
        let full = k.partial_piv_lu().solve(&full_load);
        let mut reduced_load = Mat::<c64>::zeros(r.stiffness.nrows(), 1);
        for i in 0..b {
            reduced_load[(i, 0)] = load[(i, 0)];
        }
        let ours = r.stiffness.partial_piv_lu().solve(&reduced_load);
        let scale = (0..b)
            .map(|i| full[(row[case.retained[i]], 0)].norm())
            .fold(0.0, f64::max);
        let error = (0..b)
            .map(|i| (ours[(i, 0)] - full[(row[case.retained[i]], 0)]).norm())
            .fold(0.0, f64::max)
            / scale;
        println!("ND {s}: static response, relative difference {error:.2e}");
        worst = worst.max(error);
        assert!(error <= 1e-9, "ND {s}: {error:e}");
    }
    println!("worst: {worst:.2e}");
}

#[test]
fn the_first_bending_frequency_of_every_diameter_converges_with_the_internal_modes() {
    let case = case();
    for s in 0..=(SECTORS as i64 / 2) {
        let (k, m, _) = dense_full_sector(&case, s);
        let full = hertz(lowest_eigenvalue(&k, &m));
        let mut errors = Vec::new();
        for modes in [5, 10, 20] {
            let settings = CraigBamptonSettings {
                retained: case.retained.clone(),
                internal_modes: modes,
            };
            let r = craig_bampton_nodal_diameter(&case.sector, &settings, s).unwrap();
            let ours = hertz(lowest_eigenvalue(&r.stiffness, &r.mass));
            // A Ritz projection: never below the full sector's frequency.
            assert!(
                ours >= full * (1.0 - 1e-10),
                "ND {s}, {modes} modes: {ours} < {full} Hz"
            );
            errors.push((ours - full) / full);
        }
        println!("ND {s}: full sector {full:.4} Hz, relative error at 5/10/20 modes {:.2e} {:.2e} {:.2e}", errors[0], errors[1], errors[2]);
        assert!(
            errors[1] <= errors[0] && errors[2] <= errors[1],
            "ND {s}: {errors:?}"
        );
        // The issue asks 1e-4; measured at most 6.3e-6 (ND 1).
        assert!(errors[2] <= 1e-5, "ND {s}: {errors:?}");
    }
}

/// The reference of `cyclorub modes` on a finite-element case: the full
/// sector's lowest frequencies per diameter by the sparse solver (sparse
/// `K(s)`, Cholesky, subspace iteration) equal the dense pencil's of the
/// independently built `K(s)`, `M(s)`, mode by mode, on every diameter
/// (real at 0 and N/2, complex between). Measured: at most 6.4e-10 (the
/// subspace iteration stops when the eigenvalues change by < 1e-12).
#[test]
fn the_full_sector_frequencies_are_the_dense_full_sectors_on_every_diameter() {
    let case = case();
    let count = 4;
    let sparse = full_sector_frequencies(&case.sector, count).unwrap();
    assert_eq!(sparse.len(), SECTORS / 2 + 1);
    let mut worst = 0.0_f64;
    for (d, frequencies) in &sparse {
        assert_eq!(frequencies.len(), count, "ND {d}");
        let (k, m, _) = dense_full_sector(&case, *d as i64);
        let dense: Vec<f64> = dense_eigenvalues(&k, &m)[..count]
            .iter()
            .map(|&v| hertz(v))
            .collect();
        for (mode, (ours, theirs)) in frequencies.iter().zip(&dense).enumerate() {
            let error = (ours - theirs).abs() / theirs;
            worst = worst.max(error);
            assert!(
                error <= 1e-8,
                "ND {d}, mode {}: sparse {ours} Hz, dense {theirs} Hz",
                mode + 1
            );
        }
    }
    println!("worst relative difference, sparse against dense: {worst:.1e}");
    // Zero or too many frequencies are refused, naming the count.
    let kept = dense_full_sector(&case, 0).0.nrows();
    for bad in [0, kept + 1] {
        let e = full_sector_frequencies(&case.sector, bad).unwrap_err();
        assert!(
            e.to_string()
                .contains(&format!("full-sector modes: {bad} is not allowed")),
            "{e}"
        );
    }
}

#[test]
fn an_indefinite_stiffness_is_refused_naming_the_diameter() {
    let mut case = case();
    for v in case.sector.stiffness.val_mut() {
        *v = -*v;
    }
    let settings = CraigBamptonSettings {
        retained: case.retained.clone(),
        internal_modes: 3,
    };
    let error = craig_bampton_nodal_diameter(&case.sector, &settings, 2).unwrap_err();
    assert!(
        matches!(
            error,
            ReductionError::NotPositiveDefinite {
                nodal_diameter: 2,
                ..
            }
        ),
        "{error}"
    );
    println!("{error}");
}

#[test]
fn a_retained_dof_on_the_right_boundary_or_an_asymmetric_matrix_is_refused() {
    let mut case = case();
    let right = case.sector.right_boundary[4];
    let settings = CraigBamptonSettings {
        retained: vec![case.retained[0], right],
        internal_modes: 3,
    };
    let error = craig_bampton_nodal_diameter(&case.sector, &settings, 1).unwrap_err();
    assert!(
        error.to_string().starts_with("retained dofs[2]: dof"),
        "{error}"
    );
    // One off-diagonal entry changed on one side only.
    let col_ptr = case.sector.stiffness.symbolic().col_ptr().to_vec();
    let rows = case.sector.stiffness.symbolic().row_idx().to_vec();
    let p = (col_ptr[10]..col_ptr[11]).find(|&p| rows[p] != 10).unwrap();
    case.sector.stiffness.val_mut()[p] *= 1.01;
    let settings = CraigBamptonSettings {
        retained: case.retained.clone(),
        internal_modes: 3,
    };
    let error = craig_bampton_nodal_diameter(&case.sector, &settings, 1).unwrap_err();
    assert!(
        matches!(error, ReductionError::NotSymmetric { row, col, .. } if row == 11 || col == 11),
        "{error}"
    );
}

/// The paper's modal damping: 1e-3 on the first five modes, 5e-3 beyond.
fn paper_damping() -> Damping {
    Damping::Modal(ModalDamping {
        ratios: vec![1e-3; 5],
        others: 5e-3,
    })
}

/// Eigenvalues (ascending) and `M`-orthonormal modes of a dense pencil.
fn dense_modes(k: &Mat<c64>, m: &Mat<c64>) -> (Vec<f64>, Mat<c64>) {
    let n = k.nrows();
    let l = m.llt(Side::Lower).unwrap();
    let l = l.L();
    let mut y = k.clone();
    l.solve_lower_triangular_in_place(y.as_mut());
    let mut a: Mat<c64> = y.adjoint().to_owned();
    l.solve_lower_triangular_in_place(a.as_mut());
    let a = Mat::from_fn(n, n, |i, j| (a[(i, j)] + a[(j, i)].conj()) * 0.5);
    let eig = a.self_adjoint_eigen(Side::Lower).unwrap();
    let values = (0..n).map(|i| eig.S()[i].re).collect();
    let mut phi = eig.U().to_owned();
    l.adjoint().solve_upper_triangular_in_place(phi.as_mut());
    (values, phi)
}

/// Eigenvalues (ascending) of a real symmetric dense pencil.
fn real_eigenvalues(k: &Mat<f64>, m: &Mat<f64>) -> Vec<f64> {
    let n = k.nrows();
    let l = m.llt(Side::Lower).unwrap();
    let l = l.L();
    let mut y = k.clone();
    l.solve_lower_triangular_in_place(y.as_mut());
    let mut a: Mat<f64> = y.transpose().to_owned();
    l.solve_lower_triangular_in_place(a.as_mut());
    let a = Mat::from_fn(n, n, |i, j| (a[(i, j)] + a[(j, i)]) * 0.5);
    a.self_adjoint_eigenvalues(Side::Lower).unwrap()
}

#[test]
fn the_reduced_sector_model_keeps_the_first_family_and_damps_by_mode_index() {
    let case = case();
    let settings = CraigBamptonSettings {
        retained: case.retained.clone(),
        internal_modes: 20,
    };
    let reduced = craig_bampton(&case.sector, &settings).unwrap();
    let model = reduced_sector_model(SECTORS, &settings, &reduced, paper_damping()).unwrap();
    assert_eq!(model.dofs_per_sector(), 33 + 20);
    assert_eq!(model.dof_label(0), format!("dof {}", case.retained[0] + 1));
    assert_eq!(model.dof_label(33), "mode 1");
    // The first family against the dense full sector.
    let frequencies = model.natural_frequencies().unwrap();
    for d in [0usize, 3, 8] {
        let (k, m, _) = dense_full_sector(&case, d as i64);
        let full = hertz(lowest_eigenvalue(&k, &m));
        let ours = frequencies[d].1[0];
        assert!(
            (ours - full).abs() <= 1e-5 * full,
            "ND {d}: {ours} vs {full} Hz"
        );
    }
    // Modal damping: Φᴴ C(s) Φ = diag(2 ξ_r ω_r) with the reduced model's
    // own modes, ξ = 1e-3 on the first five, 5e-3 beyond (s and −s alike).
    for s in [3i64, -3, 8] {
        let matrices = model.nodal_diameter_matrices(s).unwrap();
        let (values, phi) = dense_modes(&matrices.stiffness, &matrices.mass);
        let modal = phi.adjoint() * &matrices.damping * &phi;
        for r in 0..8 {
            let ratio = if r < 5 { 1e-3 } else { 5e-3 };
            let expected = 2.0 * ratio * values[r].sqrt();
            assert!(
                (modal[(r, r)].re - expected).abs() <= 1e-8 * expected,
                "ND {s}, mode {r}: {} vs {expected}",
                modal[(r, r)]
            );
            assert!(modal[(r, (r + 1) % 8)].norm() <= 1e-8 * expected, "ND {s}");
        }
    }
    // The full wheel assembled from the per-diameter matrices: its lowest
    // frequencies are the union of the diameters' (0, then 8, then 7 twice).
    // (Values only: faer 0.24's `self_adjoint_eigen` with vectors, real or
    // complex, solves this 848-row pencil by divide and conquer and gets
    // the lowest value 1e-5 to 7e-4 off; `model::eigen` avoids it.)
    let wheel = model.full_wheel().unwrap();
    let values = real_eigenvalues(&wheel.stiffness, &wheel.mass);
    let expected = [
        frequencies[0].1[0],
        frequencies[8].1[0],
        frequencies[7].1[0],
        frequencies[7].1[0],
    ];
    for (v, e) in values.iter().zip(expected) {
        assert!((hertz(*v) - e).abs() <= 1e-9 * e, "{} vs {e} Hz", hertz(*v));
    }
}

#[test]
fn a_second_reduction_reads_the_cache_and_a_corrupt_or_stale_file_is_recomputed() {
    let case = case();
    let settings = CraigBamptonSettings {
        retained: case.retained.clone(),
        internal_modes: 3,
    };
    let dir = std::env::temp_dir().join(format!("cyclorub-cb-cache-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    let cache = ReductionCache::new(&dir);
    let digest = InputDigest::of_reduction(&case.sector, &settings);
    let (first, outcome) = craig_bampton_cached(&case.sector, &settings, &cache, &digest).unwrap();
    assert!(
        matches!(
            outcome,
            CacheOutcome::Computed {
                store_error: None,
                ..
            }
        ),
        "{outcome:?}"
    );
    let (second, outcome) = craig_bampton_cached(&case.sector, &settings, &cache, &digest).unwrap();
    assert_eq!(outcome, CacheOutcome::Hit(cache.path(&digest)));
    for (a, b) in first.iter().zip(&second) {
        assert_eq!(a.stiffness, b.stiffness);
        assert_eq!(a.mass, b.mass);
        assert_eq!(a.interface_eigenvalues, b.interface_eigenvalues);
    }
    // One flipped byte, then a cut file: recomputed, and the file repaired.
    let path = cache.path(&digest);
    let mut bytes = std::fs::read(&path).unwrap();
    let middle = bytes.len() / 2;
    bytes[middle] ^= 0x10;
    std::fs::write(&path, &bytes).unwrap();
    let (_, outcome) = craig_bampton_cached(&case.sector, &settings, &cache, &digest).unwrap();
    assert!(
        matches!(&outcome, CacheOutcome::Computed { reason, .. } if reason.contains("checksum")),
        "{outcome:?}"
    );
    let bytes = std::fs::read(&path).unwrap();
    std::fs::write(&path, &bytes[..bytes.len() - 100]).unwrap();
    let (_, outcome) = craig_bampton_cached(&case.sector, &settings, &cache, &digest).unwrap();
    assert!(
        matches!(outcome, CacheOutcome::Computed { .. }),
        "{outcome:?}"
    );
    let (_, outcome) = craig_bampton_cached(&case.sector, &settings, &cache, &digest).unwrap();
    assert!(matches!(outcome, CacheOutcome::Hit(_)), "{outcome:?}");
    // Other inputs: another digest; a file of another input under this
    // digest's name is refused.
    let mut stiffer = case.sector.clone();
    stiffer.stiffness.val_mut()[0] *= 1.0 + 1e-12;
    let other = InputDigest::of_reduction(&stiffer, &settings);
    assert_ne!(other, digest);
    std::fs::copy(&path, cache.path(&other)).unwrap();
    let (_, outcome) = craig_bampton_cached(&stiffer, &settings, &cache, &other).unwrap();
    assert!(
        matches!(&outcome, CacheOutcome::Computed { reason, .. } if reason.contains("another input")),
        "{outcome:?}"
    );
    let _ = std::fs::remove_dir_all(&dir);
}
