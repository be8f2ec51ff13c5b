//! Craig–Bampton per nodal diameter on the coarse open fan (`refine 1`)
//! against the full sector, solved densely: the per-diameter matrices
//! built here independently (`T(s)ᴴ K T(s)` with `u_R = e^{−iαs} R(α) u_L`,
//! the sign convention of `model/mod.rs`), the static response at the
//! retained dofs, and the first bending frequency of every diameter.

use cyclorub::mesh::{assemble, fan, FanGeometry, FanMesh, SymmetricMatrix};
use cyclorub::model::craig_bampton::{
    craig_bampton, craig_bampton_nodal_diameter, CraigBamptonSettings, ReductionError, SparseSector,
};
use cyclorub::model::{Axis, BoundaryFrame};
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

/// The lowest eigenvalue of the dense pencil `(K, M)`.
fn lowest_eigenvalue(k: &Mat<c64>, m: &Mat<c64>) -> f64 {
    let n = k.nrows();
    let l = m.llt(Side::Lower).unwrap();
    let l = l.L();
    let mut y = k.clone();
    l.solve_lower_triangular_in_place(y.as_mut());
    let mut a: Mat<c64> = y.adjoint().to_owned();
    l.solve_lower_triangular_in_place(a.as_mut());
    let a = Mat::from_fn(n, n, |i, j| (a[(i, j)] + a[(j, i)].conj()) * 0.5);
    let values = a.self_adjoint_eigenvalues(Side::Lower).unwrap();
    values.iter().cloned().fold(f64::INFINITY, f64::min)
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
