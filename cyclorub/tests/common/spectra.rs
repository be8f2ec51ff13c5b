//! Comparing spectra: exponents or multipliers matched one to one.
#![allow(dead_code)]

use cyclorub::stability::Exponent;
use faer::c64;

/// Pairs each of `a` with the nearest unused of `b`; the largest distance.
pub fn largest_mismatch(a: &[c64], b: &[c64]) -> f64 {
    assert_eq!(a.len(), b.len());
    let mut used = vec![false; b.len()];
    let mut worst = 0.0_f64;
    for x in a {
        let (j, d) = b
            .iter()
            .enumerate()
            .filter(|(j, _)| !used[*j])
            .map(|(j, y)| (j, (x - y).norm()))
            .min_by(|p, q| p.1.total_cmp(&q.1))
            .unwrap();
        used[j] = true;
        worst = worst.max(d);
    }
    worst
}

pub fn values(exponents: &[Exponent]) -> Vec<c64> {
    exponents.iter().map(Exponent::value).collect()
}
