//! `hermitian_modes` and `symmetric_modes` against independent solves on a
//! pencil of the size where faer's divide and conquer went wrong (issue 45
//! item 18): the open fan's Craig–Bampton full wheel (16 sectors × 53 =
//! 848 rows, eigenvalues from 3.1e6 to 7.2e12). Its eigenvalues are the
//! union of the diameters' (cyclic symmetry), each diameter a 53-row
//! pencil solved on its own; every eigenpair's residual is checked against
//! the matrices themselves, and the pencil turned complex by a unitary
//! diagonal (`D K Dᴴ`, same eigenvalues) goes through the complex path.
//! With faer's `self_adjoint_eigen` (divide and conquer) the residuals were
//! 6.6e-4 of the matrix's size and the lowest eigenvalue 1e-5 off.

use super::{hermitian_modes, symmetric_modes};
use crate::mesh::{assemble, fan, FanGeometry, SymmetricMatrix};
use crate::model::craig_bampton::{
    craig_bampton, reduced_sector_model, CraigBamptonSettings, SparseSector,
};
use crate::model::{Axis, BoundaryFrame, Damping, FullWheelMatrices};
use faer::sparse::{SparseColMat, Triplet};
use faer::{c64, Mat, Side};

const SECTORS: usize = 16;

fn full_storage(a: &SymmetricMatrix) -> SparseColMat<usize, f64> {
    let triplets: Vec<Triplet<usize, usize, f64>> = a
        .entries()
        .flat_map(|(i, j, v)| {
            let mirror = (i != j).then(|| Triplet::new(j, i, v));
            std::iter::once(Triplet::new(i, j, v)).chain(mirror)
        })
        .collect();
    SparseColMat::try_new_from_triplets(a.size, a.size, &triplets).expect("triplets")
}

fn node_dofs(nodes: &[usize]) -> Vec<usize> {
    nodes
        .iter()
        .flat_map(|&n| (0..3).map(move |d| 3 * n + d))
        .collect()
}

/// The coarse fan reduced on its 33 contact, excitation and observation
/// dofs plus 20 modes: the full wheel, and the union of the eigenvalues of
/// its 9 diameters (the 7 travelling ones twice), ascending.
fn reduced_fan_wheel() -> (FullWheelMatrices, Vec<f64>) {
    let mesh = fan(SECTORS, 1, &FanGeometry::default()).expect("fan");
    let matrices = assemble(&mesh.mesh).expect("assembly");
    let mut retained = mesh.sets.contact.clone();
    retained.push(mesh.sets.excitation);
    retained.push(mesh.sets.observation);
    let sector = SparseSector {
        mass: full_storage(&matrices.mass),
        stiffness: full_storage(&matrices.stiffness),
        clamped: node_dofs(&mesh.sets.clamped),
        left_boundary: node_dofs(&mesh.sets.left_boundary),
        right_boundary: node_dofs(&mesh.sets.right_boundary),
        boundary_frame: BoundaryFrame::Cartesian { axis: Axis::Z },
        sectors: SECTORS,
        symmetry_tolerance: 1e-10,
    };
    let settings = CraigBamptonSettings {
        retained: node_dofs(&retained),
        internal_modes: 20,
    };
    let reduced = craig_bampton(&sector, &settings).expect("reduction");
    let model = reduced_sector_model(SECTORS, &settings, &reduced, Damping::None).expect("model");
    let mut union = Vec::new();
    for d in 0..=SECTORS / 2 {
        let nd = model.nodal_diameter_matrices(d as i64).expect("diameter");
        let values = diameter_eigenvalues(&nd.stiffness, &nd.mass);
        let copies = if d == 0 || d == SECTORS / 2 { 1 } else { 2 };
        for v in values {
            union.extend(std::iter::repeat_n(v, copies));
        }
    }
    union.sort_by(f64::total_cmp);
    (model.full_wheel().expect("wheel"), union)
}

/// The eigenvalues of one diameter's 53-row pencil, values only (faer's
/// tridiagonal QR at any order; and below 128 rows at all events).
fn diameter_eigenvalues(k: &Mat<c64>, m: &Mat<c64>) -> Vec<f64> {
    let n = k.nrows();
    let llt = m.llt(Side::Lower).expect("mass");
    let l = llt.L();
    let mut y = k.clone();
    l.solve_lower_triangular_in_place(y.as_mut());
    let mut a: Mat<c64> = y.adjoint().to_owned();
    l.solve_lower_triangular_in_place(a.as_mut());
    let a = Mat::from_fn(n, n, |i, j| (a[(i, j)] + a[(j, i)].conj()) * 0.5);
    a.self_adjoint_eigenvalues(Side::Lower)
        .expect("eigenvalues")
}

/// The largest `‖K φ − λ M φ‖ / (‖K‖ ‖φ‖)` over the eigenpairs, with the
/// shapes `Φ = M⁻¹ W` recovered from `W = M Φ`.
fn worst_residual(k: &Mat<c64>, m: &Mat<c64>, values: &[f64], w: &Mat<c64>) -> f64 {
    let llt = m.llt(Side::Lower).expect("mass");
    let mut phi = w.clone();
    llt.L().solve_lower_triangular_in_place(phi.as_mut());
    llt.L()
        .adjoint()
        .solve_upper_triangular_in_place(phi.as_mut());
    let kphi = k * &phi;
    (0..values.len())
        .map(|r| {
            let residual = kphi.col(r) - w.col(r) * values[r];
            residual.norm_l2() / (k.norm_l2() * phi.col(r).norm_l2())
        })
        .fold(0.0, f64::max)
}

fn assert_union(values: &[f64], union: &[f64], path: &str) {
    assert_eq!(values.len(), union.len());
    for (r, (v, e)) in values.iter().zip(union).enumerate() {
        assert!(
            (v - e).abs() <= 1e-9 * e.abs().max(union[0]),
            "{path}, eigenvalue {r}: {v:.12e} vs the diameters' {e:.12e}"
        );
    }
}

#[test]
fn the_full_wheels_modes_are_the_union_of_the_diameters_with_round_off_residuals_real_and_complex()
{
    let (wheel, union) = reduced_fan_wheel();
    let n = wheel.stiffness.nrows();
    assert_eq!(n, 848);

    // The real path.
    let (values, w) = symmetric_modes(&wheel.stiffness, &wheel.mass, 0, true).expect("real");
    assert_union(&values, &union, "real");
    let complex = |a: &Mat<f64>| Mat::from_fn(n, n, |i, j| c64::new(a[(i, j)], 0.0));
    let (k, m) = (complex(&wheel.stiffness), complex(&wheel.mass));
    let w = complex(&w.expect("shapes"));
    let residual = worst_residual(&k, &m, &values, &w);
    assert!(residual <= 1e-12, "real path: residual {residual:e}");

    // The complex path on the same real-valued pencil (the case of the
    // issue), then on its complex twin `D K Dᴴ`, `D = diag(e^{i·0.7 j})`.
    let modes = hermitian_modes(&k, &m, 0, true).expect("complex");
    assert_union(&modes.values, &union, "complex, real-valued");
    let w = modes.mass_times_shapes.expect("shapes");
    let residual = worst_residual(&k, &m, &modes.values, &w);
    assert!(residual <= 1e-12, "complex path: residual {residual:e}");

    let phase = |j: usize| c64::cis(0.7 * j as f64);
    let twist = |a: &Mat<c64>| Mat::from_fn(n, n, |i, j| phase(i) * a[(i, j)] * phase(j).conj());
    let (k, m) = (twist(&k), twist(&m));
    let modes = hermitian_modes(&k, &m, 0, true).expect("twisted");
    assert_union(&modes.values, &union, "complex, twisted");
    let w = modes.mass_times_shapes.expect("shapes");
    let residual = worst_residual(&k, &m, &modes.values, &w);
    assert!(
        residual <= 1e-12,
        "twisted complex path: residual {residual:e}"
    );
    // The values alone agree with the values of the modes.
    let alone = hermitian_modes(&k, &m, 0, false).expect("values");
    assert_union(&alone.values, &union, "complex, values only");
}
