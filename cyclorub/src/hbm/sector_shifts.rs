//! Which sectors repeat another sector's time signals at a point, shifted
//! by a whole number of time samples: the recovery computes each signal
//! once and carries it to the sectors that repeat it.
//!
//! A solution in the basis's pair set `P` (docs/design.md §3) satisfies
//! `X_k(j + m) = X_k(j) e^{ikτ}` for every harmonic `k` of sector `j`
//! whenever `e^{−i s α m} = e^{i k τ}` for every pair `(s, k)` of the basis:
//! sector `j + m` moves as sector `j` does, `τ/ω` later. When
//! `τ = 2π r / N_t`, its samples are sector `j`'s rotated by `r`, so their
//! extremes and counts are the same, and its force's harmonics are sector
//! `j`'s times `e^{ikτ}`. The gap's samples are checked to repeat the same
//! way before a sector is carried over.

use crate::hbm::layout::{BlockKind, Layout};

/// For every sector, the earlier sector whose samples it repeats and the
/// rotation `r` (sample `n` of the sector is sample `n + r` of its source),
/// or `None` when it is computed itself.
pub(crate) fn sector_sources(
    layout: &Layout,
    time_samples: usize,
    gaps: &[Vec<f64>],
) -> Vec<Option<(usize, usize)>> {
    let n = layout.sectors;
    let mut sources = vec![None; n];
    let pairs: Option<Vec<(i64, i64)>> = layout
        .blocks
        .iter()
        .map(|b| match b.kind {
            BlockKind::Pair { nodal_diameter } => Some((nodal_diameter, b.harmonic as i64)),
            BlockKind::Wheel => None,
        })
        .collect();
    let Some(pairs) = pairs else {
        return sources;
    };
    let shifts: Vec<Option<usize>> = (0..n)
        .map(|m| rotation(&pairs, n as i64, time_samples as i64, m as i64))
        .collect();
    // The gaps of the contact dofs that have one (the normal dofs).
    let contact_dofs = gaps.len() / n;
    let mut computed: Vec<usize> = Vec::new();
    for j in 0..n {
        let found = computed.iter().find_map(|&i| {
            let r = shifts[j - i]?;
            let repeats = (0..contact_dofs)
                .all(|c| rotated(&gaps[j * contact_dofs + c], &gaps[i * contact_dofs + c], r));
            repeats.then_some((i, r))
        });
        match found {
            Some(source) => sources[j] = Some(source),
            None => computed.push(j),
        }
    }
    sources
}

/// The rotation `r ∈ 0..N_t` with `−s m / N − k r / N_t ∈ Z` for every
/// pair `(s, k)`, if there is one.
fn rotation(pairs: &[(i64, i64)], sectors: i64, samples: i64, m: i64) -> Option<usize> {
    let period = i128::from(sectors) * i128::from(samples);
    // −s m N_t − k r N ≡ 0 (mod N N_t)
    let holds = |r: i128| {
        pairs.iter().all(|&(s, k)| {
            let value = -i128::from(s) * i128::from(m) * i128::from(samples)
                - i128::from(k) * r * i128::from(sectors);
            value.rem_euclid(period) == 0
        })
    };
    let Some(&(s, k)) = pairs.iter().filter(|p| p.1 > 0).min_by_key(|p| p.1) else {
        return holds(0).then_some(0);
    };
    // k N r ≡ −s m N_t (mod N N_t): a linear congruence in r.
    let a = i128::from(k) * i128::from(sectors);
    let b = (-i128::from(s) * i128::from(m) * i128::from(samples)).rem_euclid(period);
    let g = gcd(a, period);
    if b % g != 0 {
        return None;
    }
    let modulus = period / g;
    let first = ((b / g) * inverse(a / g, modulus)?).rem_euclid(modulus);
    let mut r = first;
    while r < i128::from(samples) {
        if holds(r) {
            return usize::try_from(r).ok();
        }
        r += modulus;
    }
    None
}

/// Whether `signal[n] = source[(n + r) mod N_t]` for every `n`, to round-off.
fn rotated(signal: &[f64], source: &[f64], r: usize) -> bool {
    let len = signal.len();
    if len != source.len() || len == 0 {
        return len == source.len();
    }
    let scale = source
        .iter()
        .fold(0.0_f64, |m, v| m.max(v.abs()))
        .max(f64::MIN_POSITIVE);
    signal
        .iter()
        .enumerate()
        .all(|(i, v)| (v - source[(i + r) % len]).abs() <= 1e-12 * scale)
}

fn gcd(a: i128, b: i128) -> i128 {
    let (mut a, mut b) = (a.abs(), b.abs());
    while b != 0 {
        (a, b) = (b, a % b);
    }
    a
}

/// `a⁻¹ mod modulus`, for `a` prime to it.
fn inverse(a: i128, modulus: i128) -> Option<i128> {
    if modulus == 1 {
        return Some(0);
    }
    let (mut old_r, mut r) = (a.rem_euclid(modulus), modulus);
    let (mut old_s, mut s) = (1_i128, 0_i128);
    while r != 0 {
        let q = old_r / r;
        (old_r, r) = (r, old_r - q * r);
        (old_s, s) = (s, old_s - q * s);
    }
    (old_r == 1).then(|| old_s.rem_euclid(modulus))
}

/// The harmonic coordinates `[a0, Re X1, Im X1, …]` of a signal delayed as
/// sector `j + m` is on sector `j`: `X_k e^{i k 2π r / N_t}`.
pub(crate) fn rotate_coordinates(coordinates: &[f64], r: usize, time_samples: usize) -> Vec<f64> {
    let mut out = coordinates.to_vec();
    let angle = 2.0 * std::f64::consts::PI * r as f64 / time_samples as f64;
    for k in 1..=(coordinates.len().saturating_sub(1)) / 2 {
        let (sin, cos) = (k as f64 * angle).sin_cos();
        let (re, im) = (coordinates[2 * k - 1], coordinates[2 * k]);
        out[2 * k - 1] = re * cos - im * sin;
        out[2 * k] = re * sin + im * cos;
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_traveling_wave_repeats_every_sector_whose_delay_is_whole_samples() {
        // (−k, k) for k = 1..3 on N = 24 and the circular casing (0, 0):
        // sector m is sector 0 delayed by m/24 of a period.
        let pairs: Vec<(i64, i64)> = (0..=3).map(|k| (-k, k)).collect();
        for m in 0..24 {
            let r = rotation(&pairs, 24, 10_000, m);
            if m % 3 == 0 {
                assert_eq!(r, Some((m as usize * 10_000 / 24) % 10_000));
            } else {
                assert_eq!(r, None, "sector {m}");
            }
            assert_eq!(rotation(&pairs, 24, 240, m), Some(m as usize * 10));
        }
        // A standing wave (±1, 1) does not travel: only m = 0 and the
        // half-turn (m = 12, a half-period delay) repeat.
        let standing = [(0, 0), (1, 1), (-1, 1)];
        let repeating: Vec<i64> = (0..24)
            .filter(|&m| rotation(&standing, 24, 240, m).is_some())
            .collect();
        assert_eq!(repeating, vec![0, 12]);
        assert_eq!(rotation(&standing, 24, 240, 12), Some(120));
    }

    #[test]
    fn rotated_coordinates_are_the_delayed_signal() {
        use crate::hbm::aft::Aft;
        let (harmonics, samples, r) = (3, 48, 5);
        let coordinates = [0.3, 1.0, -0.5, 0.25, 0.7, -0.1, 0.05];
        let mut aft = Aft::new(harmonics, samples);
        let mut signal = vec![0.0; samples];
        let mut delayed = vec![0.0; samples];
        aft.to_time(&coordinates, &mut signal);
        aft.to_time(&rotate_coordinates(&coordinates, r, samples), &mut delayed);
        for n in 0..samples {
            assert!((delayed[n] - signal[(n + r) % samples]).abs() < 1e-14);
        }
        assert!(rotated(&delayed, &signal, r));
        assert!(!rotated(&delayed, &signal, r + 1));
    }
}
