//! Small complex vector operations of the Hill solvers (targeted and
//! condensed).

use faer::c64;

/// `aᴴb`.
pub(super) fn dot(a: &[c64], b: &[c64]) -> c64 {
    a.iter().zip(b).map(|(x, y)| x.conj() * y).sum()
}

/// Orthogonalizes `v` against the orthonormal `basis` (twice) and
/// normalizes it; false when nothing independent is left.
pub(super) fn orthonormalize(basis: &[Vec<c64>], v: &mut [c64]) -> bool {
    let before = norm(v);
    for _ in 0..2 {
        for q in basis {
            let h = dot(q, v);
            v.iter_mut().zip(q).for_each(|(x, y)| *x -= h * y);
        }
    }
    norm(v) > 1e-10 * before && normalize(v).is_some()
}

/// The Euclidean norm.
pub(super) fn norm(v: &[c64]) -> f64 {
    v.iter().map(|z| z.norm_sqr()).sum::<f64>().sqrt()
}

/// Scales `v` to unit norm; `None` when its norm is 0 or not finite.
pub(super) fn normalize(v: &mut [c64]) -> Option<()> {
    let norm = v.iter().map(|z| z.norm_sqr()).sum::<f64>().sqrt();
    if !(norm > 0.0 && norm.is_finite()) {
        return None;
    }
    v.iter_mut().for_each(|z| *z /= norm);
    Some(())
}
