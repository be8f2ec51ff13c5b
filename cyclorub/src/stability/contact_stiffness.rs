//! The linearized contact force of a converged point: the stiffness the
//! contact law adds to each contact dof of each sector at each instant
//! ([`ContactLaw::linearized_stiffness`](crate::contact::ContactLaw)),
//! and its Fourier coefficients in time and in space.

use super::StabilityError;
use crate::hbm::aft::Aft;
use crate::hbm::recovery::wall_coordinates;
use crate::hbm::HarmonicBalance;
use faer::c64;
use std::f64::consts::PI;

/// The contact stiffness `d_{j,c}(τ_n)` of every sector `j` and contact
/// dof `c` at the instants `τ_n = 2π n / N_t` of one period.
#[derive(Clone, Debug)]
pub struct ContactStiffness {
    sectors: usize,
    contact_dofs: usize,
    time_samples: usize,
    /// `[(j · n_c + c) · N_t + n]`, N/m.
    samples: Vec<f64>,
    /// The largest stiffness at any instant, N/m.
    peak: f64,
}

impl ContactStiffness {
    /// Samples the law at `(x, omega)` on every sector, `time_samples`
    /// instants per period (`time_samples > 2 N_h`).
    pub fn sample(
        problem: &HarmonicBalance,
        x: &[f64],
        omega: f64,
        time_samples: usize,
    ) -> Result<Self, StabilityError> {
        let layout = problem.layout();
        let (n, contact_dofs) = (layout.sectors, layout.contact_dofs);
        let law = problem.law();
        let read = if law.input().reads_residual() {
            problem.law_variable(x, omega)?
        } else {
            x.to_vec()
        };
        let sectors: Vec<usize> = (0..n).collect();
        let mut solution = Aft::new(layout.harmonics, time_samples);
        let mut reading = vec![0.0; time_samples];
        let mut force = vec![0.0; time_samples];
        let mut samples = vec![0.0; n * contact_dofs * time_samples];
        let mut peak = 0.0_f64;
        for contact in 0..contact_dofs {
            let per_sector = wall_coordinates(problem, &read, contact, &sectors);
            for (j, coordinates) in per_sector.iter().enumerate() {
                let gap = problem.casing().gap_samples(n, j, contact, time_samples);
                solution.to_time(coordinates, &mut reading);
                let offset = (j * contact_dofs + contact) * time_samples;
                let slope = &mut samples[offset..offset + time_samples];
                law.apply(&reading, &gap, &mut force, Some(slope), None);
                for s in slope.iter_mut() {
                    *s = law.linearized_stiffness(*s);
                    peak = peak.max(s.abs());
                }
            }
        }
        if !peak.is_finite() || samples.iter().any(|s| !s.is_finite()) {
            return Err(StabilityError::NotFinite {
                what: "the contact stiffness",
                frequency_hz: omega / (2.0 * PI),
            });
        }
        Ok(Self {
            sectors: n,
            contact_dofs,
            time_samples,
            samples,
            peak,
        })
    }

    /// The largest contact stiffness at any instant on any sector, N/m.
    pub fn peak(&self) -> f64 {
        self.peak
    }

    /// The time-Fourier coefficients up to harmonic `highest`
    /// (`N_t > 2 · highest`).
    pub fn spectrum(&self, highest: usize) -> StiffnessSpectrum {
        let mut transform = Aft::new(highest, self.time_samples);
        let mut real = vec![0.0; 2 * highest + 1];
        let signals = self.sectors * self.contact_dofs;
        let mut coefficients = vec![c64::new(0.0, 0.0); signals * (highest + 1)];
        for (signal, samples) in self.samples.chunks_exact(self.time_samples).enumerate() {
            transform.to_frequency(samples, &mut real);
            let offset = signal * (highest + 1);
            coefficients[offset] = c64::new(real[0], 0.0);
            for m in 1..=highest {
                coefficients[offset + m] = c64::new(real[2 * m - 1], real[2 * m]);
            }
        }
        StiffnessSpectrum {
            sectors: self.sectors,
            contact_dofs: self.contact_dofs,
            highest,
            coefficients,
        }
    }
}

/// The time-Fourier coefficients `d̂_{j,c}(m)`, `|m| ≤ highest`, of the
/// contact stiffness: `d_{j,c}(τ) = Σ_m d̂_{j,c}(m) e^{imτ}`,
/// `d̂(−m) = conj d̂(m)`.
#[derive(Clone, Debug)]
pub struct StiffnessSpectrum {
    sectors: usize,
    contact_dofs: usize,
    highest: usize,
    /// `[(j · n_c + c) · (highest + 1) + m]`.
    coefficients: Vec<c64>,
}

impl StiffnessSpectrum {
    /// `d̂_{j,c}(m)` for any `m` (0 beyond `highest`).
    pub fn sector_coefficient(&self, sector: usize, contact: usize, harmonic: i64) -> c64 {
        let m = harmonic.unsigned_abs() as usize;
        if m > self.highest {
            return c64::new(0.0, 0.0);
        }
        let value =
            self.coefficients[(sector * self.contact_dofs + contact) * (self.highest + 1) + m];
        if harmonic < 0 {
            value.conj()
        } else {
            value
        }
    }

    /// The space-time coefficients `D̂_c(r, m) = (1/N) Σ_j e^{i r α j}
    /// d̂_{j,c}(m)` of every `r ∈ 0..N` and `|m| ≤ highest`: the coupling
    /// of the perturbation pair `(s, k)` into `(s + r, k + m)` on contact
    /// dof `c`.
    pub fn space_time_table(&self) -> SpaceTimeTable {
        let (n, h) = (self.sectors, self.highest as i64);
        let width = (2 * h + 1) as usize;
        let alpha = 2.0 * PI / n as f64;
        let mut table = vec![c64::new(0.0, 0.0); self.contact_dofs * n * width];
        for c in 0..self.contact_dofs {
            for r in 0..n {
                for m in -h..=h {
                    let sum: c64 = (0..n)
                        .map(|j| {
                            self.sector_coefficient(j, c, m)
                                * c64::cis(((r * j) % n) as f64 * alpha)
                        })
                        .sum();
                    table[(c * n + r) * width + (m + h) as usize] = sum / n as f64;
                }
            }
        }
        SpaceTimeTable {
            sectors: n,
            highest: h,
            table,
        }
    }
}

/// `D̂_c(r, m)`, see [`StiffnessSpectrum::space_time_table`].
#[derive(Clone, Debug)]
pub struct SpaceTimeTable {
    sectors: usize,
    highest: i64,
    table: Vec<c64>,
}

impl SpaceTimeTable {
    /// `D̂_c(r, m)` for any `r` (taken modulo `N`) and `|m| ≤ 2H` (0 beyond).
    pub fn at(&self, contact: usize, diameter: i64, harmonic: i64) -> c64 {
        if harmonic.abs() > self.highest {
            return c64::new(0.0, 0.0);
        }
        let n = self.sectors;
        let r = diameter.rem_euclid(n as i64) as usize;
        let width = (2 * self.highest + 1) as usize;
        self.table[(contact * n + r) * width + (harmonic + self.highest) as usize]
    }
}
