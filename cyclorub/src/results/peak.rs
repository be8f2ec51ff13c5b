//! The largest value of a periodic signal given by its harmonic
//! coordinates, between the time samples as well as on them.
//!
//! `branch.csv`'s amplitude is the largest of the run's `N_t` samples (what
//! the solver's own transform sees); a history recovered at a few samples
//! (`cyclorub recover --time-samples 8`) would understate the crest by up
//! to `1 − cos(π H / N_t)` of it. [`continuous_peak`] finds the crest of
//! the trigonometric polynomial itself.

use std::f64::consts::PI;

/// Grid points per harmonic where the crest is first bracketed: with 16
/// per harmonic, every local maximum of a polynomial of degree `H` lies
/// within a grid cell of a grid point that is the largest of its cell's
/// neighbours, and Newton converges from there.
const GRID_PER_HARMONIC: usize = 16;

/// `x(τ) = a0 + 2 Σ_k (Re X_k cos kτ − Im X_k sin kτ)` and its first two
/// derivatives, `coordinates = [a0, Re X1, Im X1, …]`.
fn value_and_derivatives(coordinates: &[f64], tau: f64) -> (f64, f64, f64) {
    let mut value = coordinates.first().copied().unwrap_or(0.0);
    let (mut first, mut second) = (0.0, 0.0);
    for (k, pair) in coordinates.get(1..).unwrap_or(&[]).chunks(2).enumerate() {
        let k = (k + 1) as f64;
        let (re, im) = (pair[0], pair.get(1).copied().unwrap_or(0.0));
        let (sin, cos) = (k * tau).sin_cos();
        value += 2.0 * (re * cos - im * sin);
        first += 2.0 * k * (-re * sin - im * cos);
        second += 2.0 * k * k * (-re * cos + im * sin);
    }
    (value, first, second)
}

/// The largest value over the period of the signal with harmonic
/// coordinates `[a0, Re X1, Im X1, …]` (as [`super::recovery::DofHistory`]
/// holds them): the largest of a grid of `16 H` points, refined by Newton
/// on the derivative within the grid cells around each of the three
/// largest grid points (a refinement that leaves its cell or lowers the
/// value is not taken).
pub fn continuous_peak(coordinates: &[f64]) -> f64 {
    let harmonics = coordinates.len().saturating_sub(1).div_ceil(2);
    if harmonics == 0 {
        return coordinates.first().copied().unwrap_or(0.0);
    }
    let grid = GRID_PER_HARMONIC * harmonics;
    let cell = 2.0 * PI / grid as f64;
    let mut sampled: Vec<(f64, f64)> = (0..grid)
        .map(|n| {
            let tau = cell * n as f64;
            (value_and_derivatives(coordinates, tau).0, tau)
        })
        .collect();
    sampled.sort_by(|a, b| b.0.total_cmp(&a.0));
    let mut best = sampled[0].0;
    for &(start_value, start) in sampled.iter().take(3) {
        let mut tau = start;
        for _ in 0..20 {
            let (_, first, second) = value_and_derivatives(coordinates, tau);
            if second >= 0.0 || first == 0.0 {
                break;
            }
            let step = -first / second;
            tau += step;
            if (tau - start).abs() > cell || step.abs() < 1e-15 * (1.0 + tau.abs()) {
                break;
            }
        }
        if (tau - start).abs() <= cell {
            let value = value_and_derivatives(coordinates, tau).0;
            if value >= start_value {
                best = best.max(value);
            }
        }
    }
    best
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::hbm::aft::Aft;

    /// A reproducible pseudo-random number in `[-1, 1)`.
    fn value(seed: u64) -> f64 {
        let x = seed
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        (x >> 11) as f64 / (1u64 << 52) as f64 - 1.0
    }

    #[test]
    fn the_crest_of_a_cosine_is_its_mean_plus_its_amplitude() {
        // 0.1 + 2·|0.3 − 0.4i| cos(τ + φ): crest 0.1 + 1.0.
        let peak = continuous_peak(&[0.1, 0.3, -0.4]);
        assert!((peak - 1.1).abs() < 1e-14, "{peak}");
        assert!((continuous_peak(&[0.25]) - 0.25).abs() < 1e-15);
    }

    #[test]
    fn the_crest_is_above_every_sample_and_reached_by_a_fine_sampling() {
        for case in 0..40u64 {
            let harmonics = 1 + (case % 10) as usize;
            // Harmonics decaying like a contact response's, some random.
            let coordinates: Vec<f64> = (0..(2 * harmonics + 1))
                .map(|i| value(case * 1000 + i as u64) / (1.0 + (i / 2) as f64))
                .collect();
            let peak = continuous_peak(&coordinates);
            let fine = 200_003;
            let mut aft = Aft::new(harmonics, fine);
            let mut samples = vec![0.0; fine];
            aft.to_time(&coordinates, &mut samples);
            let sampled = samples.iter().cloned().fold(f64::NEG_INFINITY, f64::max);
            // A sample is never above the crest; the finest sampling comes
            // within its own resolution, (2π H / N)²/2 of the range.
            let scale = coordinates.iter().map(|c| c.abs()).sum::<f64>();
            assert!(
                sampled <= peak + 1e-13 * scale,
                "case {case}: {sampled} > {peak}"
            );
            let resolution = 0.5 * (2.0 * PI * harmonics as f64 / fine as f64).powi(2) * scale;
            assert!(
                peak - sampled <= resolution + 1e-13 * scale,
                "case {case}: {peak} vs {sampled}"
            );
        }
    }
}
