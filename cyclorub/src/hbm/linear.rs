//! The linear part, condensed on the contact dofs: for each block (a signed
//! pair `(s, k)`, or a harmonic of the whole wheel) the dynamic stiffness
//! `Z = K − (kω)² M + i kω C`, its Schur complement on the contact dofs,
//! `∂/∂ω`, and the condensed loads. Recomputed once per frequency
//! (harmonic 0, which does not depend on it, kept).
//!
//! With a flexible wall (DLFT-HBM, Sec. 4.1), each contact dof `x_b` is
//! joined by a spring `κ` to a massless wall node `x_w` that touches the
//! casing. With the contact force `−f` on the wall node, the blade obeys
//! `Z x_b + κ (x_b − x_w) = F` and the node `κ (x_w − x_b) + f = 0`, so
//! `Z x_b = F − f` and `x_w = x_b − f/κ`. Eliminating `x_b` leaves
//! `Z_r x_w − F_r + f = 0` on the wall nodes, with (`A = Z + κ I`)
//! `Z_r = (Z⁻¹ + κ⁻¹ I)⁻¹ = κ I − κ² A⁻¹`, `F_r = κ A⁻¹ F`,
//! `∂Z_r = κ² A⁻¹ ∂Z A⁻¹`, `∂F_r = κ A⁻¹ (∂F − ∂Z A⁻¹ F)`; the blade is
//! recovered exactly from `A x_b = F + κ x_w`. The contact unknowns are then
//! the wall nodes' displacements.

use super::layout::{Block, Layout};
use super::HbmError;
use faer::{c64, Mat};
use rayon::prelude::*;
use std::sync::Arc;

mod any_frequency;
mod condensation;
mod derivative;
mod diameters;
mod perturbed;
use condensation::{condense, condense_for_products, with_wall};
use derivative::DerivativeOperator;
use diameters::Circulant;
pub use diameters::WheelDiameters;
pub use perturbed::PerturbedWheel;

/// Mass, stiffness and damping of one block's local dofs: a sector's at one
/// signed nodal diameter (Hermitian, complex), or the whole wheel's
/// (real). Shared between the blocks of one diameter on every harmonic.
#[derive(Clone, Debug)]
pub struct BlockMatrices {
    /// Mass `M(s)`, kg.
    pub mass: Arc<Mat<c64>>,
    /// Stiffness `K(s)`, N/m.
    pub stiffness: Arc<Mat<c64>>,
    /// Viscous damping `C(s)`, N·s/m (modal, Rayleigh or given).
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
    /// How the block is condensed: the structure of a whole wheel's block
    /// that makes it cheaper than the dense Schur complement, if any.
    pub structure: WheelStructure,
}

/// What a whole wheel's block offers its condensation beyond the dense
/// Schur complement (each exact).
#[derive(Clone, Debug)]
pub enum WheelStructure {
    /// None: densely (a sector's block, or a wheel without a structure
    /// used).
    Dense,
    /// A tuned wheel: its matrices by nodal diameter, which condense it at
    /// a sector's cost.
    Diameters(Arc<WheelDiameters>),
    /// A mistuned wheel: the tuned wheel by nodal diameters and the change
    /// on a few dofs a sector, condensed in two stages.
    Perturbed(Arc<PerturbedWheel>),
}

/// How a condensed block keeps `∂Z/∂ω`: as a matrix (entries are read: the
/// dense assembly), or as products only (the structured Jacobian applies it
/// to one vector; checks and linear solutions never read it).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum DerivativeUse {
    Entries,
    Products,
}

/// The block condensed at `omega` (by nodal diameters for the whole wheel
/// when it has them), then in series with the wall if there is one.
fn condense_block(
    block: &Block,
    local: &LocalBlock,
    omega: f64,
    wall_stiffness: Option<f64>,
    derivative: DerivativeUse,
) -> Result<Condensed, HbmError> {
    match &local.structure {
        WheelStructure::Diameters(diameters) => {
            return diameters.condense(block, &local.load, omega, wall_stiffness)
        }
        WheelStructure::Perturbed(perturbed) => {
            return perturbed.condense(block, &local.load, omega, wall_stiffness)
        }
        WheelStructure::Dense => {}
    }
    let condensed = match derivative {
        DerivativeUse::Entries => condense(block, local, omega)?,
        DerivativeUse::Products => condense_for_products(block, local, omega)?,
    };
    match wall_stiffness {
        Some(kappa) => with_wall(block, condensed, kappa, omega),
        None => Ok(condensed),
    }
}

/// A block condensed at one frequency: `Z`, `∂Z/∂ω` on its contact entries
/// (slot order) and the loads. A block of the whole wheel condensed by
/// nodal diameters keeps them so (`circulant`), and its dense matrices are
/// then empty: read entries with [`Condensed::entry`] and products with
/// [`Condensed::multiply`].
#[derive(Clone, Debug)]
pub(super) struct Condensed {
    dynamic: Mat<c64>,
    dynamic_derivative: Mat<c64>,
    load: Vec<c64>,
    load_derivative: Vec<c64>,
    circulant: Option<Circulant>,
    /// `∂Z/∂ω` as products, where `dynamic_derivative` is left empty.
    derivative_products: Option<DerivativeOperator>,
}

impl Condensed {
    /// For a block of the whole wheel kept by nodal diameters, `Ẑ(s)` on
    /// one sector's contact entries (`s` modulo `N`): the block's wave
    /// `x_j = x̂ e^{i s α j}` gives `Z x` = `(Ẑ(s) x̂) e^{i s α j}`.
    pub(super) fn diameter(&self, s: i64) -> Option<&Mat<c64>> {
        let circulant = self.circulant.as_ref()?;
        Some(circulant.diameter(s))
    }

    /// `Z[a, b]`, or `∂Z/∂ω[a, b]` if `derivative`.
    pub(super) fn entry(&self, a: usize, b: usize, derivative: bool) -> c64 {
        match (&self.circulant, &self.derivative_products, derivative) {
            (Some(circulant), _, _) => circulant.entry(a, b, derivative),
            (None, _, false) => self.dynamic[(a, b)],
            // One column's product: for checks, not for hot paths.
            (None, Some(products), true) => {
                let mut unit = vec![c64::new(0.0, 0.0); self.dynamic.ncols()];
                unit[b] = c64::new(1.0, 0.0);
                products.product(&unit)[a]
            }
            (None, None, true) => self.dynamic_derivative[(a, b)],
        }
    }

    /// `Z x`, or `∂Z/∂ω x` if `derivative`.
    pub(super) fn multiply(&self, x: &[c64], derivative: bool) -> Vec<c64> {
        if let Some(circulant) = &self.circulant {
            return circulant.multiply(x, derivative);
        }
        if let (Some(products), true) = (&self.derivative_products, derivative) {
            return products.product(x);
        }
        let z = if derivative {
            &self.dynamic_derivative
        } else {
            &self.dynamic
        };
        column_product(z, x)
    }
}

/// `Z x` by faer's matrix–vector product (vectorized; the matrices are
/// stored by columns, which a row-by-row sum strided through).
pub(super) fn column_product(z: &Mat<c64>, x: &[c64]) -> Vec<c64> {
    let product = z * faer::ColRef::from_slice(&x[..z.ncols()]);
    (0..z.nrows()).map(|r| product[r]).collect()
}

/// The condensed linear part of the whole problem at the current frequency,
/// in the real unknown layout.
#[derive(Clone, Debug)]
pub struct LinearPart {
    blocks: Vec<LocalBlock>,
    omega: f64,
    wall_stiffness: Option<f64>,
    /// `Z(ω)`, real, unknowns × unknowns.
    pub dynamic: Mat<f64>,
    /// `∂Z/∂ω`.
    pub dynamic_derivative: Mat<f64>,
    /// Condensed external load `F(ω)`.
    pub load: Vec<f64>,
    /// `∂F/∂ω`.
    pub load_derivative: Vec<f64>,
    /// Whether `dynamic` and `dynamic_derivative` are assembled; if not
    /// (see [`Self::keep_blocks_only`]) they are empty and the condensed
    /// blocks serve instead.
    dense: bool,
    /// The blocks condensed at the current frequency (without the dense
    /// assembly); harmonic 0's from the first frequency.
    condensed: Arc<Vec<Condensed>>,
}

impl LinearPart {
    /// The linear part of `layout` from its blocks' local problems (same order).
    pub fn new(layout: &Layout, blocks: Vec<LocalBlock>) -> Self {
        let n = layout.unknowns;
        Self {
            blocks,
            omega: f64::NAN,
            wall_stiffness: None,
            dynamic: Mat::zeros(n, n),
            dynamic_derivative: Mat::zeros(n, n),
            load: vec![0.0; n],
            load_derivative: vec![0.0; n],
            dense: true,
            condensed: Arc::new(Vec::new()),
        }
    }

    /// Keeps the condensed blocks alone, without assembling the dense `Z`
    /// and `∂Z/∂ω` (`unknowns²` each: 660 MB for the open fan's full wheel);
    /// products go through [`Self::multiply`].
    pub fn keep_blocks_only(mut self) -> Self {
        self.dense = false;
        self.dynamic = Mat::new();
        self.dynamic_derivative = Mat::new();
        self.omega = f64::NAN;
        self
    }

    /// Whether the dense `Z` and `∂Z/∂ω` are assembled.
    pub fn is_dense(&self) -> bool {
        self.dense
    }

    /// The blocks condensed at the last frequency (block mode).
    pub(super) fn condensed_blocks(&self) -> Arc<Vec<Condensed>> {
        Arc::clone(&self.condensed)
    }

    /// `out = Z x` (or `∂Z/∂ω x` if `derivative`) at the current frequency,
    /// from the dense matrices or block by block.
    pub fn multiply(&self, layout: &Layout, x: &[f64], derivative: bool, out: &mut [f64]) {
        if self.dense {
            let z = if derivative {
                &self.dynamic_derivative
            } else {
                &self.dynamic
            };
            out.fill(0.0);
            for (col, &v) in x.iter().enumerate().take(z.ncols()) {
                if v != 0.0 {
                    for (o, a) in out.iter_mut().zip(z.col_as_slice(col)) {
                        *o += a * v;
                    }
                }
            }
            return;
        }
        multiply_blocks(layout, &self.condensed, x, derivative, out);
    }

    /// `‖ |Z| |x| ‖` in the real layout (the size of the terms that cancel in
    /// `Z x`, for round-off bounds).
    pub fn absolute_product_norm(&self, layout: &Layout, x: &[f64]) -> f64 {
        let mut squares = 0.0;
        if self.dense {
            let z = &self.dynamic;
            for r in 0..z.nrows() {
                let row: f64 = (0..z.ncols()).map(|c| (z[(r, c)] * x[c]).abs()).sum();
                squares += row * row;
            }
            return squares.sqrt();
        }
        for (block, condensed) in layout.blocks.iter().zip(self.condensed.iter()) {
            for (a, slot_a) in block.slots.iter().enumerate() {
                let (mut re_row, mut im_row) = (0.0, 0.0);
                for (b, slot_b) in block.slots.iter().enumerate() {
                    let z = condensed.entry(a, b, false);
                    let (xr, xi) = (x[slot_b.re].abs(), slot_b.im.map_or(0.0, |i| x[i].abs()));
                    re_row += z.re.abs() * xr + z.im.abs() * xi;
                    im_row += z.im.abs() * xr + z.re.abs() * xi;
                }
                squares += re_row * re_row;
                if slot_a.im.is_some() {
                    squares += im_row * im_row;
                }
            }
        }
        squares.sqrt()
    }

    /// The local problems.
    pub fn blocks(&self) -> &[LocalBlock] {
        &self.blocks
    }

    /// Puts a wall of stiffness `κ` (N/m) between every contact dof and the
    /// casing (`None`: rigid casing, the contact dofs touch it directly).
    /// The contact unknowns become the wall nodes' displacements.
    pub fn with_wall_stiffness(mut self, wall_stiffness: Option<f64>) -> Self {
        self.wall_stiffness = wall_stiffness;
        self.omega = f64::NAN;
        self.condensed = Arc::new(Vec::new());
        self
    }

    /// The wall stiffness `κ`, if there is a wall.
    pub fn wall_stiffness(&self) -> Option<f64> {
        self.wall_stiffness
    }

    /// Brings `Z`, `∂Z/∂ω`, `F`, `∂F/∂ω` to frequency `omega` (rad/s);
    /// nothing to do if it is already there.
    pub fn update(&mut self, layout: &Layout, omega: f64) -> Result<(), HbmError> {
        #[allow(clippy::float_cmp)] // the cache key is the exact frequency
        if omega == self.omega {
            return Ok(());
        }
        let mut target = Assembly {
            dynamic: std::mem::replace(&mut self.dynamic, Mat::new()),
            dynamic_derivative: std::mem::replace(&mut self.dynamic_derivative, Mat::new()),
            load: std::mem::take(&mut self.load),
            load_derivative: std::mem::take(&mut self.load_derivative),
        };
        let outcome = if self.dense {
            self.assemble(layout, omega, &mut target)
        } else {
            self.assemble_blocks(layout, omega, &mut target)
        };
        self.dynamic = target.dynamic;
        self.dynamic_derivative = target.dynamic_derivative;
        self.load = target.load;
        self.load_derivative = target.load_derivative;
        // A failed assembly leaves no frequency cached.
        self.omega = if outcome.is_ok() { omega } else { f64::NAN };
        outcome
    }

    /// Condenses every block at `omega` into [`Self::condensed`] and fills
    /// `target`'s loads (its matrices are left empty).
    fn assemble_blocks(
        &mut self,
        layout: &Layout,
        omega: f64,
        target: &mut Assembly,
    ) -> Result<(), HbmError> {
        // The harmonics are independent: on every thread. Harmonic 0 does
        // not depend on ω (`Z = K`, static loads): kept from the last
        // frequency.
        let previous = Arc::clone(&self.condensed);
        let kept: Vec<Result<Condensed, HbmError>> = layout
            .blocks
            .par_iter()
            .zip(self.blocks.par_iter())
            .enumerate()
            .map(|(index, (block, local))| {
                if let (0, Some(static_block)) = (block.harmonic, previous.get(index)) {
                    return Ok(static_block.clone());
                }
                condense_block(
                    block,
                    local,
                    omega,
                    self.wall_stiffness,
                    DerivativeUse::Products,
                )
            })
            .collect();
        let kept = kept.into_iter().collect::<Result<Vec<_>, _>>()?;
        for (block, condensed) in layout.blocks.iter().zip(&kept) {
            scatter_loads(block, condensed, target);
        }
        self.condensed = Arc::new(kept);
        Ok(())
    }

    /// Fills `target` with `Z`, `∂Z/∂ω`, `F`, `∂F/∂ω` at `omega`, block by
    /// block: the matrices' entries between blocks are left as they are
    /// (zero: `target`'s matrices are only ever written here), each block's
    /// are overwritten.
    fn assemble(&self, layout: &Layout, omega: f64, target: &mut Assembly) -> Result<(), HbmError> {
        target.load.fill(0.0);
        target.load_derivative.fill(0.0);
        layout
            .blocks
            .iter()
            .zip(&self.blocks)
            .try_for_each(|(block, local)| {
                let condensed = condense_block(
                    block,
                    local,
                    omega,
                    self.wall_stiffness,
                    DerivativeUse::Entries,
                )?;
                scatter(block, &condensed, target);
                Ok(())
            })
    }
}

/// The real matrices and loads of the whole layout at one frequency.
struct Assembly {
    dynamic: Mat<f64>,
    dynamic_derivative: Mat<f64>,
    load: Vec<f64>,
    load_derivative: Vec<f64>,
}

/// `out = Z x` (or `∂Z/∂ω x`) block by block from the condensed blocks, in
/// the real layout (`[[Re Z, −Im Z], [Im Z, Re Z]]`).
pub(super) fn multiply_blocks(
    layout: &Layout,
    condensed: &[Condensed],
    x: &[f64],
    derivative: bool,
    out: &mut [f64],
) {
    out.fill(0.0);
    for (block, part) in layout.blocks.iter().zip(condensed) {
        let values: Vec<c64> = block
            .slots
            .iter()
            .map(|slot| c64::new(x[slot.re], slot.im.map_or(0.0, |im| x[im])))
            .collect();
        let product = part.multiply(&values, derivative);
        for (a, slot) in block.slots.iter().enumerate() {
            let sum = product[a];
            out[slot.re] = sum.re;
            if let Some(im) = slot.im {
                out[im] = sum.im;
            }
        }
    }
}

/// Writes a condensed block's loads `F`, `∂F/∂ω` into the real layout.
fn scatter_loads(block: &Block, condensed: &Condensed, part: &mut Assembly) {
    for (a, slot) in block.slots.iter().enumerate() {
        part.load[slot.re] = condensed.load[a].re;
        part.load_derivative[slot.re] = condensed.load_derivative[a].re;
        if let Some(im) = slot.im {
            part.load[im] = condensed.load[a].im;
            part.load_derivative[im] = condensed.load_derivative[a].im;
        }
    }
}

/// Adds a condensed block to the real layout: a complex coefficient is the
/// pair `(Re, Im)` and `Z` acts as `[[Re Z, −Im Z], [Im Z, Re Z]]`.
fn scatter(block: &Block, condensed: &Condensed, part: &mut Assembly) {
    scatter_loads(block, condensed, part);
    for (a, slot_a) in block.slots.iter().enumerate() {
        for (b, slot_b) in block.slots.iter().enumerate() {
            for (target, derivative) in [
                (&mut part.dynamic, false),
                (&mut part.dynamic_derivative, true),
            ] {
                // Each entry of the block once: overwritten, not added.
                let z = condensed.entry(a, b, derivative);
                target[(slot_a.re, slot_b.re)] = z.re;
                if let Some(im_b) = slot_b.im {
                    target[(slot_a.re, im_b)] = -z.im;
                }
                if let Some(im_a) = slot_a.im {
                    target[(im_a, slot_b.re)] = z.im;
                    if let Some(im_b) = slot_b.im {
                        target[(im_a, im_b)] = z.re;
                    }
                }
            }
        }
    }
}
