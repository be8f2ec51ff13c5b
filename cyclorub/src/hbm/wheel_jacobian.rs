//! The full wheel's Jacobian in physical coordinates without forming it
//! (9072² on the open fan): its product with a vector from the condensed
//! harmonic blocks and the contact blocks of each sampled signal, and a
//! factored approximation in the frame of the traveling wave.
//!
//! `J = Z + C_law (a I + b Z) + C_disp`: `Z` block-circulant over sectors
//! (per harmonic `k`, `Z_k(s − s')` between sectors `s` and `s'`), the
//! contact blocks sector by sector. Undo the wave in each sector,
//! `y_s = R_s x_s` with `R_s` the rotation of each harmonic's `(Re, Im)` by
//! `k h α s` (`α = 2π/N`, `h` the engine order): `Z` stays circulant
//! (`Z̃(d) = Z_k(d) e^{i k h α d}`), and at a solution of the traveling
//! wave every sector's contact blocks become the same, `C̃_s = R_s C_s R_sᵀ
//! = C̄`. The Fourier transform over sectors then splits `J` into one
//! complex block per wave number `m`, `M_m = Ẑ(m) + C̄_law (a + b Ẑ(m)) +
//! C̄_disp` (`n_c (2 N_h + 1)` unknowns: 567 on the fan), `M_{N−m} =
//! conj(M_m)`. With `C̄` the sectors' average the blocks are exact at
//! symmetric points and a preconditioner elsewhere (GMRES iterates).

use super::friction::{Column, BLOCKS};
use super::layout::Layout;
use super::linear::{multiply_blocks, Condensed};
use crate::continuation::{Approximation, StructuredJacobian};
use faer::dyn_stack::{MemBuffer, MemStack};
use faer::linalg::lu::partial_pivoting::{factor, solve};
use faer::{c64, Mat, Par};
use rayon::prelude::*;
use std::f64::consts::PI;
use std::sync::Arc;

/// `∂R/∂x` of the physical full wheel at one evaluation.
#[derive(Debug)]
pub(super) struct WheelJacobian {
    pub(super) layout: Arc<Layout>,
    /// The condensed harmonic blocks of `Z` at the evaluation's frequency.
    pub(super) linear: Arc<Vec<Condensed>>,
    /// The law's weights `(a, b)`: it reads `a x + b r`.
    pub(super) weights: (f64, f64),
    /// Normal contact dofs per sector (the first of its contact dofs).
    pub(super) normal_dofs: usize,
    /// `H × H` law blocks per signal (sector-major, normal dof).
    pub(super) law_blocks: Vec<f64>,
    /// With friction, six `H × H` blocks per signal (see `friction::BLOCKS`).
    pub(super) friction_blocks: Option<Vec<f64>>,
    /// The engine order whose traveling wave the approximation undoes.
    pub(super) engine_order: i64,
}

impl WheelJacobian {
    fn coordinates(&self) -> usize {
        self.layout.coordinates()
    }

    /// The normal band and the two tangential bands of signal `index`, as
    /// offsets within its sector's coordinates.
    fn local_bands(&self, index: usize) -> (usize, [usize; 2]) {
        let size = self.coordinates();
        let c = index % self.normal_dofs;
        let theta = (self.normal_dofs + 2 * c) * size;
        (c * size, [theta, theta + size])
    }

    /// `(block, row band, column band, law)` of every contact block of
    /// signal `index`, bands local to its sector.
    fn blocks_of(&self, index: usize) -> Vec<(&[f64], usize, usize, bool)> {
        let square = self.coordinates() * self.coordinates();
        let (normal, tangents) = self.local_bands(index);
        let mut out = vec![(
            &self.law_blocks[index * square..(index + 1) * square],
            normal,
            normal,
            true,
        )];
        if let Some(friction) = &self.friction_blocks {
            for (b, &(row, column)) in BLOCKS.iter().enumerate() {
                let at = (index * BLOCKS.len() + b) * square;
                let (from, law) = match column {
                    Column::Normal => (normal, true),
                    Column::Circumferential => (tangents[0], false),
                    Column::Axial => (tangents[1], false),
                };
                out.push((&friction[at..at + square], tangents[row], from, law));
            }
        }
        out
    }
}

impl StructuredJacobian for WheelJacobian {
    fn apply(&self, v: &[f64], out: &mut [f64]) {
        let size = self.coordinates();
        let sector = self.layout.contact_dofs * size;
        let (a, b) = self.weights;
        multiply_blocks(&self.layout, &self.linear, v, false, out);
        let law_input: Vec<f64> = if b == 0.0 {
            v.iter().map(|x| a * x).collect()
        } else {
            v.iter()
                .zip(out.iter())
                .map(|(x, z)| a * x + b * z)
                .collect()
        };
        let signals = self.layout.sampled_sectors * self.normal_dofs;
        for index in 0..signals {
            let base = (index / self.normal_dofs) * sector;
            for (block, row, column, law) in self.blocks_of(index) {
                let input = if law { &law_input } else { v };
                let input = &input[base + column..base + column + size];
                for (r, o) in out[base + row..base + row + size].iter_mut().enumerate() {
                    *o += block[r * size..(r + 1) * size]
                        .iter()
                        .zip(input)
                        .map(|(t, x)| t * x)
                        .sum::<f64>();
                }
            }
        }
    }

    fn approximation(&self) -> Result<Arc<dyn Approximation>, String> {
        WaveFrame::new(self).map(|frame| Arc::new(frame) as Arc<dyn Approximation>)
    }
}

/// `B ← R B Rᵀ` for an `H × H` row-major block, `R` the rotation of each
/// harmonic `k`'s `(Re, Im)` by `k φ`.
fn rotate_block(block: &mut [f64], size: usize, phi: f64) {
    let harmonics = (size - 1) / 2;
    let rotations: Vec<(f64, f64)> = (1..=harmonics)
        .map(|k| (k as f64 * phi).sin_cos())
        .collect();
    // Rows: R B.
    for col in 0..size {
        for (k, &(s, c)) in rotations.iter().enumerate() {
            let (i, j) = (2 * k + 1, 2 * k + 2);
            let (x, y) = (block[i * size + col], block[j * size + col]);
            block[i * size + col] = c * x - s * y;
            block[j * size + col] = s * x + c * y;
        }
    }
    // Columns: (R B) Rᵀ.
    for row in block.chunks_exact_mut(size) {
        for (k, &(s, c)) in rotations.iter().enumerate() {
            let (i, j) = (2 * k + 1, 2 * k + 2);
            let (x, y) = (row[i], row[j]);
            row[i] = c * x - s * y;
            row[j] = s * x + c * y;
        }
    }
}

/// `(sin k φ, cos k φ)` for `k = 1..=harmonics`: a sector's rotation.
fn rotation(harmonics: usize, phi: f64) -> Vec<(f64, f64)> {
    (1..=harmonics)
        .map(|k| (k as f64 * phi).sin_cos())
        .collect()
}

/// `v ← R v` (or `Rᵀ v` if `back`) for one sector's coordinates, `R` the
/// rotation of each harmonic by `k φ` (`rotation`, see [`rotation`]).
fn rotate_sector(v: &mut [f64], size: usize, rotation: &[(f64, f64)], back: bool) {
    let harmonics = (size - 1) / 2;
    let sign = if back { -1.0 } else { 1.0 };
    for band in v.chunks_exact_mut(size) {
        for k in 1..=harmonics {
            let (s, c) = rotation[k - 1];
            let s = sign * s;
            let (x, y) = (band[2 * k - 1], band[2 * k]);
            band[2 * k - 1] = c * x - s * y;
            band[2 * k] = s * x + c * y;
        }
    }
}

/// The sectors' average of the contact blocks in the frame of the wave
/// of engine order `order`, and their largest departure from it relative
/// to the average's largest entry (0 at a solution of that wave).
fn averaged_blocks(jacobian: &WheelJacobian, order: i64) -> (Vec<Vec<f64>>, f64) {
    let size = jacobian.coordinates();
    let sectors = jacobian.layout.sampled_sectors;
    let alpha = 2.0 * PI / sectors as f64;
    let per_signal = jacobian.blocks_of(0).len();
    let mut average = vec![vec![0.0; size * size]; jacobian.normal_dofs * per_signal];
    let rotated = |index: usize, b: usize| -> Vec<f64> {
        let sector = index / jacobian.normal_dofs;
        let mut block = jacobian.blocks_of(index)[b].0.to_vec();
        rotate_block(&mut block, size, order as f64 * alpha * sector as f64);
        block
    };
    let signals = sectors * jacobian.normal_dofs;
    for index in 0..signals {
        for b in 0..per_signal {
            let slot = &mut average[(index % jacobian.normal_dofs) * per_signal + b];
            for (a, r) in slot.iter_mut().zip(rotated(index, b)) {
                *a += r / sectors as f64;
            }
        }
    }
    let largest = average
        .iter()
        .flatten()
        .fold(0.0_f64, |m, v| m.max(v.abs()));
    let mut spread = 0.0_f64;
    for index in 0..signals {
        for b in 0..per_signal {
            let slot = &average[(index % jacobian.normal_dofs) * per_signal + b];
            for (a, r) in slot.iter().zip(rotated(index, b)) {
                spread = spread.max((a - r).abs());
            }
        }
    }
    (average, spread / largest.max(f64::MIN_POSITIVE))
}

/// `L U` in place and the row permutation.
#[derive(Debug)]
struct Lu<T> {
    lu: Mat<T>,
    forward: Vec<usize>,
    inverse: Vec<usize>,
}

/// One factored block: complex, or real for the real blocks (`m = 0` and
/// `N/2`, whose waves are ±1): a quarter of the work.
#[derive(Debug)]
enum Factored {
    Complex(Lu<c64>),
    Real(Lu<f64>),
}

impl Factored {
    /// `hat ← M⁻¹ hat`.
    fn solve_in_place(&self, hat: &mut Mat<c64>) {
        fn substitute<T: faer::traits::ComplexField>(factors: &Lu<T>, rhs: &mut Mat<T>) {
            let n = factors.lu.nrows();
            let columns = rhs.ncols();
            let permutation =
                faer::perm::PermRef::new_checked(&factors.forward, &factors.inverse, n);
            solve::solve_in_place(
                factors.lu.as_ref(),
                factors.lu.as_ref(),
                permutation,
                rhs.as_mut(),
                Par::Seq,
                MemStack::new(&mut MemBuffer::new(
                    solve::solve_in_place_scratch::<usize, T>(n, columns, Par::Seq),
                )),
            );
        }
        match self {
            Self::Complex(factors) => substitute(factors, hat),
            Self::Real(factors) => {
                // Real and imaginary parts as two real right-hand sides.
                let n = hat.nrows();
                let mut parts = Mat::<f64>::from_fn(n, 2, |r, c| {
                    if c == 0 {
                        hat[(r, 0)].re
                    } else {
                        hat[(r, 0)].im
                    }
                });
                substitute(factors, &mut parts);
                for r in 0..n {
                    hat[(r, 0)] = c64::new(parts[(r, 0)], parts[(r, 1)]);
                }
            }
        }
    }
}

/// The factored blocks `M_m`, `m = 0..=N/2`, and how to reach them.
#[derive(Debug)]
struct WaveFrame {
    sectors: usize,
    size: usize,
    /// Coordinates per sector, `n_c H`.
    width: usize,
    /// Per wave number, its block's factors.
    blocks: Vec<Factored>,
    /// `e^{iαp}`, `p = 0..N`: the transforms over sectors.
    waves: Vec<c64>,
    /// Per sector `s`, the rotation by `k h α s` of each harmonic.
    rotations: Vec<Vec<(f64, f64)>>,
    determinant_sign: f64,
}

impl WaveFrame {
    fn new(jacobian: &WheelJacobian) -> Result<Self, String> {
        let layout = &jacobian.layout;
        let (sectors, size) = (layout.sampled_sectors, layout.coordinates());
        let contacts = layout.contact_dofs;
        let width = contacts * size;
        let alpha = 2.0 * PI / sectors as f64;
        // The wave's frame: the sign of the engine order that makes the
        // sectors' contact blocks alike.
        let candidates = if jacobian.engine_order == 0 {
            vec![0]
        } else {
            vec![jacobian.engine_order, -jacobian.engine_order]
        };
        let (order, (average, spread)) = candidates
            .into_iter()
            .map(|order| (order, averaged_blocks(jacobian, order)))
            .min_by(|a, b| a.1 .1.total_cmp(&b.1 .1))
            .ok_or("no wave frame")?;
        if spread > 1e-9 {
            tracing::debug!(
                "full wheel: the contact blocks differ between sectors by {spread:.1e} in the \
                 frame of engine order {order}: GMRES iterates"
            );
        }
        let (a, b) = jacobian.weights;
        let per_signal = average.len() / jacobian.normal_dofs;
        let mut template = Vec::new();
        for c in 0..jacobian.normal_dofs {
            for (k, (_, row, column, law)) in jacobian.blocks_of(c).into_iter().enumerate() {
                template.push((&average[c * per_signal + k], row, column, law));
            }
        }
        let columns = circulant_columns(jacobian);
        let last = sectors / 2;
        let blocks: Vec<Result<(Factored, c64), String>> = (0..=last)
            .into_par_iter()
            .map(|m| {
                let hat = linear_block(jacobian, &columns, order, m, alpha, width);
                let mut matrix = hat.clone();
                for &(block, row, column, law) in &template {
                    for r in 0..size {
                        for q in 0..size {
                            let t = block[r * size + q];
                            if t == 0.0 {
                                continue;
                            }
                            if law {
                                matrix[(row + r, column + q)] += c64::new(a * t, 0.0);
                                if b != 0.0 {
                                    // t · b Ẑ(m)[column + q, :]: Ẑ(m) couples the
                                    // coordinates of one harmonic only.
                                    let k = q.div_ceil(2);
                                    let same = if k == 0 { 0..1 } else { 2 * k - 1..2 * k + 1 };
                                    for dof in 0..contacts {
                                        for col in same.clone().map(|c| dof * size + c) {
                                            let z = hat[(column + q, col)];
                                            matrix[(row + r, col)] += z * (b * t);
                                        }
                                    }
                                }
                            } else {
                                matrix[(row + r, column + q)] += c64::new(t, 0.0);
                            }
                        }
                    }
                }
                let real = m == 0 || 2 * m == sectors;
                factorize(matrix, real).ok_or_else(|| format!("wave number {m}: singular block"))
            })
            .collect();
        let mut sign = 1.0;
        let mut factored = Vec::with_capacity(blocks.len());
        for (m, block) in blocks.into_iter().enumerate() {
            let (factors, phase) = block?;
            // Conjugate pairs give |det|²; the real blocks (m = 0, N/2) their sign.
            if m == 0 || 2 * m == sectors {
                sign *= phase.re.signum();
            }
            factored.push(factors);
        }
        let harmonics = (size - 1) / 2;
        Ok(Self {
            sectors,
            size,
            width,
            blocks: factored,
            waves: (0..sectors).map(|p| c64::cis(alpha * p as f64)).collect(),
            rotations: (0..sectors)
                .map(|s| rotation(harmonics, order as f64 * alpha * s as f64))
                .collect(),
            determinant_sign: sign,
        })
    }
}

/// Per harmonic block kept densely (a mistuned wheel, which is not
/// block-circulant), the first block column of its nearest block-circulant
/// matrix: `Z̄(d) = (1/N) Σ_s Z(s + d, s)`, the sectors' average of each
/// block diagonal (the tuned wheel's `Z(d)` plus the mean mistuning, exact
/// for a tuned wheel). Empty for blocks kept by diameters.
fn circulant_columns(jacobian: &WheelJacobian) -> Vec<Mat<c64>> {
    let layout = &jacobian.layout;
    let (sectors, contacts) = (layout.sampled_sectors, layout.contact_dofs);
    jacobian
        .linear
        .iter()
        .map(|condensed| {
            if condensed.diameter(0).is_some() {
                return Mat::new();
            }
            let mut column = Mat::<c64>::zeros(sectors * contacts, contacts);
            let share = 1.0 / sectors as f64;
            for d in 0..sectors {
                for s in 0..sectors {
                    let (r, c) = (((s + d) % sectors) * contacts, s * contacts);
                    for row in 0..contacts {
                        for col in 0..contacts {
                            column[(d * contacts + row, col)] +=
                                condensed.entry(r + row, c + col, false) * share;
                        }
                    }
                }
            }
            column
        })
        .collect()
}

/// `Ẑ(m) = Σ_d Z̃(d) e^{−iαmd}` on one sector's coordinates, `Z̃(d)` the
/// real form of `Z_k(d) e^{i k h α d}` per harmonic.
fn linear_block(
    jacobian: &WheelJacobian,
    columns: &[Mat<c64>],
    order: i64,
    m: usize,
    alpha: f64,
    width: usize,
) -> Mat<c64> {
    let layout = &jacobian.layout;
    let (sectors, size, contacts) = (
        layout.sampled_sectors,
        layout.coordinates(),
        layout.contact_dofs,
    );
    let mut out = Mat::<c64>::zeros(width, width);
    for (index, (block, condensed)) in layout.blocks.iter().zip(jacobian.linear.iter()).enumerate()
    {
        let k = block.harmonic;
        // Kept by diameters: the real form's transform takes Re and Im of
        // Z̃(d) apart, A = Σ_d w_d Re Z̃(d) = (P + Q̄)/2 and B = Σ_d w_d Im Z̃(d)
        // = (P − Q̄)/2i, with w_d = e^{−iαmd}, P = Σ_d w_d Z̃(d) = Ẑ(m − k h)
        // and Q̄ = Σ_d w_d conj Z̃(d) = conj Ẑ(−m − k h).
        let twist = k as i64 * order;
        if let (Some(p), Some(q)) = (
            condensed.diameter(m as i64 - twist),
            condensed.diameter(-(m as i64) - twist),
        ) {
            for row in 0..contacts {
                for col in 0..contacts {
                    let (p, q) = (p[(row, col)], q[(row, col)].conj());
                    let a = (p + q) * 0.5;
                    let (r, c) = (row * size, col * size);
                    if k == 0 {
                        out[(r, c)] += a;
                    } else {
                        let b = (p - q) * c64::new(0.0, -0.5);
                        let (ri, ci) = (r + 2 * k - 1, c + 2 * k - 1);
                        out[(ri, ci)] += a;
                        out[(ri, ci + 1)] -= b;
                        out[(ri + 1, ci)] += b;
                        out[(ri + 1, ci + 1)] += a;
                    }
                }
            }
            continue;
        }
        let column = &columns[index];
        for d in 0..sectors {
            let wave = c64::cis(-alpha * (m * d) as f64);
            let twist = c64::cis(k as f64 * order as f64 * alpha * d as f64);
            for row in 0..contacts {
                for col in 0..contacts {
                    // Z_k(d) between sector d's dof `row` and sector 0's `col`.
                    let z = column[(d * contacts + row, col)] * twist;
                    let (r, c) = (row * size, col * size);
                    if k == 0 {
                        out[(r, c)] += wave * z.re;
                    } else {
                        let (ri, ci) = (r + 2 * k - 1, c + 2 * k - 1);
                        out[(ri, ci)] += wave * z.re;
                        out[(ri, ci + 1)] -= wave * z.im;
                        out[(ri + 1, ci)] += wave * z.im;
                        out[(ri + 1, ci + 1)] += wave * z.re;
                    }
                }
            }
        }
    }
    out
}

/// LU with partial pivoting in place: the factors, the permutation and
/// `det / |det|`; `None` if singular. A `real` block is factored in real
/// arithmetic (its imaginary parts are zero, or round-off of the waves ±1).
fn factorize(matrix: Mat<c64>, real: bool) -> Option<(Factored, c64)> {
    fn in_place<T: faer::traits::ComplexField>(mut matrix: Mat<T>) -> Lu<T> {
        let n = matrix.nrows();
        let (mut forward, mut inverse) = (vec![0; n], vec![0; n]);
        factor::lu_in_place(
            matrix.as_mut(),
            &mut forward,
            &mut inverse,
            Par::Seq,
            MemStack::new(&mut MemBuffer::new(
                factor::lu_in_place_scratch::<usize, T>(n, n, Par::Seq, Default::default()),
            )),
            Default::default(),
        );
        Lu {
            lu: matrix,
            forward,
            inverse,
        }
    }
    let n = matrix.nrows();
    let (factors, diagonal): (Factored, Vec<c64>) = if real {
        let lu = in_place(Mat::<f64>::from_fn(n, n, |r, c| matrix[(r, c)].re));
        let diagonal = (0..n).map(|i| c64::new(lu.lu[(i, i)], 0.0)).collect();
        (Factored::Real(lu), diagonal)
    } else {
        let lu = in_place(matrix);
        let diagonal = (0..n).map(|i| lu.lu[(i, i)]).collect();
        (Factored::Complex(lu), diagonal)
    };
    let forward = match &factors {
        Factored::Complex(lu) => &lu.forward,
        Factored::Real(lu) => &lu.forward,
    };
    let mut phase = if crate::continuation::permutation_is_odd(forward) {
        c64::new(-1.0, 0.0)
    } else {
        c64::new(1.0, 0.0)
    };
    for u in diagonal {
        let modulus = u.norm();
        if modulus == 0.0 || !modulus.is_finite() {
            return None;
        }
        phase *= u / modulus;
    }
    Some((factors, phase))
}

impl Approximation for WaveFrame {
    fn solve_in_place(&self, r: &mut [f64]) {
        let (sectors, width, size) = (self.sectors, self.width, self.size);
        // Into the wave's frame, then over sectors: ŷ_m = Σ_s y_s e^{−iαms}.
        for (s, sector) in r.chunks_exact_mut(width).enumerate() {
            rotate_sector(sector, size, &self.rotations[s], false);
        }
        let waves = &self.waves;
        let mut solved = Vec::with_capacity(self.blocks.len());
        for (m, factors) in self.blocks.iter().enumerate() {
            let mut hat = Mat::<c64>::zeros(width, 1);
            for (s, sector) in r.chunks_exact(width).enumerate() {
                let wave = waves[(m * s) % sectors].conj();
                for (i, v) in sector.iter().enumerate() {
                    hat[(i, 0)] += wave * *v;
                }
            }
            factors.solve_in_place(&mut hat);
            solved.push(hat);
        }
        // Back: y_s = (1/N) Σ_m ẑ_m e^{iαms}, ẑ_{N−m} = conj(ẑ_m).
        for (s, sector) in r.chunks_exact_mut(width).enumerate() {
            for (i, v) in sector.iter_mut().enumerate() {
                let mut sum = 0.0;
                for (m, hat) in solved.iter().enumerate() {
                    let term = (hat[(i, 0)] * waves[(m * s) % sectors]).re;
                    let twice = m != 0 && 2 * m != sectors;
                    sum += if twice { 2.0 * term } else { term };
                }
                *v = sum / sectors as f64;
            }
            rotate_sector(sector, size, &self.rotations[s], true);
        }
    }

    fn determinant_sign(&self) -> f64 {
        self.determinant_sign
    }
}
