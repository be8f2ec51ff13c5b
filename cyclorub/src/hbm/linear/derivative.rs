//! `∂Z/∂ω` of a block condensed densely, kept as products `∂Z/∂ω x`
//! instead of a matrix. The structured Jacobian only ever applies it to
//! one vector a Newton iteration (the frequency column), while the matrix
//! `∂S = ∂Z_cc − ∂Z_ci W − Z_ci Z_ii⁻¹ (∂Z_ic − ∂Z_ii W)` (with
//! `W = Z_ii⁻¹ Z_ic`), and with a wall `κ² A⁻¹ ∂S A⁻¹`, costs about as much
//! again as the Schur complement itself: on a mistuned finite-element
//! wheel (docs/mistuning.md) it was most of each frequency's condensation.
//! A product costs a few matrix–vector products and one solve with the
//! interior LU kept from the condensation.

use super::{column_product, BlockMatrices};
use faer::linalg::solvers::{PartialPivLu, Solve};
use faer::{c64, Mat};
use std::sync::Arc;

/// What a block's condensation keeps to apply `∂Z/∂ω` (of its Schur
/// complement on the contact dofs, and in series with the wall if there is
/// one) to vectors.
pub(super) struct DerivativeProducts {
    matrices: BlockMatrices,
    harmonic: usize,
    omega: f64,
    contact: Vec<usize>,
    interior: Vec<usize>,
    /// The LU of `Z_ii` and `W = Z_ii⁻¹ Z_ic` (none without interior dofs).
    interior_solve: Option<(PartialPivLu<c64>, Mat<c64>)>,
}

/// `∂Z/∂ω` of a condensed block as products: its Schur complement's, then
/// in series with the wall `κ` (`A⁻¹ = (S + κ I)⁻¹`) if there is one.
#[derive(Clone, Debug)]
pub(super) struct DerivativeOperator {
    schur: Arc<DerivativeProducts>,
    wall: Option<Arc<(f64, Mat<c64>)>>,
}

impl DerivativeOperator {
    /// The Schur complement's products, without a wall.
    pub(super) fn new(schur: DerivativeProducts) -> Self {
        Self {
            schur: Arc::new(schur),
            wall: None,
        }
    }

    /// `∂S x` of the Schur complement alone.
    pub(super) fn schur_product(&self, x: &[c64]) -> Vec<c64> {
        self.schur.schur_product(x)
    }

    /// The same products in series with a wall `κ`, `inverse = (S + κ I)⁻¹`.
    pub(super) fn with_wall(self, kappa: f64, inverse: Mat<c64>) -> Self {
        Self {
            schur: self.schur,
            wall: Some(Arc::new((kappa, inverse))),
        }
    }

    /// `∂Z/∂ω x` of the condensed block: `∂S x`, or with a wall
    /// `κ² A⁻¹ ∂S A⁻¹ x`.
    pub(super) fn product(&self, x: &[c64]) -> Vec<c64> {
        let Some(wall) = &self.wall else {
            return self.schur.schur_product(x);
        };
        let (kappa, inverse) = (wall.0, &wall.1);
        let apply = |v: &[c64]| column_product(inverse, v);
        let inner = self.schur.schur_product(&apply(x));
        apply(&inner)
            .into_iter()
            .map(|v| v * (kappa * kappa))
            .collect()
    }
}

impl std::fmt::Debug for DerivativeProducts {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("DerivativeProducts")
            .field("harmonic", &self.harmonic)
            .field("omega", &self.omega)
            .field("contact", &self.contact.len())
            .field("interior", &self.interior.len())
            .finish()
    }
}

/// The coefficients `(a, b, c)` of `Z = a K + b M + c C` at harmonic `k`
/// and `ω` (`1, −(kω)², i kω`), or of `∂Z/∂ω` (`0, −2 k² ω, i k`).
fn coefficients(harmonic: usize, omega: f64, derivative: bool) -> (f64, f64, c64) {
    let k = harmonic as f64;
    if derivative {
        (0.0, -2.0 * k * k * omega, c64::new(0.0, k))
    } else {
        (1.0, -(k * k * omega * omega), c64::new(0.0, k * omega))
    }
}

/// The rows `rows` and columns `cols` of `Z = K − (kω)² M + i kω C` (or of
/// `∂Z/∂ω = −2 k² ω M + i k C` if `derivative`), read column by column.
pub(super) fn sub_dynamic(
    matrices: &BlockMatrices,
    harmonic: usize,
    omega: f64,
    rows: &[usize],
    cols: &[usize],
    derivative: bool,
) -> Mat<c64> {
    let (a, b, c) = coefficients(harmonic, omega, derivative);
    let mut out = Mat::<c64>::zeros(rows.len(), cols.len());
    for (j, &col) in cols.iter().enumerate() {
        let (kk, m, d) = (
            matrices.stiffness.col_as_slice(col),
            matrices.mass.col_as_slice(col),
            matrices.damping.col_as_slice(col),
        );
        for (o, &r) in out.col_as_slice_mut(j).iter_mut().zip(rows) {
            *o = kk[r] * a + m[r] * b + d[r] * c;
        }
    }
    out
}

/// `Σ_b Z[rows[a], cols[b]] x[b]` (or `∂Z/∂ω`), read column by column.
pub(super) fn gathered_product(
    matrices: &BlockMatrices,
    harmonic: usize,
    omega: f64,
    (rows, cols): (&[usize], &[usize]),
    x: &[c64],
    derivative: bool,
) -> Vec<c64> {
    let (a, b, c) = coefficients(harmonic, omega, derivative);
    let mut out = vec![c64::new(0.0, 0.0); rows.len()];
    for (&col, &v) in cols.iter().zip(x) {
        let (kk, m, d) = (
            matrices.stiffness.col_as_slice(col),
            matrices.mass.col_as_slice(col),
            matrices.damping.col_as_slice(col),
        );
        let (av, bv, cv) = (v * a, v * b, c * v);
        if derivative {
            for (o, &r) in out.iter_mut().zip(rows) {
                *o += m[r] * bv + d[r] * cv;
            }
        } else {
            for (o, &r) in out.iter_mut().zip(rows) {
                *o += kk[r] * av + m[r] * bv + d[r] * cv;
            }
        }
    }
    out
}

impl DerivativeProducts {
    /// The products of a block condensed at `omega` on `contact`, with the
    /// interior LU and `W` its condensation computed.
    pub(super) fn new(
        matrices: &BlockMatrices,
        harmonic: usize,
        omega: f64,
        contact: &[usize],
        interior: &[usize],
        interior_solve: Option<(PartialPivLu<c64>, Mat<c64>)>,
    ) -> Self {
        Self {
            matrices: matrices.clone(),
            harmonic,
            omega,
            contact: contact.to_vec(),
            interior: interior.to_vec(),
            interior_solve,
        }
    }

    /// `Σ_b Z[rows[a], cols[b]] x[b]` (or `∂Z/∂ω`).
    fn gathered(&self, rows: &[usize], cols: &[usize], x: &[c64], derivative: bool) -> Vec<c64> {
        gathered_product(
            &self.matrices,
            self.harmonic,
            self.omega,
            (rows, cols),
            x,
            derivative,
        )
    }

    /// `∂S x` for the Schur complement `S` (no wall).
    pub(super) fn schur_product(&self, x: &[c64]) -> Vec<c64> {
        let (c, i) = (&self.contact, &self.interior);
        if self.harmonic == 0 {
            // Nothing depends on ω.
            return vec![c64::new(0.0, 0.0); c.len()];
        }
        let mut out = self.gathered(c, c, x, true);
        let Some((lu, w)) = &self.interior_solve else {
            return out;
        };
        // y = W x, then u = Z_ii⁻¹ (∂Z_ic x − ∂Z_ii y).
        let y = column_product(w, x);
        let direct = self.gathered(i, c, x, true);
        let through = self.gathered(i, i, &y, true);
        let rhs = Mat::from_fn(i.len(), 1, |r, _| direct[r] - through[r]);
        let u = lu.solve(&rhs);
        let u: Vec<c64> = (0..i.len()).map(|r| u[(r, 0)]).collect();
        let via_y = self.gathered(c, i, &y, true);
        let via_u = self.gathered(c, i, &u, false);
        for ((o, a), b) in out.iter_mut().zip(&via_y).zip(&via_u) {
            *o -= a + b;
        }
        out
    }

    /// The load's derivative `∂F_c = −∂Z_ci w_f + Z_ci Z_ii⁻¹ ∂Z_ii w_f` of
    /// the Schur complement (the loads do not depend on `ω`), from
    /// `w_f = Z_ii⁻¹ f_i`.
    pub(super) fn load_derivative(&self, w_f: &[c64]) -> Vec<c64> {
        let (c, i) = (&self.contact, &self.interior);
        let Some((lu, _)) = &self.interior_solve else {
            return vec![c64::new(0.0, 0.0); c.len()];
        };
        let through = self.gathered(i, i, w_f, true);
        let rhs = Mat::from_fn(i.len(), 1, |r, _| through[r]);
        let u = lu.solve(&rhs);
        let u: Vec<c64> = (0..i.len()).map(|r| u[(r, 0)]).collect();
        let direct = self.gathered(c, i, w_f, true);
        let back = self.gathered(c, i, &u, false);
        direct.iter().zip(&back).map(|(a, b)| b - a).collect()
    }
}

#[cfg(test)]
mod tests;
