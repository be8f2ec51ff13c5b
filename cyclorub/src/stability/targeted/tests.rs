//! The structured solve and the Hill product against each other and
//! against the dense solver.

use super::block::solver::Solver;
use super::*;
use crate::stability::hill::LocalDynamics;
use crate::stability::vectors::normalize;
use faer::Mat;
use std::sync::Arc;

/// A 3-dof chain with a damper, its harmonics −2..2, contact on dof 2.
fn block_parts() -> (Vec<Group>, Vec<(usize, usize, c64)>) {
    let real = |rows: [[f64; 3]; 3]| Mat::from_fn(3, 3, |r, c| c64::new(rows[r][c], 0.0));
    let mass = real([[2.0, 0.1, 0.0], [0.1, 1.0, 0.0], [0.0, 0.0, 0.5]]);
    let stiffness = real([
        [300.0, -100.0, 0.0],
        [-100.0, 200.0, -100.0],
        [0.0, -100.0, 100.0],
    ]);
    let damping = real([[0.3, 0.0, 0.0], [0.0, 0.2, -0.1], [0.0, -0.1, 0.1]]);
    let dynamics = Arc::new(LocalDynamics::new(&mass, &stiffness, &damping, "test").unwrap());
    let groups: Vec<Group> = (-2..=2)
        .map(|k| Group {
            harmonic: k,
            dynamics: Arc::clone(&dynamics),
        })
        .collect();
    let mut coupling = Vec::new();
    for row in 0..5 {
        for col in 0..5 {
            let m = row as f64 - col as f64;
            let value = c64::new(40.0 / (1.0 + m * m), 3.0 * m);
            coupling.push((3 * row + 2, 3 * col + 2, value));
        }
    }
    (groups, coupling)
}

#[test]
fn the_structured_solve_inverts_the_hill_matrix() {
    // (A − sI) applied to the solve's result gives back the right side,
    // A applied entry by entry (`hill_times`), not through the solve.
    let (groups, coupling) = block_parts();
    let block = Block::new(&groups, &coupling, 7.0, 1).unwrap();
    let shift = c64::new(0.03, 1.7);
    let solver = Solver::at(&block, shift).unwrap();
    let b: Vec<c64> = (0..2 * block.m)
        .map(|i| c64::new((i as f64).sin(), (2.0 * i as f64).cos()))
        .collect();
    let x = solver.apply(&block, &b);
    let back: Vec<c64> = block
        .hill_times(&x)
        .iter()
        .zip(&x)
        .map(|(ax, x)| ax - shift * x)
        .collect();
    let error = norm(&back.iter().zip(&b).map(|(p, q)| p - q).collect::<Vec<_>>());
    assert!(error < 1e-11 * norm(&b), "{error:e}");
}

#[test]
fn the_dense_solvers_eigenvalues_are_eigenvalues_of_hill_times() {
    // `hill_times` against the dense matrix the dense solver builds:
    // its eigenvalues are eigenvalues of `A` by the residual.
    let (groups, coupling) = block_parts();
    let omega = 7.0;
    let block = Block::new(&groups, &coupling, omega, 1).unwrap();
    let dense =
        crate::stability::hill::physical_exponents(&groups, &coupling, &[], omega, 1).unwrap();
    for picked in dense {
        let mu = picked.exponent / omega;
        let solver = Solver::at(&block, mu + c64::new(1e-7, 1e-7)).unwrap();
        let mut v: Vec<c64> = (0..2 * block.m).map(|i| c64::new(1.0, i as f64)).collect();
        for _ in 0..3 {
            v = solver.apply(&block, &v);
            normalize(&mut v).unwrap();
        }
        let av = block.hill_times(&v);
        let residual = norm(
            &av.iter()
                .zip(&v)
                .map(|(a, x)| a - mu * x)
                .collect::<Vec<_>>(),
        );
        assert!(residual < 1e-6 * (1.0 + mu.norm()), "{mu}: {residual:e}");
    }
}

#[test]
fn hill_times_is_the_hill_matrix_column_by_column() {
    // Entry by entry: `hill_times(e_j)` is column j of the matrix the dense
    // solver decomposes.
    let (groups, coupling) = block_parts();
    let omega = 7.0;
    let block = Block::new(&groups, &coupling, omega, 1).unwrap();
    let a = crate::stability::hill::hill_matrix(&groups, &coupling, &[], omega);
    let n = 2 * block.m;
    for j in 0..n {
        let mut e = vec![c64::new(0.0, 0.0); n];
        e[j] = c64::new(1.0, 0.0);
        let column = block.hill_times(&e);
        for (i, value) in column.iter().enumerate() {
            let error = (value - a[(i, j)]).norm();
            assert!(
                error <= 1e-14 * (1.0 + a[(i, j)].norm()),
                "({i}, {j}): {value} {}",
                a[(i, j)]
            );
        }
    }
}
