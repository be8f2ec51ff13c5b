//! The condensed harmonic balance residual (Eq. 43) with the contact
//! forces by AFT-CP, and its analytic Jacobians.
//!
//! `R(x, ω) = Z(ω) x − F(ω) + G̃ F[f]`: the contact force acts as `−f` on
//! the structure, `f ≥ 0`, and the penetration is `p = Ḡ x − g0`
//! (`Ḡ`, `G̃` the maps to and from the sampled sectors, the identity for the
//! physical full wheel; `F`, `F⁻¹` the real DFT and its inverse).
//!
//! - **R-HBM** (a law `f(p)` at each instant): `∂R/∂x = Z + G̃ T Ḡ` with
//!   `T = F diag(f'(p)) F⁻¹`, and `∂R/∂ω = ∂Z/∂ω x − ∂F/∂ω` (a synchronous
//!   casing is fixed in `τ = ωt`).
//! - **DLFT-HBM** (dynamic Lagrangian, Sec. 3.4.3): with the linear residual
//!   `r = Z x − F` the contact force predicted by equilibrium is `−r`, so the
//!   prediction at each sampled sector and instant is
//!   `λ = F⁻¹[Ḡ(−r + ε x)] − ε g0 = −Ḡ r + ε p`, corrected to
//!   `f = max(0, λ)`. In the paper's signs (force `f_nl = −f ≤ 0`, gap
//!   `g = −p`) this is `f_nl^p = (Z x − F) + ε g` and `f_nl = min(0, f_nl^p)`:
//!   the paper's Eq. (71) prints `−ε ĝ`, which would push a penetrating node
//!   further in. With the contact mask `m = [λ > 0]` and
//!   `T = F diag(m) F⁻¹`: `∂R/∂x = Z + G̃ T (ε Ḡ − Ḡ Z)` (`Ḡ Z ≠ Z Ḡ`: the
//!   prediction is formed in the unknowns' space and then mapped), and
//!   `∂R/∂ω = ∂r/∂ω − G̃ T Ḡ ∂r/∂ω` with `∂r/∂ω = ∂Z/∂ω x − ∂F/∂ω`.
//!   At convergence `λ = f + ε p` up to the harmonic truncation of `f`, so
//!   contact (`λ > 0`) gives `p ≈ 0` and separation `p ≤ 0`.

use super::aft::Aft;
use super::layout::{Layout, SectorMaps};
use super::linear::LinearPart;
use super::HbmError;
use crate::contact::ContactLaw;
use crate::continuation::{Evaluation, Problem};
use faer::linalg::matmul::matmul;
use faer::linalg::solvers::Solve;
use faer::{Accum, Mat, MatMut, MatRef, Par};
use std::sync::Arc;

/// How the contact forces are computed from the unknowns.
#[derive(Clone, Debug)]
pub enum ContactTreatment {
    /// A law `f(p)` evaluated instant by instant (R-HBM).
    Law(Arc<dyn ContactLaw>),
    /// The dynamic Lagrangian prediction–correction (DLFT-HBM).
    Lagrangian {
        /// The weight `ε`, N/m.
        epsilon: f64,
    },
}

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
    /// DLFT only: the predicted multiplier `λ` before correction (N).
    pub multiplier: Option<Vec<Vec<f64>>>,
}

/// The residual of one harmonic balance problem, with its buffers.
pub struct HarmonicBalance {
    layout: Layout,
    linear: LinearPart,
    aft: Aft,
    treatment: ContactTreatment,
    /// Gap `g0(τ_n)` per sampled sector and contact dof (sector-major).
    gap_samples: Vec<Vec<f64>>,
    sector_coordinates: Vec<f64>,
    sector_forces: Vec<f64>,
    displacement: Vec<f64>,
    force: Vec<f64>,
    slope: Vec<f64>,
    /// `H × H` Jacobian blocks per sampled sector and contact dof.
    derivative_blocks: Vec<f64>,
    /// DLFT: the prediction `−r + ε x` in the unknowns' space.
    prediction: Vec<f64>,
    /// DLFT: a hash of the contact state at the last evaluation.
    piece: u64,
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
        Self::with_treatment(
            layout,
            linear,
            ContactTreatment::Law(law),
            gap_samples,
            time_samples,
            force_scale,
        )
    }

    /// A residual from its layout, linear part, contact treatment and gap
    /// samples (`layout.sampled_sectors × contact_dofs` signals of
    /// `time_samples`).
    pub fn with_treatment(
        layout: Layout,
        linear: LinearPart,
        treatment: ContactTreatment,
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
            prediction: vec![0.0; layout.unknowns],
            piece: 0,
            layout,
            linear,
            aft,
            treatment,
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

    /// The contact treatment.
    pub fn treatment(&self) -> &ContactTreatment {
        &self.treatment
    }

    /// Law: contact forces and their derivatives on every sampled sector;
    /// fills `sector_forces` (and the derivative blocks if asked).
    fn law_forces(&mut self, law: &dyn ContactLaw, x: &[f64], jacobian: bool) {
        let size = self.layout.coordinates();
        let mut coordinates = std::mem::take(&mut self.sector_coordinates);
        self.to_sectors(x, &mut coordinates);
        for (signal, gap) in self.gap_samples.iter().enumerate() {
            let range = signal * size..(signal + 1) * size;
            self.aft
                .to_time(&coordinates[range.clone()], &mut self.displacement);
            for (((u, g), f), df) in self
                .displacement
                .iter()
                .zip(gap)
                .zip(self.force.iter_mut())
                .zip(self.slope.iter_mut())
            {
                (*f, *df) = law.force(u - g);
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

    /// DLFT: from the linear residual `r = Z x − F`, the prediction
    /// `λ = F⁻¹ Ḡ (−r + ε x) − ε g0`, the correction `f = max(0, λ)`, the
    /// forces' coordinates in `sector_forces` and, if asked, the blocks of
    /// `T = F diag([λ > 0]) F⁻¹`.
    fn lagrangian_forces(
        &mut self,
        epsilon: f64,
        x: &[f64],
        linear_residual: &[f64],
        jacobian: bool,
    ) {
        let size = self.layout.coordinates();
        let mut prediction = std::mem::take(&mut self.prediction);
        for ((q, r), v) in prediction.iter_mut().zip(linear_residual).zip(x) {
            *q = epsilon * v - r;
        }
        let mut coordinates = std::mem::take(&mut self.sector_coordinates);
        self.to_sectors(&prediction, &mut coordinates);
        // FNV-1a over the contact state of every sampled instant.
        let mut piece: u64 = 0xcbf2_9ce4_8422_2325;
        for (signal, gap) in self.gap_samples.iter().enumerate() {
            let range = signal * size..(signal + 1) * size;
            self.aft
                .to_time(&coordinates[range.clone()], &mut self.displacement);
            for (((u, g), f), m) in self
                .displacement
                .iter()
                .zip(gap)
                .zip(self.force.iter_mut())
                .zip(self.slope.iter_mut())
            {
                let lambda = u - epsilon * g;
                let contact = lambda > 0.0;
                *f = if contact { lambda } else { 0.0 };
                *m = if contact { 1.0 } else { 0.0 };
                piece = (piece ^ u64::from(contact)).wrapping_mul(0x0100_0000_01b3);
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
        self.prediction = prediction;
        self.piece = piece;
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
    /// penetration, the force and (DLFT) the multiplier before correction.
    pub fn contact_samples(&mut self, x: &[f64], omega: f64) -> Result<ContactSamples, HbmError> {
        let n = self.layout.unknowns;
        let size = self.layout.coordinates();
        let mut residual = vec![0.0; n];
        self.linear.update(&self.layout, omega)?;
        multiply(&self.linear.dynamic, x, &mut residual);
        for (r, f) in residual.iter_mut().zip(&self.linear.load) {
            *r -= f;
        }
        let mut coordinates = vec![0.0; self.layout.sector_coordinates()];
        self.to_sectors(x, &mut coordinates);
        let mut lagrangian_coordinates = None;
        if let ContactTreatment::Lagrangian { epsilon } = self.treatment {
            let prediction: Vec<f64> = residual
                .iter()
                .zip(x)
                .map(|(r, v)| epsilon * v - r)
                .collect();
            let mut c = vec![0.0; self.layout.sector_coordinates()];
            self.to_sectors(&prediction, &mut c);
            lagrangian_coordinates = Some((epsilon, c));
        }
        let signals = self.gap_samples.len();
        let n_t = self.aft.time_samples();
        let mut penetration = Vec::with_capacity(signals);
        let mut force = Vec::with_capacity(signals);
        let mut multiplier = Vec::with_capacity(signals);
        let mut samples = vec![0.0; n_t];
        for (signal, gap) in self.gap_samples.iter().enumerate() {
            let range = signal * size..(signal + 1) * size;
            self.aft.to_time(&coordinates[range.clone()], &mut samples);
            let p: Vec<f64> = samples.iter().zip(gap).map(|(x, g)| x - g).collect();
            match (&self.treatment, &lagrangian_coordinates) {
                (ContactTreatment::Lagrangian { .. }, Some((epsilon, c))) => {
                    self.aft.to_time(&c[range], &mut samples);
                    let lambda: Vec<f64> = samples
                        .iter()
                        .zip(gap)
                        .map(|(l, g)| l - epsilon * g)
                        .collect();
                    force.push(lambda.iter().map(|l| l.max(0.0)).collect());
                    multiplier.push(lambda);
                }
                (ContactTreatment::Law(law), _) => {
                    force.push(p.iter().map(|&p| law.force(p).0).collect());
                }
                (ContactTreatment::Lagrangian { .. }, None) => {}
            }
            penetration.push(p);
        }
        Ok(ContactSamples {
            sampled_sectors: self.layout.sampled_sectors,
            contact_dofs: self.layout.contact_dofs,
            penetration,
            force,
            multiplier: matches!(self.treatment, ContactTreatment::Lagrangian { .. })
                .then_some(multiplier),
        })
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
        matches!(&self.treatment, ContactTreatment::Law(law) if law.is_smooth())
    }

    /// DLFT: a hash of the contact state at every sampled instant (the
    /// residual is affine in `x` for a given state); R-HBM: smooth, `None`.
    fn piece(&mut self, x: &[f64], omega: f64) -> Result<Option<u64>, HbmError> {
        if !matches!(self.treatment, ContactTreatment::Lagrangian { .. }) {
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
        let n = self.layout.unknowns;
        self.linear.update(&self.layout, omega)?;
        // r = Z x − F.
        out.residual.resize(n, 0.0);
        multiply(&self.linear.dynamic, x, &mut out.residual);
        for (r, f) in out.residual.iter_mut().zip(&self.linear.load) {
            *r -= f;
        }
        let treatment = self.treatment.clone();
        match &treatment {
            ContactTreatment::Law(law) => self.law_forces(law.as_ref(), x, jacobian),
            ContactTreatment::Lagrangian { epsilon } => {
                self.lagrangian_forces(*epsilon, x, &out.residual, jacobian);
            }
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
        // ∂r/∂ω = ∂Z/∂ω x − ∂F/∂ω.
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
        if out.jacobian.nrows() == n && out.jacobian.ncols() == n {
            out.jacobian.copy_from(&self.linear.dynamic);
        } else {
            out.jacobian = self.linear.dynamic.clone();
        }
        let size = self.layout.coordinates();
        match (&treatment, &self.layout.maps) {
            // ∂R/∂x = Z + T.
            (ContactTreatment::Law(_), SectorMaps::Identity) => {
                for (signal, block) in self.derivative_blocks.chunks_exact(size * size).enumerate()
                {
                    let offset = signal * size;
                    for r in 0..size {
                        for c in 0..size {
                            out.jacobian[(offset + r, offset + c)] += block[r * size + c];
                        }
                    }
                }
            }
            // ∂R/∂x = Z + G̃ T Ḡ.
            (
                ContactTreatment::Law(_),
                SectorMaps::Dense {
                    to_sectors,
                    from_sectors,
                },
            ) => {
                let mut t_g = Mat::<f64>::zeros(to_sectors.nrows(), n);
                apply_blocks(
                    &self.derivative_blocks,
                    size,
                    to_sectors.as_ref(),
                    t_g.as_mut(),
                );
                matmul(
                    out.jacobian.as_mut(),
                    Accum::Add,
                    from_sectors.as_ref(),
                    t_g.as_ref(),
                    1.0,
                    Par::Seq,
                );
            }
            (ContactTreatment::Lagrangian { epsilon }, maps) => {
                let epsilon = *epsilon;
                // ∂R/∂ω = ∂r/∂ω − G̃ T Ḡ ∂r/∂ω.
                let mut mapped = vec![0.0; self.layout.sector_coordinates()];
                self.to_sectors(&out.derivative_omega, &mut mapped);
                let mut t_mapped = self.apply_derivative_blocks(&mapped);
                t_mapped.iter_mut().for_each(|v| *v = -*v);
                self.add_from_sectors(&t_mapped, &mut out.derivative_omega);
                // ∂R/∂x = Z + G̃ T (ε Ḡ − Ḡ Z).
                match maps {
                    // Z + T (ε I − Z), band by band of T: no n × n temporary.
                    SectorMaps::Identity => {
                        for (signal, block) in
                            self.derivative_blocks.chunks_exact(size * size).enumerate()
                        {
                            let t = MatRef::from_row_major_slice(block, size, size);
                            let band = signal * size;
                            matmul(
                                out.jacobian.as_mut().subrows_mut(band, size),
                                Accum::Add,
                                t,
                                self.linear.dynamic.as_ref().subrows(band, size),
                                -1.0,
                                Par::Seq,
                            );
                            for r in 0..size {
                                for c in 0..size {
                                    out.jacobian[(band + r, band + c)] += epsilon * t[(r, c)];
                                }
                            }
                        }
                    }
                    // Z + G̃ T (ε Ḡ − Ḡ Z).
                    SectorMaps::Dense {
                        to_sectors,
                        from_sectors,
                    } => {
                        let mut m = Mat::from_fn(to_sectors.nrows(), n, |r, c| {
                            epsilon * to_sectors[(r, c)]
                        });
                        matmul(
                            m.as_mut(),
                            Accum::Add,
                            to_sectors.as_ref(),
                            self.linear.dynamic.as_ref(),
                            -1.0,
                            Par::Seq,
                        );
                        let mut t_m = Mat::<f64>::zeros(m.nrows(), n);
                        apply_blocks(&self.derivative_blocks, size, m.as_ref(), t_m.as_mut());
                        matmul(
                            out.jacobian.as_mut(),
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
        Ok(())
    }
}
