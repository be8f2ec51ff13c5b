//! The condensed harmonic balance residual (Eq. 43) with the contact
//! forces by AFT-CP, and its analytic Jacobians.
//!
//! `R(x, ω) = r + G̃ F[f(q)]` with the linear residual `r = Z(ω) x − F(ω)`:
//! the contact force acts as `−f` on the structure, `f ≥ 0`. The law reads
//! at each sampled sector and instant `q = v − a g0` with `v = a x + b r`
//! formed in the unknowns' space and mapped to the sampled sectors
//! (`Ḡ`; `G̃` maps back; both the identity for the physical full wheel; `F`,
//! `F⁻¹` the real DFT and its inverse). See [`crate::contact`] for the laws'
//! weights `(a, b)`: `(1, 0)` for R-HBM, `(ε, −1)` for DLFT-HBM. With
//! `T = F diag(df/dq) F⁻¹`:
//! `∂R/∂x = Z + G̃ T Ḡ (a I + b Z)` (`Ḡ Z ≠ Z Ḡ`: `v` is formed in the
//! unknowns' space and then mapped) and `∂R/∂ω = ∂r/∂ω + b G̃ T Ḡ ∂r/∂ω`
//! with `∂r/∂ω = ∂Z/∂ω x − ∂F/∂ω` (a synchronous casing is fixed in
//! `τ = ωt`).

use super::aft::Aft;
use super::layout::{Layout, SectorMaps};
use super::linear::LinearPart;
use super::HbmError;
use crate::contact::{Casing, ContactLaw, Smoothness, EMPTY_STATE};
use crate::continuation::{Evaluation, Problem};
use faer::linalg::matmul::matmul;
use faer::linalg::solvers::Solve;
use faer::{Accum, Mat, MatMut, MatRef, Par};
use std::sync::Arc;

/// Time samples of the contact state at one point, one signal per sampled
/// sector and contact dof (sector-major, as in the layout).
#[derive(Clone, Debug)]
pub struct ContactSamples {
    /// Sectors sampled (0-based `0..sampled_sectors`).
    pub sampled_sectors: usize,
    /// Contact dofs per sector.
    pub contact_dofs: usize,
    /// Penetration `p = x − g0` at `τ_n = 2π n / N_t` (m; `p ≤ 0` is a gap).
    /// With a wall, `x` is the wall node's displacement.
    pub penetration: Vec<Vec<f64>>,
    /// Contact force `f ≥ 0` (N), acting as `−f` on the structure.
    pub force: Vec<Vec<f64>>,
    /// For a law that reads the linear residual (DLFT): its input `q`, the
    /// multiplier `λ` before correction (N).
    pub multiplier: Option<Vec<Vec<f64>>>,
}

/// The residual of one harmonic balance problem, with its buffers.
pub struct HarmonicBalance {
    layout: Layout,
    linear: LinearPart,
    aft: Aft,
    law: Arc<dyn ContactLaw>,
    casing: Casing,
    /// Gap `g0(τ_n)` per sampled sector and contact dof (sector-major).
    gap_samples: Vec<Vec<f64>>,
    sector_coordinates: Vec<f64>,
    sector_forces: Vec<f64>,
    reading: Vec<f64>,
    force: Vec<f64>,
    slope: Vec<f64>,
    /// `H × H` Jacobian blocks per sampled sector and contact dof.
    derivative_blocks: Vec<f64>,
    /// `v = a x + b r` in the unknowns' space (laws that read `r`).
    law_variable: Vec<f64>,
    /// A hash of the contact state at the last evaluation (piecewise laws).
    piece: u64,
    force_scale: f64,
}

impl std::fmt::Debug for HarmonicBalance {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("HarmonicBalance")
            .field("unknowns", &self.layout.unknowns)
            .field("sampled_sectors", &self.layout.sampled_sectors)
            .field("law", &self.law)
            .field("aft", &self.aft)
            .finish()
    }
}

impl HarmonicBalance {
    /// A residual from its layout, linear part, contact law and casing, with
    /// `time_samples` instants per period; residuals are divided by
    /// `force_scale` (N) in the convergence test.
    ///
    /// # Panics
    /// If the casing does not give one gap and one amplitude per contact dof
    /// of the layout ([`crate::hbm::ProblemSpec::build`] checks it).
    pub fn new(
        layout: Layout,
        linear: LinearPart,
        law: Arc<dyn ContactLaw>,
        casing: Casing,
        time_samples: usize,
        force_scale: f64,
    ) -> Self {
        assert!(
            casing.fits(layout.contact_dofs),
            "one gap and amplitude per contact dof"
        );
        let aft = Aft::new(layout.harmonics, time_samples);
        let size = layout.coordinates();
        let signals = layout.sampled_sectors * layout.contact_dofs;
        let gap_samples = (0..layout.sampled_sectors)
            .flat_map(|j| {
                let casing = &casing;
                (0..layout.contact_dofs)
                    .map(move |c| casing.gap_samples(layout.sectors, j, c, time_samples))
            })
            .collect();
        Self {
            sector_coordinates: vec![0.0; layout.sector_coordinates()],
            sector_forces: vec![0.0; layout.sector_coordinates()],
            reading: vec![0.0; time_samples],
            force: vec![0.0; time_samples],
            slope: vec![0.0; time_samples],
            derivative_blocks: vec![0.0; signals * size * size],
            law_variable: vec![0.0; layout.unknowns],
            piece: 0,
            layout,
            linear,
            aft,
            law,
            casing,
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

    /// The contact law.
    pub fn law(&self) -> &dyn ContactLaw {
        self.law.as_ref()
    }

    /// The hash of the contact state at the last evaluation (piecewise
    /// laws; see [`Problem::piece`]).
    pub fn last_piece(&self) -> u64 {
        self.piece
    }

    /// The casing the problem was built with.
    pub fn casing(&self) -> &Casing {
        &self.casing
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

    /// What the law reads at `(x, omega)`, in the unknowns' space:
    /// `v = a x + b (Z x − F)` (see [`crate::contact`]); `x` itself for a
    /// law of the penetration. Reads the problem only, so that points can
    /// be recovered in parallel.
    pub fn law_variable(&self, x: &[f64], omega: f64) -> Result<Vec<f64>, HbmError> {
        let input = self.law.input();
        if !input.reads_residual() {
            return Ok(x.to_vec());
        }
        let residual = self.linear.residual_at(&self.layout, x, omega)?;
        let mut v = vec![0.0; x.len()];
        form_law_variable(input.penetration, input.residual, x, &residual, &mut v);
        Ok(v)
    }

    /// The law at every sampled instant from `v` (see [`Self::law_variable`]):
    /// fills `sector_forces` with the forces' coordinates and, if asked, the
    /// derivative blocks `T`; keeps the contact state's hash for a
    /// piecewise law.
    fn contact_forces(&mut self, v: &[f64], jacobian: bool) {
        let size = self.layout.coordinates();
        let law = Arc::clone(&self.law);
        let hash = matches!(law.smoothness(), Smoothness::Piecewise).then_some(EMPTY_STATE);
        let mut state = EMPTY_STATE;
        let mut coordinates = std::mem::take(&mut self.sector_coordinates);
        self.to_sectors(v, &mut coordinates);
        for (signal, gap) in self.gap_samples.iter().enumerate() {
            let range = signal * size..(signal + 1) * size;
            self.aft
                .to_time(&coordinates[range.clone()], &mut self.reading);
            let found = law.apply(
                &self.reading,
                gap,
                &mut self.force,
                jacobian.then_some(self.slope.as_mut_slice()),
                hash.map(|_| state),
            );
            state = found.state;
            self.aft
                .to_frequency(&self.force, &mut self.sector_forces[range]);
            if jacobian {
                let block =
                    &mut self.derivative_blocks[signal * size * size..(signal + 1) * size * size];
                self.aft.derivative_block(&self.slope, block);
            }
        }
        self.sector_coordinates = coordinates;
        self.piece = state;
    }

    /// `out += G̃ v` for sector coordinates `v`.
    fn add_from_sectors(&self, v: &[f64], out: &mut [f64]) {
        match &self.layout.maps {
            SectorMaps::Identity => {
                for (o, f) in out.iter_mut().zip(v) {
                    *o += f;
                }
            }
            SectorMaps::Dense { from_sectors, .. } => {
                let mut projected = vec![0.0; out.len()];
                multiply(from_sectors, v, &mut projected);
                for (o, f) in out.iter_mut().zip(&projected) {
                    *o += f;
                }
            }
        }
    }

    /// `T v` for sector coordinates `v`, `T` block diagonal per signal.
    fn apply_derivative_blocks(&self, v: &[f64]) -> Vec<f64> {
        let size = self.layout.coordinates();
        let mut out = vec![0.0; v.len()];
        for (signal, block) in self.derivative_blocks.chunks_exact(size * size).enumerate() {
            let offset = signal * size;
            for r in 0..size {
                out[offset + r] = (0..size).map(|c| block[r * size + c] * v[offset + c]).sum();
            }
        }
        out
    }

    /// The contact state at `(x, omega)` at every sampled instant: the
    /// penetration, the force and, for a law that reads the linear residual,
    /// its input before correction.
    pub fn contact_samples(&mut self, x: &[f64], omega: f64) -> Result<ContactSamples, HbmError> {
        self.linear.update(&self.layout, omega)?;
        let size = self.layout.coordinates();
        let input = self.law.input();
        // `v` as the residual forms it, from the dense `Z` just updated.
        let mut residual = vec![0.0; x.len()];
        multiply(&self.linear.dynamic, x, &mut residual);
        for (r, f) in residual.iter_mut().zip(&self.linear.load) {
            *r -= f;
        }
        let mut v = vec![0.0; x.len()];
        form_law_variable(input.penetration, input.residual, x, &residual, &mut v);
        let mut coordinates = vec![0.0; self.layout.sector_coordinates()];
        self.to_sectors(x, &mut coordinates);
        let mut read = vec![0.0; self.layout.sector_coordinates()];
        self.to_sectors(&v, &mut read);
        let n_t = self.aft.time_samples();
        let (mut penetration, mut force, mut multiplier) = (vec![], vec![], vec![]);
        let mut samples = vec![0.0; n_t];
        for (signal, gap) in self.gap_samples.iter().enumerate() {
            let range = signal * size..(signal + 1) * size;
            self.aft.to_time(&coordinates[range.clone()], &mut samples);
            penetration.push(samples.iter().zip(gap).map(|(x, g)| x - g).collect());
            self.aft.to_time(&read[range], &mut samples);
            let mut f = vec![0.0; n_t];
            self.law.apply(&samples, gap, &mut f, None, None);
            force.push(f);
            if input.reads_residual() {
                multiplier.push(
                    samples
                        .iter()
                        .zip(gap)
                        .map(|(v, g)| v - input.penetration * g)
                        .collect(),
                );
            }
        }
        Ok(ContactSamples {
            sampled_sectors: self.layout.sampled_sectors,
            contact_dofs: self.layout.contact_dofs,
            penetration,
            force,
            multiplier: input.reads_residual().then_some(multiplier),
        })
    }
}

/// `out = a x + b r`, the law's variable in the unknowns' space.
fn form_law_variable(a: f64, b: f64, x: &[f64], r: &[f64], out: &mut [f64]) {
    for ((o, x), r) in out.iter_mut().zip(x).zip(r) {
        *o = a * x + b * r;
    }
}

/// `out = a · x` for a dense matrix.
fn multiply(a: &Mat<f64>, x: &[f64], out: &mut [f64]) {
    out.fill(0.0);
    for (col, &v) in x.iter().enumerate().take(a.ncols()) {
        if v == 0.0 {
            continue;
        }
        let column = a.col(col);
        for (row, o) in out.iter_mut().enumerate() {
            *o += column[row] * v;
        }
    }
}

/// `out = T · input`, `T` block diagonal with row-major `size × size`
/// blocks, one per band of `size` rows.
fn apply_blocks(blocks: &[f64], size: usize, input: MatRef<'_, f64>, mut out: MatMut<'_, f64>) {
    for (signal, block) in blocks.chunks_exact(size * size).enumerate() {
        let t = MatRef::from_row_major_slice(block, size, size);
        matmul(
            out.as_mut().subrows_mut(signal * size, size),
            Accum::Replace,
            t,
            input.subrows(signal * size, size),
            1.0,
            Par::Seq,
        );
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

    /// R-HBM with `γ > 0`: smooth; the plain penalty law (`γ = 0`) and
    /// DLFT have kinks.
    fn is_smooth(&self) -> bool {
        matches!(self.law.smoothness(), Smoothness::Smooth)
    }

    /// A piecewise law (DLFT): a hash of the contact state at every sampled
    /// instant (the residual is affine in `x` for a given state); `None`
    /// otherwise.
    fn piece(&mut self, x: &[f64], omega: f64) -> Result<Option<u64>, HbmError> {
        if !matches!(self.law.smoothness(), Smoothness::Piecewise) {
            return Ok(None);
        }
        let mut scratch = Evaluation::default();
        self.evaluate(x, omega, false, &mut scratch)?;
        Ok(Some(self.piece))
    }

    fn evaluate(
        &mut self,
        x: &[f64],
        omega: f64,
        jacobian: bool,
        out: &mut Evaluation,
    ) -> Result<(), HbmError> {
        self.evaluate_along(x, omega, 1.0, Along::Frequency, jacobian, out)
    }
}

/// The parameter whose derivative an evaluation gives in
/// [`Evaluation::derivative_omega`].
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Along {
    /// The frequency ω: `∂R/∂ω`.
    Frequency,
    /// The scale `s` of the external load `s F`: `∂R/∂s`.
    LoadScale,
}

impl HarmonicBalance {
    /// `R(x, ω)` with the external load scaled by `load_scale` (`r = Z x −
    /// s F`), `∂R/∂x` and the derivative along `along` if `jacobian`.
    pub fn evaluate_along(
        &mut self,
        x: &[f64],
        omega: f64,
        load_scale: f64,
        along: Along,
        jacobian: bool,
        out: &mut Evaluation,
    ) -> Result<(), HbmError> {
        let n = self.layout.unknowns;
        self.linear.update(&self.layout, omega)?;
        // r = Z x − s F.
        out.residual.resize(n, 0.0);
        multiply(&self.linear.dynamic, x, &mut out.residual);
        for (r, f) in out.residual.iter_mut().zip(&self.linear.load) {
            *r -= load_scale * f;
        }
        let input = self.law.input();
        let (a, b) = (input.penetration, input.residual);
        if input.reads_residual() {
            let mut v = std::mem::take(&mut self.law_variable);
            form_law_variable(a, b, x, &out.residual, &mut v);
            self.contact_forces(&v, jacobian);
            self.law_variable = v;
        } else {
            self.contact_forces(x, jacobian);
        }
        // R = r + G̃ f.
        let forces = std::mem::take(&mut self.sector_forces);
        self.add_from_sectors(&forces, &mut out.residual);
        self.sector_forces = forces;
        if out.residual.iter().any(|v| !v.is_finite()) {
            return Err(HbmError::NotFinite {
                frequency_hz: omega / (2.0 * std::f64::consts::PI),
            });
        }
        if !jacobian {
            return Ok(());
        }
        out.derivative_omega.resize(n, 0.0);
        match along {
            // ∂r/∂ω = ∂Z/∂ω x − s ∂F/∂ω.
            Along::Frequency => {
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
                    *r -= load_scale * f;
                }
            }
            // ∂r/∂s = −F.
            Along::LoadScale => {
                for (r, f) in out.derivative_omega.iter_mut().zip(&self.linear.load) {
                    *r = -f;
                }
            }
        }
        if out.jacobian.nrows() == n && out.jacobian.ncols() == n {
            out.jacobian.copy_from(&self.linear.dynamic);
        } else {
            out.jacobian = self.linear.dynamic.clone();
        }
        if input.reads_residual() {
            // ∂R/∂p = ∂r/∂p + b G̃ T Ḡ ∂r/∂p.
            let mut mapped = vec![0.0; self.layout.sector_coordinates()];
            self.to_sectors(&out.derivative_omega, &mut mapped);
            let mut t_mapped = self.apply_derivative_blocks(&mapped);
            t_mapped.iter_mut().for_each(|v| *v *= b);
            self.add_from_sectors(&t_mapped, &mut out.derivative_omega);
        }
        self.add_contact_jacobian(a, b, &mut out.jacobian);
        Ok(())
    }
}

impl HarmonicBalance {
    /// `J += G̃ T Ḡ (a I + b Z)`, the contact part of `∂R/∂x`.
    fn add_contact_jacobian(&self, a: f64, b: f64, jacobian: &mut Mat<f64>) {
        let n = self.layout.unknowns;
        let size = self.layout.coordinates();
        let blocks = self.derivative_blocks.chunks_exact(size * size).enumerate();
        match &self.layout.maps {
            // T (a I + b Z), band by band of T: no n × n temporary.
            SectorMaps::Identity => {
                for (signal, block) in blocks {
                    let t = MatRef::from_row_major_slice(block, size, size);
                    let band = signal * size;
                    if b != 0.0 {
                        matmul(
                            jacobian.as_mut().subrows_mut(band, size),
                            Accum::Add,
                            t,
                            self.linear.dynamic.as_ref().subrows(band, size),
                            b,
                            Par::Seq,
                        );
                    }
                    for r in 0..size {
                        for c in 0..size {
                            jacobian[(band + r, band + c)] += a * t[(r, c)];
                        }
                    }
                }
            }
            // G̃ T (a Ḡ + b Ḡ Z).
            SectorMaps::Dense {
                to_sectors,
                from_sectors,
            } => {
                let mut m = Mat::from_fn(to_sectors.nrows(), n, |r, c| a * to_sectors[(r, c)]);
                if b != 0.0 {
                    matmul(
                        m.as_mut(),
                        Accum::Add,
                        to_sectors.as_ref(),
                        self.linear.dynamic.as_ref(),
                        b,
                        Par::Seq,
                    );
                }
                let mut t_m = Mat::<f64>::zeros(m.nrows(), n);
                apply_blocks(&self.derivative_blocks, size, m.as_ref(), t_m.as_mut());
                matmul(
                    jacobian.as_mut(),
                    Accum::Add,
                    from_sectors.as_ref(),
                    t_m.as_ref(),
                    1.0,
                    Par::Seq,
                );
            }
        }
    }
}
