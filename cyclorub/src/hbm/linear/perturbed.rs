//! A mistuned wheel's linear part condensed in two stages. The mistuned
//! stiffness is the tuned (block-circulant) one plus a change `ΔK` that
//! touches a few dofs of each sector (on the academic model the blade
//! springs k1, k2: m1, m2, m3). Keeping those dofs beside the contact dofs,
//! the tuned wheel is condensed on them by nodal diameters (`N`
//! condensations of a sector's size, `first_stage.rs`, with the diameters'
//! matrices of `diameters.rs`); `ΔK` lies entirely on
//! the kept dofs, so it adds to that Schur complement as it is, and a dense
//! condensation of the kept dofs on the contact dofs ends the job. A Schur
//! complement of a Schur complement is the Schur complement on the smaller
//! set (the quotient formula), so this is the dense condensation of the
//! mistuned wheel, exactly; its dense step is on `N (r − c)` interior dofs
//! (`r` kept, `c` contact a sector: 48 for the academic wheel) instead of
//! `N (n − c)` (96), a factor `((n − c)/(r − c))³` (8) on the LU. On the
//! default case mistuned at 1 % (400 points) the run's CPU time fell from
//! 26.0 s to 20.2 s, the branch the same to 6e-12 with the same iterations.

use super::super::layout::Block;
use super::super::HbmError;
use super::condensation::{singular, submatrix, with_wall};
use super::{BlockMatrices, Condensed, WheelDiameters};
use faer::linalg::solvers::Solve;
use faer::{c64, Mat};
use first_stage::{first_stage, Split};
use std::sync::Arc;

mod first_stage;

/// A wheel that is a tuned one plus a stiffness change on a few dofs of
/// each sector (the same dofs in every sector), condensed in two stages.
#[derive(Debug)]
pub struct PerturbedWheel {
    sectors: usize,
    /// The tuned wheel by nodal diameters, kept dofs as its contact dofs:
    /// its diameters' matrices, and the recovery of the other dofs.
    tuned: Arc<WheelDiameters>,
    /// `ΔK` on the kept dofs of the wheel (sector-major, `kept` a sector).
    change: Mat<c64>,
    /// Kept dofs a sector: the contact dofs (slot order), then the others.
    kept: usize,
    /// Contact dofs a sector (the first of the kept ones).
    contact: usize,
    /// One sector's kept dofs (contact first) and the others.
    kept_dofs: Vec<usize>,
    inner_dofs: Vec<usize>,
    /// `e^{i α t}`, `t = 0..N`.
    twiddles: Vec<c64>,
}

impl PerturbedWheel {
    /// The two-stage form of the wheel `matrices` (`sectors` sectors,
    /// `contact` one sector's contact dofs in slot order), whose tuned
    /// wheel is `tuned`: `None` unless mass and damping are the tuned ones
    /// exactly, the stiffness differs, the tuned wheel is block-circulant
    /// and the changed dofs leave a sector some dofs to condense (the
    /// dense condensation, or the diameters for a tuned wheel, serve then).
    pub fn new(
        matrices: &BlockMatrices,
        tuned: &BlockMatrices,
        sectors: usize,
        contact: &[usize],
    ) -> Option<Arc<Self>> {
        let size = matrices.mass.nrows();
        if sectors < 2 || !size.is_multiple_of(sectors) || tuned.mass.nrows() != size {
            return None;
        }
        let same = |a: &Mat<c64>, b: &Mat<c64>| {
            (0..size).all(|c| (0..size).all(|r| a[(r, c)] == b[(r, c)]))
        };
        if !same(&matrices.mass, &tuned.mass) || !same(&matrices.damping, &tuned.damping) {
            return None;
        }
        let dofs = size / sectors;
        let change = Mat::from_fn(size, size, |r, c| {
            matrices.stiffness[(r, c)] - tuned.stiffness[(r, c)]
        });
        // The sector dofs whose row or column changes in some sector.
        let zero = c64::new(0.0, 0.0);
        let changed: Vec<usize> = (0..dofs)
            .filter(|&d| {
                (0..sectors).any(|j| {
                    let e = j * dofs + d;
                    (0..size).any(|o| change[(e, o)] != zero || change[(o, e)] != zero)
                })
            })
            .collect();
        if changed.is_empty() || contact.iter().any(|&d| d >= dofs) {
            return None;
        }
        let mut kept = contact.to_vec();
        kept.extend(changed.iter().filter(|d| !contact.contains(d)));
        if kept.len() >= dofs {
            return None;
        }
        let wheel_kept: Vec<usize> = (0..sectors)
            .flat_map(|j| kept.iter().map(move |&d| j * dofs + d))
            .collect();
        let wheel_interior: Vec<usize> =
            (0..size).filter(|e| !kept.contains(&(e % dofs))).collect();
        let diameters = WheelDiameters::new(tuned, sectors, &wheel_kept, &wheel_interior)?;
        Some(Arc::new(Self {
            sectors,
            tuned: diameters,
            change: submatrix(&change, &wheel_kept, &wheel_kept),
            kept: kept.len(),
            contact: contact.len(),
            inner_dofs: (0..dofs).filter(|d| !kept.contains(d)).collect(),
            kept_dofs: kept,
            twiddles: (0..sectors)
                .map(|t| c64::cis(2.0 * std::f64::consts::PI * t as f64 / sectors as f64))
                .collect(),
        }))
    }

    /// The kept dofs' contact and interior positions (sector-major).
    fn split(&self) -> (Vec<usize>, Vec<usize>) {
        let (n, r, c) = (self.sectors, self.kept, self.contact);
        let contact = (0..n).flat_map(|j| (0..c).map(move |q| j * r + q));
        let interior = (0..n).flat_map(|j| (c..r).map(move |q| j * r + q));
        (contact.collect(), interior.collect())
    }

    /// The tuned wheel condensed on the kept dofs plus `ΔK`: `Z`, `∂Z/∂ω`
    /// (dense, sector-major kept dofs) and the condensed load `F`, `∂F/∂ω`.
    fn kept_problem(&self, block: &Block, load: &[c64], omega: f64) -> Result<Kept, HbmError> {
        let diameters: Vec<&BlockMatrices> = (0..self.sectors)
            .map(|s| self.tuned.diameter_matrices(s))
            .collect();
        let split = Split {
            kept: &self.kept_dofs,
            inner: &self.inner_dofs,
            twiddles: &self.twiddles,
        };
        let first = first_stage(&diameters, &split, block.harmonic, omega, load)
            .ok_or_else(|| singular(block, omega))?;
        Ok(Kept {
            dynamic: first.dynamic + &self.change,
            derivative: first.derivative,
            load: first.load,
            load_derivative: first.load_derivative,
        })
    }

    /// The wheel block condensed on its contact dofs at `omega` (then in
    /// series with a wall `κ`), with the block's `load` on the wheel's
    /// dofs: the dense Schur complement of the mistuned wheel.
    pub(super) fn condense(
        &self,
        block: &Block,
        load: &[c64],
        omega: f64,
        wall_stiffness: Option<f64>,
    ) -> Result<Condensed, HbmError> {
        let kept = self.kept_problem(block, load, omega)?;
        let (contact, interior) = self.split();
        let condensed = schur(&kept, &contact, &interior);
        if !condensed.is_finite() {
            return Err(singular(block, omega));
        }
        match wall_stiffness {
            Some(kappa) => with_wall(block, condensed, kappa, omega),
            None => Ok(condensed),
        }
    }

    /// The wheel's dofs from the contact dofs' values (sector-major): the
    /// kept dofs from the dense second stage, then the others diameter by
    /// diameter.
    pub(super) fn recover(
        &self,
        block: &Block,
        load: &[c64],
        omega: f64,
        contact_values: &[c64],
    ) -> Result<Vec<c64>, HbmError> {
        let kept = self.kept_problem(block, load, omega)?;
        let (contact, interior) = self.split();
        let z = &kept.dynamic;
        let rhs = Mat::from_fn(interior.len(), 1, |r, _| {
            let i = interior[r];
            contact
                .iter()
                .zip(contact_values)
                .fold(kept.load[i], |sum, (&c, v)| sum - z[(i, c)] * v)
        });
        let solved = submatrix(z, &interior, &interior)
            .partial_piv_lu()
            .solve(&rhs);
        let mut values = vec![c64::new(0.0, 0.0); self.sectors * self.kept];
        for (&c, &v) in contact.iter().zip(contact_values) {
            values[c] = v;
        }
        for (r, &i) in interior.iter().enumerate() {
            values[i] = solved[(r, 0)];
        }
        self.tuned.recover(block, load, omega, &values)
    }
}

/// The second stage's problem: the kept dofs' dynamic stiffness, its
/// derivative, and their loads (which depend on `ω` through the first
/// stage).
struct Kept {
    dynamic: Mat<c64>,
    derivative: Mat<c64>,
    load: Vec<c64>,
    load_derivative: Vec<c64>,
}

/// The Schur complement of `kept` on `contact`, with `∂/∂ω` and the loads:
/// `W = Z_ii⁻¹ [Z_ic | F_i]`, `∂W = Z_ii⁻¹ ([∂Z_ic | ∂F_i] − ∂Z_ii W)`,
/// `S = Z_cc − Z_ci W_c`, `∂S = ∂Z_cc − ∂Z_ci W_c − Z_ci ∂W_c`, and the
/// same for the load column.
fn schur(kept: &Kept, contact: &[usize], interior: &[usize]) -> Condensed {
    let (z, dz) = (&kept.dynamic, &kept.derivative);
    let nc = contact.len();
    let mut rhs = Mat::<c64>::zeros(interior.len(), nc + 1);
    let mut d_rhs = Mat::<c64>::zeros(interior.len(), nc + 1);
    for (r, &row) in interior.iter().enumerate() {
        for (col, &c) in contact.iter().enumerate() {
            rhs[(r, col)] = z[(row, c)];
            d_rhs[(r, col)] = dz[(row, c)];
        }
        rhs[(r, nc)] = kept.load[row];
        d_rhs[(r, nc)] = kept.load_derivative[row];
    }
    let lu = submatrix(z, interior, interior).partial_piv_lu();
    let w = lu.solve(&rhs);
    let q = lu.solve(&(&d_rhs - &submatrix(dz, interior, interior) * &w));
    let zci = submatrix(z, contact, interior);
    let zci_w = &zci * &w;
    let dzci_w = &submatrix(dz, contact, interior) * &w;
    let zci_q = &zci * &q;
    let dynamic = Mat::from_fn(nc, nc, |a, b| z[(contact[a], contact[b])] - zci_w[(a, b)]);
    let dynamic_derivative = Mat::from_fn(nc, nc, |a, b| {
        dz[(contact[a], contact[b])] - dzci_w[(a, b)] - zci_q[(a, b)]
    });
    let load = (0..nc)
        .map(|a| kept.load[contact[a]] - zci_w[(a, nc)])
        .collect();
    let load_derivative = (0..nc)
        .map(|a| kept.load_derivative[contact[a]] - dzci_w[(a, nc)] - zci_q[(a, nc)])
        .collect();
    Condensed {
        dynamic,
        dynamic_derivative,
        load,
        load_derivative,
        circulant: None,
        derivative_products: None,
    }
}

#[cfg(test)]
mod tests;
