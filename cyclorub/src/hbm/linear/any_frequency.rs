//! The linear part read at any frequency, without touching the matrices
//! kept for the current one (so that points and linear responses can be
//! computed in parallel from a shared problem): linear solutions and
//! residuals, the free response of a block, and the recovery of a block's
//! dofs from its contact values.

use super::super::layout::Layout;
use super::super::HbmError;
use super::condensation::{condense, condense_for_products, singular};
use super::{condense_block, derivative, DerivativeUse, LinearPart, WheelStructure};
use faer::linalg::solvers::Solve;
use faer::{c64, Mat};

impl LinearPart {
    /// The contact dofs' own values of block `index` at `omega` from the
    /// contact unknowns: the unknowns themselves for a rigid casing; with a
    /// wall, the blade side of the spring, `x_b = (Z + κ I)⁻¹ (F + κ x_w)`
    /// (`Z`, `F` condensed on the contact dofs).
    pub fn blade_contact_values(
        &self,
        layout: &Layout,
        index: usize,
        omega: f64,
        contact_values: &[c64],
    ) -> Result<Vec<c64>, HbmError> {
        let Some(kappa) = self.wall_stiffness else {
            return Ok(contact_values.to_vec());
        };
        let block = &layout.blocks[index];
        // `Z` and `F` only: a dense wheel's derivative is not formed.
        let local = &self.blocks[index];
        let condensed = match local.structure {
            WheelStructure::Dense => condense_for_products(block, local, omega)?,
            _ => condense(block, local, omega)?,
        };
        let nc = contact_values.len();
        let mut a = condensed.dynamic;
        for d in 0..nc {
            a[(d, d)] += kappa;
        }
        let rhs = Mat::from_fn(nc, 1, |r, _| condensed.load[r] + contact_values[r] * kappa);
        let x = a.partial_piv_lu().solve(&rhs);
        let x: Vec<c64> = (0..nc).map(|r| x[(r, 0)]).collect();
        if x.iter().any(|v| !(v.re.is_finite() && v.im.is_finite())) {
            return Err(singular(block, omega));
        }
        Ok(x)
    }

    /// The solution of the linear problem `Z(ω) x = F(ω)` (no contact) at
    /// any frequency, without touching the matrices kept for the current
    /// frequency (so that linear responses can be computed in parallel
    /// from a shared problem). `Z` is block diagonal: each block (a pair,
    /// or a harmonic of the wheel) is condensed as in [`Self::update`] and
    /// solved alone, in the real layout's own form (`[[Re Z, −Im Z], [Im Z,
    /// Re Z]]`, a real coefficient keeping its real row and column only).
    pub fn solution_at(&self, layout: &Layout, omega: f64) -> Result<Vec<f64>, HbmError> {
        let singular = || HbmError::SingularLinearSystem {
            frequency_hz: omega / (2.0 * std::f64::consts::PI),
        };
        let mut x = vec![0.0; layout.unknowns];
        for (block, local) in layout.blocks.iter().zip(&self.blocks) {
            // An unloaded block's solution is zero (only the forced
            // harmonics cost a condensation: a mistuned wheel's dense one
            // on every harmonic made its linear curve the run's longest
            // output step).
            if local.load.iter().all(|f| f.re == 0.0 && f.im == 0.0) {
                continue;
            }
            let condensed = condense_block(
                block,
                local,
                omega,
                self.wall_stiffness,
                DerivativeUse::Products,
            )?;
            // The block's unknowns, numbered locally: each slot's real part,
            // then its imaginary part if it has one.
            let mut index = Vec::with_capacity(2 * block.slots.len());
            let local_slots: Vec<(usize, Option<usize>)> = block
                .slots
                .iter()
                .map(|slot| {
                    index.push(slot.re);
                    let re = index.len() - 1;
                    let im = slot.im.map(|im| {
                        index.push(im);
                        index.len() - 1
                    });
                    (re, im)
                })
                .collect();
            let m = index.len();
            let mut matrix = Mat::<f64>::zeros(m, m);
            let mut rhs = Mat::<f64>::zeros(m, 1);
            for (a, &(re_a, im_a)) in local_slots.iter().enumerate() {
                rhs[(re_a, 0)] = condensed.load[a].re;
                if let Some(im_a) = im_a {
                    rhs[(im_a, 0)] = condensed.load[a].im;
                }
                for (b, &(re_b, im_b)) in local_slots.iter().enumerate() {
                    let z = condensed.entry(a, b, false);
                    matrix[(re_a, re_b)] = z.re;
                    if let Some(im_b) = im_b {
                        matrix[(re_a, im_b)] = -z.im;
                    }
                    if let Some(im_a) = im_a {
                        matrix[(im_a, re_b)] = z.im;
                        if let Some(im_b) = im_b {
                            matrix[(im_a, im_b)] = z.re;
                        }
                    }
                }
            }
            let solved = matrix.partial_piv_lu().solve(&rhs);
            for (r, &global) in index.iter().enumerate() {
                x[global] = solved[(r, 0)];
            }
        }
        if x.iter().all(|v| v.is_finite()) {
            Ok(x)
        } else {
            Err(singular())
        }
    }

    /// The linear residual `Z(ω) x − F(ω)` at any frequency, block by block,
    /// without touching the matrices kept for the current frequency (so
    /// that points can be recovered in parallel from a shared problem).
    pub fn residual_at(
        &self,
        layout: &Layout,
        x: &[f64],
        omega: f64,
    ) -> Result<Vec<f64>, HbmError> {
        let mut out = vec![0.0; layout.unknowns];
        for (block, local) in layout.blocks.iter().zip(&self.blocks) {
            let condensed = condense_block(
                block,
                local,
                omega,
                self.wall_stiffness,
                DerivativeUse::Products,
            )?;
            let values: Vec<c64> = block
                .slots
                .iter()
                .map(|slot| c64::new(x[slot.re], slot.im.map_or(0.0, |im| x[im])))
                .collect();
            let product = condensed.multiply(&values, false);
            for (a, slot) in block.slots.iter().enumerate() {
                // A slot without an imaginary part is a real coefficient:
                // its row keeps the real part, as the real layout does.
                let value = product[a] - condensed.load[a];
                out[slot.re] = value.re;
                if let Some(im) = slot.im {
                    out[im] = value.im;
                }
            }
        }
        Ok(out)
    }

    /// The linear response of block `index` at `omega` on all its local
    /// dofs, `u = Z(kω)⁻¹ f` (no contact force, so no wall: its node
    /// follows the blade), by one dense LU of the block (a wheel with a
    /// structure: its condensed solution, recovered); `None` for a block
    /// without load (its response is zero).
    pub fn free_response(
        &self,
        layout: &Layout,
        index: usize,
        omega: f64,
    ) -> Result<Option<Vec<c64>>, HbmError> {
        let (local, block) = (&self.blocks[index], &layout.blocks[index]);
        if local.load.iter().all(|f| f.re == 0.0 && f.im == 0.0) {
            return Ok(None);
        }
        if !matches!(local.structure, WheelStructure::Dense) {
            // A wheel by diameters (or in two stages) condenses cheaper
            // than a dense LU of the whole wheel: the condensed solution,
            // recovered.
            let condensed = condense_block(block, local, omega, None, DerivativeUse::Products)?;
            let nc = local.contact.len();
            let z = Mat::from_fn(nc, nc, |a, b| condensed.entry(a, b, false));
            let rhs = Mat::from_fn(nc, 1, |r, _| condensed.load[r]);
            let solved = z.partial_piv_lu().solve(&rhs);
            let contact: Vec<c64> = (0..nc).map(|r| solved[(r, 0)]).collect();
            if contact
                .iter()
                .any(|v| !(v.re.is_finite() && v.im.is_finite()))
            {
                return Err(singular(block, omega));
            }
            return self.recover(layout, index, omega, &contact).map(Some);
        }
        let all: Vec<usize> = (0..local.load.len()).collect();
        let z = derivative::sub_dynamic(&local.matrices, block.harmonic, omega, &all, &all, false);
        let rhs = Mat::from_fn(all.len(), 1, |r, _| local.load[r]);
        let solution = z.partial_piv_lu().solve(&rhs);
        let u: Vec<c64> = (0..all.len()).map(|r| solution[(r, 0)]).collect();
        if u.iter().any(|v| !(v.re.is_finite() && v.im.is_finite())) {
            return Err(singular(block, omega));
        }
        Ok(Some(u))
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
        match &local.structure {
            WheelStructure::Diameters(diameters) => {
                return diameters.recover(block, &local.load, omega, contact_values)
            }
            WheelStructure::Perturbed(perturbed) => {
                return perturbed.recover(block, &local.load, omega, contact_values)
            }
            WheelStructure::Dense => {}
        }
        let (matrices, k, interior) = (&local.matrices, block.harmonic, &local.interior);
        let zii = derivative::sub_dynamic(matrices, k, omega, interior, interior, false);
        let contact: Vec<c64> = local.contact.iter().map(|&c| x[c]).collect();
        let zic_x = derivative::gathered_product(
            matrices,
            k,
            omega,
            (interior, &local.contact),
            &contact,
            false,
        );
        let rhs = Mat::from_fn(interior.len(), 1, |r, _| local.load[interior[r]] - zic_x[r]);
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
