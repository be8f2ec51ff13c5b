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
use super::friction::FrictionPart;
use super::layout::Layout;
use super::linear::LinearPart;
use super::sector_products::SectorProducts;
use super::wheel_jacobian::WheelJacobian;
use super::HbmError;
use crate::contact::{Casing, ContactLaw, SlidingFriction, Smoothness, EMPTY_STATE};
use crate::continuation::{ArcLengthSettings, Evaluation, Interrupt, Problem};
use faer::linalg::solvers::Solve;
use faer::Mat;
use std::sync::Arc;

/// Time samples of the contact state at one point, one signal per sampled
/// sector and contact dof (sector-major, as in the layout).
#[derive(Clone, Debug)]
pub struct ContactSamples {
    /// Sectors sampled (0-based `0..sampled_sectors`).
    pub sampled_sectors: usize,
    /// Normal contact dofs per sector (those with a gap).
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

/// The residual of one harmonic balance problem, with its buffers (`Debug`
/// and `Clone` in `residual/traits.rs`).
pub struct HarmonicBalance {
    layout: Layout,
    linear: LinearPart,
    aft: Aft,
    law: Arc<dyn ContactLaw>,
    casing: Casing,
    /// Contact dofs with a gap and the normal law, first among the contact
    /// dofs of a sector; with friction, two tangential dofs per normal one
    /// follow them.
    normal_dofs: usize,
    /// Gap `g0(τ_n)` per sampled sector and normal dof (sector-major).
    gap_samples: Vec<Vec<f64>>,
    friction: Option<FrictionPart>,
    sector_coordinates: Vec<f64>,
    /// The unknowns on the sampled sectors (`Ḡ x`) when the law reads
    /// another variable (friction reads the velocities of `x`).
    sector_displacements: Vec<f64>,
    sector_forces: Vec<f64>,
    reading: Vec<f64>,
    force: Vec<f64>,
    slope: Vec<f64>,
    /// `H × H` Jacobian blocks `F diag(df/dq) F⁻¹` per sampled sector and
    /// normal dof.
    derivative_blocks: Vec<f64>,
    /// `v = a x + b r` in the unknowns' space (laws that read `r`).
    law_variable: Vec<f64>,
    /// A hash of the contact state at the last evaluation (piecewise laws).
    piece: u64,
    force_scale: f64,
    /// The cyclic sector maps by their nonzeros and the contact Jacobian's
    /// buffers; `None` for the physical layout, whose maps are the
    /// identity.
    products: Option<SectorProducts>,
    /// The physical layout, shared with the structured Jacobians, when the
    /// Jacobian is kept structured (see [`Self::with_structured_jacobian`]),
    /// and the engine order of the traveling wave its approximation undoes.
    structured: Option<(Arc<Layout>, i64)>,
    /// Raised from outside: a contact Jacobian being assembled is given up
    /// ([`HbmError::Interrupted`]).
    interrupt: Option<Interrupt>,
}

impl HarmonicBalance {
    /// A residual from its layout, linear part, contact law and casing, with
    /// `time_samples` instants per period; residuals are divided by
    /// `force_scale` (N) in the convergence test.
    ///
    /// With `friction`, the layout's contact dofs of a sector are the
    /// normal dofs (one per friction node) followed by each node's
    /// circumferential and axial dofs.
    ///
    /// # Panics
    /// If the casing does not give one gap and one amplitude per normal dof
    /// of the layout, or the contact dofs are not three per friction node
    /// ([`crate::hbm::ProblemSpec::build`] checks both).
    pub fn new(
        layout: Layout,
        linear: LinearPart,
        law: Arc<dyn ContactLaw>,
        casing: Casing,
        friction: Option<&SlidingFriction>,
        time_samples: usize,
        force_scale: f64,
    ) -> Self {
        let normal_dofs = match friction {
            Some(f) => f.nodes().len(),
            None => layout.contact_dofs,
        };
        assert_eq!(
            layout.contact_dofs,
            normal_dofs * if friction.is_some() { 3 } else { 1 },
            "three contact dofs per friction node"
        );
        assert!(
            casing.fits(normal_dofs),
            "one gap and amplitude per normal contact dof"
        );
        let aft = Aft::new(layout.harmonics(), time_samples);
        let size = layout.coordinates();
        let normal_signals = layout.sampled_sectors * normal_dofs;
        let gap_samples = (0..layout.sampled_sectors)
            .flat_map(|j| {
                let casing = &casing;
                (0..normal_dofs)
                    .map(move |c| casing.gap_samples(layout.sectors, j, c, time_samples))
            })
            .collect();
        Self {
            sector_coordinates: vec![0.0; layout.sector_coordinates()],
            sector_displacements: vec![0.0; layout.sector_coordinates()],
            sector_forces: vec![0.0; layout.sector_coordinates()],
            reading: vec![0.0; time_samples],
            force: vec![0.0; time_samples],
            slope: vec![0.0; time_samples],
            derivative_blocks: vec![0.0; normal_signals * size * size],
            law_variable: vec![0.0; layout.unknowns],
            piece: 0,
            friction: friction.map(|f| FrictionPart::new(f, &layout, time_samples)),
            products: SectorProducts::new(&layout),
            structured: None,
            interrupt: None,
            normal_dofs,
            layout,
            linear,
            aft,
            law,
            casing,
            gap_samples,
            force_scale,
        }
    }

    /// Keeps the Jacobian of the physical full wheel structured instead of
    /// dense (`Evaluation::structured`, see [`super::wheel_jacobian`]): its
    /// solves run GMRES preconditioned in the frame of the traveling wave of
    /// `engine_order`, exact at that wave's solutions. A cyclic layout keeps
    /// its dense Jacobian.
    pub fn with_structured_jacobian(mut self, engine_order: i64) -> Self {
        if self.products.is_none() {
            self.linear = self.linear.keep_blocks_only();
            self.structured = Some((Arc::new(self.layout.clone()), engine_order));
        }
        self
    }

    /// Whether the Jacobian is kept structured.
    pub fn is_structured(&self) -> bool {
        self.structured.is_some()
    }

    /// The contact signals the AFT samples at each evaluation: every normal
    /// one and, with friction, its node's two tangential ones.
    pub fn contact_signals(&self) -> usize {
        let per_node = if self.friction.is_some() { 3 } else { 1 };
        self.gap_samples.len() * per_node
    }

    /// Contact dofs per sector that carry a gap and the normal law (all of
    /// them without friction; the first third with it).
    pub fn normal_dofs(&self) -> usize {
        self.normal_dofs
    }

    /// The sliding friction, if any.
    pub fn friction(&self) -> Option<&SlidingFriction> {
        self.friction.as_ref().map(|f| &f.spec)
    }

    /// The offset in the sector coordinates of normal signal `index`
    /// (`j · n_n + c`: sampled sector `j`, normal dof `c`).
    fn normal_band(&self, index: usize) -> usize {
        let (j, c) = (index / self.normal_dofs, index % self.normal_dofs);
        (j * self.layout.contact_dofs + c) * self.layout.coordinates()
    }

    /// The offsets of the circumferential and axial signals of friction
    /// node `index` (`j · n_n + c`).
    fn tangent_bands(&self, index: usize) -> [usize; 2] {
        let (j, c) = (index / self.normal_dofs, index % self.normal_dofs);
        let size = self.layout.coordinates();
        let theta = (j * self.layout.contact_dofs + self.normal_dofs + 2 * c) * size;
        [theta, theta + size]
    }

    /// The unknown layout.
    pub fn layout(&self) -> &Layout {
        &self.layout
    }

    /// The linear part (at the last frequency evaluated).
    pub fn linear(&self) -> &LinearPart {
        &self.linear
    }

    /// The run's interrupt, once the driver let the problem watch it.
    pub(crate) fn interrupt(&self) -> Option<&Interrupt> {
        self.interrupt.as_ref()
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
        match &self.products {
            Some(products) => products.to_sectors(x, out),
            None => out.copy_from_slice(x),
        }
    }

    /// The linear response (no contact) at `omega`: `Z⁻¹ F`.
    pub fn linear_solution(&mut self, omega: f64) -> Result<Vec<f64>, HbmError> {
        if self.structured.is_some() {
            return self.linear.solution_at(&self.layout, omega);
        }
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

    /// The law at every sampled instant from `v` (see [`Self::law_variable`];
    /// `None`: the law reads `x` itself) and, with friction, the sliding
    /// forces from the velocities of `x` at `omega`: fills `sector_forces`
    /// with the forces' coordinates and, if asked, the derivative blocks;
    /// keeps the contact state's hash for a piecewise law.
    fn contact_forces(&mut self, x: &[f64], v: Option<&[f64]>, omega: f64, jacobian: bool) {
        let size = self.layout.coordinates();
        let law = Arc::clone(&self.law);
        let hash = matches!(law.smoothness(), Smoothness::Piecewise).then_some(EMPTY_STATE);
        let mut state = EMPTY_STATE;
        let mut coordinates = std::mem::take(&mut self.sector_coordinates);
        self.to_sectors(v.unwrap_or(x), &mut coordinates);
        let mut friction = self.friction.take();
        let mut displacements = std::mem::take(&mut self.sector_displacements);
        if friction.is_some() {
            match v {
                Some(_) => self.to_sectors(x, &mut displacements),
                None => displacements.copy_from_slice(&coordinates),
            }
        }
        for index in 0..self.gap_samples.len() {
            let band = self.normal_band(index);
            let range = band..band + size;
            self.aft
                .to_time(&coordinates[range.clone()], &mut self.reading);
            let found = law.apply(
                &self.reading,
                &self.gap_samples[index],
                &mut self.force,
                jacobian.then_some(self.slope.as_mut_slice()),
                hash.map(|_| state),
            );
            state = found.state;
            self.aft
                .to_frequency(&self.force, &mut self.sector_forces[range]);
            if jacobian {
                let block =
                    &mut self.derivative_blocks[index * size * size..(index + 1) * size * size];
                self.aft.derivative_block(&self.slope, block);
            }
            if let Some(friction) = friction.as_mut() {
                let bands = self.tangent_bands(index);
                friction.node(
                    &mut self.aft,
                    index,
                    bands,
                    &displacements,
                    &self.force,
                    &self.slope,
                    omega,
                    jacobian,
                    &mut self.sector_forces,
                );
            }
        }
        self.friction = friction;
        self.sector_coordinates = coordinates;
        self.sector_displacements = displacements;
        self.piece = state;
    }

    /// `out = Z x` for the dynamic stiffness or its derivative: block by
    /// block for a cyclic layout.
    fn multiply_dynamic(&self, z: &Mat<f64>, x: &[f64], out: &mut [f64]) {
        match &self.products {
            Some(products) => products.multiply_block_diagonal(z.as_ref(), x, out),
            None => multiply(z, x, out),
        }
    }

    /// `out += G̃ v` for sector coordinates `v`.
    fn add_from_sectors(&self, v: &[f64], out: &mut [f64]) {
        match &self.products {
            Some(products) => products.add_from_sectors(v, out),
            None => {
                for (o, f) in out.iter_mut().zip(v) {
                    *o += f;
                }
            }
        }
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

    fn watch_interrupt(&mut self, interrupt: &Interrupt) {
        self.interrupt = Some(interrupt.clone());
    }

    /// The linear response at `omega` corrected by Newton where that
    /// converges, else the continuation in the load's point, else none
    /// (`HarmonicBalance::fresh_start`, hbm/homotopy.rs).
    fn fresh_guess(
        &mut self,
        omega: f64,
        steps: &ArcLengthSettings,
    ) -> Result<Option<Vec<f64>>, HbmError> {
        self.fresh_start(omega, steps)
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

    fn piece_of_last_evaluation(&self) -> Option<u64> {
        matches!(self.law.smoothness(), Smoothness::Piecewise).then_some(self.piece)
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
        if self.structured.is_some() {
            self.linear
                .multiply(&self.layout, x, false, &mut out.residual);
        } else {
            self.multiply_dynamic(&self.linear.dynamic, x, &mut out.residual);
        }
        for (r, f) in out.residual.iter_mut().zip(&self.linear.load) {
            *r -= load_scale * f;
        }
        let input = self.law.input();
        let (a, b) = (input.penetration, input.residual);
        if input.reads_residual() {
            let mut v = std::mem::take(&mut self.law_variable);
            form_law_variable(a, b, x, &out.residual, &mut v);
            self.contact_forces(x, Some(&v), omega, jacobian);
            self.law_variable = v;
        } else {
            self.contact_forces(x, None, omega, jacobian);
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
                if self.structured.is_some() {
                    self.linear
                        .multiply(&self.layout, x, true, &mut out.derivative_omega);
                } else {
                    self.multiply_dynamic(
                        &self.linear.dynamic_derivative,
                        x,
                        &mut out.derivative_omega,
                    );
                }
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
        if let Some((layout, engine_order)) = &self.structured {
            out.jacobian = Mat::new();
            out.structured = Some(Arc::new(WheelJacobian {
                layout: Arc::clone(layout),
                linear: self.linear.condensed_blocks(),
                weights: (a, b),
                normal_dofs: self.normal_dofs,
                law_blocks: self.derivative_blocks.clone(),
                friction_blocks: self.friction.as_ref().map(|f| f.blocks.clone()),
                engine_order: *engine_order,
            }));
        } else if out.jacobian.nrows() == n && out.jacobian.ncols() == n {
            out.structured = None;
            out.jacobian.copy_from(&self.linear.dynamic);
        } else {
            out.structured = None;
            out.jacobian = self.linear.dynamic.clone();
        }
        // The contact's part of ∂R/∂p, in sector coordinates: the law's,
        // b T Ḡ ∂r/∂p, and along ω the sliding velocities' (friction).
        let mut contact_part = None;
        if input.reads_residual() {
            let mut mapped = vec![0.0; self.layout.sector_coordinates()];
            self.to_sectors(&out.derivative_omega, &mut mapped);
            let mut t_mapped = self.apply_derivative_blocks(&mapped);
            t_mapped.iter_mut().for_each(|v| *v *= b);
            contact_part = Some(t_mapped);
        }
        if let (Some(friction), Along::Frequency) = (&self.friction, along) {
            let part =
                contact_part.get_or_insert_with(|| vec![0.0; self.layout.sector_coordinates()]);
            for (p, d) in part.iter_mut().zip(&friction.frequency_derivative) {
                *p += d;
            }
        }
        if let Some(part) = contact_part {
            self.add_from_sectors(&part, &mut out.derivative_omega);
        }
        if self.structured.is_none() && !self.add_contact_jacobian(a, b, &mut out.jacobian) {
            return Err(HbmError::Interrupted);
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests;

mod jacobian;
mod samples;
mod traits;
