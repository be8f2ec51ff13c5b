//! The condensation of one block's dynamic stiffness on its contact dofs
//! (a Schur complement, with its frequency derivative and loads), densely:
//! a pair's block, or a block of the whole wheel without its diameters
//! (`diameters.rs`); and its series condensation with a flexible wall (see
//! the parent module's header).

use super::super::layout::Block;
use super::super::HbmError;
use super::derivative::{sub_dynamic, DerivativeOperator, DerivativeProducts};
use super::{BlockMatrices, Condensed, LocalBlock};
use faer::linalg::solvers::Solve;
use faer::{c64, Mat};

/// `Z = K − (kω)² M + i kω C` and `∂Z/∂ω = −2 k² ω M + i k C`.
pub(super) fn dynamic_stiffness(
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

pub(super) fn submatrix(a: &Mat<c64>, rows: &[usize], cols: &[usize]) -> Mat<c64> {
    Mat::from_fn(rows.len(), cols.len(), |r, c| a[(rows[r], cols[c])])
}

pub(super) fn singular(block: &Block, omega: f64) -> HbmError {
    HbmError::SingularDynamicStiffness {
        harmonic: block.harmonic,
        block: block.kind.to_string(),
        frequency_hz: omega / (2.0 * std::f64::consts::PI),
    }
}

/// The Schur complement on the contact dofs, its derivative, and the loads.
pub(super) fn condense(
    block: &Block,
    local: &LocalBlock,
    omega: f64,
) -> Result<Condensed, HbmError> {
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
    let condensed = Condensed {
        dynamic,
        dynamic_derivative,
        load,
        load_derivative,
        circulant: None,
        derivative_products: None,
    };
    if !condensed.is_finite() {
        return Err(singular(block, omega));
    }
    Ok(condensed)
}

/// The Schur complement on the contact dofs and the loads, as [`condense`],
/// with `∂Z/∂ω` kept as products ([`DerivativeProducts`]): for blocks whose
/// derivative is only ever applied to vectors (the structured Jacobian's
/// frequency column), at about 40 % of [`condense`]'s cost.
pub(super) fn condense_for_products(
    block: &Block,
    local: &LocalBlock,
    omega: f64,
) -> Result<Condensed, HbmError> {
    let (c, i) = (&local.contact, &local.interior);
    let (matrices, k) = (&local.matrices, block.harmonic);
    let z = |rows: &[usize], cols: &[usize]| sub_dynamic(matrices, k, omega, rows, cols, false);
    let mut dynamic = z(c, c);
    let mut load: Vec<c64> = c.iter().map(|&d| local.load[d]).collect();
    let mut products = DerivativeProducts::new(matrices, k, omega, c, i, None);
    let mut load_derivative = vec![c64::new(0.0, 0.0); c.len()];
    if !i.is_empty() {
        let nc = c.len();
        // W = Z_ii⁻¹ [Z_ic | f_i].
        let mut rhs = z(i, c);
        rhs.resize_with(i.len(), nc + 1, |r, _| local.load[i[r]]);
        let lu = z(i, i).partial_piv_lu();
        let w = lu.solve(&rhs);
        let zci_w = &z(c, i) * &w;
        for a in 0..nc {
            for b in 0..nc {
                dynamic[(a, b)] -= zci_w[(a, b)];
            }
            load[a] -= zci_w[(a, nc)];
        }
        let w_f: Vec<c64> = (0..i.len()).map(|r| w[(r, nc)]).collect();
        let w_c = w.subcols(0, nc).to_owned();
        products = DerivativeProducts::new(matrices, k, omega, c, i, Some((lu, w_c)));
        load_derivative = products.load_derivative(&w_f);
    }
    let condensed = Condensed {
        dynamic,
        dynamic_derivative: Mat::new(),
        load,
        load_derivative,
        circulant: None,
        derivative_products: Some(DerivativeOperator::new(products)),
    };
    if !condensed.is_finite() {
        return Err(singular(block, omega));
    }
    Ok(condensed)
}

/// The series condensation of a condensed block with a wall `κ`:
/// `Z_r = κ I − κ² A⁻¹`, `F_r = κ A⁻¹ F` with `A = Z + κ I`, and their
/// derivatives (see the module header).
pub(super) fn with_wall(
    block: &Block,
    condensed: Condensed,
    kappa: f64,
    omega: f64,
) -> Result<Condensed, HbmError> {
    let nc = condensed.dynamic.nrows();
    let mut a = condensed.dynamic;
    for d in 0..nc {
        a[(d, d)] += kappa;
    }
    let lu = a.partial_piv_lu();
    // [A⁻¹ | A⁻¹ F].
    let mut rhs = Mat::<c64>::zeros(nc, nc + 1);
    for r in 0..nc {
        rhs[(r, r)] = c64::new(1.0, 0.0);
        rhs[(r, nc)] = condensed.load[r];
    }
    let solved = lu.solve(&rhs);
    let inverse = solved.subcols(0, nc).to_owned();
    let b_f = solved.col(nc).to_owned();
    let kappa2 = kappa * kappa;
    let dynamic = Mat::from_fn(nc, nc, |r, c| {
        let identity = if r == c { kappa } else { 0.0 };
        c64::new(identity, 0.0) - inverse[(r, c)] * kappa2
    });
    let load = (0..nc).map(|r| b_f[r] * kappa).collect();
    // ∂F − ∂Z A⁻¹ F, and ∂Z_r = κ² A⁻¹ ∂Z A⁻¹ as a matrix or as products.
    let (d_z_b_f, dynamic_derivative, derivative_products) = match condensed.derivative_products {
        Some(products) => {
            let b_f: Vec<c64> = (0..nc).map(|r| b_f[r]).collect();
            let d_z_b_f = products.schur_product(&b_f);
            (
                d_z_b_f,
                Mat::new(),
                Some(products.with_wall(kappa, inverse.clone())),
            )
        }
        None => {
            let d_inverse = &condensed.dynamic_derivative * &inverse;
            let product = &inverse * &d_inverse;
            let derivative = Mat::from_fn(nc, nc, |r, c| product[(r, c)] * kappa2);
            let d_z_b_f = &condensed.dynamic_derivative * &b_f;
            let d_z_b_f: Vec<c64> = (0..nc).map(|r| d_z_b_f[r]).collect();
            (d_z_b_f, derivative, None)
        }
    };
    let source = faer::Col::<c64>::from_fn(nc, |r| condensed.load_derivative[r] - d_z_b_f[r]);
    let d_load = &inverse * &source;
    let load_derivative = (0..nc).map(|r| d_load[r] * kappa).collect();
    let result = Condensed {
        dynamic,
        dynamic_derivative,
        load,
        load_derivative,
        circulant: None,
        derivative_products,
    };
    if !result.is_finite() {
        return Err(singular(block, omega));
    }
    Ok(result)
}

impl Condensed {
    pub(super) fn is_finite(&self) -> bool {
        let finite = |v: &c64| v.re.is_finite() && v.im.is_finite();
        if let Some(circulant) = &self.circulant {
            return circulant.is_finite()
                && self.load.iter().chain(&self.load_derivative).all(finite);
        }
        // Kept as products, the derivative is finite where `Z` is (the
        // same LUs).
        let all_finite =
            |m: &Mat<c64>| (0..m.ncols()).all(|col| (0..m.nrows()).all(|r| finite(&m[(r, col)])));
        all_finite(&self.dynamic)
            && all_finite(&self.dynamic_derivative)
            && self.load.iter().chain(&self.load_derivative).all(finite)
    }
}
