//! Modal damping of a sector model: the ratios checked, and `C(s)` computed
//! once per unsigned nodal diameter, on demand, and cached.

use super::SectorModel;
use crate::model::damping::ModalDamping;
use crate::model::eigen::{angular_frequencies, hermitian_modes, symmetric_modes};
use crate::model::input::{SectorInput, Subject};
use crate::model::matrices::SectorOperator;
use crate::model::ModelError;
use faer::{c64, Mat};
use rayon::prelude::*;
use std::sync::{Arc, OnceLock};

/// The damping of a built sector model.
#[derive(Clone, Debug)]
pub(super) enum DampingModel {
    /// No damping.
    None,
    /// Modal ratios, with `C(s)` for `s = 0..=N/2` computed once on demand.
    Modal(ModalDamping, ModalCache),
    /// A viscous matrix, as circulant blocks.
    Viscous(SectorOperator),
}

/// `C(s)` of the diameters `0..=N/2`, filled on first use (shared by clones:
/// the model is immutable).
#[derive(Clone, Debug)]
pub(super) struct ModalCache(Arc<Vec<OnceLock<Mat<c64>>>>);

impl ModalCache {
    pub(super) fn new(sectors: usize) -> Self {
        Self(Arc::new(
            (0..=sectors / 2).map(|_| OnceLock::new()).collect(),
        ))
    }
}

/// Finite, non-negative ratios.
pub(super) fn check_modal(modal: &ModalDamping) -> Result<(), ModelError> {
    for (r, &x) in modal.ratios.iter().enumerate() {
        if !(x.is_finite() && x >= 0.0) {
            return Err(ModelError::invalid(
                Subject::Input(SectorInput::Damping, format!(".ratios[{}]", r + 1)),
                format!("{x} is not allowed: damping ratios must be finite and ≥ 0"),
            ));
        }
    }
    if !(modal.others.is_finite() && modal.others >= 0.0) {
        return Err(ModelError::invalid(
            Subject::Input(SectorInput::Damping, ".others".into()),
            format!(
                "{} is not allowed: damping ratios must be finite and ≥ 0",
                modal.others
            ),
        ));
    }
    Ok(())
}

/// Finite, non-negative Rayleigh factors.
pub(super) fn check_rayleigh(alpha: f64, beta: f64) -> Result<(), ModelError> {
    for (name, x) in [("alpha", alpha), ("beta", beta)] {
        if !(x.is_finite() && x >= 0.0) {
            return Err(ModelError::invalid(
                Subject::Input(SectorInput::Damping, format!(".{name}")),
                format!("{x} is not allowed: Rayleigh factors must be finite and ≥ 0"),
            ));
        }
    }
    Ok(())
}

impl SectorModel {
    /// `C(s)` for `0 ≤ s ≤ N/2`, from the cache or computed once.
    pub(super) fn cached_modal_damping<'a>(
        &self,
        s: i64,
        modal: &ModalDamping,
        cache: &'a ModalCache,
    ) -> Result<&'a Mat<c64>, ModelError> {
        let slot = &cache.0[s as usize];
        if let Some(c) = slot.get() {
            return Ok(c);
        }
        let c = self.modal_damping(s, modal)?;
        Ok(slot.get_or_init(|| c))
    }

    /// Computes the modal damping of the diameters `0..=N/2` not yet cached,
    /// in parallel.
    pub(super) fn fill_modal_cache(&self) -> Result<(), ModelError> {
        if let DampingModel::Modal(modal, cache) = &self.damping {
            (0..=self.sectors as i64 / 2)
                .into_par_iter()
                .try_for_each(|s| self.cached_modal_damping(s, modal, cache).map(|_| ()))?;
        }
        Ok(())
    }

    /// `C(s) = M Φ diag(2 ξ_r ω_r) Φᴴ M` for `0 ≤ s ≤ N/2`, with `Φ` the
    /// mass-normalized modes: `M Φ = L U` for `M = L Lᴴ` and `U` the
    /// eigenvectors of `L⁻¹ K L⁻ᴴ`.
    fn modal_damping(&self, s: i64, modal: &ModalDamping) -> Result<Mat<c64>, ModelError> {
        let n = self.dofs_per_sector();
        if s == 0 || 2 * s == self.sectors as i64 {
            let mass = self.mass.at_real(s, self.sectors);
            let stiffness = self.stiffness.at_real(s, self.sectors);
            let (values, w) = symmetric_modes(&stiffness, &mass, s, true)?;
            let w = w.unwrap_or_else(|| Mat::zeros(n, n));
            let factors = self.modal_factors(&values, modal, s)?;
            let scaled = Mat::from_fn(n, n, |i, r| w[(i, r)] * factors[r]);
            let c = &scaled * w.transpose();
            return Ok(Mat::from_fn(n, n, |i, j| {
                c64::new(0.5 * (c[(i, j)] + c[(j, i)]), 0.0)
            }));
        }
        let mass = self.mass.at(s, self.sectors);
        let stiffness = self.stiffness.at(s, self.sectors);
        let modes = hermitian_modes(&stiffness, &mass, s, true)?;
        let factors = self.modal_factors(&modes.values, modal, s)?;
        let w = modes.mass_times_shapes.unwrap_or_else(|| Mat::zeros(n, n));
        let scaled = Mat::from_fn(n, n, |i, r| w[(i, r)] * factors[r]);
        let c = &scaled * w.adjoint();
        Ok(Mat::from_fn(n, n, |i, j| {
            (c[(i, j)] + c[(j, i)].conj()) * 0.5
        }))
    }

    /// `2 ξ_r ω_r` for each mode `r`.
    fn modal_factors(
        &self,
        values: &[f64],
        modal: &ModalDamping,
        s: i64,
    ) -> Result<Vec<f64>, ModelError> {
        Ok(angular_frequencies(values, s)?
            .iter()
            .enumerate()
            .map(|(r, &omega)| 2.0 * modal.ratio(r) * omega)
            .collect())
    }
}
