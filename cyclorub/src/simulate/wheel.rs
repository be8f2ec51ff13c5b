//! The full wheel's linear operators in physical coordinates.
//!
//! A tuned wheel's mass, stiffness and damping are block-circulant: the
//! force on sector `j` is `Σ_d B_d x_{j+d}` (sectors modulo `N`), with
//! `n × n` blocks `B_d` (`n` dofs per sector). Only the blocks that are not
//! zero are kept: `d = 0, ±1` for the stiffness and mass of a lumped chain
//! or a finite-element sector, every `d` for modal damping (a mode of the
//! wheel spans every sector). Nothing of size `(N n)²` is formed.
//!
//! The blocks come from the per-diameter matrices of the model
//! ([`SectorModel::nodal_diameter_matrices`]): with `x_j = X e^{−isαj}`
//! (sectors `j` from 0), `A(s) = Σ_d B_d e^{−isαd}`, so
//! `B_d = (1/N) Σ_s A(s) e^{isαd}`.

use super::SimulateError;
use crate::model::{NodalDiameterMatrices, SectorModel};
use faer::{c64, Mat};
use std::f64::consts::PI;

/// Blocks below this fraction of the largest block entry are round-off of
/// the inverse transform over sectors and are dropped.
const NEGLIGIBLE_BLOCK: f64 = 1e-13;

/// A real block-circulant full-wheel matrix held by its nonzero blocks.
#[derive(Clone, Debug)]
pub struct CirculantMatrix {
    sectors: usize,
    dofs: usize,
    /// `(d, B_d)`, `B_d` row-major `n × n`.
    blocks: Vec<(usize, Vec<f64>)>,
    /// With many blocks (modal damping: every offset), the product goes
    /// through the nodal diameters instead (see [`PerDiameter`]).
    per_diameter: Option<PerDiameter>,
}

/// `A(s)`, `s = 0..=N/2`, split into real and imaginary parts (row-major
/// `n × n` each): `y = A x` as `Y_s = A(s) X_s` between the transforms
/// over sectors, `(N/2 + 1)·4n²` products and `2(N/2 + 1)·N·n` for the
/// transforms against `N n²` per kept block.
#[derive(Clone, Debug)]
struct PerDiameter {
    real: Vec<Vec<f64>>,
    imaginary: Vec<Vec<f64>>,
}

impl PerDiameter {
    /// `y += scale · A x` through the nodal diameters: `X_s = Σ_j x_j
    /// e^{isαj}`, `Y_s = A(s) X_s`, `y_j = (1/N) Σ_s Y_s e^{−isαj}` (the
    /// diameters `N − s` are the conjugates of `s`).
    fn apply_add(&self, sectors: usize, n: usize, scale: f64, x: &[f64], y: &mut [f64]) {
        let diameters = self.real.len();
        let roots: Vec<c64> = (0..sectors as i64)
            .map(|r| root_of_unity(r, sectors))
            .collect();
        // [Re X_s, Im X_s, Re Y_s, Im Y_s] per diameter.
        let mut work = vec![0.0; 4 * n * diameters];
        for (s, spectra) in work.chunks_exact_mut(4 * n).enumerate() {
            let (input, output) = spectra.split_at_mut(2 * n);
            let (re, im) = input.split_at_mut(n);
            for (j, block) in x.chunks_exact(n).enumerate() {
                let phase = roots[(s * j) % sectors];
                for ((r, i), &v) in re.iter_mut().zip(im.iter_mut()).zip(block) {
                    *r += phase.re * v;
                    *i += phase.im * v;
                }
            }
            let (out_re, out_im) = output.split_at_mut(n);
            let rows = self.real[s]
                .chunks_exact(n)
                .zip(self.imaginary[s].chunks_exact(n));
            for ((a_re, a_im), (o_re, o_im)) in rows.zip(out_re.iter_mut().zip(out_im.iter_mut())) {
                *o_re = dot(a_re, re) - dot(a_im, im);
                *o_im = dot(a_re, im) + dot(a_im, re);
            }
        }
        for (j, target) in y.chunks_exact_mut(n).enumerate() {
            for (s, spectra) in work.chunks_exact(4 * n).enumerate() {
                // Diameters 0 and N/2 stand alone; the others for ±s.
                let weight =
                    if s == 0 || 2 * s == sectors { 1.0 } else { 2.0 } * scale / sectors as f64;
                // Re(Y e^{−isαj}) = Re Y cos + Im Y sin.
                let phase = roots[(s * j) % sectors];
                let (c, d) = (weight * phase.re, weight * phase.im);
                let (re, im) = spectra[2 * n..].split_at(n);
                for ((t, r), i) in target.iter_mut().zip(re).zip(im) {
                    *t += c * r + d * i;
                }
            }
        }
    }
}

/// `Σ a_k b_k` over the shorter slice, in eight interleaved partial sums
/// (so that it vectorizes; the order of the additions differs from a plain
/// loop's in round-off only).
pub(crate) fn dot(a: &[f64], b: &[f64]) -> f64 {
    let n = a.len().min(b.len());
    let (a, b) = (&a[..n], &b[..n]);
    let mut sums = [0.0; 8];
    let (a_chunks, b_chunks) = (a.chunks_exact(8), b.chunks_exact(8));
    let tail: f64 = a_chunks
        .remainder()
        .iter()
        .zip(b_chunks.remainder())
        .map(|(x, y)| x * y)
        .sum();
    for (x, y) in a_chunks.zip(b_chunks) {
        for k in 0..8 {
            sums[k] += x[k] * y[k];
        }
    }
    sums.iter().sum::<f64>() + tail
}

/// `e^{2πi r / N}` with `r` reduced modulo `N` first (no drift for large `r`).
pub(crate) fn root_of_unity(r: i64, sectors: usize) -> c64 {
    let r = r.rem_euclid(sectors as i64);
    let angle = 2.0 * PI * r as f64 / sectors as f64;
    c64::new(angle.cos(), angle.sin())
}

impl CirculantMatrix {
    /// The matrix whose nodal-diameter matrices are `per_diameter[s]`,
    /// `s = 0..=N/2` (the negative diameters are their conjugates).
    pub fn from_nodal_diameters(per_diameter: &[Mat<c64>], sectors: usize) -> Self {
        let dofs = per_diameter.first().map_or(0, |m| m.nrows());
        let at = |s: usize| -> (usize, bool) {
            if s <= sectors / 2 {
                (s, false)
            } else {
                (sectors - s, true)
            }
        };
        let mut blocks = Vec::new();
        let mut largest = 0.0_f64;
        for d in 0..sectors {
            let mut block = vec![0.0; dofs * dofs];
            for s in 0..sectors {
                let (index, conjugate) = at(s);
                let a = &per_diameter[index];
                let phase = root_of_unity((s * d) as i64, sectors);
                for i in 0..dofs {
                    for k in 0..dofs {
                        let value = if conjugate {
                            a[(i, k)].conj()
                        } else {
                            a[(i, k)]
                        };
                        block[i * dofs + k] += (value * phase).re / sectors as f64;
                    }
                }
            }
            largest = block.iter().fold(largest, |m, v| m.max(v.abs()));
            blocks.push((d, block));
        }
        blocks.retain(|(_, b)| b.iter().any(|v| v.abs() > NEGLIGIBLE_BLOCK * largest));
        // Products by block cost `blocks·N·n²`, through the diameters
        // `(N/2 + 1)(4n² + 4Nn)`: the cheaper is taken.
        let diameters = per_diameter.len();
        let through_diameters = 4 * diameters * dofs * (dofs + sectors);
        let per_diameter = (blocks.len() * sectors * dofs * dofs > through_diameters).then(|| {
            let part = |pick: fn(c64) -> f64| -> Vec<Vec<f64>> {
                per_diameter
                    .iter()
                    .map(|a| {
                        (0..dofs * dofs)
                            .map(|k| pick(a[(k / dofs, k % dofs)]))
                            .collect()
                    })
                    .collect()
            };
            PerDiameter {
                real: part(|v| v.re),
                imaginary: part(|v| v.im),
            }
        });
        Self {
            sectors,
            dofs,
            blocks,
            per_diameter,
        }
    }

    /// The number of sectors `N`.
    pub fn sectors(&self) -> usize {
        self.sectors
    }

    /// The dofs per sector `n`.
    pub fn dofs_per_sector(&self) -> usize {
        self.dofs
    }

    /// The sector offsets `d` whose block is kept.
    pub fn offsets(&self) -> Vec<usize> {
        self.blocks.iter().map(|(d, _)| *d).collect()
    }

    /// `y += scale · A x` (vectors sector-major, `N n` long).
    pub fn apply_add(&self, scale: f64, x: &[f64], y: &mut [f64]) {
        match &self.per_diameter {
            Some(diameters) => diameters.apply_add(self.sectors, self.dofs, scale, x, y),
            None => self.apply_add_by_blocks(scale, x, y),
        }
    }

    /// Whether products go through the nodal diameters (many blocks).
    pub fn by_nodal_diameters(&self) -> bool {
        self.per_diameter.is_some()
    }

    /// `y += scale · A x` block by block: `y_j += Σ_d B_d x_{j+d}`.
    fn apply_add_by_blocks(&self, scale: f64, x: &[f64], y: &mut [f64]) {
        let n = self.dofs;
        for (d, block) in &self.blocks {
            for j in 0..self.sectors {
                let source = &x[((j + d) % self.sectors) * n..][..n];
                let target = &mut y[j * n..][..n];
                for (i, row) in block.chunks_exact(n).enumerate() {
                    target[i] += scale * dot(row, source);
                }
            }
        }
    }

    /// The matrix times `factor`.
    pub fn scaled(&self, factor: f64) -> Self {
        let times = |list: &[Vec<f64>]| -> Vec<Vec<f64>> {
            list.iter()
                .map(|b| b.iter().map(|v| v * factor).collect())
                .collect()
        };
        Self {
            blocks: self
                .blocks
                .iter()
                .map(|(d, b)| (*d, b.iter().map(|v| v * factor).collect()))
                .collect(),
            per_diameter: self.per_diameter.as_ref().map(|p| PerDiameter {
                real: times(&p.real),
                imaginary: times(&p.imaginary),
            }),
            ..self.clone()
        }
    }

    /// `xᵀ A y`.
    pub fn quadratic(&self, x: &[f64], y: &[f64], work: &mut [f64]) -> f64 {
        work.iter_mut().for_each(|w| *w = 0.0);
        self.apply_add(1.0, y, work);
        x.iter().zip(work.iter()).map(|(a, b)| a * b).sum()
    }
}

/// Mass, stiffness and damping of the full wheel, block-circulant, with
/// the nodal-diameter matrices `s = 0..=N/2` they come from (the solver
/// factorizes those).
#[derive(Clone, Debug)]
pub struct WheelMatrices {
    /// Mass `M`.
    pub mass: CirculantMatrix,
    /// Stiffness `K`.
    pub stiffness: CirculantMatrix,
    /// Damping `C`.
    pub damping: CirculantMatrix,
    /// `M(s)`, `K(s)`, `C(s)` for `s = 0..=N/2`.
    pub nodal_diameters: Vec<NodalDiameterMatrices>,
}

impl WheelMatrices {
    /// The full wheel of `model`.
    pub fn new(model: &SectorModel) -> Result<Self, SimulateError> {
        let sectors = model.sectors();
        let diameters: Vec<i64> = (0..=(sectors / 2) as i64).collect();
        let nodal_diameters = model.nodal_diameter_matrices_for(&diameters)?;
        let build = |pick: fn(&NodalDiameterMatrices) -> &Mat<c64>| {
            let list: Vec<Mat<c64>> = nodal_diameters.iter().map(|m| pick(m).clone()).collect();
            CirculantMatrix::from_nodal_diameters(&list, sectors)
        };
        Ok(Self {
            mass: build(|m| &m.mass),
            stiffness: build(|m| &m.stiffness),
            damping: build(|m| &m.damping),
            nodal_diameters,
        })
    }

    /// The wheel whose response at `s = iΩ_w` is this one's at
    /// `s = iΩ`, `ratio = Ω/Ω_w`: the mass times `ratio²`, the damping
    /// times `ratio`, the stiffness as it is (see [`dispersion_ratio`]).
    pub fn time_warped(&self, ratio: f64) -> Self {
        Self {
            mass: self.mass.scaled(ratio * ratio),
            stiffness: self.stiffness.clone(),
            damping: self.damping.scaled(ratio),
            nodal_diameters: self
                .nodal_diameters
                .iter()
                .map(|m| NodalDiameterMatrices {
                    mass: Mat::from_fn(m.mass.nrows(), m.mass.ncols(), |i, j| {
                        m.mass[(i, j)] * (ratio * ratio)
                    }),
                    stiffness: m.stiffness.clone(),
                    damping: Mat::from_fn(m.damping.nrows(), m.damping.ncols(), |i, j| {
                        m.damping[(i, j)] * ratio
                    }),
                })
                .collect(),
        }
    }

    /// The number of sectors `N`.
    pub fn sectors(&self) -> usize {
        self.mass.sectors()
    }

    /// The dofs per sector `n`.
    pub fn dofs_per_sector(&self) -> usize {
        self.mass.dofs_per_sector()
    }

    /// `N n`, the length of a full-wheel vector.
    pub fn size(&self) -> usize {
        self.sectors() * self.dofs_per_sector()
    }
}

/// The trapezoidal rule's (Newmark average acceleration's) dispersion
/// correction at the excitation frequency `omega` with steps of `step`:
/// `Ω/Ω_w`, `Ω_w = (2/h) tan(Ωh/2)`.
///
/// The rule is the bilinear map `s = (2/h)(z − 1)/(z + 1)`: its steady
/// response to a forcing `e^{iΩt}` sampled every `h` is the continuous
/// system's at `s = iΩ_w`, a frequency above `Ω` by `(Ωh)²/12` (at 256 steps
/// a period 5e-5, enough to move a lightly damped resonance's amplitude by
/// a percent). Integrating the wheel of mass `M (Ω/Ω_w)²` and damping
/// `C Ω/Ω_w` instead ([`WheelMatrices::time_warped`]) makes the scheme's
/// response at the excitation frequency the exact one, for every dof and
/// whatever the step; the harmonics `kΩ` the contact excites keep an error
/// of order `(k² − 1)(Ωh)²/12`.
pub fn dispersion_ratio(omega: f64, step: f64) -> f64 {
    let half = 0.5 * omega * step;
    half / half.tan()
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A real circulant matrix from arbitrary complex nodal-diameter
    /// matrices (real at the diameters 0 and N/2, which stand alone).
    fn matrix(sectors: usize, dofs: usize) -> CirculantMatrix {
        let value = |s: usize, i: usize, k: usize, part: usize| {
            (((s * 31 + i * 7 + k * 13 + part * 5) % 23) as f64 / 23.0 - 0.45) * (1.0 + s as f64)
        };
        let per_diameter: Vec<Mat<c64>> = (0..=sectors / 2)
            .map(|s| {
                let real = s == 0 || 2 * s == sectors;
                Mat::from_fn(dofs, dofs, |i, k| {
                    c64::new(
                        value(s, i, k, 0),
                        if real { 0.0 } else { value(s, i, k, 1) },
                    )
                })
            })
            .collect();
        CirculantMatrix::from_nodal_diameters(&per_diameter, sectors)
    }

    #[test]
    fn the_product_through_the_nodal_diameters_is_the_block_by_block_one() {
        for (sectors, dofs) in [(16, 9), (7, 5), (10, 6)] {
            let a = matrix(sectors, dofs);
            assert!(
                a.by_nodal_diameters(),
                "{sectors} sectors: every offset kept"
            );
            let x: Vec<f64> = (0..sectors * dofs)
                .map(|i| (i as f64 * 0.37).sin())
                .collect();
            let start: Vec<f64> = (0..sectors * dofs).map(|i| i as f64 * 0.01).collect();
            let (mut fast, mut blocks) = (start.clone(), start);
            a.apply_add(-0.7, &x, &mut fast);
            a.apply_add_by_blocks(-0.7, &x, &mut blocks);
            let largest = blocks.iter().fold(0.0_f64, |m, v| m.max(v.abs()));
            for (f, b) in fast.iter().zip(&blocks) {
                assert!(
                    (f - b).abs() < 1e-13 * largest,
                    "{sectors} sectors: {f} vs {b}"
                );
            }
            // Scaled alike both ways.
            let twice = a.scaled(2.0);
            let (mut fast, mut blocks) = (vec![0.0; x.len()], vec![0.0; x.len()]);
            twice.apply_add(1.0, &x, &mut fast);
            twice.apply_add_by_blocks(1.0, &x, &mut blocks);
            for (f, b) in fast.iter().zip(&blocks) {
                assert!(
                    (f - b).abs() < 2e-13 * largest,
                    "{sectors} sectors scaled: {f} vs {b}"
                );
            }
        }
    }
}
