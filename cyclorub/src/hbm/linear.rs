//! The linear part, condensed on the contact dofs: for each block (a signed
//! pair `(s, k)`, or a harmonic of the whole wheel) the dynamic stiffness
//! `Z = K − (kω)² M + i kω C`, its Schur complement on the contact dofs,
//! `∂/∂ω`, and the condensed loads. Recomputed once per frequency.

use super::layout::{Block, Layout};
use super::HbmError;
use faer::linalg::solvers::Solve;
use faer::{c64, Mat};
use std::sync::Arc;

/// Mass, stiffness and damping of one block's local dofs.
#[derive(Clone, Debug)]
pub struct BlockMatrices {
    /// Mass.
    pub mass: Arc<Mat<c64>>,
    /// Stiffness.
    pub stiffness: Arc<Mat<c64>>,
    /// Viscous damping.
    pub damping: Arc<Mat<c64>>,
}

/// One block's local problem: matrices, contact/interior split and load.
#[derive(Clone, Debug)]
pub struct LocalBlock {
    /// Matrices of the local dofs.
    pub matrices: BlockMatrices,
    /// Local indices of the contact entries, in slot order.
    pub contact: Vec<usize>,
    /// Local indices of the other dofs.
    pub interior: Vec<usize>,
    /// External load on the local dofs (harmonic coefficient).
    pub load: Vec<c64>,
}

/// A block condensed at one frequency.
#[derive(Clone, Debug)]
struct Condensed {
    dynamic: Mat<c64>,
    dynamic_derivative: Mat<c64>,
    load: Vec<c64>,
    load_derivative: Vec<c64>,
}

/// The condensed linear part of the whole problem at the current frequency,
/// in the real unknown layout.
#[derive(Clone, Debug)]
pub struct LinearPart {
    blocks: Vec<LocalBlock>,
    omega: f64,
    /// `Z(ω)`, real, unknowns × unknowns.
    pub dynamic: Mat<f64>,
    /// `∂Z/∂ω`.
    pub dynamic_derivative: Mat<f64>,
    /// Condensed external load `F(ω)`.
    pub load: Vec<f64>,
    /// `∂F/∂ω`.
    pub load_derivative: Vec<f64>,
}

impl LinearPart {
    /// The linear part of `layout` from its blocks' local problems (same order).
    pub fn new(layout: &Layout, blocks: Vec<LocalBlock>) -> Self {
        let n = layout.unknowns;
        Self {
            blocks,
            omega: f64::NAN,
            dynamic: Mat::zeros(n, n),
            dynamic_derivative: Mat::zeros(n, n),
            load: vec![0.0; n],
            load_derivative: vec![0.0; n],
        }
    }

    /// The local problems.
    pub fn blocks(&self) -> &[LocalBlock] {
        &self.blocks
    }

    /// Brings `Z`, `∂Z/∂ω`, `F`, `∂F/∂ω` to frequency `omega` (rad/s);
    /// nothing to do if it is already there.
    pub fn update(&mut self, layout: &Layout, omega: f64) -> Result<(), HbmError> {
        #[allow(clippy::float_cmp)] // the cache key is the exact frequency
        if omega == self.omega {
            return Ok(());
        }
        self.dynamic.fill(0.0);
        self.dynamic_derivative.fill(0.0);
        self.load.fill(0.0);
        self.load_derivative.fill(0.0);
        let blocks = std::mem::take(&mut self.blocks);
        let outcome: Result<(), HbmError> =
            layout
                .blocks
                .iter()
                .zip(&blocks)
                .try_for_each(|(block, local)| {
                    let condensed = condense(block, local, omega)?;
                    scatter(block, &condensed, self);
                    Ok(())
                });
        self.blocks = blocks;
        outcome?;
        self.omega = omega;
        Ok(())
    }

    /// The local dofs of block `index` at `omega`, from its contact values:
    /// `x_i = Z_ii⁻¹ (f_i − Z_ic x_c)`.
    pub fn recover(
        &self,
        layout: &Layout,
        index: usize,
        omega: f64,
        contact_values: &[c64],
    ) -> Result<Vec<c64>, HbmError> {
        let local = &self.blocks[index];
        let block = &layout.blocks[index];
        let size = local.matrices.mass.nrows();
        let mut x = vec![c64::new(0.0, 0.0); size];
        for (&c, &v) in local.contact.iter().zip(contact_values) {
            x[c] = v;
        }
        if local.interior.is_empty() {
            return Ok(x);
        }
        let (z, _) = dynamic_stiffness(&local.matrices, block.harmonic, omega);
        let zii = submatrix(&z, &local.interior, &local.interior);
        let mut rhs = Mat::<c64>::zeros(local.interior.len(), 1);
        for (r, &i) in local.interior.iter().enumerate() {
            let mut value = local.load[i];
            for &c in &local.contact {
                value -= z[(i, c)] * x[c];
            }
            rhs[(r, 0)] = value;
        }
        let solution = zii.partial_piv_lu().solve(&rhs);
        for (r, &i) in local.interior.iter().enumerate() {
            x[i] = solution[(r, 0)];
        }
        if x.iter().any(|v| !(v.re.is_finite() && v.im.is_finite())) {
            return Err(singular(block, omega));
        }
        Ok(x)
    }
}

/// `Z = K − (kω)² M + i kω C` and `∂Z/∂ω = −2 k² ω M + i k C`.
fn dynamic_stiffness(
    matrices: &BlockMatrices,
    harmonic: usize,
    omega: f64,
) -> (Mat<c64>, Mat<c64>) {
    let k = harmonic as f64;
    let (m, kk, c) = (&*matrices.mass, &*matrices.stiffness, &*matrices.damping);
    let size = m.nrows();
    let mut z = Mat::<c64>::zeros(size, size);
    let mut dz = Mat::<c64>::zeros(size, size);
    let i_k_omega = c64::new(0.0, k * omega);
    let i_k = c64::new(0.0, k);
    for col in 0..size {
        for row in 0..size {
            z[(row, col)] = kk[(row, col)] - m[(row, col)] * (k * k * omega * omega)
                + c[(row, col)] * i_k_omega;
            dz[(row, col)] = m[(row, col)] * (-2.0 * k * k * omega) + c[(row, col)] * i_k;
        }
    }
    (z, dz)
}

fn submatrix(a: &Mat<c64>, rows: &[usize], cols: &[usize]) -> Mat<c64> {
    Mat::from_fn(rows.len(), cols.len(), |r, c| a[(rows[r], cols[c])])
}

fn singular(block: &Block, omega: f64) -> HbmError {
    HbmError::SingularDynamicStiffness {
        harmonic: block.harmonic,
        block: format!("{:?}", block.kind),
        frequency_hz: omega / (2.0 * std::f64::consts::PI),
    }
}

/// The Schur complement on the contact dofs, its derivative, and the loads.
fn condense(block: &Block, local: &LocalBlock, omega: f64) -> Result<Condensed, HbmError> {
    let (z, dz) = dynamic_stiffness(&local.matrices, block.harmonic, omega);
    let (c, i) = (&local.contact, &local.interior);
    let mut dynamic = submatrix(&z, c, c);
    let mut dynamic_derivative = submatrix(&dz, c, c);
    let mut load: Vec<c64> = c.iter().map(|&d| local.load[d]).collect();
    let mut load_derivative = vec![c64::new(0.0, 0.0); c.len()];
    if !i.is_empty() {
        let nc = c.len();
        let zci = submatrix(&z, c, i);
        let dzci = submatrix(&dz, c, i);
        let dzii = submatrix(&dz, i, i);
        // W = Z_ii⁻¹ [Z_ic | f_i].
        let mut rhs = Mat::<c64>::zeros(i.len(), nc + 1);
        for (r, &row) in i.iter().enumerate() {
            for (col, &cc) in c.iter().enumerate() {
                rhs[(r, col)] = z[(row, cc)];
            }
            rhs[(r, nc)] = local.load[row];
        }
        let lu = submatrix(&z, i, i).partial_piv_lu();
        let w = lu.solve(&rhs);
        // Q = Z_ii⁻¹ (∂Z_ic − ∂Z_ii W_c | −∂Z_ii W_f).
        let dzii_w = &dzii * &w;
        let mut q_rhs = Mat::<c64>::zeros(i.len(), nc + 1);
        for (r, &row) in i.iter().enumerate() {
            for (col, &cc) in c.iter().enumerate() {
                q_rhs[(r, col)] = dz[(row, cc)] - dzii_w[(r, col)];
            }
            q_rhs[(r, nc)] = -dzii_w[(r, nc)];
        }
        let q = lu.solve(&q_rhs);
        let zci_w = &zci * &w;
        let dzci_w = &dzci * &w;
        let zci_q = &zci * &q;
        for a in 0..nc {
            for b in 0..nc {
                dynamic[(a, b)] -= zci_w[(a, b)];
                dynamic_derivative[(a, b)] -= dzci_w[(a, b)] + zci_q[(a, b)];
            }
            load[a] -= zci_w[(a, nc)];
            load_derivative[a] = -(dzci_w[(a, nc)] + zci_q[(a, nc)]);
        }
    }
    let finite = |v: &c64| v.re.is_finite() && v.im.is_finite();
    let all_finite = (0..dynamic.nrows()).all(|r| {
        (0..dynamic.ncols())
            .all(|col| finite(&dynamic[(r, col)]) && finite(&dynamic_derivative[(r, col)]))
    }) && load.iter().chain(&load_derivative).all(finite);
    if !all_finite {
        return Err(singular(block, omega));
    }
    Ok(Condensed {
        dynamic,
        dynamic_derivative,
        load,
        load_derivative,
    })
}

/// Adds a condensed block to the real layout: a complex coefficient is the
/// pair `(Re, Im)` and `Z` acts as `[[Re Z, −Im Z], [Im Z, Re Z]]`.
fn scatter(block: &Block, condensed: &Condensed, part: &mut LinearPart) {
    for (a, slot_a) in block.slots.iter().enumerate() {
        part.load[slot_a.re] = condensed.load[a].re;
        part.load_derivative[slot_a.re] = condensed.load_derivative[a].re;
        if let Some(im) = slot_a.im {
            part.load[im] = condensed.load[a].im;
            part.load_derivative[im] = condensed.load_derivative[a].im;
        }
        for (b, slot_b) in block.slots.iter().enumerate() {
            for (target, source) in [
                (&mut part.dynamic, &condensed.dynamic),
                (&mut part.dynamic_derivative, &condensed.dynamic_derivative),
            ] {
                let z = source[(a, b)];
                target[(slot_a.re, slot_b.re)] += z.re;
                if let Some(im_b) = slot_b.im {
                    target[(slot_a.re, im_b)] -= z.im;
                }
                if let Some(im_a) = slot_a.im {
                    target[(im_a, slot_b.re)] += z.im;
                    if let Some(im_b) = slot_b.im {
                        target[(im_a, im_b)] += z.re;
                    }
                }
            }
        }
    }
}
