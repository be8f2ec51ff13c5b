//! The condensed harmonic balance residual (Eq. 43) with the regularized
//! contact forces by AFT-CP, and its analytic Jacobians:
//! `R(x, ω) = Z(ω) x + G̃ F[f(Ḡ x − g0)] − F_ex(ω)` (the contact force acts
//! as `−f` on the structure), `∂R/∂x = Z + G̃ F diag(f') F⁻¹ Ḡ`,
//! `∂R/∂ω = ∂Z/∂ω x − ∂F_ex/∂ω` (a synchronous casing is fixed in `τ = ωt`).

use super::aft::Aft;
use super::layout::{Layout, SectorMaps};
use super::linear::LinearPart;
use super::HbmError;
use crate::contact::ContactLaw;
use crate::continuation::{Evaluation, Problem};
use faer::linalg::matmul::matmul;
use faer::linalg::solvers::Solve;
use faer::{Accum, Mat, Par};
use std::sync::Arc;

/// The residual of one harmonic balance problem, with its buffers.
pub struct HarmonicBalance {
    layout: Layout,
    linear: LinearPart,
    aft: Aft,
    law: Arc<dyn ContactLaw>,
    /// Gap `g0(τ_n)` per sampled sector and contact dof (sector-major).
    gap_samples: Vec<Vec<f64>>,
    sector_coordinates: Vec<f64>,
    sector_forces: Vec<f64>,
    displacement: Vec<f64>,
    force: Vec<f64>,
    slope: Vec<f64>,
    /// `H × H` Jacobian blocks per sampled sector and contact dof.
    derivative_blocks: Vec<f64>,
    force_scale: f64,
}

impl std::fmt::Debug for HarmonicBalance {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("HarmonicBalance")
            .field("unknowns", &self.layout.unknowns)
            .field("sampled_sectors", &self.layout.sampled_sectors)
            .field("aft", &self.aft)
            .finish()
    }
}

impl HarmonicBalance {
    /// A residual from its layout, linear part, law and gap samples
    /// (`layout.sampled_sectors × contact_dofs` signals of `time_samples`).
    pub fn new(
        layout: Layout,
        linear: LinearPart,
        law: Arc<dyn ContactLaw>,
        gap_samples: Vec<Vec<f64>>,
        time_samples: usize,
        force_scale: f64,
    ) -> Self {
        let aft = Aft::new(layout.harmonics, time_samples);
        let size = layout.coordinates();
        let signals = layout.sampled_sectors * layout.contact_dofs;
        Self {
            sector_coordinates: vec![0.0; layout.sector_coordinates()],
            sector_forces: vec![0.0; layout.sector_coordinates()],
            displacement: vec![0.0; time_samples],
            force: vec![0.0; time_samples],
            slope: vec![0.0; time_samples],
            derivative_blocks: vec![0.0; signals * size * size],
            layout,
            linear,
            aft,
            law,
            gap_samples,
            force_scale,
        }
    }

    /// The unknown layout.
    pub fn layout(&self) -> &Layout {
        &self.layout
    }

    /// The linear part (at the last frequency evaluated).
    pub fn linear(&self) -> &LinearPart {
        &self.linear
    }

    /// `N_t`.
    pub fn time_samples(&self) -> usize {
        self.aft.time_samples()
    }

    /// The sampled sectors' coordinates of the unknowns `x` (`Ḡ x`).
    pub fn to_sectors(&self, x: &[f64], out: &mut [f64]) {
        match &self.layout.maps {
            SectorMaps::Identity => out.copy_from_slice(x),
            SectorMaps::Dense { to_sectors, .. } => multiply(to_sectors, x, out),
        }
    }

    /// The linear response (no contact) at `omega`: `Z⁻¹ F`.
    pub fn linear_solution(&mut self, omega: f64) -> Result<Vec<f64>, HbmError> {
        self.linear.update(&self.layout, omega)?;
        let n = self.layout.unknowns;
        let rhs = Mat::from_fn(n, 1, |r, _| self.linear.load[r]);
        let x = self.linear.dynamic.partial_piv_lu().solve(&rhs);
        let x: Vec<f64> = (0..n).map(|r| x[(r, 0)]).collect();
        if x.iter().all(|v| v.is_finite()) {
            Ok(x)
        } else {
            Err(HbmError::SingularLinearSystem {
                frequency_hz: omega / (2.0 * std::f64::consts::PI),
            })
        }
    }

    /// Contact forces and their derivatives on every sampled sector; fills
    /// `sector_forces` (and the derivative blocks if asked).
    fn contact_forces(&mut self, x: &[f64], jacobian: bool) {
        let size = self.layout.coordinates();
        let mut coordinates = std::mem::take(&mut self.sector_coordinates);
        self.to_sectors(x, &mut coordinates);
        for (signal, gap) in self.gap_samples.iter().enumerate() {
            let range = signal * size..(signal + 1) * size;
            self.aft
                .to_time(&coordinates[range.clone()], &mut self.displacement);
            for n in 0..self.displacement.len() {
                let (f, df) = self.law.force(self.displacement[n] - gap[n]);
                self.force[n] = f;
                self.slope[n] = df;
            }
            self.aft
                .to_frequency(&self.force, &mut self.sector_forces[range]);
            if jacobian {
                let block =
                    &mut self.derivative_blocks[signal * size * size..(signal + 1) * size * size];
                self.aft.derivative_block(&self.slope, block);
            }
        }
        self.sector_coordinates = coordinates;
    }
}

/// `out = a · x` for a dense matrix.
fn multiply(a: &Mat<f64>, x: &[f64], out: &mut [f64]) {
    out.fill(0.0);
    for col in 0..a.ncols() {
        let v = x[col];
        if v == 0.0 {
            continue;
        }
        let column = a.col(col);
        for (row, o) in out.iter_mut().enumerate() {
            *o += column[row] * v;
        }
    }
}

impl Problem for HarmonicBalance {
    type Error = HbmError;

    fn unknowns(&self) -> usize {
        self.layout.unknowns
    }

    fn force_scale(&self) -> f64 {
        self.force_scale
    }

    fn norm_weights(&self) -> Vec<f64> {
        self.layout.norm_weights()
    }

    fn evaluate(
        &mut self,
        x: &[f64],
        omega: f64,
        jacobian: bool,
        out: &mut Evaluation,
    ) -> Result<(), HbmError> {
        let n = self.layout.unknowns;
        self.linear.update(&self.layout, omega)?;
        self.contact_forces(x, jacobian);
        // R = Z x − F + G̃ f.
        out.residual.resize(n, 0.0);
        multiply(&self.linear.dynamic, x, &mut out.residual);
        for (r, f) in out.residual.iter_mut().zip(&self.linear.load) {
            *r -= f;
        }
        match &self.layout.maps {
            SectorMaps::Identity => {
                for (r, f) in out.residual.iter_mut().zip(&self.sector_forces) {
                    *r += f;
                }
            }
            SectorMaps::Dense { from_sectors, .. } => {
                let mut projected = vec![0.0; n];
                multiply(from_sectors, &self.sector_forces, &mut projected);
                for (r, f) in out.residual.iter_mut().zip(&projected) {
                    *r += f;
                }
            }
        }
        if out.residual.iter().any(|v| !v.is_finite()) {
            return Err(HbmError::NotFinite {
                frequency_hz: omega / (2.0 * std::f64::consts::PI),
            });
        }
        if !jacobian {
            return Ok(());
        }
        // ∂R/∂ω = ∂Z/∂ω x − ∂F/∂ω.
        out.derivative_omega.resize(n, 0.0);
        multiply(
            &self.linear.dynamic_derivative,
            x,
            &mut out.derivative_omega,
        );
        for (r, f) in out
            .derivative_omega
            .iter_mut()
            .zip(&self.linear.load_derivative)
        {
            *r -= f;
        }
        // ∂R/∂x = Z + G̃ T Ḡ, T block diagonal per sampled sector and dof.
        out.jacobian = self.linear.dynamic.clone();
        let size = self.layout.coordinates();
        match &self.layout.maps {
            SectorMaps::Identity => {
                for signal in 0..self.gap_samples.len() {
                    let block =
                        &self.derivative_blocks[signal * size * size..(signal + 1) * size * size];
                    let offset = signal * size;
                    for r in 0..size {
                        for c in 0..size {
                            out.jacobian[(offset + r, offset + c)] += block[r * size + c];
                        }
                    }
                }
            }
            SectorMaps::Dense {
                to_sectors,
                from_sectors,
            } => {
                // T Ḡ, one H-row band per signal.
                let mut t_g = Mat::<f64>::zeros(to_sectors.nrows(), n);
                for signal in 0..self.gap_samples.len() {
                    let block =
                        &self.derivative_blocks[signal * size * size..(signal + 1) * size * size];
                    let offset = signal * size;
                    for r in 0..size {
                        for c in 0..size {
                            let t = block[r * size + c];
                            if t == 0.0 {
                                continue;
                            }
                            for col in 0..n {
                                t_g[(offset + r, col)] += t * to_sectors[(offset + c, col)];
                            }
                        }
                    }
                }
                matmul(
                    out.jacobian.as_mut(),
                    Accum::Add,
                    from_sectors.as_ref(),
                    t_g.as_ref(),
                    1.0,
                    Par::Seq,
                );
            }
        }
        Ok(())
    }
}
