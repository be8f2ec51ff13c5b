//! The hex20 element against closed forms: the patch test (a linear field
//! is reproduced exactly by distorted elements) and a slender cantilever's
//! first bending frequency against Euler–Bernoulli.

use super::super::lattice::Lattice;
use super::super::{assemble, strain, Element, Material, Mesh, GAUSS3, HEX20_DOFS, HEX20_NODES};
use super::{complex, dense, generalized_eigenvalues, hertz};
use faer::linalg::solvers::Solve;
use faer::{Mat, Side};

/// A structured block of `e` elements over the box `size`, with nodes moved by
/// `distort(lattice point, position)`; returns the mesh and each node's
/// lattice point.
fn block(
    e: [usize; 3],
    size: [f64; 3],
    material: Material,
    distort: impl Fn([usize; 3], [f64; 3]) -> [f64; 3],
) -> (Mesh, Vec<[usize; 3]>) {
    let mut lattice = Lattice::new(e);
    let points = lattice.node_points();
    let mut nodes = Vec::new();
    for &p in &points {
        let x = [0, 1, 2].map(|d| size[d] * p[d] as f64 / (2 * e[d]) as f64);
        lattice.set(p, nodes.len());
        nodes.push(distort(p, x));
    }
    let elements = lattice
        .element_indices()
        .into_iter()
        .map(|idx| {
            let mut ids = [0; HEX20_NODES];
            for (id, p) in ids.iter_mut().zip(Lattice::element_points(idx)) {
                *id = lattice.get(p).unwrap();
            }
            Element {
                nodes: ids,
                material: 0,
            }
        })
        .collect();
    (
        Mesh {
            nodes,
            elements,
            materials: vec![material],
        },
        points,
    )
}

const STEEL: Material = Material {
    young: 210e9,
    poisson: 0.3,
    density: 7800.0,
};

/// A fixed pseudo-random number in [−1, 1] from three integers.
fn wobble(p: [usize; 3], salt: usize) -> f64 {
    let h =
        (p[0] * 73_856_093) ^ (p[1] * 19_349_663) ^ (p[2] * 83_492_791) ^ (salt * 2_654_435_761);
    ((h % 20_001) as f64) / 10_000.0 - 1.0
}

#[test]
fn the_patch_test_distorted_hex20_blocks_reproduce_a_linear_field_exactly() {
    let e = [2, 2, 2];
    // Every node moved by up to 6 % of an element (mid-edge nodes too: the
    // elements have curved edges and faces).
    let (mesh, points) = block(e, [1.0, 0.8, 1.2], STEEL, |p, x| {
        [0, 1, 2].map(|d| x[d] + 0.03 * wobble(p, d))
    });
    let a = [
        [1.0e-3, 2.0e-4, -3.0e-4],
        [-5.0e-4, 4.0e-4, 6.0e-4],
        [7.0e-4, -1.0e-4, -2.0e-4],
    ];
    let b = [1.0e-3, -2.0e-3, 5.0e-4];
    let field = |x: [f64; 3]| [0, 1, 2].map(|i| b[i] + (0..3).map(|j| a[i][j] * x[j]).sum::<f64>());
    let n = 3 * mesh.nodes.len();
    let exact: Vec<f64> = mesh.nodes.iter().flat_map(|&x| field(x)).collect();
    let interior: Vec<bool> = points
        .iter()
        .map(|p| (0..3).all(|d| p[d] > 0 && p[d] < 2 * e[d]))
        .collect();
    assert_eq!(interior.iter().filter(|&&i| i).count(), 7);
    let k = assemble(&mesh).unwrap().stiffness;
    let k_max = k.values.iter().fold(0.0f64, |m, v| m.max(v.abs()));
    let u_max = exact.iter().fold(0.0f64, |m, v| m.max(v.abs()));

    // Equilibrium of the internal nodes under the exact field: K u = 0 there.
    let r = k.multiply(&exact);
    for (node, _) in interior.iter().enumerate().filter(|(_, &i)| i) {
        for d in 0..3 {
            assert!(
                r[3 * node + d].abs() <= 1e-10 * k_max * u_max,
                "node {node} dof {d}: residual {:e}",
                r[3 * node + d]
            );
        }
    }

    // The field imposed on the boundary: the interior solves to it.
    let free: Vec<usize> = (0..n).filter(|i| interior[i / 3]).collect();
    let fixed: Vec<usize> = (0..n).filter(|i| !interior[i / 3]).collect();
    let kd = dense(&k);
    let kii = Mat::from_fn(free.len(), free.len(), |i, j| kd[(free[i], free[j])]);
    let rhs = Mat::from_fn(free.len(), 1, |i, _| {
        -fixed
            .iter()
            .map(|&j| kd[(free[i], j)] * exact[j])
            .sum::<f64>()
    });
    let solved = kii.llt(Side::Lower).unwrap().solve(&rhs);
    let mut u = exact.clone();
    for (i, &dof) in free.iter().enumerate() {
        assert!(
            (solved[(i, 0)] - exact[dof]).abs() <= 1e-10 * u_max,
            "dof {dof}: {} against {}",
            solved[(i, 0)],
            exact[dof]
        );
        u[dof] = solved[(i, 0)];
    }

    // Constant strain and stress at every Gauss point of every element.
    let eps = [
        a[0][0],
        a[1][1],
        a[2][2],
        a[0][1] + a[1][0],
        a[1][2] + a[2][1],
        a[2][0] + a[0][2],
    ];
    let d = STEEL.elasticity();
    let sigma: Vec<f64> = (0..6)
        .map(|i| (0..6).map(|j| d[i][j] * eps[j]).sum())
        .collect();
    let sigma_max = sigma.iter().fold(0.0f64, |m, v| m.max(v.abs()));
    for element in &mesh.elements {
        let coords = element.nodes.map(|n| mesh.nodes[n]);
        let mut ue = [0.0; HEX20_DOFS];
        for (a, &node) in element.nodes.iter().enumerate() {
            ue[3 * a..3 * a + 3].copy_from_slice(&u[3 * node..3 * node + 3]);
        }
        for &(x, _) in &GAUSS3 {
            for &(y, _) in &GAUSS3 {
                for &(z, _) in &GAUSS3 {
                    let e = strain(&coords, &ue, [x, y, z]).unwrap();
                    for i in 0..6 {
                        let s: f64 = (0..6).map(|j| d[i][j] * e[j]).sum();
                        assert!(
                            (s - sigma[i]).abs() <= 1e-10 * sigma_max,
                            "stress {i}: {s:e} against {:e}",
                            sigma[i]
                        );
                    }
                }
            }
        }
    }
}

#[test]
fn a_slender_hex20_cantilever_bends_at_the_euler_bernoulli_frequency_within_1_percent() {
    // 20:1, square section, one element across. With ν = 0.3 the fully
    // clamped root and one fully integrated element across stiffen the
    // beam: 1.0 % high with 10 elements along, 0.47 % with 20. With ν = 0,
    // 10 elements give 0.09 % (20: 0.14 % low, the shear of Timoshenko).
    for (along, poisson) in [(20usize, 0.3f64), (10, 0.0)] {
        let material = Material { poisson, ..STEEL };
        let (length, side) = (0.2, 0.01);
        let (mesh, points) = block([along, 1, 1], [length, side, side], material, |_, x| x);
        let m = assemble(&mesh).unwrap();
        let free: Vec<usize> = (0..3 * mesh.nodes.len())
            .filter(|i| points[i / 3][0] > 0)
            .collect();
        let (kd, md) = (dense(&m.stiffness), dense(&m.mass));
        let k = Mat::from_fn(free.len(), free.len(), |i, j| kd[(free[i], free[j])]);
        let mm = Mat::from_fn(free.len(), free.len(), |i, j| md[(free[i], free[j])]);
        let f = hertz(&generalized_eigenvalues(&complex(&k), &complex(&mm)));
        let inertia = side.powi(4) / 12.0;
        let area = side * side;
        let beta = 1.875_104_068_711_961;
        let euler_bernoulli = beta * beta / (2.0 * std::f64::consts::PI * length * length)
            * (STEEL.young * inertia / (STEEL.density * area)).sqrt();
        // The section is square: two bending modes at the same frequency.
        for (mode, &found) in f.iter().enumerate().take(2) {
            let error = (found - euler_bernoulli).abs() / euler_bernoulli;
            println!(
                "mode {mode}: {found:.3} Hz, Euler–Bernoulli {euler_bernoulli:.3} Hz, {error:.2e}"
            );
            assert!(
                error < 0.01,
                "ν = {poisson}, mode {mode}: {found} Hz against {euler_bernoulli} Hz"
            );
        }
    }
}

#[test]
fn an_inverted_element_and_a_non_physical_material_are_refused() {
    // Mirrored in x: a negative Jacobian everywhere.
    let (mut mesh, _) = block([1, 1, 1], [1.0, 1.0, 1.0], STEEL, |_, x| {
        [-x[0], x[1], x[2]]
    });
    let error = assemble(&mesh).unwrap_err();
    assert!(error.to_string().starts_with("element 1:"), "{error}");
    assert!(error.to_string().contains("inverted"), "{error}");
    mesh.nodes.iter_mut().for_each(|x| x[0] = -x[0]);
    assert!(assemble(&mesh).is_ok());
    for bad in [
        Material {
            poisson: 0.5,
            ..STEEL
        },
        Material {
            young: 0.0,
            ..STEEL
        },
        Material {
            density: f64::NAN,
            ..STEEL
        },
    ] {
        let error = bad.check("blade material").unwrap_err();
        assert!(error.is_input_error() && error.to_string().starts_with("blade material"));
    }
    assert!(STEEL.check("steel").is_ok());
}
