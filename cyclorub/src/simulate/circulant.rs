//! Solving with a block-circulant full-wheel matrix: the transform over
//! sectors turns `A x = b` into one `n × n` system per nodal diameter,
//! factorized once (Cholesky of the Hermitian positive definite
//! `A(s) = k K(s) + c C(s) + m M(s)`, `s = 0..=N/2`; the negative
//! diameters are the conjugates).

use super::wheel::{dot, root_of_unity, WheelMatrices};
use super::SimulateError;
use faer::c64;

/// The factorized `k K + c C + m M` of a full wheel.
#[derive(Clone, Debug)]
pub struct CirculantFactorization {
    sectors: usize,
    dofs: usize,
    /// The Cholesky factors `L(s)`, `s = 0..=N/2`.
    factors: Vec<Factor>,
    /// `e^{2πi r / N}`, `r = 0..N`.
    roots: Vec<c64>,
    /// Per-diameter work vectors: real parts, then imaginary parts.
    spectrum: Vec<Vec<f64>>,
}

/// A lower Cholesky factor `L` and `Lᴴ`, row-major, real and imaginary
/// parts apart (so that the substitutions are real dot products of
/// contiguous rows, which vectorize), and the diagonal of `L` (real).
#[derive(Clone, Debug)]
struct Factor {
    lower: [Vec<f64>; 2],
    upper: [Vec<f64>; 2],
    diagonal: Vec<f64>,
}

impl Factor {
    fn new(l: &[c64], n: usize) -> Self {
        let part = |f: &dyn Fn(usize, usize) -> c64| -> [Vec<f64>; 2] {
            let values: Vec<c64> = (0..n * n).map(|k| f(k / n, k % n)).collect();
            [
                values.iter().map(|v| v.re).collect(),
                values.iter().map(|v| v.im).collect(),
            ]
        };
        Self {
            lower: part(&|i, k| l[i * n + k]),
            upper: part(&|i, k| l[k * n + i].conj()),
            diagonal: (0..n).map(|i| l[i * n + i].re).collect(),
        }
    }

    /// Solves `L Lᴴ y = b` in place (`b` real parts then imaginary parts).
    fn solve(&self, b: &mut [f64]) {
        let n = self.diagonal.len();
        let (re, im) = b.split_at_mut(n);
        // b_i − Σ_k A_ik b_k over the row's range, A by its parts.
        let reduce =
            |a: &[Vec<f64>; 2], i: usize, range: std::ops::Range<usize>, re: &[f64], im: &[f64]| {
                let (ar, ai) = (&a[0][i * n..][range.clone()], &a[1][i * n..][range.clone()]);
                let (br, bi) = (&re[range.clone()], &im[range]);
                (
                    re[i] - (dot(ar, br) - dot(ai, bi)),
                    im[i] - (dot(ar, bi) + dot(ai, br)),
                )
            };
        for i in 0..n {
            let (r, m) = reduce(&self.lower, i, 0..i, re, im);
            re[i] = r / self.diagonal[i];
            im[i] = m / self.diagonal[i];
        }
        for i in (0..n).rev() {
            let (r, m) = reduce(&self.upper, i, i + 1..n, re, im);
            re[i] = r / self.diagonal[i];
            im[i] = m / self.diagonal[i];
        }
    }
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
            factors.push(Factor::new(&a, dofs));
        }
        Ok(Self {
            sectors,
            dofs,
            roots: (0..sectors as i64)
                .map(|r| root_of_unity(r, sectors))
                .collect(),
            spectrum: vec![vec![0.0; 2 * dofs]; factors.len()],
            factors,
        })
    }

    /// Solves `A x = b` (vectors sector-major, `N n` long).
    pub fn solve(&mut self, b: &[f64], x: &mut [f64]) {
        let (sectors, n) = (self.sectors, self.dofs);
        // X_s = Σ_j b_j e^{isαj}.
        for (s, spectrum) in self.spectrum.iter_mut().enumerate() {
            spectrum.iter_mut().for_each(|v| *v = 0.0);
            let (re, im) = spectrum.split_at_mut(n);
            for j in 0..sectors {
                let phase = self.roots[(s * j) % sectors];
                let block = &b[j * n..][..n];
                if block.iter().all(|v| *v == 0.0) {
                    continue;
                }
                for ((r, i), &bj) in re.iter_mut().zip(im.iter_mut()).zip(block) {
                    *r += phase.re * bj;
                    *i += phase.im * bj;
                }
            }
            self.factors[s].solve(spectrum);
        }
        // x_j = (1/N) Σ_s Y_s e^{−isαj}, with Y_{−s} = conj(Y_s).
        let scale = 1.0 / sectors as f64;
        for j in 0..sectors {
            let target = &mut x[j * n..][..n];
            target.iter_mut().for_each(|v| *v = 0.0);
            for (s, spectrum) in self.spectrum.iter().enumerate() {
                let phase = self.roots[(s * j) % sectors];
                // Diameters 0 and N/2 stand alone; the others for ±s.
                let weight = if s == 0 || 2 * s == sectors {
                    scale
                } else {
                    2.0 * scale
                };
                // Re(Y e^{−iθ}) = Re Y cos θ + Im Y sin θ.
                let (c, d) = (weight * phase.re, weight * phase.im);
                let (re, im) = spectrum.split_at(n);
                for ((t, r), i) in target.iter_mut().zip(re).zip(im) {
                    *t += c * r + d * i;
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
