//! The amplitude spectrum of the last periods' time histories: what a rig's
//! analyser shows, per sector, to read harmonics, sub-harmonics and the
//! side bands of a modulated (quasi-periodic) response.
//!
//! One real FFT of the recorded window (whole excitation periods at a fixed
//! frequency, so the excitation's harmonics fall on bins and a rectangular
//! window is exact; a sweep's window is not periodic, and takes a Hann
//! window against leakage). Amplitudes are single-sided and scaled by the
//! window's coherent gain: a sinusoid `a cos(2πft + φ)` on a bin reads `a`.

use super::run::History;
use realfft::RealFftPlanner;

/// The window applied before the transform.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Window {
    /// None: exact for signals periodic in the window.
    Rectangular,
    /// The periodic Hann window `½(1 − cos(2πi/n))`: leakage falls off
    /// fast, a tone between bins reads at most 1.42 dB (15 %) low.
    Hann,
}

/// Spectra of the observed dof, one per sector, over the recorded window.
#[derive(Clone, Debug, PartialEq)]
pub struct Spectra {
    /// Bin frequencies `k / (n h)`, Hz, `k = 0..=n/2`.
    pub frequency_hz: Vec<f64>,
    /// `amplitude[sector][k]`, m.
    pub amplitude: Vec<Vec<f64>>,
    /// The window used.
    pub window: Window,
}

/// The single-sided amplitude spectrum of `samples` taken every `step`
/// seconds: `(bin frequencies in Hz, amplitudes)`, `n/2 + 1` bins. Empty
/// for fewer than 2 samples.
pub fn amplitude_spectrum(samples: &[f64], step: f64, window: Window) -> (Vec<f64>, Vec<f64>) {
    let mut planner = RealFftPlanner::<f64>::new();
    let mut transform = Transform::new(&mut planner, samples.len(), window);
    let amplitudes = transform.amplitudes(samples.iter().copied());
    (bin_frequencies(samples.len(), step), amplitudes)
}

fn bin_frequencies(n: usize, step: f64) -> Vec<f64> {
    if n < 2 {
        return Vec::new();
    }
    let resolution = 1.0 / (n as f64 * step);
    (0..=n / 2).map(|k| k as f64 * resolution).collect()
}

/// A planned transform of one length with its window and buffers, reused
/// for every sector.
struct Transform {
    plan: std::sync::Arc<dyn realfft::RealToComplex<f64>>,
    weights: Vec<f64>,
    gain: f64,
    input: Vec<f64>,
    output: Vec<realfft::num_complex::Complex<f64>>,
}

impl Transform {
    fn new(planner: &mut RealFftPlanner<f64>, n: usize, window: Window) -> Self {
        let weights: Vec<f64> = (0..n)
            .map(|i| match window {
                Window::Rectangular => 1.0,
                Window::Hann => {
                    0.5 * (1.0 - (2.0 * std::f64::consts::PI * i as f64 / n as f64).cos())
                }
            })
            .collect();
        let gain = weights.iter().sum::<f64>();
        let plan = planner.plan_fft_forward(n.max(1));
        let output = plan.make_output_vec();
        Self {
            plan,
            weights,
            gain,
            input: vec![0.0; n.max(1)],
            output,
        }
    }

    fn amplitudes(&mut self, samples: impl Iterator<Item = f64>) -> Vec<f64> {
        let n = self.weights.len();
        if n < 2 {
            return Vec::new();
        }
        for ((slot, x), w) in self.input.iter_mut().zip(samples).zip(&self.weights) {
            *slot = x * w;
        }
        // The lengths are the plan's own: the transform cannot fail.
        if self
            .plan
            .process(&mut self.input, &mut self.output)
            .is_err()
        {
            return vec![f64::NAN; n / 2 + 1];
        }
        let last = n / 2;
        self.output
            .iter()
            .enumerate()
            .map(|(k, c)| {
                // DC, and the Nyquist bin of an even length, are not doubled.
                let single = if k == 0 || (n.is_multiple_of(2) && k == last) {
                    1.0
                } else {
                    2.0
                };
                single * c.norm() / self.gain
            })
            .collect()
    }
}

impl History {
    /// The spectra of the observed dof on each of `sectors` sectors over
    /// the recorded steps (`step` seconds apart), with `window`.
    pub fn observed_spectra(&self, sectors: usize, step: f64, window: Window) -> Spectra {
        let n = self.time.len();
        let mut planner = RealFftPlanner::<f64>::new();
        let mut transform = Transform::new(&mut planner, n, window);
        let amplitude = (0..sectors)
            .map(|j| {
                let series = (0..n).map(|i| self.observed_displacement[i * sectors + j]);
                transform.amplitudes(series)
            })
            .collect();
        Spectra {
            frequency_hz: bin_frequencies(n, step),
            amplitude,
            window,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::f64::consts::PI;

    /// Two tones on bins 3 and 7 and an offset, over 64 samples.
    fn tones(n: usize, step: f64) -> Vec<f64> {
        let f = |k: f64| k / (n as f64 * step);
        (0..n)
            .map(|i| {
                let t = i as f64 * step;
                0.25 + 1.5 * (2.0 * PI * f(3.0) * t + 0.3).cos()
                    + 0.02 * (2.0 * PI * f(7.0) * t - 1.1).sin()
            })
            .collect()
    }

    #[test]
    fn tones_on_bins_read_their_amplitudes_and_nothing_else() {
        let step = 1e-3;
        let (frequency, amplitude) =
            amplitude_spectrum(&tones(64, step), step, Window::Rectangular);
        assert_eq!(frequency.len(), 33);
        assert!((frequency[1] - 1.0 / 0.064).abs() < 1e-9);
        for (k, a) in amplitude.iter().enumerate() {
            let expected = match k {
                0 => 0.25,
                3 => 1.5,
                7 => 0.02,
                _ => 0.0,
            };
            assert!((a - expected).abs() < 1e-12, "bin {k}: {a} vs {expected}");
        }
    }

    #[test]
    fn hann_keeps_a_tone_on_a_bin_and_spreads_half_of_it_on_each_neighbour() {
        let step = 1e-3;
        let (_, amplitude) = amplitude_spectrum(&tones(64, step), step, Window::Hann);
        assert!((amplitude[3] - 1.5).abs() < 1e-12);
        assert!((amplitude[2] - 0.75).abs() < 1e-12);
        assert!((amplitude[4] - 0.75).abs() < 1e-12);
        assert!(amplitude[5] < 1e-12 && amplitude[10] < 1e-12);
        // Odd lengths too: no Nyquist bin.
        let (frequency, amplitude) =
            amplitude_spectrum(&tones(63, step), step, Window::Rectangular);
        assert_eq!(frequency.len(), 32);
        assert!((amplitude[3] - 1.5).abs() < 1e-12 && (amplitude[31]).abs() < 1e-12);
    }

    #[test]
    fn a_history_gives_one_spectrum_per_sector() {
        let step = 1e-3;
        let sectors = 3;
        let one = tones(64, step);
        let history = History {
            time: (0..64).map(|i| i as f64 * step).collect(),
            observed_displacement: one
                .iter()
                .flat_map(|x| (0..sectors).map(move |j| x * (j + 1) as f64))
                .collect(),
            ..History::default()
        };
        let spectra = history.observed_spectra(sectors, step, Window::Rectangular);
        for j in 0..sectors {
            let scale = (j + 1) as f64;
            assert!((spectra.amplitude[j][3] - 1.5 * scale).abs() < 1e-12);
        }
        let empty = History::default().observed_spectra(2, step, Window::Hann);
        assert!(empty.frequency_hz.is_empty() && empty.amplitude.iter().all(Vec::is_empty));
    }
}
