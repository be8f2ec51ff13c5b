//! Symmetry classes of perturbations: the cosets of the solution's pair
//! subgroup `P` in `Z_N × Z` (docs/design.md §10).
//!
//! The linearized dynamics at a solution whose pairs lie in `P` couples a
//! perturbation pair `(s, k)` only with `(s, k) + P`, so Hill's matrix of
//! the full wheel is block diagonal over the cosets `(σ, 0) + P`, one per
//! `σ ∈ Z_N / P₀` (`P₀`: the nodal diameters `P` holds on harmonic 0, the
//! multiples of its diameter step `a`). Cosets `(σ, κ) + P` with a harmonic
//! offset `κ` give the same exponents shifted by `iκω`, the same Floquet
//! multipliers: they are not separate classes.

use crate::basis::PairLattice;
use crate::cyclic::{fold_nodal_diameter, HarmonicSet, SignedPair};

/// One class of perturbations: the pairs `(s, k)`, `|k| ≤ H`, of the coset
/// `(σ, 0) + P`.
#[derive(Clone, Debug, PartialEq)]
pub struct SymmetryClass {
    /// `σ`, the nodal diameter of the class's perturbations on harmonic 0
    /// (with every diameter `σ + P₀`), folded into `(−a/2, a/2]`.
    pub nodal_diameter: i64,
    /// The class of the complex-conjugate perturbations, `−σ` folded: its
    /// exponents are the conjugates of this class's. Equal to
    /// `nodal_diameter` for a class closed under conjugation.
    pub conjugate: i64,
    /// The pairs, by harmonic `k` from `−H` to `H`, then by diameter.
    pub pairs: Vec<SignedPair>,
    /// `|P₀|`: the class has `2 · dofs · |P₀|` physical exponents.
    pub diameters_at_rest: usize,
    /// The harmonic step `g` of `P` (harmonics hold pairs iff `g | k`; 0
    /// when only harmonic 0 does).
    pub harmonic_step: usize,
}

/// The classes of `lattice` truncated to harmonics `|k| ≤ harmonics`, in
/// increasing `σ`.
pub fn symmetry_classes(lattice: &PairLattice, harmonics: usize) -> Vec<SymmetryClass> {
    let sectors = lattice.sectors();
    let step = lattice.diameter_step() as i64;
    let g = lattice.harmonic_step() as i64;
    let mut sigmas: Vec<i64> = (0..step).map(|s| fold_modulo(s, step)).collect();
    sigmas.sort_unstable();
    sigmas
        .into_iter()
        .map(|sigma| {
            let mut pairs = Vec::new();
            for k in HarmonicSet::up_to(harmonics).signed() {
                let holds = if g == 0 { k == 0 } else { k % g == 0 };
                if !holds {
                    continue;
                }
                let mut diameters: Vec<i64> = (0..sectors as i64)
                    .filter(|&s| lattice.contains(s - sigma, k))
                    .map(|s| fold_nodal_diameter(s, sectors))
                    .collect();
                diameters.sort_unstable();
                pairs.extend(diameters.into_iter().map(|s| SignedPair {
                    nodal_diameter: s,
                    harmonic: k,
                }));
            }
            SymmetryClass {
                nodal_diameter: sigma,
                conjugate: fold_modulo(-sigma, step),
                pairs,
                diameters_at_rest: sectors / step as usize,
                harmonic_step: g as usize,
            }
        })
        .collect()
}

/// The number of pairs in each class of `lattice` truncated to
/// `|k| ≤ harmonics`, without listing them (every class has as many):
/// `|P₀|` diameters on each harmonic the lattice reaches. Saturates
/// instead of overflowing, so a memory check can refuse an absurd
/// truncation before anything is allocated.
pub fn pairs_per_class(lattice: &PairLattice, harmonics: usize) -> usize {
    let diameters = lattice.sectors() / lattice.diameter_step().max(1);
    let reached = match lattice.harmonic_step() {
        0 => 1,
        g => (harmonics / g).saturating_mul(2).saturating_add(1),
    };
    diameters.saturating_mul(reached)
}

/// `value` modulo `modulus`, folded into `(−modulus/2, modulus/2]`.
fn fold_modulo(value: i64, modulus: i64) -> i64 {
    let r = value.rem_euclid(modulus);
    if 2 * r > modulus {
        r - modulus
    } else {
        r
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn lattice(sectors: usize, pairs: &[(i64, i64)]) -> PairLattice {
        let pairs: Vec<SignedPair> = pairs
            .iter()
            .map(|&(s, k)| SignedPair::new(s, k, sectors))
            .collect();
        PairLattice::generated_by(sectors, &pairs).unwrap()
    }

    #[test]
    fn the_classes_partition_every_pair_of_the_full_wheel() {
        // Traveling h = 1, standing h = 1, the mixed case of Sec. 4.3.3 and
        // a casing alone: every pair (s, k), |k| ≤ H, of a harmonic that P
        // reaches lies in exactly one class; the counts are N / |P₀| classes
        // of |P₀| diameters per harmonic.
        let cases: [(usize, &[(i64, i64)]); 4] = [
            (24, &[(-1, 1)]),
            (24, &[(-1, 1), (1, 1)]),
            (24, &[(-6, 1), (8, 8)]),
            (16, &[(4, 4)]),
        ];
        for (n, generators) in cases {
            let l = lattice(n, generators);
            let classes = symmetry_classes(&l, 5);
            assert_eq!(classes.len(), l.diameter_step());
            let mut seen = std::collections::BTreeSet::new();
            for class in &classes {
                for pair in &class.pairs {
                    assert!(seen.insert((pair.nodal_diameter, pair.harmonic)));
                    assert!(l.contains(pair.nodal_diameter - class.nodal_diameter, pair.harmonic));
                }
                let conjugate = classes
                    .iter()
                    .find(|c| c.nodal_diameter == class.conjugate)
                    .unwrap();
                // The conjugate class holds (−s, −k) of every pair.
                for pair in &class.pairs {
                    let c = pair.conjugate(n);
                    assert!(conjugate.pairs.contains(&c));
                }
            }
            let g = l.harmonic_step() as i64;
            let harmonics = (-5..=5_i64)
                .filter(|k| if g == 0 { *k == 0 } else { k % g == 0 })
                .count();
            assert_eq!(seen.len(), n * harmonics, "{generators:?}");
            for truncation in [0, 1, 4, 5, 7] {
                let listed = symmetry_classes(&l, truncation);
                for class in &listed {
                    assert_eq!(class.pairs.len(), pairs_per_class(&l, truncation));
                }
            }
        }
    }

    #[test]
    fn a_traveling_wave_has_one_class_per_nodal_diameter() {
        let classes = symmetry_classes(&lattice(24, &[(-1, 1)]), 10);
        assert_eq!(classes.len(), 24);
        let class = classes.iter().find(|c| c.nodal_diameter == 3).unwrap();
        assert_eq!(class.conjugate, -3);
        assert_eq!(class.pairs.len(), 21);
        // Harmonic k carries diameter σ − k: (3 − k, k).
        assert!(class.pairs.contains(&SignedPair::new(2, 1, 24)));
        assert!(class.pairs.contains(&SignedPair::new(5, -2, 24)));
        assert_eq!(class.diameters_at_rest, 1);
    }
}
