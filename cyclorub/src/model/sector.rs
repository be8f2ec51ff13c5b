//! The sector model: one description of a sector, from which come the
//! matrices of every signed nodal diameter and those of the full wheel.

use super::damping::{Damping, ModalDamping};
use super::eigen::{angular_frequencies, hermitian_modes, symmetric_modes};
use super::matrices::{
    assemble_from_nodal_diameters, fold, CirculantBlocks, FullWheelMatrices, NodalDiameterMatrices,
};
use super::validate::{
    check_positive_definite, check_size, symmetrized, DEFAULT_SYMMETRY_TOLERANCE,
};
use super::ModelError;
use faer::{c64, Mat};
use rayon::prelude::*;
use std::sync::{Arc, OnceLock};

/// Largest full wheel (`N·dofs_per_sector` rows) that [`SectorModel::full_wheel`]
/// assembles: the full wheel is dense and meant for validating reductions on
/// small models (three matrices of this size take about 0.9 GB).
pub const FULL_WHEEL_MAX_DOFS: usize = 6000;

/// A sector given by its within-sector blocks and its coupling to the next
/// sector (lumped models such as the paper's academic chain).
///
/// The full wheel holds `mass`, `stiffness` on its diagonal blocks, the
/// couplings on block `(j, j+1)` (row: sector `j`, column: sector `j+1`) and
/// their transposes on block `(j+1, j)`. Hence
/// `K(s) = K0 + K1·exp(−iαs) + K1ᵀ·exp(iαs)`.
#[derive(Clone, Debug)]
pub struct BlockCirculantSector {
    /// Within-sector mass `M0` (symmetric positive definite).
    pub mass: Mat<f64>,
    /// Within-sector stiffness `K0` (symmetric).
    pub stiffness: Mat<f64>,
    /// Mass coupling `M1` to the next sector, if any.
    pub mass_coupling: Option<Mat<f64>>,
    /// Stiffness coupling `K1` to the next sector, if any.
    pub stiffness_coupling: Option<Mat<f64>>,
}

/// A finite-element sector: its full mass and stiffness matrices with the
/// left and right cyclic boundary dofs (0-based, paired in order).
///
/// The right boundary of sector `j` is the left boundary of sector `j+1`, so
/// for the wave of nodal diameter `s`, `u_R = exp(−iαs)·u_L`. The independent
/// dofs of a sector are all dofs but the right boundary ones, in their
/// original order.
#[derive(Clone, Debug)]
pub struct FiniteElementSector {
    /// Sector mass (symmetric positive definite).
    pub mass: Mat<f64>,
    /// Sector stiffness (symmetric).
    pub stiffness: Mat<f64>,
    /// Left cyclic boundary dofs (0-based).
    pub left_boundary: Vec<usize>,
    /// Right cyclic boundary dofs (0-based), `right_boundary[i]` matching
    /// `left_boundary[i]` of the next sector.
    pub right_boundary: Vec<usize>,
}

/// Names used in error messages (case-file keys when built from a case file).
#[derive(Clone, Debug)]
pub(crate) struct Names {
    pub(crate) mass: String,
    pub(crate) stiffness: String,
    pub(crate) mass_coupling: String,
    pub(crate) stiffness_coupling: String,
    pub(crate) damping: String,
    pub(crate) damping_matrix: String,
    pub(crate) damping_coupling: String,
    pub(crate) left: String,
    pub(crate) right: String,
    pub(crate) symmetry_tolerance: f64,
}

impl Default for Names {
    fn default() -> Self {
        Self {
            mass: "mass".into(),
            stiffness: "stiffness".into(),
            mass_coupling: "mass coupling".into(),
            stiffness_coupling: "stiffness coupling".into(),
            damping: "damping".into(),
            damping_matrix: "damping matrix".into(),
            damping_coupling: "damping coupling".into(),
            left: "left boundary".into(),
            right: "right boundary".into(),
            symmetry_tolerance: DEFAULT_SYMMETRY_TOLERANCE,
        }
    }
}

#[derive(Clone, Debug)]
enum DampingModel {
    None,
    /// Modal ratios, with `C(s)` for `s = 0..=N/2` computed once on demand.
    Modal(ModalDamping, ModalCache),
    Viscous(CirculantBlocks),
}

/// `C(s)` of the diameters `0..=N/2`, filled on first use (shared by clones:
/// the model is immutable).
#[derive(Clone, Debug)]
struct ModalCache(Arc<Vec<OnceLock<Mat<c64>>>>);

impl ModalCache {
    fn new(sectors: usize) -> Self {
        Self(Arc::new(
            (0..=sectors / 2).map(|_| OnceLock::new()).collect(),
        ))
    }
}

/// One sector of a tuned cyclic structure, with its damping, and the number
/// of sectors `N`.
///
/// Storage is dense: per-diameter matrices are fine up to a few hundred dofs
/// per sector (a diameter's modal damping costs one Cholesky factorization and
/// one Hermitian eigendecomposition of that size); the full wheel is limited
/// to [`FULL_WHEEL_MAX_DOFS`] rows.
#[derive(Clone, Debug)]
pub struct SectorModel {
    sectors: usize,
    labels: Vec<String>,
    mass: CirculantBlocks,
    stiffness: CirculantBlocks,
    damping: DampingModel,
}

fn check_sectors(sectors: usize) -> Result<(), ModelError> {
    if sectors == 0 {
        return Err(ModelError::invalid(
            "sectors",
            "0 is not allowed: the number of sectors N must be at least 1",
        ));
    }
    Ok(())
}

fn check_modal(modal: &ModalDamping, key: &str) -> Result<(), ModelError> {
    for (r, &x) in modal.ratios.iter().enumerate() {
        if !(x.is_finite() && x >= 0.0) {
            return Err(ModelError::invalid(
                format!("{key}.ratios[{}]", r + 1),
                format!("{x} is not allowed: damping ratios must be finite and ≥ 0"),
            ));
        }
    }
    if !(modal.others.is_finite() && modal.others >= 0.0) {
        return Err(ModelError::invalid(
            format!("{key}.others"),
            format!(
                "{} is not allowed: damping ratios must be finite and ≥ 0",
                modal.others
            ),
        ));
    }
    Ok(())
}

fn check_rayleigh(alpha: f64, beta: f64, key: &str) -> Result<(), ModelError> {
    for (name, x) in [("alpha", alpha), ("beta", beta)] {
        if !(x.is_finite() && x >= 0.0) {
            return Err(ModelError::invalid(
                format!("{key}.{name}"),
                format!("{x} is not allowed: Rayleigh factors must be finite and ≥ 0"),
            ));
        }
    }
    Ok(())
}

fn coupling_or_zero(
    coupling: Option<Mat<f64>>,
    n: usize,
    what: &str,
    reference: &str,
) -> Result<Mat<f64>, ModelError> {
    match coupling {
        Some(c) => {
            check_size(&c, what, n, reference)?;
            Ok(c)
        }
        None => Ok(Mat::zeros(n, n)),
    }
}

impl SectorModel {
    /// A block-circulant sector (within-sector blocks and coupling to the
    /// next sector), `sectors` sectors, with `damping`.
    pub fn block_circulant(
        sectors: usize,
        sector: BlockCirculantSector,
        damping: Damping,
    ) -> Result<Self, ModelError> {
        Self::block_circulant_named(sectors, sector, damping, &Names::default())
    }

    /// A finite-element sector with left/right cyclic boundary dofs,
    /// `sectors` sectors, with `damping` (a damping matrix is then a full
    /// sector matrix like the stiffness).
    pub fn finite_element(
        sectors: usize,
        sector: FiniteElementSector,
        damping: Damping,
    ) -> Result<Self, ModelError> {
        Self::finite_element_named(sectors, sector, damping, &Names::default())
    }

    pub(crate) fn block_circulant_named(
        sectors: usize,
        sector: BlockCirculantSector,
        damping: Damping,
        names: &Names,
    ) -> Result<Self, ModelError> {
        check_sectors(sectors)?;
        let tol = names.symmetry_tolerance;
        let stiffness = symmetrized(&sector.stiffness, &names.stiffness, tol)?;
        let n = stiffness.nrows();
        if n == 0 {
            return Err(ModelError::invalid(
                &names.stiffness,
                "a sector needs at least one dof",
            ));
        }
        check_size(&sector.mass, &names.mass, n, &names.stiffness)?;
        let mass = symmetrized(&sector.mass, &names.mass, tol)?;
        let mass = CirculantBlocks {
            within: mass,
            coupling: coupling_or_zero(
                sector.mass_coupling,
                n,
                &names.mass_coupling,
                &names.stiffness,
            )?,
        };
        let stiffness = CirculantBlocks {
            within: stiffness,
            coupling: coupling_or_zero(
                sector.stiffness_coupling,
                n,
                &names.stiffness_coupling,
                &names.stiffness,
            )?,
        };
        // M(s) must be positive definite for every diameter; without a mass
        // coupling M(s) = M0 for all s.
        if mass.has_coupling() {
            for s in 0..=(sectors as i64 / 2) {
                if mass.at(s, sectors).llt(faer::Side::Lower).is_err() {
                    return Err(ModelError::MassNotPositiveDefinite {
                        what: names.mass.clone(),
                        nodal_diameter: Some(s),
                    });
                }
            }
        } else {
            check_positive_definite(&mass.within, &names.mass)?;
        }
        let damping = match damping {
            Damping::None => DampingModel::None,
            Damping::Modal(modal) => {
                check_modal(&modal, &names.damping)?;
                DampingModel::Modal(modal, ModalCache::new(sectors))
            }
            Damping::Rayleigh { alpha, beta } => {
                check_rayleigh(alpha, beta, &names.damping)?;
                DampingModel::Viscous(mass.combine(alpha, &stiffness, beta))
            }
            Damping::Matrix { matrix, coupling } => {
                check_size(&matrix, &names.damping_matrix, n, &names.stiffness)?;
                let within = symmetrized(&matrix, &names.damping_matrix, tol)?;
                let coupling =
                    coupling_or_zero(coupling, n, &names.damping_coupling, &names.stiffness)?;
                DampingModel::Viscous(CirculantBlocks { within, coupling })
            }
        };
        Ok(Self {
            sectors,
            labels: (1..=n).map(|d| format!("dof {d}")).collect(),
            mass,
            stiffness,
            damping,
        })
    }

    pub(crate) fn finite_element_named(
        sectors: usize,
        sector: FiniteElementSector,
        damping: Damping,
        names: &Names,
    ) -> Result<Self, ModelError> {
        check_sectors(sectors)?;
        let tol = names.symmetry_tolerance;
        let stiffness = symmetrized(&sector.stiffness, &names.stiffness, tol)?;
        let size = stiffness.nrows();
        check_size(&sector.mass, &names.mass, size, &names.stiffness)?;
        let mass = symmetrized(&sector.mass, &names.mass, tol)?;
        let layout =
            BoundaryLayout::new(size, &sector.left_boundary, &sector.right_boundary, names)?;
        if layout.kept.is_empty() {
            return Err(ModelError::invalid(
                &names.stiffness,
                "a sector needs at least one dof",
            ));
        }
        check_positive_definite(&mass, &names.mass)?;
        let mass_blocks = layout.blocks(&mass);
        let stiffness_blocks = layout.blocks(&stiffness);
        let damping = match damping {
            Damping::None => DampingModel::None,
            Damping::Modal(modal) => {
                check_modal(&modal, &names.damping)?;
                DampingModel::Modal(modal, ModalCache::new(sectors))
            }
            Damping::Rayleigh { alpha, beta } => {
                check_rayleigh(alpha, beta, &names.damping)?;
                DampingModel::Viscous(mass_blocks.combine(alpha, &stiffness_blocks, beta))
            }
            Damping::Matrix { matrix, coupling } => {
                if coupling.is_some() {
                    return Err(ModelError::invalid(
                        &names.damping_coupling,
                        "a finite-element sector takes its coupling from the boundary dofs; give only the damping matrix",
                    ));
                }
                check_size(&matrix, &names.damping_matrix, size, &names.stiffness)?;
                let matrix = symmetrized(&matrix, &names.damping_matrix, tol)?;
                DampingModel::Viscous(layout.blocks(&matrix))
            }
        };
        Ok(Self {
            sectors,
            labels: layout
                .kept
                .iter()
                .map(|&o| format!("dof {}", o + 1))
                .collect(),
            mass: mass_blocks,
            stiffness: stiffness_blocks,
            damping,
        })
    }

    /// Replaces the dof labels (one per independent dof of a sector).
    pub fn with_dof_labels(mut self, labels: Vec<String>) -> Result<Self, ModelError> {
        if labels.len() != self.dofs_per_sector() {
            return Err(ModelError::invalid(
                "dof labels",
                format!(
                    "{} labels given for {} dofs per sector",
                    labels.len(),
                    self.dofs_per_sector()
                ),
            ));
        }
        self.labels = labels;
        Ok(self)
    }

    /// The number of sectors `N`.
    pub fn sectors(&self) -> usize {
        self.sectors
    }

    /// The independent dofs of one sector (finite-element sectors: interior
    /// and left boundary dofs).
    pub fn dofs_per_sector(&self) -> usize {
        self.labels.len()
    }

    /// A readable name of sector dof `dof` (0-based): `m1`… for the academic
    /// model, `dof 17` (1-based original numbering) for imported sectors.
    pub fn dof_label(&self, dof: usize) -> String {
        self.labels
            .get(dof)
            .cloned()
            .unwrap_or_else(|| format!("dof {}", dof + 1))
    }

    /// The dof (0-based) whose label is `label` (e.g. `"m1"`, `"dof 17"`).
    pub fn dof_by_label(&self, label: &str) -> Option<usize> {
        self.labels.iter().position(|l| l == label)
    }

    /// Whether the model is damped.
    pub fn is_damped(&self) -> bool {
        !matches!(self.damping, DampingModel::None)
    }

    /// `M(s)`, `K(s)`, `C(s)` of the signed nodal diameter `s` (any integer,
    /// taken modulo `N`). See [`NodalDiameterMatrices`] for the convention.
    pub fn nodal_diameter_matrices(
        &self,
        nodal_diameter: i64,
    ) -> Result<NodalDiameterMatrices, ModelError> {
        let s = fold(nodal_diameter, self.sectors);
        let mass = self.mass.at(s, self.sectors);
        let stiffness = self.stiffness.at(s, self.sectors);
        let n = self.dofs_per_sector();
        let damping = match &self.damping {
            DampingModel::None => Mat::zeros(n, n),
            DampingModel::Viscous(c) => c.at(s, self.sectors),
            DampingModel::Modal(modal, cache) => {
                let positive = self.cached_modal_damping(s.abs(), modal, cache)?;
                if s < 0 {
                    Mat::from_fn(n, n, |i, j| positive[(i, j)].conj())
                } else {
                    positive.clone()
                }
            }
        };
        Ok(NodalDiameterMatrices {
            mass,
            stiffness,
            damping,
        })
    }

    /// `C(s)` for `0 ≤ s ≤ N/2`, from the cache or computed once.
    fn cached_modal_damping<'a>(
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
    fn fill_modal_cache(&self) -> Result<(), ModelError> {
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

    /// The real full-wheel matrices (dense, at most [`FULL_WHEEL_MAX_DOFS`]
    /// rows). Modal damping is assembled back from the per-diameter `C(s)`,
    /// so that both agree exactly.
    pub fn full_wheel(&self) -> Result<FullWheelMatrices, ModelError> {
        let size = self.sectors * self.dofs_per_sector();
        if size > FULL_WHEEL_MAX_DOFS {
            return Err(ModelError::TooLarge {
                what: "full wheel".into(),
                size,
                limit: FULL_WHEEL_MAX_DOFS,
            });
        }
        let mass = self.mass.assemble(self.sectors);
        let stiffness = self.stiffness.assemble(self.sectors);
        let damping = match &self.damping {
            DampingModel::None => Mat::zeros(size, size),
            DampingModel::Viscous(c) => c.assemble(self.sectors),
            DampingModel::Modal(..) => {
                self.fill_modal_cache()?;
                let half = self.sectors as i64 / 2;
                let distinct = (0..=half)
                    .map(|s| Ok(self.nodal_diameter_matrices(s)?.damping))
                    .collect::<Result<Vec<_>, ModelError>>()?;
                let per_diameter: Vec<Mat<c64>> = (0..self.sectors as i64)
                    .map(|s| {
                        let f = fold(s, self.sectors);
                        if f >= 0 {
                            distinct[f as usize].clone()
                        } else {
                            let c = &distinct[(-f) as usize];
                            Mat::from_fn(c.nrows(), c.ncols(), |i, j| c[(i, j)].conj())
                        }
                    })
                    .collect();
                assemble_from_nodal_diameters(&per_diameter, self.sectors)
            }
        };
        Ok(FullWheelMatrices {
            mass,
            stiffness,
            damping,
        })
    }

    /// Natural frequencies (Hz, ascending) of every unsigned nodal diameter
    /// `0..=N/2`. Diameters `0 < d < N/2` stand for the two waves `±d`
    /// (each frequency is double in the full wheel).
    pub fn natural_frequencies(&self) -> Result<Vec<(usize, Vec<f64>)>, ModelError> {
        (0..=self.sectors / 2)
            .into_par_iter()
            .map(|d| {
                let s = d as i64;
                let values = if s == 0 || 2 * d == self.sectors {
                    let mass = self.mass.at_real(s, self.sectors);
                    let stiffness = self.stiffness.at_real(s, self.sectors);
                    symmetric_modes(&stiffness, &mass, s, false)?.0
                } else {
                    let mass = self.mass.at(s, self.sectors);
                    let stiffness = self.stiffness.at(s, self.sectors);
                    hermitian_modes(&stiffness, &mass, s, false)?.values
                };
                let omegas = angular_frequencies(&values, s)?;
                let hz = omegas
                    .iter()
                    .map(|w| w / (2.0 * std::f64::consts::PI))
                    .collect();
                Ok((d, hz))
            })
            .collect()
    }

    /// The matrices of several signed diameters, computed in parallel.
    pub fn nodal_diameter_matrices_for(
        &self,
        diameters: &[i64],
    ) -> Result<Vec<NodalDiameterMatrices>, ModelError> {
        diameters
            .par_iter()
            .map(|&s| self.nodal_diameter_matrices(s))
            .collect()
    }
}

/// Where the independent dofs of a finite-element sector sit.
struct BoundaryLayout {
    /// Original indices of the independent dofs (all but the right boundary).
    kept: Vec<usize>,
    /// For each original dof: its column among the independent dofs of its
    /// own sector (`Own`) or of the next sector (`Next`, right boundary).
    place: Vec<Place>,
}

#[derive(Clone, Copy)]
enum Place {
    Own(usize),
    Next(usize),
}

impl BoundaryLayout {
    fn new(
        size: usize,
        left: &[usize],
        right: &[usize],
        names: &Names,
    ) -> Result<Self, ModelError> {
        if left.len() != right.len() {
            return Err(ModelError::invalid(
                format!("{} / {}", names.left, names.right),
                format!(
                    "the boundary lists have unequal lengths ({} left dofs, {} right dofs); \
                     they must pair dof by dof",
                    left.len(),
                    right.len()
                ),
            ));
        }
        let mut role = vec![None::<(&str, usize)>; size];
        for (list, key) in [(left, &names.left), (right, &names.right)] {
            for (i, &d) in list.iter().enumerate() {
                if d >= size {
                    return Err(ModelError::invalid(
                        format!("{key}[{}]", i + 1),
                        format!(
                            "dof {} is out of range: the sector matrices have dofs 1..={size}",
                            d + 1
                        ),
                    ));
                }
                if let Some((other, j)) = role[d] {
                    return Err(ModelError::invalid(
                        format!("{key}[{}]", i + 1),
                        format!(
                            "dof {} is already listed at {other}[{}]; a dof may appear once in the boundary lists",
                            d + 1,
                            j + 1
                        ),
                    ));
                }
                role[d] = Some((key.as_str(), i));
            }
        }
        let is_right: Vec<bool> = {
            let mut v = vec![false; size];
            for &d in right {
                v[d] = true;
            }
            v
        };
        let kept: Vec<usize> = (0..size).filter(|&d| !is_right[d]).collect();
        let mut column = vec![usize::MAX; size];
        for (c, &d) in kept.iter().enumerate() {
            column[d] = c;
        }
        let mut place: Vec<Place> = (0..size).map(|d| Place::Own(column[d])).collect();
        for (&l, &r) in left.iter().zip(right) {
            place[r] = Place::Next(column[l]);
        }
        Ok(Self { kept, place })
    }

    /// `A0 = PᵀAP + QᵀAQ`, `A1 = PᵀAQ` where `u_sector = P q_j + Q q_{j+1}`.
    fn blocks(&self, a: &Mat<f64>) -> CirculantBlocks {
        let n = self.kept.len();
        let mut within = Mat::<f64>::zeros(n, n);
        let mut coupling = Mat::<f64>::zeros(n, n);
        let size = a.nrows();
        for j in 0..size {
            for i in 0..size {
                let v = a[(i, j)];
                if v == 0.0 {
                    continue;
                }
                match (self.place[i], self.place[j]) {
                    (Place::Own(p), Place::Own(q)) | (Place::Next(p), Place::Next(q)) => {
                        within[(p, q)] += v
                    }
                    (Place::Own(p), Place::Next(q)) => coupling[(p, q)] += v,
                    (Place::Next(_), Place::Own(_)) => {}
                }
            }
        }
        CirculantBlocks { within, coupling }
    }
}
