//! The real cyclic Fourier matrix (Eqs. 2, 3, 90, 91) and the zig-zag
//! diagram (Eq. 49), checked against their definitions.

use cyclorub::cyclic::{fold_nodal_diameter, real_cyclic_fourier_matrix, zigzag};
use std::f64::consts::PI;

#[test]
fn s_is_orthogonal_for_every_n_from_2_to_64() {
    for n in 2..=64 {
        let s = real_cyclic_fourier_matrix(n);
        assert_eq!((s.nrows(), s.ncols()), (n, n));
        let mut worst: f64 = 0.0;
        for r in 0..n {
            for c in 0..n {
                let dot: f64 = (0..n).map(|j| s[(r, j)] * s[(c, j)]).sum();
                let expected = if r == c { 1.0 } else { 0.0 };
                worst = worst.max((dot - expected).abs());
            }
        }
        assert!(worst < 1e-13, "N = {n}: |S Sᵀ − I| = {worst:e}");
        // Sᵀ S = I as well (square and orthogonal).
        for j in 0..n {
            let norm: f64 = (0..n).map(|r| s[(r, j)] * s[(r, j)]).sum();
            assert!((norm - 1.0).abs() < 1e-13);
        }
    }
}

/// `x = Sᵀ x̂` reproduces Eq. (2) (even N) and Eq. (3) (odd N) term by term.
#[test]
fn x_equals_s_transpose_xhat_follows_eqs_2_and_3() {
    for n in [5usize, 6, 16, 24, 45] {
        let s = real_cyclic_fourier_matrix(n);
        let alpha = 2.0 * PI / n as f64;
        // Spectral coefficients with distinct values.
        let xhat: Vec<f64> = (0..n)
            .map(|i| 0.3 + 0.7 * i as f64 - 0.01 * (i * i) as f64)
            .collect();
        for j in 1..=n {
            let from_s: f64 = (0..n).map(|r| s[(r, j - 1)] * xhat[r]).sum();
            let mut eq = xhat[0] / (n as f64).sqrt();
            let mut row = 1;
            for h in 1..=((n - 1) / 2) {
                let a = (h * j) as f64 * alpha;
                eq += (2.0 / n as f64).sqrt() * (xhat[row] * a.cos() + xhat[row + 1] * a.sin());
                row += 2;
            }
            if n % 2 == 0 {
                let sign = if j % 2 == 0 { 1.0 } else { -1.0 };
                eq += sign * xhat[row] / (n as f64).sqrt();
            }
            assert!((from_s - eq).abs() < 1e-12, "N = {n}, sector {j}");
        }
    }
}

#[test]
fn one_sector_is_the_identity() {
    let s = real_cyclic_fourier_matrix(1);
    assert_eq!((s.nrows(), s.ncols()), (1, 1));
    assert!((s[(0, 0)] - 1.0).abs() < 1e-15);
}

#[test]
fn zigzag_reproduces_the_papers_lists() {
    let list = |n: usize, h: i64| -> Vec<i64> { (0..=10).map(|k| zigzag(h, k, n)).collect() };
    // Eq. (76), (77): N = 24.
    assert_eq!(
        list(24, 1),
        vec![0, -1, -2, -3, -4, -5, -6, -7, -8, -9, -10]
    );
    assert_eq!(list(24, 3), vec![0, -3, -6, -9, 12, 9, 6, 3, 0, -3, -6]);
    // Eq. (85): N = 16.
    assert_eq!(list(16, 1), vec![0, -1, -2, -3, -4, -5, -6, -7, 8, 7, 6]);
    // Eq. (104), (105): N = 45.
    assert_eq!(
        list(45, 2),
        vec![0, -2, -4, -6, -8, -10, -12, -14, -16, -18, -20]
    );
    assert_eq!(
        list(45, 17),
        vec![0, -17, 11, -6, 22, 5, -12, 16, -1, -18, 10]
    );
}

/// The excitation is the wave `(−h, 1)` (docs/design.md §2), so on harmonic `k`
/// it lives on `Z(k h) ≡ −k h (mod N)`, always shown in `(−N/2, N/2]`.
#[test]
fn zigzag_is_minus_k_h_folded() {
    for n in 1..=40usize {
        for h in 0..n as i64 {
            for k in 0..=25 {
                let z = zigzag(h, k, n);
                assert!(2 * z > -(n as i64) && 2 * z <= n as i64);
                assert_eq!((z + k * h).rem_euclid(n as i64), 0);
                assert_eq!(z, fold_nodal_diameter(-k * h, n));
            }
        }
    }
}
