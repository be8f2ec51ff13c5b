//! The set of temporal harmonics a harmonic balance holds (docs/design.md
//! §5): which harmonics, in which order, where each sits among a signal's
//! real harmonic coordinates, and how finely a period must be sampled.
//!
//! Today every layout holds all harmonics `0..=N_h`; a basis may leave a
//! harmonic without pairs, but the harmonic is still in the set (its
//! coordinates exist, they are zero). Per-harmonic truncation or a
//! quasi-periodic set would change this type, not its users.
//!
//! Real harmonic coordinates of a signal, length `2 N_h + 1`:
//! `[a0, Re X1, Im X1, …, Re X_Nh, Im X_Nh]` for
//! `u(τ) = a0 + Σ_k 2 Re(X_k e^{i k τ})`.

use std::ops::{Range, RangeInclusive};

/// The harmonics `0..=N_h` of a periodic balance, in ascending order.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct HarmonicSet {
    highest: usize,
}

impl HarmonicSet {
    /// Every harmonic `0..=highest` (`highest = N_h`).
    pub fn up_to(highest: usize) -> Self {
        Self { highest }
    }

    /// The set whose signals have `coordinates` real harmonic coordinates
    /// (`2 N_h + 1`); `None` for an even count, which no set has.
    pub fn from_coordinates(coordinates: usize) -> Option<Self> {
        (!coordinates.is_multiple_of(2)).then(|| Self::up_to((coordinates - 1) / 2))
    }

    /// The highest harmonic `N_h`.
    pub fn highest(&self) -> usize {
        self.highest
    }

    /// How many harmonics the set holds, `N_h + 1`.
    pub fn count(&self) -> usize {
        self.highest + 1
    }

    /// Whether harmonic `k` is in the set.
    pub fn contains(&self, harmonic: usize) -> bool {
        harmonic <= self.highest
    }

    /// The harmonics in the set's order (ascending, `0` first).
    pub fn iter(&self) -> RangeInclusive<usize> {
        0..=self.highest
    }

    /// The harmonics above the static one, `1..=N_h`: those with a
    /// complex coefficient.
    pub fn oscillating(&self) -> RangeInclusive<usize> {
        1..=self.highest
    }

    /// The signed harmonics `−N_h..=N_h` of a complex (Hill) expansion.
    pub fn signed(&self) -> RangeInclusive<i64> {
        let h = self.highest as i64;
        -h..=h
    }

    /// Position of harmonic `k` in the set's order (`None` outside): the
    /// row of per-harmonic tables such as the cyclic components.
    pub fn position(&self, harmonic: usize) -> Option<usize> {
        self.contains(harmonic).then_some(harmonic)
    }

    /// Real unknowns of one complex amplitude on harmonic `k`: 1 on the
    /// static harmonic (real), 2 (real and imaginary parts) above it.
    pub fn real_parts(harmonic: usize) -> usize {
        if harmonic == 0 {
            1
        } else {
            2
        }
    }

    /// Length of a signal's real harmonic coordinates, `2 N_h + 1`.
    pub fn coordinates(&self) -> usize {
        self.iter().map(Self::real_parts).sum()
    }

    /// Where harmonic `k` sits among the real harmonic coordinates: `0..1`
    /// for `a0`, `2k − 1..2k + 1` for `(Re X_k, Im X_k)`.
    pub fn coordinate_range(harmonic: usize) -> Range<usize> {
        if harmonic == 0 {
            0..1
        } else {
            2 * harmonic - 1..2 * harmonic + 1
        }
    }

    /// The coefficient `(Re X_k, Im X_k)` of harmonic `k` in `coordinates`
    /// (`(a0, 0)` on the static harmonic).
    ///
    /// # Panics
    /// If `coordinates` is shorter than the set's coordinates.
    pub fn coefficient(coordinates: &[f64], harmonic: usize) -> (f64, f64) {
        if harmonic == 0 {
            (coordinates[0], 0.0)
        } else {
            (coordinates[2 * harmonic - 1], coordinates[2 * harmonic])
        }
    }

    /// The fewest instants per period on which a signal of the set and its
    /// samples determine each other (the AFT's transforms exact):
    /// `2 N_h + 1`, the check of `harmonic_balance.time_samples`.
    pub fn min_time_samples(&self) -> usize {
        2 * self.highest + 1
    }

    /// The fewest instants per period on which the spectrum of a product
    /// `d · u`, `u` of the set, is alias-free on every coupling between two
    /// harmonics of the set (the derivative's coefficients up to `2 N_h`):
    /// `4 N_h + 1`, the sampling of Hill's contact stiffness.
    pub fn coupling_time_samples(&self) -> usize {
        4 * self.highest + 1
    }
}

impl IntoIterator for HarmonicSet {
    type Item = usize;
    type IntoIter = RangeInclusive<usize>;

    fn into_iter(self) -> Self::IntoIter {
        self.iter()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn counts_and_coordinates_of_a_set() {
        for h in 0..7 {
            let set = HarmonicSet::up_to(h);
            assert_eq!(set.count(), h + 1);
            assert_eq!(set.iter().count(), set.count());
            assert_eq!(set.coordinates(), 2 * h + 1);
            assert_eq!(HarmonicSet::from_coordinates(2 * h + 1), Some(set));
            assert_eq!(HarmonicSet::from_coordinates(2 * h + 2), None);
            assert_eq!(set.signed().count(), 2 * h + 1);
            // The coordinate ranges tile 0..2 N_h + 1 in the set's order.
            let mut next = 0;
            for k in set {
                let range = HarmonicSet::coordinate_range(k);
                assert_eq!(range.start, next);
                assert_eq!(range.len(), HarmonicSet::real_parts(k));
                next = range.end;
                assert_eq!(set.position(k), Some(k));
            }
            assert_eq!(next, set.coordinates());
            assert!(!set.contains(h + 1) && set.position(h + 1).is_none());
        }
    }
}
