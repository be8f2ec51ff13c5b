//! The whole wheel's linear part by nodal diameters. Its matrices are
//! block-circulant over the sectors (sector-major dofs, `A(j, j') =
//! B(j' − j)`), so they are block-diagonal in the sectors' Fourier basis
//! `x_j = Σ_s x̂(s) e^{i s α j}`, `x̂(s) = (1/N) Σ_j x_j e^{−i s α j}`, with
//! `Â(s) = Σ_t B(t) e^{i s α t}`. The Schur complement on the contact dofs
//! (the same dofs in every sector) is block-circulant too, `Ŝ(s) = Â_cc −
//! Â_ci Â_ii⁻¹ Â_ic`: condensing a harmonic of the wheel costs N condensations
//! of a sector's size instead of one of the wheel's (on the open fan, 16
//! of 53 dofs instead of one of 848). Exact: the diameters come from the
//! assembled wheel's first block row, not from the model's own nodal
//! diameter matrices, and the dense condensation of the wheel is the tests'
//! reference.

use super::super::layout::Block;
use super::super::HbmError;
use super::condensation::{condense, dynamic_stiffness, singular, submatrix, with_wall};
use super::{BlockMatrices, Condensed, LocalBlock};
use faer::linalg::solvers::Solve;
use faer::{c64, Mat};
use std::f64::consts::PI;
use std::sync::Arc;

/// Relative tolerance of the block-circulant check: the wheel is assembled
/// from identical sectors, so its blocks repeat to round-off.
const CIRCULANT_TOLERANCE: f64 = 1e-12;

/// A wheel's matrices by nodal diameter `s = 0..N`, with one sector's
/// contact and interior dofs.
#[derive(Debug)]
pub struct WheelDiameters {
    sectors: usize,
    dofs: usize,
    diameters: Vec<BlockMatrices>,
    contact: Vec<usize>,
    interior: Vec<usize>,
    /// `e^{i α k}`, read by the transforms over sectors (no sines on the
    /// hot path: every harmonic at every new frequency).
    twiddles: Twiddles,
}

impl WheelDiameters {
    /// The diameters of a wheel block (`sectors` sectors, `contact` and
    /// `interior` sector-major and the same in every sector), or `None`
    /// when the matrices are not block-circulant or the split differs
    /// between sectors (the dense condensation serves then).
    pub fn new(
        matrices: &BlockMatrices,
        sectors: usize,
        contact: &[usize],
        interior: &[usize],
    ) -> Option<Arc<Self>> {
        let size = matrices.mass.nrows();
        if sectors < 2 || !size.is_multiple_of(sectors) {
            return None;
        }
        let dofs = size / sectors;
        let first = |all: &[usize]| -> Option<Vec<usize>> {
            let per = all.len() / sectors;
            if per * sectors != all.len() {
                return None;
            }
            let sector: Vec<usize> = all[..per].to_vec();
            let repeated = all
                .iter()
                .enumerate()
                .all(|(e, &d)| d == (e / per) * dofs + sector[e % per]);
            (repeated && sector.iter().all(|&d| d < dofs)).then_some(sector)
        };
        let (contact, interior) = (first(contact)?, first(interior)?);
        let all = [&*matrices.mass, &*matrices.stiffness, &*matrices.damping];
        if !all.iter().all(|m| is_block_circulant(m, sectors)) {
            return None;
        }
        let alpha = 2.0 * PI / sectors as f64;
        let transform = |a: &Mat<c64>, s: usize| {
            Arc::new(Mat::from_fn(dofs, dofs, |r, c| {
                (0..sectors).fold(c64::new(0.0, 0.0), |sum, t| {
                    sum + a[(r, t * dofs + c)] * c64::cis((s * t) as f64 * alpha)
                })
            }))
        };
        let diameters = (0..sectors)
            .map(|s| BlockMatrices {
                mass: transform(&matrices.mass, s),
                stiffness: transform(&matrices.stiffness, s),
                damping: transform(&matrices.damping, s),
            })
            .collect();
        Some(Arc::new(Self {
            sectors,
            dofs,
            diameters,
            contact,
            interior,
            twiddles: Twiddles::new(sectors),
        }))
    }

    /// The matrices of nodal diameter `s` (`0..N`).
    pub(super) fn diameter_matrices(&self, s: usize) -> &BlockMatrices {
        &self.diameters[s]
    }

    /// `x̂(s)` of sector-major values, `per` of them per sector.
    fn forward(&self, values: &[c64], per: usize, s: usize) -> Vec<c64> {
        let n = self.sectors;
        (0..per)
            .map(|d| {
                (0..n).fold(c64::new(0.0, 0.0), |sum, j| {
                    sum + values[j * per + d] * self.twiddles.at(s * j).conj()
                }) / n as f64
            })
            .collect()
    }

    /// `out_j += x̂ e^{i s α j}` for sector-major `out`.
    fn add_inverse(&self, hat: &[c64], s: usize, out: &mut [c64]) {
        let n = self.sectors;
        let per = hat.len();
        for j in 0..n {
            let w = self.twiddles.at(s * j);
            for (o, h) in out[j * per..(j + 1) * per].iter_mut().zip(hat) {
                *o += h * w;
            }
        }
    }

    /// The wheel block condensed on its contact dofs at `omega` (then in
    /// series with a wall `κ`, which every diameter sees alike), with the
    /// block's `load` on the wheel's dofs: what the dense Schur complement
    /// gives, kept by diameters.
    pub(super) fn condense(
        &self,
        block: &Block,
        load: &[c64],
        omega: f64,
        wall_stiffness: Option<f64>,
    ) -> Result<Condensed, HbmError> {
        let n = self.sectors;
        let per = self.contact.len();
        let zero = c64::new(0.0, 0.0);
        let mut circulant = Circulant {
            twiddles: self.twiddles.clone(),
            per,
            diameters: Vec::with_capacity(n),
            row: Mat::zeros(per, n * per),
            derivative_row: Mat::zeros(per, n * per),
        };
        let mut condensed_load = vec![zero; n * per];
        let mut load_derivative = vec![zero; n * per];
        for s in 0..n {
            let local = LocalBlock {
                matrices: self.diameters[s].clone(),
                contact: self.contact.clone(),
                interior: self.interior.clone(),
                load: self.forward(load, self.dofs, s),
                structure: super::WheelStructure::Dense,
            };
            let mut hat = condense(block, &local, omega)?;
            if let Some(kappa) = wall_stiffness {
                hat = with_wall(block, hat, kappa, omega)?;
            }
            // S(0, t) = (1/N) Σ_s Ŝ(s) e^{−i s α t}.
            for t in 0..n {
                let w = circulant.twiddles.at(s * t).conj() / n as f64;
                for b in 0..per {
                    for a in 0..per {
                        circulant.row[(a, t * per + b)] += hat.dynamic[(a, b)] * w;
                        circulant.derivative_row[(a, t * per + b)] +=
                            hat.dynamic_derivative[(a, b)] * w;
                    }
                }
            }
            self.add_inverse(&hat.load, s, &mut condensed_load);
            self.add_inverse(&hat.load_derivative, s, &mut load_derivative);
            circulant
                .diameters
                .push((hat.dynamic, hat.dynamic_derivative));
        }
        let condensed = Condensed {
            dynamic: Mat::new(),
            dynamic_derivative: Mat::new(),
            load: condensed_load,
            load_derivative,
            circulant: Some(circulant),
            derivative_products: None,
        };
        if !condensed.is_finite() {
            return Err(singular(block, omega));
        }
        Ok(condensed)
    }

    /// The wheel's dofs from the contact dofs' values (sector-major):
    /// `x̂_i(s) = Â_ii⁻¹ (f̂_i − Â_ic x̂_c)` diameter by diameter.
    pub(super) fn recover(
        &self,
        block: &Block,
        load: &[c64],
        omega: f64,
        contact_values: &[c64],
    ) -> Result<Vec<c64>, HbmError> {
        let n = self.sectors;
        let (per, inner) = (self.contact.len(), self.interior.len());
        let mut interior = vec![c64::new(0.0, 0.0); n * inner];
        for s in 0..n {
            let (z, _) = dynamic_stiffness(&self.diameters[s], block.harmonic, omega);
            let f = self.forward(load, self.dofs, s);
            let x = self.forward(contact_values, per, s);
            let rhs = Mat::from_fn(inner, 1, |r, _| {
                let i = self.interior[r];
                self.contact
                    .iter()
                    .zip(&x)
                    .fold(f[i], |sum, (&c, v)| sum - z[(i, c)] * v)
            });
            let zii = submatrix(&z, &self.interior, &self.interior);
            let solved = zii.partial_piv_lu().solve(&rhs);
            let hat: Vec<c64> = (0..inner).map(|r| solved[(r, 0)]).collect();
            self.add_inverse(&hat, s, &mut interior);
        }
        let mut out = vec![c64::new(0.0, 0.0); n * self.dofs];
        for j in 0..n {
            for (q, &d) in self.contact.iter().enumerate() {
                out[j * self.dofs + d] = contact_values[j * per + q];
            }
            for (r, &d) in self.interior.iter().enumerate() {
                out[j * self.dofs + d] = interior[j * inner + r];
            }
        }
        if out.iter().any(|v| !(v.re.is_finite() && v.im.is_finite())) {
            return Err(singular(block, omega));
        }
        Ok(out)
    }
}

/// `e^{i α k}` for `k = 0..N` (`α = 2π/N`), read modulo `N`.
#[derive(Clone, Debug)]
struct Twiddles(Vec<c64>);

impl Twiddles {
    fn new(sectors: usize) -> Self {
        let alpha = 2.0 * PI / sectors as f64;
        Self((0..sectors).map(|k| c64::cis(alpha * k as f64)).collect())
    }

    /// `e^{i α k}`.
    fn at(&self, k: usize) -> c64 {
        self.0[k % self.0.len()]
    }
}

/// A block-circulant condensed block of the whole wheel (contact entries
/// sector-major, `per` a sector): `Ŝ(s)`, `∂Ŝ(s)/∂ω` per nodal diameter,
/// and the first block rows `S(0, ·)`, `∂S(0, ·)/∂ω` for single entries.
#[derive(Clone, Debug)]
pub(in crate::hbm) struct Circulant {
    twiddles: Twiddles,
    per: usize,
    diameters: Vec<(Mat<c64>, Mat<c64>)>,
    row: Mat<c64>,
    derivative_row: Mat<c64>,
}

impl Circulant {
    fn sectors(&self) -> usize {
        self.diameters.len()
    }

    /// `Ŝ(s)`, `s` modulo `N`.
    pub(super) fn diameter(&self, s: i64) -> &Mat<c64> {
        let n = self.sectors() as i64;
        &self.diameters[s.rem_euclid(n) as usize].0
    }

    /// `S[a, b] = S(0, t − s)[p, q]` for `a = s·per + p`, `b = t·per + q`.
    pub(super) fn entry(&self, a: usize, b: usize, derivative: bool) -> c64 {
        let (n, per) = (self.sectors(), self.per);
        let (s, p) = (a / per, a % per);
        let (t, q) = (b / per, b % per);
        let row = if derivative {
            &self.derivative_row
        } else {
            &self.row
        };
        row[(p, ((t + n - s) % n) * per + q)]
    }

    /// `S x` diameter by diameter: `(S x)_j = Σ_s e^{i s α j} Ŝ(s) x̂(s)`.
    pub(super) fn multiply(&self, x: &[c64], derivative: bool) -> Vec<c64> {
        let (n, per) = (self.sectors(), self.per);
        let zero = c64::new(0.0, 0.0);
        let mut out = vec![zero; n * per];
        let mut hat = vec![zero; per];
        let mut product = vec![zero; per];
        for (s, (dynamic, dynamic_derivative)) in self.diameters.iter().enumerate() {
            let z = if derivative {
                dynamic_derivative
            } else {
                dynamic
            };
            hat.fill(zero);
            for j in 0..n {
                let w = self.twiddles.at(s * j).conj() / n as f64;
                for (h, v) in hat.iter_mut().zip(&x[j * per..(j + 1) * per]) {
                    *h += v * w;
                }
            }
            for (a, p) in product.iter_mut().enumerate() {
                *p = hat
                    .iter()
                    .enumerate()
                    .fold(zero, |sum, (b, h)| sum + z[(a, b)] * h);
            }
            for j in 0..n {
                let w = self.twiddles.at(s * j);
                for (o, p) in out[j * per..(j + 1) * per].iter_mut().zip(&product) {
                    *o += p * w;
                }
            }
        }
        out
    }

    pub(super) fn is_finite(&self) -> bool {
        let finite = |m: &Mat<c64>| {
            (0..m.nrows()).all(|r| {
                (0..m.ncols()).all(|c| m[(r, c)].re.is_finite() && m[(r, c)].im.is_finite())
            })
        };
        self.diameters.iter().all(|(z, dz)| finite(z) && finite(dz))
            && finite(&self.row)
            && finite(&self.derivative_row)
    }
}

/// Whether `a` (sector-major, `sectors` equal blocks a side) is
/// block-circulant: `A(j, j') = A(0, j' − j)` to round-off.
fn is_block_circulant(a: &Mat<c64>, sectors: usize) -> bool {
    let size = a.nrows();
    let dofs = size / sectors;
    let scale = (0..size)
        .flat_map(|r| (0..size).map(move |c| (r, c)))
        .fold(0.0_f64, |m, (r, c)| m.max(a[(r, c)].norm()));
    let tolerance = CIRCULANT_TOLERANCE * scale.max(f64::MIN_POSITIVE);
    (0..size).all(|r| {
        let (j, p) = (r / dofs, r % dofs);
        (0..size).all(|c| {
            let (k, q) = (c / dofs, c % dofs);
            let first = a[(p, ((k + sectors - j) % sectors) * dofs + q)];
            (a[(r, c)] - first).norm() <= tolerance
        })
    })
}

#[cfg(test)]
pub(super) mod tests;
