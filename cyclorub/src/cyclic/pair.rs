//! Signed pairs `(s, k)`: the spatio-temporal wave `exp(i(k ω t − s α (j−1)))`.

use serde::Serialize;

/// A signed pair `(s, k)`: the wave `exp(i(k ω t − s α (j−1)))` on sectors
/// `j = 1..N`. `s > 0` travels forward in blade numbering, `s < 0` backward.
/// A real field holding `(s, k)` also holds its conjugate `(−s, −k)`.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord, Serialize)]
pub struct SignedPair {
    /// Signed nodal diameter `s`, folded into `(−N/2, N/2]`.
    pub nodal_diameter: i64,
    /// Temporal harmonic `k` (may be negative only for conjugates).
    pub harmonic: i64,
}

impl SignedPair {
    /// The pair `(s mod N, k)` with `s` folded into `(−N/2, N/2]`.
    pub fn new(nodal_diameter: i64, harmonic: i64, sectors: usize) -> Self {
        Self {
            nodal_diameter: fold_nodal_diameter(nodal_diameter, sectors),
            harmonic,
        }
    }

    /// The conjugate pair `(−s, −k)`.
    pub fn conjugate(self, sectors: usize) -> Self {
        Self::new(-self.nodal_diameter, -self.harmonic, sectors)
    }
}

/// Folds a signed nodal diameter into `(−N/2, N/2]` (modulo `N`).
///
/// `sectors` must be at least 1; with one sector every diameter is 0.
pub fn fold_nodal_diameter(nodal_diameter: i64, sectors: usize) -> i64 {
    let n = sectors.max(1) as i64;
    let r = nodal_diameter.rem_euclid(n);
    // r in [0, N): shift the upper half down so the result is in (−N/2, N/2].
    if 2 * r > n {
        r - n
    } else {
        r
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn folding_is_into_the_half_open_interval() {
        assert_eq!(fold_nodal_diameter(12, 24), 12);
        assert_eq!(fold_nodal_diameter(-12, 24), 12);
        assert_eq!(fold_nodal_diameter(13, 24), -11);
        assert_eq!(fold_nodal_diameter(-1, 24), -1);
        assert_eq!(fold_nodal_diameter(23, 45), 23 - 45);
        assert_eq!(fold_nodal_diameter(22, 45), 22);
        assert_eq!(fold_nodal_diameter(5, 1), 0);
        for n in 1..30usize {
            for s in -100..100 {
                let f = fold_nodal_diameter(s, n);
                assert!(2 * f > -(n as i64) && 2 * f <= n as i64);
                assert_eq!((f - s).rem_euclid(n as i64), 0);
            }
        }
    }
}
