//! Solving with a block-circulant full-wheel matrix: the transform over
//! sectors turns `A x = b` into one `n × n` system per nodal diameter,
//! factorized once (Cholesky of the Hermitian positive definite
//! `A(s) = k K(s) + c C(s) + m M(s)`, `s = 0..=N/2`; the negative
//! diameters are the conjugates).

use super::wheel::{root_of_unity, WheelMatrices};
use super::SimulateError;
use faer::c64;

/// The factorized `k K + c C + m M` of a full wheel.
#[derive(Clone, Debug)]
pub struct CirculantFactorization {
    sectors: usize,
    dofs: usize,
    /// Lower Cholesky factor `L(s)`, row-major, `s = 0..=N/2`.
    factors: Vec<Vec<c64>>,
    /// `e^{2πi r / N}`, `r = 0..N`.
    roots: Vec<c64>,
    /// Per-diameter work vectors.
    spectrum: Vec<Vec<c64>>,
}

impl CirculantFactorization {
    /// Factorizes `stiffness_factor K + damping_factor C + mass_factor M`.
    pub fn new(
        wheel: &WheelMatrices,
        stiffness_factor: f64,
        damping_factor: f64,
        mass_factor: f64,
    ) -> Result<Self, SimulateError> {
        let sectors = wheel.sectors();
        let dofs = wheel.dofs_per_sector();
        let mut factors = Vec::with_capacity(wheel.nodal_diameters.len());
        for (s, m) in wheel.nodal_diameters.iter().enumerate() {
            let mut a = vec![c64::new(0.0, 0.0); dofs * dofs];
            for i in 0..dofs {
                for k in 0..dofs {
                    a[i * dofs + k] = m.stiffness[(i, k)] * stiffness_factor
                        + m.damping[(i, k)] * damping_factor
                        + m.mass[(i, k)] * mass_factor;
                }
            }
            cholesky(&mut a, dofs)
                .ok_or(SimulateError::NotPositiveDefinite { nodal_diameter: s })?;
            factors.push(a);
        }
        Ok(Self {
            sectors,
            dofs,
            roots: (0..sectors as i64)
                .map(|r| root_of_unity(r, sectors))
                .collect(),
            spectrum: vec![vec![c64::new(0.0, 0.0); dofs]; factors.len()],
            factors,
        })
    }

    /// Solves `A x = b` (vectors sector-major, `N n` long).
    pub fn solve(&mut self, b: &[f64], x: &mut [f64]) {
        let (sectors, n) = (self.sectors, self.dofs);
        // X_s = Σ_j b_j e^{isαj}.
        for (s, spectrum) in self.spectrum.iter_mut().enumerate() {
            spectrum.iter_mut().for_each(|v| *v = c64::new(0.0, 0.0));
            for j in 0..sectors {
                let phase = self.roots[(s * j) % sectors];
                let block = &b[j * n..][..n];
                if block.iter().all(|v| *v == 0.0) {
                    continue;
                }
                for (v, &bj) in spectrum.iter_mut().zip(block) {
                    *v += phase * bj;
                }
            }
            solve_cholesky(&self.factors[s], n, spectrum);
        }
        // x_j = (1/N) Σ_s Y_s e^{−isαj}, with Y_{−s} = conj(Y_s).
        let scale = 1.0 / sectors as f64;
        for j in 0..sectors {
            let target = &mut x[j * n..][..n];
            target.iter_mut().for_each(|v| *v = 0.0);
            for (s, spectrum) in self.spectrum.iter().enumerate() {
                let phase = self.roots[(s * j) % sectors].conj();
                // Diameters 0 and N/2 stand alone; the others for ±s.
                let weight = if s == 0 || 2 * s == sectors {
                    scale
                } else {
                    2.0 * scale
                };
                for (t, y) in target.iter_mut().zip(spectrum) {
                    *t += weight * (y * phase).re;
                }
            }
        }
    }
}

/// In-place lower Cholesky `A = L Lᴴ` of a Hermitian matrix (row-major,
/// lower triangle read); `None` when it is not positive definite.
fn cholesky(a: &mut [c64], n: usize) -> Option<()> {
    for j in 0..n {
        let mut diagonal = a[j * n + j].re;
        for k in 0..j {
            diagonal -= a[j * n + k].norm_sqr();
        }
        if !(diagonal > 0.0 && diagonal.is_finite()) {
            return None;
        }
        let pivot = diagonal.sqrt();
        a[j * n + j] = c64::new(pivot, 0.0);
        for i in j + 1..n {
            let mut value = a[i * n + j];
            for k in 0..j {
                value -= a[i * n + k] * a[j * n + k].conj();
            }
            a[i * n + j] = value / pivot;
        }
        for k in j + 1..n {
            a[j * n + k] = c64::new(0.0, 0.0);
        }
    }
    Some(())
}

/// Solves `L Lᴴ y = b` in place.
fn solve_cholesky(l: &[c64], n: usize, b: &mut [c64]) {
    for i in 0..n {
        let mut value = b[i];
        for k in 0..i {
            value -= l[i * n + k] * b[k];
        }
        b[i] = value / l[i * n + i].re;
    }
    for i in (0..n).rev() {
        let mut value = b[i];
        for k in i + 1..n {
            value -= l[k * n + i].conj() * b[k];
        }
        b[i] = value / l[i * n + i].re;
    }
}
