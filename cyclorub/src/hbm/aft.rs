//! The alternating frequency/time transform of one real signal (Sec. 3.4.1,
//! steps 2–4), with real FFTs planned once and buffers reused.
//!
//! Real harmonic coordinates of a signal with `N_h` harmonics, length
//! `H = 2 N_h + 1`: `[a0, Re X1, Im X1, …, Re X_Nh, Im X_Nh]` for
//! `u(τ) = a0 + Σ_k 2 Re(X_k e^{i k τ})`, `τ = ω t`, sampled at
//! `τ_n = 2π n / N_t`.

use crate::cyclic::HarmonicSet;
use realfft::num_complex::Complex;
use realfft::{ComplexToReal, RealFftPlanner, RealToComplex};
use std::sync::Arc;

/// Plans and buffers for one `(N_h, N_t)`; not shared between threads (a
/// clone shares the plans and has buffers of its own).
#[derive(Clone)]
pub struct Aft {
    harmonic_set: HarmonicSet,
    time_samples: usize,
    forward: Arc<dyn RealToComplex<f64>>,
    inverse: Arc<dyn ComplexToReal<f64>>,
    time_buffer: Vec<f64>,
    spectrum: Vec<Complex<f64>>,
    forward_scratch: Vec<Complex<f64>>,
    inverse_scratch: Vec<Complex<f64>>,
    /// Discrete spectrum of a derivative signal, indices `0..=2 N_h`.
    derivative_spectrum: Vec<Complex<f64>>,
}

impl std::fmt::Debug for Aft {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Aft")
            .field("harmonics", &self.harmonic_set.highest())
            .field("time_samples", &self.time_samples)
            .finish()
    }
}

impl Aft {
    /// Plans for `harmonics` harmonics on `time_samples ≥ 2 harmonics + 1` instants.
    ///
    /// The caller checks the sampling (the case file does, naming the key).
    pub fn new(harmonics: usize, time_samples: usize) -> Self {
        Self::for_set(HarmonicSet::up_to(harmonics), time_samples)
    }

    /// Plans for the harmonics of `harmonic_set` on `time_samples` instants,
    /// at least [`HarmonicSet::min_time_samples`].
    pub fn for_set(harmonic_set: HarmonicSet, time_samples: usize) -> Self {
        debug_assert!(time_samples >= harmonic_set.min_time_samples());
        let mut planner = RealFftPlanner::<f64>::new();
        Self::with_plans(
            harmonic_set,
            time_samples,
            planner.plan_fft_forward(time_samples),
            planner.plan_fft_inverse(time_samples),
        )
    }

    fn with_plans(
        harmonic_set: HarmonicSet,
        time_samples: usize,
        forward: Arc<dyn RealToComplex<f64>>,
        inverse: Arc<dyn ComplexToReal<f64>>,
    ) -> Self {
        Self {
            harmonic_set,
            time_samples,
            time_buffer: vec![0.0; time_samples],
            spectrum: vec![Complex::new(0.0, 0.0); time_samples / 2 + 1],
            forward_scratch: forward.make_scratch_vec(),
            inverse_scratch: inverse.make_scratch_vec(),
            forward,
            inverse,
            // The derivative's coefficients 0..=2 N_h: every coupling of two harmonics.
            derivative_spectrum: vec![Complex::new(0.0, 0.0); 2 * harmonic_set.highest() + 1],
        }
    }

    /// The same plans (same instants) for the harmonics of `harmonic_set`,
    /// with buffers of its own: no planning.
    pub fn with_set(&self, harmonic_set: HarmonicSet) -> Self {
        debug_assert!(self.time_samples >= harmonic_set.min_time_samples());
        Self::with_plans(
            harmonic_set,
            self.time_samples,
            Arc::clone(&self.forward),
            Arc::clone(&self.inverse),
        )
    }

    /// `N_h`.
    pub fn harmonics(&self) -> usize {
        self.harmonic_set.highest()
    }

    /// The harmonics transformed.
    pub fn harmonic_set(&self) -> HarmonicSet {
        self.harmonic_set
    }

    /// `N_t`.
    pub fn time_samples(&self) -> usize {
        self.time_samples
    }

    /// The forward real FFT of `time_buffer` into `spectrum` (both sized at
    /// planning: realfft has nothing to refuse).
    fn forward_transform(&mut self) {
        self.forward
            .process_with_scratch(
                &mut self.time_buffer,
                &mut self.spectrum,
                &mut self.forward_scratch,
            )
            .expect("buffers sized by the plan");
    }

    /// Length of the real harmonic coordinates, `2 N_h + 1`.
    pub fn coordinates(&self) -> usize {
        self.harmonic_set.coordinates()
    }

    /// Time samples of the signal whose coordinates are `coordinates`.
    ///
    /// # Panics
    /// If `samples` is not `N_t` long or `coordinates` not `2 N_h + 1` (the
    /// layouts fix both when the problem is built: a programming error).
    pub fn to_time(&mut self, coordinates: &[f64], samples: &mut [f64]) {
        assert_eq!(samples.len(), self.time_samples, "N_t time samples");
        assert_eq!(
            coordinates.len(),
            self.coordinates(),
            "2 N_h + 1 coordinates"
        );
        self.spectrum.fill(Complex::new(0.0, 0.0));
        // The inverse real FFT sums X_k e^{ikτ} over ±k: exactly u(τ_n).
        for k in self.harmonic_set {
            let (re, im) = HarmonicSet::coefficient(coordinates, k);
            self.spectrum[k] = Complex::new(re, im);
        }
        // N_t > 2 N_h: the Nyquist bin (if any) stays zero, DC is real; the
        // lengths are checked above: realfft has nothing to refuse.
        self.inverse
            .process_with_scratch(&mut self.spectrum, samples, &mut self.inverse_scratch)
            .expect("real spectrum of N_t / 2 + 1 bins, real at DC and Nyquist");
    }

    /// Real harmonic coordinates (truncated to `N_h`) of time samples.
    ///
    /// # Panics
    /// If `samples` is not `N_t` long (see [`Self::to_time`]).
    pub fn to_frequency(&mut self, samples: &[f64], coordinates: &mut [f64]) {
        self.time_buffer.copy_from_slice(samples);
        self.forward_transform();
        let scale = 1.0 / self.time_samples as f64;
        for k in self.harmonic_set {
            let range = HarmonicSet::coordinate_range(k);
            coordinates[range.start] = self.spectrum[k].re * scale;
            if range.len() == 2 {
                coordinates[range.start + 1] = self.spectrum[k].im * scale;
            }
        }
    }

    /// The `H × H` real matrix (row-major in `block`) of the linearized map
    /// `u ↦ F(d · F⁻¹ u)` for the time samples `d` of a derivative: the exact
    /// Jacobian of the discrete AFT, built from the FFT of `d` (Toeplitz
    /// part `D_{k−l}`, Hankel part `D_{k+l}`), never from DFT matrices.
    pub fn derivative_block(&mut self, derivative: &[f64], block: &mut [f64]) {
        let harmonics = self.harmonic_set;
        let h = harmonics.highest();
        let n_t = self.time_samples;
        self.time_buffer.copy_from_slice(derivative);
        self.forward_transform();
        let scale = 1.0 / n_t as f64;
        for m in 0..=2 * h {
            // Aliased index m mod N_t, folded on the Hermitian half.
            let r = m % n_t;
            self.derivative_spectrum[m] = if r <= n_t / 2 {
                self.spectrum[r] * scale
            } else {
                self.spectrum[n_t - r].conj() * scale
            };
        }
        let d = |m: i64| -> Complex<f64> {
            if m >= 0 {
                self.derivative_spectrum[m as usize]
            } else {
                self.derivative_spectrum[(-m) as usize].conj()
            }
        };
        // Coordinates as in HarmonicSet::coordinate_range: a0, then (Re, Im) at 2k − 1, 2k.
        let size = harmonics.coordinates();
        block[..size * size].fill(0.0);
        let mut set = |row: usize, col: usize, value: f64| block[row * size + col] = value;
        // Row 0: G_0 = D_0 a0 + Σ_l 2 Re(D_l conj X_l).
        set(0, 0, d(0).re);
        for l in harmonics.oscillating() {
            set(0, 2 * l - 1, 2.0 * d(l as i64).re);
            set(0, 2 * l, 2.0 * d(l as i64).im);
        }
        // Rows k ≥ 1: G_k = D_k a0 + Σ_l (D_{k−l} X_l + D_{k+l} conj X_l).
        for k in harmonics.oscillating() {
            let dk = d(k as i64);
            set(2 * k - 1, 0, dk.re);
            set(2 * k, 0, dk.im);
            for l in harmonics.oscillating() {
                let toeplitz = d(k as i64 - l as i64);
                let hankel = d((k + l) as i64);
                let sum = toeplitz + hankel;
                let difference = toeplitz - hankel;
                set(2 * k - 1, 2 * l - 1, sum.re);
                set(2 * k, 2 * l - 1, sum.im);
                set(2 * k - 1, 2 * l, -difference.im);
                set(2 * k, 2 * l, difference.re);
            }
        }
    }
}

/// The real harmonic coordinates of `du/dτ` from those of `u`:
/// `X'_k = i k X_k`.
pub fn derivative_coordinates(coordinates: &[f64], out: &mut [f64]) {
    out[0] = 0.0;
    for k in 1..=(coordinates.len() - 1) / 2 {
        let (re, im) = (coordinates[2 * k - 1], coordinates[2 * k]);
        out[2 * k - 1] = -(k as f64) * im;
        out[2 * k] = k as f64 * re;
    }
}

#[cfg(test)]
pub(crate) mod naive {
    //! The naive-DFT AFT: the oracle of the FFT one.
    use std::f64::consts::PI;

    /// `u(τ_n)` by direct summation.
    pub fn to_time(coordinates: &[f64], time_samples: usize) -> Vec<f64> {
        let h = (coordinates.len() - 1) / 2;
        (0..time_samples)
            .map(|n| {
                let tau = 2.0 * PI * n as f64 / time_samples as f64;
                let mut u = coordinates[0];
                for k in 1..=h {
                    let (s, c) = (k as f64 * tau).sin_cos();
                    u += 2.0 * (coordinates[2 * k - 1] * c - coordinates[2 * k] * s);
                }
                u
            })
            .collect()
    }

    /// Coordinates by direct DFT sums, truncated to `harmonics`.
    pub fn to_frequency(samples: &[f64], harmonics: usize) -> Vec<f64> {
        let n_t = samples.len();
        let mut out = vec![0.0; 2 * harmonics + 1];
        for (n, &f) in samples.iter().enumerate() {
            let tau = 2.0 * PI * n as f64 / n_t as f64;
            out[0] += f / n_t as f64;
            for k in 1..=harmonics {
                let (s, c) = (k as f64 * tau).sin_cos();
                out[2 * k - 1] += f * c / n_t as f64;
                out[2 * k] -= f * s / n_t as f64;
            }
        }
        out
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn pseudo_random(seed: u64, count: usize) -> Vec<f64> {
        let mut state = seed;
        (0..count)
            .map(|_| {
                state = state
                    .wrapping_mul(6364136223846793005)
                    .wrapping_add(1442695040888963407);
                ((state >> 11) as f64 / (1u64 << 53) as f64) - 0.5
            })
            .collect()
    }

    #[test]
    fn fft_transforms_equal_the_naive_dft() {
        for &(h, n_t) in &[
            (1, 3),
            (3, 7),
            (5, 16),
            (10, 21),
            (10, 64),
            (10, 100),
            (7, 1000),
        ] {
            let mut aft = Aft::new(h, n_t);
            let coordinates = pseudo_random(h as u64 * 31 + n_t as u64, 2 * h + 1);
            let mut samples = vec![0.0; n_t];
            aft.to_time(&coordinates, &mut samples);
            let oracle = naive::to_time(&coordinates, n_t);
            for (a, b) in samples.iter().zip(&oracle) {
                assert!((a - b).abs() < 1e-12, "h={h} n_t={n_t}");
            }
            let signal = pseudo_random(7 + n_t as u64, n_t);
            let mut back = vec![0.0; 2 * h + 1];
            aft.to_frequency(&signal, &mut back);
            let oracle = naive::to_frequency(&signal, h);
            for (a, b) in back.iter().zip(&oracle) {
                assert!((a - b).abs() < 1e-13, "h={h} n_t={n_t}");
            }
            // Round trip of a band-limited signal is exact.
            aft.to_frequency(&samples, &mut back);
            for (a, b) in back.iter().zip(&coordinates) {
                assert!((a - b).abs() < 1e-13);
            }
        }
    }

    #[test]
    fn the_harmonic_sets_sampling_bound_is_the_transforms_exactness() {
        // On 2 N_h + 1 instants a band-limited signal round-trips exactly
        // (naive DFT as the oracle); on one fewer its top harmonic aliases.
        for h in 1..8 {
            let set = HarmonicSet::up_to(h);
            let coordinates = pseudo_random(h as u64 + 5, set.coordinates());
            let n_t = set.min_time_samples();
            let back = naive::to_frequency(&naive::to_time(&coordinates, n_t), h);
            let error = |b: &[f64]| {
                b.iter()
                    .zip(&coordinates)
                    .map(|(a, c)| (a - c).abs())
                    .fold(0.0_f64, f64::max)
            };
            assert!(error(&back) < 1e-13, "h={h}");
            let aliased = naive::to_frequency(&naive::to_time(&coordinates, n_t - 1), h);
            assert!(error(&aliased) > 1e-3, "h={h}");
        }
    }

    #[test]
    fn the_harmonic_sets_coupling_sampling_keeps_the_stiffness_alias_free() {
        // A derivative with harmonics up to 2 N_h (every coupling of two
        // harmonics of the set): on 4 N_h + 1 instants the AFT's block is the
        // exact linearization (oracle: naive DFTs on many instants, where
        // nothing aliases); on one fewer it is not.
        for h in 1..6 {
            let set = HarmonicSet::up_to(h);
            let wide = HarmonicSet::up_to(2 * h);
            let derivative = pseudo_random(h as u64 + 40, wide.coordinates());
            let size = set.coordinates();
            let exact = |col: usize| {
                let fine = 16 * size;
                let mut unit = vec![0.0; size];
                unit[col] = 1.0;
                let u = naive::to_time(&unit, fine);
                let d = naive::to_time(&derivative, fine);
                let product: Vec<f64> = u.iter().zip(&d).map(|(a, b)| a * b).collect();
                naive::to_frequency(&product, h)
            };
            let deviation = |n_t: usize| {
                let mut aft = Aft::for_set(set, n_t);
                let mut block = vec![0.0; size * size];
                aft.derivative_block(&naive::to_time(&derivative, n_t), &mut block);
                (0..size)
                    .flat_map(|col| {
                        let column = exact(col);
                        (0..size)
                            .map(|row| (block[row * size + col] - column[row]).abs())
                            .collect::<Vec<_>>()
                    })
                    .fold(0.0_f64, f64::max)
            };
            assert!(deviation(set.coupling_time_samples()) < 1e-13, "h={h}");
            assert!(deviation(set.coupling_time_samples() - 1) > 1e-3, "h={h}");
        }
    }

    #[test]
    fn derivative_block_equals_the_naive_linearization() {
        // Aliasing included: N_t small compared with 4 N_h.
        for &(h, n_t) in &[(2, 5), (4, 9), (4, 12), (10, 21), (10, 50), (6, 200)] {
            let mut aft = Aft::new(h, n_t);
            let derivative = pseudo_random(99 + n_t as u64, n_t);
            let size = 2 * h + 1;
            let mut block = vec![0.0; size * size];
            aft.derivative_block(&derivative, &mut block);
            for col in 0..size {
                let mut unit = vec![0.0; size];
                unit[col] = 1.0;
                let u = naive::to_time(&unit, n_t);
                let product: Vec<f64> = u.iter().zip(&derivative).map(|(a, b)| a * b).collect();
                let column = naive::to_frequency(&product, h);
                for row in 0..size {
                    let a = block[row * size + col];
                    assert!(
                        (a - column[row]).abs() < 1e-13,
                        "h={h} n_t={n_t} row={row} col={col}: {a} vs {}",
                        column[row]
                    );
                }
            }
        }
    }
}
