//! The first bending family per nodal diameter of the coarse fan, by a dense
//! cyclic reduction written for this test only: bore clamped, Cartesian
//! boundary dofs rotated, `u_R = e^{−iαs} R(α) u_L` (the sign convention of
//! `model/mod.rs`), `K(s) = Tᴴ K T`, `M(s) = Tᴴ M T`.

use super::super::{assemble, fan, Element, FanGeometry, FanMesh, Mesh, SymmetricMatrix};
use super::{generalized_eigenvalues, hertz};
use faer::{c64, Mat};

/// For each sector dof, the reduced dofs it is made of, with coefficients:
/// `u = T q`. Clamped dofs map to nothing; right boundary dofs to their left
/// twins rotated by `α` and phased by `e^{−iαs}`.
fn reduction(fan: &FanMesh, s: i64) -> (Vec<Vec<(usize, c64)>>, usize) {
    let nodes = fan.mesh.nodes.len();
    let mut clamped = vec![false; nodes];
    for &n in &fan.sets.clamped {
        clamped[n] = true;
    }
    let mut twin = vec![None; nodes];
    for (&l, &r) in fan.sets.left_boundary.iter().zip(&fan.sets.right_boundary) {
        twin[r] = Some(l);
    }
    // Reduced numbering: every free dof that is not on the right face.
    let mut index = vec![usize::MAX; 3 * nodes];
    let mut count = 0;
    for n in 0..nodes {
        if !clamped[n] && twin[n].is_none() {
            for d in 0..3 {
                index[3 * n + d] = count;
                count += 1;
            }
        }
    }
    let alpha = 2.0 * std::f64::consts::PI / fan.sectors as f64;
    let (sa, ca) = alpha.sin_cos();
    let rotation = [[ca, -sa, 0.0], [sa, ca, 0.0], [0.0, 0.0, 1.0]];
    let phase = c64::new((alpha * s as f64).cos(), -(alpha * s as f64).sin());
    let mut map = vec![Vec::new(); 3 * nodes];
    for n in 0..nodes {
        if clamped[n] {
            continue;
        }
        match twin[n] {
            None => {
                for d in 0..3 {
                    map[3 * n + d] = vec![(index[3 * n + d], c64::new(1.0, 0.0))];
                }
            }
            Some(l) => {
                for d in 0..3 {
                    map[3 * n + d] = (0..3)
                        .filter(|&e| rotation[d][e] != 0.0)
                        .map(|e| (index[3 * l + e], phase * rotation[d][e]))
                        .collect();
                }
            }
        }
    }
    (map, count)
}

/// `Tᴴ A T`, dense.
fn reduce(matrix: &SymmetricMatrix, map: &[Vec<(usize, c64)>], size: usize) -> Mat<c64> {
    let mut out = Mat::<c64>::zeros(size, size);
    let mut add = |i: usize, j: usize, v: f64| {
        for &(a, ta) in &map[i] {
            for &(b, tb) in &map[j] {
                out[(a, b)] += ta.conj() * tb * v;
            }
        }
    };
    for (i, j, v) in matrix.entries() {
        add(i, j, v);
        if i != j {
            add(j, i, v);
        }
    }
    out
}

/// The lowest `count` frequencies (Hz) of nodal diameter `s`.
pub(super) fn frequencies(
    fan: &FanMesh,
    mass: &SymmetricMatrix,
    stiffness: &SymmetricMatrix,
    s: i64,
    count: usize,
) -> Vec<f64> {
    let (map, size) = reduction(fan, s);
    let k = reduce(stiffness, &map, size);
    let m = reduce(mass, &map, size);
    let mut f = hertz(&generalized_eigenvalues(&k, &m));
    f.truncate(count);
    f
}

#[test]
fn the_reduced_matrices_are_hermitian_and_real_at_diameters_0_and_n_over_2() {
    let fan = fan(16, 1, &FanGeometry::default()).unwrap();
    let matrices = assemble(&fan.mesh).unwrap();
    for s in [0i64, 3, 8] {
        let (map, size) = reduction(&fan, s);
        let k = reduce(&matrices.stiffness, &map, size);
        let scale = (0..size).map(|i| k[(i, i)].re).fold(0.0, f64::max);
        let mut worst_hermitian = 0.0f64;
        let mut worst_imaginary = 0.0f64;
        for i in 0..size {
            for j in 0..size {
                worst_hermitian = worst_hermitian.max((k[(i, j)] - k[(j, i)].conj()).norm());
                worst_imaginary = worst_imaginary.max(k[(i, j)].im.abs());
            }
        }
        assert!(
            worst_hermitian <= 1e-12 * scale,
            "s = {s}: {worst_hermitian:e}"
        );
        if s == 0 || s == 8 {
            assert!(
                worst_imaginary <= 1e-12 * scale,
                "s = {s}: {worst_imaginary:e}"
            );
        }
    }
}

/// The coarse mesh's first family lies in 230–320 Hz (the paper's Table 3:
/// 263–288 Hz), is lowest at nodal diameter 0 and rises from there, as a
/// bladed disk's does where the disk takes part (the disk's torsion at
/// diameter 0). The full-width titanium disk barely moves beyond: diameters
/// 2 to 8 stay within 0.1 % of each other (measured: they fall by 0.05 %,
/// the rim's in-plane flexibility between blades moving in opposition).
/// The sparse solver (checked against the dense one below) keeps it short.
#[test]
fn the_coarse_fan_first_bending_family_lies_near_table_3_and_rises_from_diameter_0() {
    let fan = fan(16, 1, &FanGeometry::default()).unwrap();
    let matrices = assemble(&fan.mesh).unwrap();
    let family: Vec<f64> = (0..=8)
        .map(|s| frequencies_sparse(&fan, &matrices.mass, &matrices.stiffness, s, 1)[0])
        .collect();
    println!("first family (Hz), refine 1: {family:.2?}");
    for (s, f) in family.iter().enumerate() {
        assert!((230.0..=320.0).contains(f), "ND {s}: {f} Hz");
    }
    assert!(family[1] > family[0] * (1.0 + 1e-4), "{family:?}");
    assert!(family[2] > family[1], "{family:?}");
    let high = family[2..].iter().fold(f64::MIN, |m, &f| m.max(f));
    let low = family[2..].iter().fold(f64::MAX, |m, &f| m.min(f));
    assert!(high - low < 1e-3 * low, "{family:?}");
    assert!(low > family[1] * (1.0 - 1e-3), "{family:?}");
}

/// Not a check: prints the lowest frequencies per diameter for a refine
/// level (`FAN_REFINE`, default 1) to calibrate the blade and fill the README.
#[test]
#[ignore = "a measuring tool, not a check: it asserts nothing and prints the fan's frequencies per diameter (dense solver, minutes above refine 1); run with FAN_REFINE=R cargo test -p cyclorub --lib print_the_frequencies_per_diameter -- --ignored --nocapture"]
fn print_the_frequencies_per_diameter() {
    let refine = std::env::var("FAN_REFINE")
        .ok()
        .and_then(|v| v.parse().ok())
        .unwrap_or(1);
    let diameters: Vec<i64> = std::env::var("FAN_DIAMETERS")
        .ok()
        .map(|v| v.split(',').filter_map(|x| x.parse().ok()).collect())
        .unwrap_or_else(|| (0..=8).collect());
    let fan = fan(16, refine, &FanGeometry::default()).unwrap();
    let matrices = assemble(&fan.mesh).unwrap();
    println!("refine {refine}: {} dofs", fan.dofs());
    for s in diameters {
        let f = frequencies(&fan, &matrices.mass, &matrices.stiffness, s, 4);
        println!("ND {s}: {f:.2?}");
    }
}

/// The reduced `Tᴴ A T` as lower-triangle triplets of the Hermitian matrix.
fn reduce_sparse(matrix: &SymmetricMatrix, map: &[Vec<(usize, c64)>]) -> Vec<(usize, usize, c64)> {
    let mut out = Vec::new();
    let mut add = |i: usize, j: usize, v: f64| {
        for &(a, ta) in &map[i] {
            for &(b, tb) in &map[j] {
                if a >= b {
                    out.push((a, b, ta.conj() * tb * v));
                }
            }
        }
    };
    for (i, j, v) in matrix.entries() {
        add(i, j, v);
        if i != j {
            add(j, i, v);
        }
    }
    out
}

/// `Y = A X` for a Hermitian `A` given by its lower triplets.
fn hermitian_times(lower: &[(usize, usize, c64)], x: &Mat<c64>) -> Mat<c64> {
    let mut y = Mat::<c64>::zeros(x.nrows(), x.ncols());
    for &(a, b, v) in lower {
        for c in 0..x.ncols() {
            let (xa, xb) = (x[(a, c)], x[(b, c)]);
            y[(a, c)] += v * xb;
            if a != b {
                y[(b, c)] += v.conj() * xa;
            }
        }
    }
    y
}

/// The lowest `count` frequencies (Hz) of nodal diameter `s` by subspace
/// iteration on the sparse Cholesky factor of `K(s)` (the bore is clamped,
/// so `K(s)` is positive definite), for meshes too large for the dense
/// solver.
fn frequencies_sparse(
    fan: &FanMesh,
    mass: &SymmetricMatrix,
    stiffness: &SymmetricMatrix,
    s: i64,
    count: usize,
) -> Vec<f64> {
    let (map, n) = reduction(fan, s);
    let k = reduce_sparse(stiffness, &map);
    let m = reduce_sparse(mass, &map);
    lowest_sparse(&k, &m, n, count)
}

/// The lowest `count` frequencies (Hz) of `K φ = ω² M φ` (Hermitian, lower
/// triplets, `K` positive definite): block inverse iteration with
/// Rayleigh–Ritz, until the values settle to 1e-11.
fn lowest_sparse(
    k: &[(usize, usize, c64)],
    m: &[(usize, usize, c64)],
    n: usize,
    count: usize,
) -> Vec<f64> {
    use faer::linalg::solvers::Solve;
    use faer::sparse::{SparseColMat, Triplet};
    use faer::Side;
    let triplets: Vec<Triplet<usize, usize, c64>> =
        k.iter().map(|&(a, b, v)| Triplet::new(a, b, v)).collect();
    let factor = SparseColMat::<usize, c64>::try_new_from_triplets(n, n, &triplets)
        .unwrap()
        .sp_cholesky(Side::Lower)
        .unwrap();
    let p = count + 6;
    let mut x = Mat::<c64>::from_fn(n, p, |i, j| {
        c64::new(
            (((i * 7 + j * 13) % 17) as f64) - 8.0,
            ((i * 3 + j) % 5) as f64 - 2.0,
        )
    });
    let mut previous = vec![0.0; count];
    for _ in 0..200 {
        let mut y = hermitian_times(m, &x);
        factor.solve_in_place(y.as_mut());
        let ky = hermitian_times(k, &y);
        let my = hermitian_times(m, &y);
        let kr: Mat<c64> = y.adjoint() * &ky;
        let mr: Mat<c64> = y.adjoint() * &my;
        let kr = Mat::from_fn(p, p, |i, j| (kr[(i, j)] + kr[(j, i)].conj()) * 0.5);
        let mr = Mat::from_fn(p, p, |i, j| (mr[(i, j)] + mr[(j, i)].conj()) * 0.5);
        let llt = mr.llt(Side::Lower).unwrap();
        let l = llt.L();
        let mut z = kr.clone();
        l.solve_lower_triangular_in_place(z.as_mut());
        let mut a: Mat<c64> = z.adjoint().to_owned();
        l.solve_lower_triangular_in_place(a.as_mut());
        let a = Mat::from_fn(p, p, |i, j| (a[(i, j)] + a[(j, i)].conj()) * 0.5);
        let eig = a.self_adjoint_eigen(Side::Lower).unwrap();
        let values: Vec<f64> = eig.S().column_vector().iter().map(|v| v.re).collect();
        // Ritz vectors Y L⁻ᴴ U, in ascending order of the values.
        let mut phi = eig.U().to_owned();
        l.adjoint().solve_upper_triangular_in_place(phi.as_mut());
        x = &y * &phi;
        let done = (0..count).all(|i| (values[i] - previous[i]).abs() <= 1e-11 * values[i]);
        previous = values[..count].to_vec();
        if done {
            break;
        }
    }
    hertz(&previous)
}

/// Not a check: the first frequencies per diameter by sparse subspace
/// iteration, for a refine level (`FAN_REFINE`, default 3).
#[test]
#[ignore = "a measuring tool, not a check: it asserts nothing and prints the default fan's frequencies per diameter (17,379 dofs, about a minute); run with FAN_REFINE=R cargo test -p cyclorub --lib print_the_frequencies_per_diameter_sparse -- --ignored --nocapture"]
fn print_the_frequencies_per_diameter_sparse() {
    let refine = std::env::var("FAN_REFINE")
        .ok()
        .and_then(|v| v.parse().ok())
        .unwrap_or(3);
    let fan = fan(16, refine, &FanGeometry::default()).unwrap();
    let matrices = assemble(&fan.mesh).unwrap();
    println!("refine {refine}: {} dofs", fan.dofs());
    for s in 0..=8 {
        let started = std::time::Instant::now();
        let f = frequencies_sparse(&fan, &matrices.mass, &matrices.stiffness, s, 3);
        println!("ND {s}: {f:.2?} ({:.1} s)", started.elapsed().as_secs_f64());
    }
}

#[test]
fn sparse_subspace_iteration_agrees_with_the_dense_solver_on_the_coarse_fan() {
    let fan = fan(16, 1, &FanGeometry::default()).unwrap();
    let matrices = assemble(&fan.mesh).unwrap();
    for s in [0, 3, 8] {
        let dense = frequencies(&fan, &matrices.mass, &matrices.stiffness, s, 2);
        let sparse = frequencies_sparse(&fan, &matrices.mass, &matrices.stiffness, s, 2);
        for (d, sp) in dense.iter().zip(&sparse) {
            assert!(
                (d - sp).abs() <= 1e-8 * d,
                "ND {s}: dense {d} Hz, sparse {sp} Hz"
            );
        }
    }
}

/// The full wheel of `sectors` coarse sectors, meshed by rotating the
/// sector's nodes (element matrices computed on the rotated coordinates),
/// each right face merged with the next sector's left face: its lowest
/// frequencies (the first family: diameter 0 once, diameter 1 twice) are
/// the union of the per-diameter ones (the oracle of the rotated Cartesian
/// boundaries, `u_R = e^{−iαs} R(α) u_L`).
#[test]
fn the_per_diameter_frequencies_are_those_of_the_assembled_full_wheel() {
    let sectors = 3;
    let fan = fan(sectors, 1, &FanGeometry::default()).unwrap();
    let nodes = fan.mesh.nodes.len();
    let mut twin = vec![None; nodes];
    for (&l, &r) in fan.sets.left_boundary.iter().zip(&fan.sets.right_boundary) {
        twin[r] = Some(l);
    }
    // Node numbers: every non-right node of every sector, then right nodes
    // are the next sector's left nodes.
    let mut ids = vec![vec![usize::MAX; nodes]; sectors];
    let mut coords = Vec::new();
    let alpha = 2.0 * std::f64::consts::PI / sectors as f64;
    for (j, sector_ids) in ids.iter_mut().enumerate() {
        let (sa, ca) = (alpha * j as f64).sin_cos();
        for n in (0..nodes).filter(|&n| twin[n].is_none()) {
            sector_ids[n] = coords.len();
            let [x, y, z] = fan.mesh.nodes[n];
            coords.push([ca * x - sa * y, sa * x + ca * y, z]);
        }
    }
    for j in 0..sectors {
        for n in 0..nodes {
            if let Some(l) = twin[n] {
                ids[j][n] = ids[(j + 1) % sectors][l];
            }
        }
    }
    let elements = (0..sectors)
        .flat_map(|j| {
            let ids = &ids[j];
            fan.mesh.elements.iter().map(move |e| Element {
                nodes: e.nodes.map(|n| ids[n]),
                material: e.material,
            })
        })
        .collect();
    let wheel = Mesh {
        nodes: coords,
        elements,
        materials: fan.mesh.materials.clone(),
    };
    let matrices = assemble(&wheel).unwrap();
    let mut clamped = vec![false; wheel.nodes.len()];
    for sector_ids in &ids {
        for &n in &fan.sets.clamped {
            clamped[sector_ids[n]] = true;
        }
    }
    let mut index = vec![usize::MAX; 3 * wheel.nodes.len()];
    let mut free = 0;
    for (dof, slot) in index.iter_mut().enumerate() {
        if !clamped[dof / 3] {
            *slot = free;
            free += 1;
        }
    }
    let map: Vec<Vec<(usize, c64)>> = index
        .iter()
        .map(|&i| {
            if i == usize::MAX {
                vec![]
            } else {
                vec![(i, c64::new(1.0, 0.0))]
            }
        })
        .collect();
    let k = reduce_sparse(&matrices.stiffness, &map);
    let m = reduce_sparse(&matrices.mass, &map);
    let full = lowest_sparse(&k, &m, free, 3);
    let sector = assemble(&fan.mesh).unwrap();
    let mut union: Vec<f64> = Vec::new();
    for s in [0i64, 1, -1] {
        union.extend(frequencies(&fan, &sector.mass, &sector.stiffness, s, 1));
    }
    union.sort_by(f64::total_cmp);
    println!("full wheel: {full:.6?}\nper diameter: {union:.6?}");
    for (a, b) in full.iter().zip(&union) {
        assert!(
            (a - b).abs() <= 1e-8 * a,
            "full wheel {a} Hz, per diameter {b} Hz"
        );
    }
}
