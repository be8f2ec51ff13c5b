//! The sector model: one description of a sector, from which come the
//! matrices of every signed nodal diameter and those of the full wheel.

mod boundary;
mod dofs;
mod modal;
mod per_diameter;
mod static_response;

use super::damping::Damping;
use super::eigen::{angular_frequencies, hermitian_modes, symmetric_modes};
use super::input::{SectorInput, Subject};
use super::matrices::{
    assemble_from_nodal_diameters, fold, CirculantBlocks, FullWheelMatrices, NodalDiameterMatrices,
    SectorOperator,
};
use super::validate::{
    check_positive_definite, check_size, symmetrized, DEFAULT_SYMMETRY_TOLERANCE,
};
use super::ModelError;
use boundary::BoundaryLayout;
pub use boundary::{Axis, BoundaryFrame};
use faer::{c64, Mat};
use modal::{check_modal, check_rayleigh, DampingModel, ModalCache};
use rayon::prelude::*;

/// Largest full wheel (`N·dofs_per_sector` rows) that [`SectorModel::full_wheel`]
/// assembles: the full wheel is dense and meant for validating reductions on
/// small models (three matrices of this size take about 0.9 GB).
pub const FULL_WHEEL_MAX_DOFS: usize = 6000;

/// The most sectors a model may have: ten thousand, beyond any bladed
/// wheel; per-diameter storage and per-sector results grow with `N`.
pub const MAX_SECTORS: usize = 10_000;

/// The most dofs a sector may have (rows of its matrices): the sector is
/// stored dense, and a few matrices of this size per nodal diameter
/// (64 MB each, complex) must fit in memory. Larger sectors call for a
/// reduction (Craig–Bampton) before they are given here.
pub const SECTOR_MAX_DOFS: usize = 2_000;

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
/// for the wave of nodal diameter `s`, `u_R = exp(−iαs)·u_L` when the
/// boundary dofs turn with the sector, `u_R = exp(−iαs)·R(α)·u_L` when they
/// are Cartesian ([`BoundaryFrame`]). The independent dofs of a sector are
/// all dofs but the right boundary ones, in their original order.
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
    /// How the boundary dofs are expressed.
    pub boundary_frame: BoundaryFrame,
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
    /// The distance of each dof's node to the rotation axis, m, where the
    /// model knows it (finite-element sectors' retained dofs); empty
    /// otherwise.
    radii: Vec<Option<f64>>,
    /// The node (1-based, as in the coordinates file) of each dof, where
    /// the model knows it (finite-element sectors' retained dofs); empty
    /// otherwise.
    nodes: Vec<Option<usize>>,
    mass: SectorOperator,
    stiffness: SectorOperator,
    damping: DampingModel,
    /// Per-sector blade stiffness deviations (issue 44), added to the full
    /// wheel only: the per-diameter matrices stay the tuned sector's.
    mistuning: Option<std::sync::Arc<super::mistuning::Mistuning>>,
}
/// A whole sector input as an error's subject.
fn input(input: SectorInput) -> Subject {
    Subject::input(input)
}

fn check_sectors(sectors: usize) -> Result<(), ModelError> {
    if sectors == 0 {
        return Err(ModelError::invalid(
            SectorInput::Sectors,
            "0 is not allowed: the number of sectors N must be at least 1",
        ));
    }
    if sectors > MAX_SECTORS {
        return Err(ModelError::invalid(
            SectorInput::Sectors,
            format!("{sectors} is not allowed: at most {MAX_SECTORS} sectors"),
        ));
    }
    Ok(())
}

/// The nodal diameters whose matrices are real: 0, and `N/2` for even `N`.
fn real_diameters(sectors: usize) -> Vec<i64> {
    if sectors.is_multiple_of(2) && sectors > 0 {
        vec![0, sectors as i64 / 2]
    } else {
        vec![0]
    }
}

/// `C(s)` of `blocks` positive semidefinite on the real nodal diameters.
fn check_dissipative(blocks: &SectorOperator, sectors: usize) -> Result<(), ModelError> {
    for s in real_diameters(sectors) {
        let c = blocks.at_real(s, sectors);
        let values =
            c.self_adjoint_eigenvalues(faer::Side::Lower)
                .map_err(|_| ModelError::Eigen {
                    nodal_diameter: s,
                    message: "the symmetric eigenvalue solver did not converge on the damping"
                        .into(),
                })?;
        let largest = values.iter().fold(0.0_f64, |m, v| m.max(v.abs()));
        let lowest = values.iter().cloned().fold(f64::INFINITY, f64::min);
        if lowest < -1e-9 * largest {
            return Err(ModelError::invalid(
                SectorInput::DampingMatrix,
                format!(
                    "the damping is not positive semidefinite: nodal diameter {s} has the \
                     eigenvalue {lowest:e}; a damping matrix must dissipate energy"
                ),
            ));
        }
    }
    Ok(())
}

/// At most [`SECTOR_MAX_DOFS`] rows in the sector matrix `input`.
pub(crate) fn check_sector_dofs(rows: usize, input: impl Into<Subject>) -> Result<(), ModelError> {
    if rows > SECTOR_MAX_DOFS {
        return Err(ModelError::invalid(
            input,
            format!(
                "{rows} dofs is too many: a sector is stored dense and may have at most \
                 {SECTOR_MAX_DOFS} dofs (reduce the model first)"
            ),
        ));
    }
    Ok(())
}
fn coupling_or_zero(
    coupling: Option<Mat<f64>>,
    n: usize,
    what: SectorInput,
) -> Result<Mat<f64>, ModelError> {
    match coupling {
        Some(c) => {
            check_size(&c, &input(what), n, &input(SectorInput::Stiffness))?;
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
        Self::block_circulant_with_tolerance(sectors, sector, damping, DEFAULT_SYMMETRY_TOLERANCE)
    }

    /// A finite-element sector with left/right cyclic boundary dofs,
    /// `sectors` sectors, with `damping` (a damping matrix is then a full
    /// sector matrix like the stiffness).
    pub fn finite_element(
        sectors: usize,
        sector: FiniteElementSector,
        damping: Damping,
    ) -> Result<Self, ModelError> {
        Self::finite_element_with_tolerance(sectors, sector, damping, DEFAULT_SYMMETRY_TOLERANCE)
    }

    /// [`SectorModel::block_circulant`] with the relative tolerance `tol` on the
    /// symmetry of the matrices (instead of [`DEFAULT_SYMMETRY_TOLERANCE`]).
    pub fn block_circulant_with_tolerance(
        sectors: usize,
        sector: BlockCirculantSector,
        damping: Damping,
        tol: f64,
    ) -> Result<Self, ModelError> {
        check_sectors(sectors)?;
        check_sector_dofs(sector.stiffness.nrows(), SectorInput::Stiffness)?;
        let stiffness = symmetrized(&sector.stiffness, &input(SectorInput::Stiffness), tol)?;
        let n = stiffness.nrows();
        if n == 0 {
            return Err(ModelError::invalid(
                SectorInput::Stiffness,
                "a sector needs at least one dof",
            ));
        }
        check_size(
            &sector.mass,
            &input(SectorInput::Mass),
            n,
            &input(SectorInput::Stiffness),
        )?;
        let mass = symmetrized(&sector.mass, &input(SectorInput::Mass), tol)?;
        let mass = CirculantBlocks {
            within: mass,
            coupling: coupling_or_zero(sector.mass_coupling, n, SectorInput::MassCoupling)?,
        };
        let stiffness = CirculantBlocks {
            within: stiffness,
            coupling: coupling_or_zero(
                sector.stiffness_coupling,
                n,
                SectorInput::StiffnessCoupling,
            )?,
        };
        // M(s) must be positive definite for every diameter; without a mass
        // coupling M(s) = M0 for all s.
        if mass.has_coupling() {
            for s in 0..=(sectors as i64 / 2) {
                if mass.at(s, sectors).llt(faer::Side::Lower).is_err() {
                    return Err(ModelError::MassNotPositiveDefinite {
                        what: input(SectorInput::Mass),
                        nodal_diameter: Some(s),
                    });
                }
            }
        } else {
            check_positive_definite(&mass.within, &input(SectorInput::Mass))?;
        }
        let damping = match damping {
            Damping::None => DampingModel::None,
            Damping::Modal(modal) => {
                check_modal(&modal)?;
                DampingModel::Modal(modal, ModalCache::new(sectors))
            }
            Damping::Rayleigh { alpha, beta } => {
                check_rayleigh(alpha, beta)?;
                DampingModel::Viscous(SectorOperator::Circulant(
                    mass.combine(alpha, &stiffness, beta),
                ))
            }
            Damping::Matrix { matrix, coupling } => {
                check_size(
                    &matrix,
                    &input(SectorInput::DampingMatrix),
                    n,
                    &input(SectorInput::Stiffness),
                )?;
                let within = symmetrized(&matrix, &input(SectorInput::DampingMatrix), tol)?;
                let coupling = coupling_or_zero(coupling, n, SectorInput::DampingCoupling)?;
                DampingModel::Viscous(SectorOperator::Circulant(CirculantBlocks {
                    within,
                    coupling,
                }))
            }
        };
        Ok(Self {
            sectors,
            labels: (1..=n).map(|d| format!("dof {d}")).collect(),
            radii: Vec::new(),
            nodes: Vec::new(),
            mass: SectorOperator::Circulant(mass),
            stiffness: SectorOperator::Circulant(stiffness),
            damping,
            mistuning: None,
        })
    }

    /// [`SectorModel::finite_element`] with the relative tolerance `tol` on the
    /// symmetry of the matrices (instead of [`DEFAULT_SYMMETRY_TOLERANCE`]).
    pub fn finite_element_with_tolerance(
        sectors: usize,
        sector: FiniteElementSector,
        damping: Damping,
        tol: f64,
    ) -> Result<Self, ModelError> {
        check_sectors(sectors)?;
        check_sector_dofs(sector.stiffness.nrows(), SectorInput::Stiffness)?;
        let stiffness = symmetrized(&sector.stiffness, &input(SectorInput::Stiffness), tol)?;
        let size = stiffness.nrows();
        check_size(
            &sector.mass,
            &input(SectorInput::Mass),
            size,
            &input(SectorInput::Stiffness),
        )?;
        let mass = symmetrized(&sector.mass, &input(SectorInput::Mass), tol)?;
        let rotation = match sector.boundary_frame {
            BoundaryFrame::Cylindrical => None,
            BoundaryFrame::Cartesian { axis } => {
                Some(axis.rotation(2.0 * std::f64::consts::PI / sectors as f64))
            }
        };
        let layout = BoundaryLayout::new(
            size,
            &sector.left_boundary,
            &sector.right_boundary,
            rotation,
        )?;
        if layout.kept.is_empty() {
            return Err(ModelError::invalid(
                SectorInput::Stiffness,
                "a sector needs at least one dof",
            ));
        }
        check_positive_definite(&mass, &input(SectorInput::Mass))?;
        let mass_blocks = layout.blocks(&mass);
        let stiffness_blocks = layout.blocks(&stiffness);
        let damping = match damping {
            Damping::None => DampingModel::None,
            Damping::Modal(modal) => {
                check_modal(&modal)?;
                DampingModel::Modal(modal, ModalCache::new(sectors))
            }
            Damping::Rayleigh { alpha, beta } => {
                check_rayleigh(alpha, beta)?;
                DampingModel::Viscous(SectorOperator::Circulant(mass_blocks.combine(
                    alpha,
                    &stiffness_blocks,
                    beta,
                )))
            }
            Damping::Matrix { matrix, coupling } => {
                if coupling.is_some() {
                    return Err(ModelError::invalid(
                        SectorInput::DampingCoupling,
                        "a finite-element sector takes its coupling from the boundary dofs; give only the damping matrix",
                    ));
                }
                check_size(
                    &matrix,
                    &input(SectorInput::DampingMatrix),
                    size,
                    &input(SectorInput::Stiffness),
                )?;
                let matrix = symmetrized(&matrix, &input(SectorInput::DampingMatrix), tol)?;
                DampingModel::Viscous(SectorOperator::Circulant(layout.blocks(&matrix)))
            }
        };
        Ok(Self {
            sectors,
            radii: Vec::new(),
            nodes: Vec::new(),
            labels: layout
                .kept
                .iter()
                .map(|&o| format!("dof {}", o + 1))
                .collect(),
            mass: SectorOperator::Circulant(mass_blocks),
            stiffness: SectorOperator::Circulant(stiffness_blocks),
            damping,
            mistuning: None,
        })
    }

    /// Checks that the wheel holds at rest: the stiffness of the real
    /// nodal diameters (0, and `N/2` for even `N`) is positive definite
    /// with respect to the mass. A zero eigenvalue is a motion without
    /// strain energy, a rigid-body motion of a wheel that is not grounded,
    /// and makes the static harmonic singular; a negative one is an
    /// indefinite stiffness. The error names the stiffness
    /// ([`SectorInput::Stiffness`]).
    pub fn check_stiffness_at_rest(&self) -> Result<(), ModelError> {
        for s in real_diameters(self.sectors) {
            let mass = self.mass.at_real(s, self.sectors);
            let stiffness = self.stiffness.at_real(s, self.sectors);
            let (values, _) = symmetric_modes(&stiffness, &mass, s, false)?;
            let largest = values.iter().fold(0.0_f64, |m, v| m.max(v.abs()));
            let lowest = values.iter().cloned().fold(f64::INFINITY, f64::min);
            let problem = if lowest < -1e-9 * largest {
                format!(
                    "is not positive semidefinite: nodal diameter {s} has the eigenvalue \
                     {lowest:e} (rad/s)²"
                )
            } else if lowest <= 1e-10 * largest || largest == 0.0 {
                format!(
                    "is singular at nodal diameter {s}: a motion without strain energy \
                     (a rigid-body motion: the wheel is not grounded, or a dof has no spring); \
                     the static response is undefined"
                )
            } else {
                continue;
            };
            return Err(ModelError::invalid(
                SectorInput::Stiffness,
                format!("the stiffness {problem}"),
            ));
        }
        Ok(())
    }

    /// Checks that a viscous damping (a given matrix, or Rayleigh's)
    /// dissipates energy: `C(s)` positive semidefinite on the real nodal
    /// diameters (0, and `N/2` for even `N`), as negative modal ratios and
    /// Rayleigh factors are refused. The error names the damping matrix
    /// ([`SectorInput::DampingMatrix`]). The constructors leave it to the
    /// caller: a model of any damping can be built (to test conventions).
    pub fn check_damping_dissipates(&self) -> Result<(), ModelError> {
        match &self.damping {
            DampingModel::Viscous(blocks) => check_dissipative(blocks, self.sectors),
            _ => Ok(()),
        }
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

    /// The real full-wheel matrices (dense, at most [`FULL_WHEEL_MAX_DOFS`]
    /// rows). Modal damping is assembled back from the per-diameter `C(s)`,
    /// so that both agree exactly. A mistuned wheel's stiffness holds each
    /// sector's blade deviation ([`Self::with_mistuning`]).
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
        let mut stiffness = self.stiffness.assemble(self.sectors);
        if let Some(mistuning) = &self.mistuning {
            super::mistuning::add_blade_perturbation(&mut stiffness, mistuning);
        }
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
