//! The real cyclic Fourier matrix `S` (Eqs. 2, 3, 90, 91) and the zig-zag
//! diagram (Eq. 49).

use super::pair::fold_nodal_diameter;
use faer::Mat;
use std::f64::consts::PI;

/// The real cyclic Fourier matrix `S` of Eqs. (90) (even `N`) and (91)
/// (odd `N`), orthogonal, with `x = Sᵀ x̂` for one dof per sector.
///
/// Columns are the sectors `j = 1..N`; rows are, in order, the mean
/// (`1/√N`), then `√(2/N) cos(h j α)` and `√(2/N) sin(h j α)` for
/// `h = 1..(N−1)/2`, and for even `N` the alternating row
/// `(−1)^j/√N` of nodal diameter `N/2`. With `sectors = 0` the matrix is
/// empty; with `sectors = 1` it is `[1]`.
pub fn real_cyclic_fourier_matrix(sectors: usize) -> Mat<f64> {
    let n = sectors;
    let mut s = Mat::<f64>::zeros(n, n);
    if n == 0 {
        return s;
    }
    let alpha = 2.0 * PI / n as f64;
    let mean = 1.0 / (n as f64).sqrt();
    let wave = (2.0 / n as f64).sqrt();
    for col in 0..n {
        s[(0, col)] = mean;
        let mut row = 1;
        let mut h = 1;
        while 2 * h < n {
            // Reduce the angle modulo 2π through integers to keep it exact.
            let angle = alpha * ((h * (col + 1)) % n) as f64;
            s[(row, col)] = wave * angle.cos();
            s[(row + 1, col)] = wave * angle.sin();
            row += 2;
            h += 1;
        }
        if n.is_multiple_of(2) {
            s[(row, col)] = if (col + 1).is_multiple_of(2) {
                mean
            } else {
                -mean
            };
        }
    }
    s
}

/// The zig-zag diagram (Eq. 49): the signed nodal diameter on which the
/// traveling wave `(−h, 1)` of engine order `h` (Eq. 48) lives on harmonic
/// `k`, that is `−k h` folded into `(−N/2, N/2]`.
///
/// Examples from the paper: `N = 24, h = 3` gives `−3, −6, −9, 12, 9` on
/// harmonics 1 to 5 (Eq. 77); `N = 45, h = 17` gives `−17, 11, −6, 22`
/// on harmonics 1 to 4 (Eq. 105).
pub fn zigzag(engine_order: i64, harmonic: i64, sectors: usize) -> i64 {
    let n = sectors.max(1) as i64;
    // Reduce before multiplying so that large orders cannot overflow.
    let h = engine_order.rem_euclid(n);
    let k = harmonic.rem_euclid(n);
    fold_nodal_diameter(-(h * k), sectors)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn small_matrices() {
        let s1 = real_cyclic_fourier_matrix(1);
        assert!((s1[(0, 0)] - 1.0).abs() < 1e-15);
        let s2 = real_cyclic_fourier_matrix(2);
        let r = 1.0 / 2f64.sqrt();
        assert!((s2[(1, 0)] + r).abs() < 1e-15 && (s2[(1, 1)] - r).abs() < 1e-15);
    }

    #[test]
    fn zigzag_folds_minus_k_h() {
        assert_eq!(zigzag(1, 8, 16), 8);
        assert_eq!(zigzag(1, 9, 16), 7);
        assert_eq!(zigzag(0, 5, 16), 0);
        assert_eq!(zigzag(3, 4, 1), 0);
    }
}
