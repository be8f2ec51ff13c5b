//! The sector maps of every basis kind are invertible and well conditioned
//! for every N ≤ 150 (docs/design.md §5: cosets of subgroups give scaled DFTs).

use cyclorub::basis::{
    condition_number, condition_number_bound, sector_map, sector_map_inverse, SpectralBasis,
};
use cyclorub::cyclic::{ExcitationPattern, LoadCase};
use faer::c64;
use std::collections::HashSet;

const NH: usize = 10;

/// Every basis we build for `N` sectors: full, traveling-wave hypothesis,
/// nodal-diameter rule with and without parity, and the paper's, the
/// nodal-diameter and the symmetry rule's bases for traveling, standing and
/// mixed loads, alone and with two casing orders.
fn every_basis(n: usize) -> Vec<SpectralBasis> {
    let mut bases = vec![SpectralBasis::full(n, NH).unwrap()];
    for h in 0..=n / 2 {
        bases.push(SpectralBasis::traveling_wave(n, NH, h).unwrap());
        for parity in [false, true] {
            bases.push(SpectralBasis::nodal_diameter_rule(n, NH, &[h], parity).unwrap());
        }
        let patterns = [
            ExcitationPattern::Traveling { engine_order: h },
            ExcitationPattern::Standing { engine_order: h },
            ExcitationPattern::Mixed {
                engine_order: h,
                backward_weight: 0.9,
                forward_weight: 0.1,
            },
        ];
        for excitation in patterns {
            for casing_order in [None, Some((h + 1) % n), Some((2 * h + 3) % n)] {
                let load = LoadCase {
                    sectors: n,
                    excitation: Some(excitation.clone()),
                    casing_order,
                };
                bases.push(SpectralBasis::paper(&load, NH).unwrap());
                bases.push(SpectralBasis::symmetry(&load, NH).unwrap());
                bases.push(SpectralBasis::nodal_diameter(&load, NH).unwrap());
            }
        }
    }
    bases
}

/// A set shifted so that its first diameter is 0 (modulo `N`): shifting
/// every diameter by `t` multiplies the sector map on the left by the
/// unitary `diag(exp(−i t α j))`, which changes neither invertibility nor
/// the condition number, so one check per shape is enough.
fn shape(n: usize, set: &[i64]) -> Vec<i64> {
    let n = n as i64;
    let mut shifted: Vec<i64> = set.iter().map(|s| (s - set[0]).rem_euclid(n)).collect();
    shifted.sort_unstable();
    shifted
}

/// `|V (V⁻¹ x) − x| / |x|` for a few fixed pseudo-random `x` (products by
/// hand: O(n²), cheap even unoptimized).
fn inverse_residual(v: &faer::Mat<c64>, inverse: &faer::Mat<c64>) -> f64 {
    let n = v.nrows();
    let mut worst: f64 = 0.0;
    let mut state: u64 = 0x9e37_79b9_7f4a_7c15;
    for _ in 0..3 {
        let x: Vec<c64> = (0..n)
            .map(|_| {
                state = state
                    .wrapping_mul(6364136223846793005)
                    .wrapping_add(1442695040888963407);
                let a = (state >> 11) as f64 / (1u64 << 53) as f64 - 0.5;
                state = state
                    .wrapping_mul(6364136223846793005)
                    .wrapping_add(1442695040888963407);
                let b = (state >> 11) as f64 / (1u64 << 53) as f64 - 0.5;
                c64::new(a, b)
            })
            .collect();
        let y: Vec<c64> = (0..n)
            .map(|i| (0..n).map(|j| inverse[(i, j)] * x[j]).sum())
            .collect();
        let mut err = 0.0;
        let mut norm = 0.0;
        for i in 0..n {
            let vy: c64 = (0..n).map(|j| v[(i, j)] * y[j]).sum();
            err += (vy - x[i]).norm_sqr();
            norm += x[i].norm_sqr();
        }
        worst = worst.max((err / norm).sqrt());
    }
    worst
}

#[test]
fn sector_maps_are_invertible_and_well_conditioned_up_to_150_sectors() {
    let mut worst_bound: f64 = 1.0;
    let mut worst_svd: f64 = 1.0;
    let mut worst_residual: f64 = 0.0;
    let mut shapes = 0;
    for n in 1..=150usize {
        let mut seen: HashSet<Vec<i64>> = HashSet::new();
        for basis in every_basis(n) {
            for k in 0..=NH {
                let set = basis.nodal_diameters(k);
                if set.is_empty() || !seen.insert(shape(n, set)) {
                    continue;
                }
                shapes += 1;
                let v = sector_map(n, set);
                let inverse = sector_map_inverse(n, set)
                    .unwrap_or_else(|e| panic!("N = {n}, k = {k}, {set:?}: {e}"));
                let bound = condition_number_bound(n, set);
                assert!(bound < 1e3, "N = {n}, set {set:?}: condition ≤ {bound:e}");
                worst_bound = worst_bound.max(bound);
                worst_residual = worst_residual.max(inverse_residual(&v, &inverse));
                // The exact value, by the singular values.
                let exact = condition_number(v.as_ref());
                assert!(exact < 1e3, "N = {n}, set {set:?}: condition {exact:e}");
                assert!(
                    exact <= bound * (1.0 + 1e-9),
                    "N = {n}, {set:?}: {exact} > {bound}"
                );
                worst_svd = worst_svd.max(exact);
            }
        }
    }
    eprintln!(
        "{shapes} set shapes: worst condition bound 1 + {:.3e}, worst SVD condition \
         1 + {:.3e}, worst |V V⁻¹ x − x|/|x| {worst_residual:.3e}",
        worst_bound - 1.0,
        worst_svd - 1.0
    );
    assert!(worst_bound < 1.0 + 1e-9, "cosets should give scaled DFTs");
    assert!(worst_svd < 1.0 + 1e-9);
    assert!(worst_residual < 1e-12);
}

/// The map sends pair coefficients to sector coefficients: check `X = V c`
/// against the wave `exp(−i s α (j − 1))` sector by sector.
#[test]
fn sector_map_samples_the_waves() {
    let n = 24;
    let set = [-6, 2, 10];
    let v = sector_map(n, &set);
    let alpha = 2.0 * std::f64::consts::PI / n as f64;
    for (p, &s) in set.iter().enumerate() {
        for j in 0..3 {
            let angle = -(s as f64) * alpha * j as f64;
            assert!((v[(j, p)] - c64::new(angle.cos(), angle.sin())).norm() < 1e-14);
        }
    }
    let basis = SpectralBasis::full(n, 2).unwrap();
    assert_eq!(basis.sector_map(1).nrows(), n);
    assert!(basis.sector_map_inverse(1).is_ok());
}

/// A non-coset set is still invertible (Vandermonde of distinct roots) but
/// can be badly conditioned: the helper must see it.
#[test]
fn condition_number_sees_clustered_diameters() {
    let v = sector_map(150, &[0, 1, 2, 3]);
    let c = condition_number(v.as_ref());
    assert!(c > 1e3, "clustered roots of unity: condition {c:e}");
    assert!(condition_number_bound(150, &[0, 1, 2, 3]) >= c);
    // Not a coset: the LU path, still an inverse.
    let inverse = sector_map_inverse(150, &[0, 1, 2, 3]).unwrap();
    assert!(inverse_residual(&v, &inverse) < 1e-6);
    // A non-coset set spread out enough for the bound to be finite.
    let set = [0, 37, 75, 112, 20];
    let exact = condition_number(sector_map(150, &set).as_ref());
    let bound = condition_number_bound(150, &set);
    assert!(exact > 1.0 + 1e-6 && exact <= bound, "{exact} vs {bound}");
}
