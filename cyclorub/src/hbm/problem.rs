//! Builds a harmonic balance problem from a sector model, a formulation
//! (a cyclic basis or the physical full wheel), the loads, the casing and
//! the contact law.

use super::layout::Layout;
use super::linear::LinearPart;
use super::residual::HarmonicBalance;
use super::HbmError;
use crate::basis::SpectralBasis;
pub use crate::contact::Casing;
use crate::contact::{ContactModel, SlidingFriction};
use crate::cyclic::{ExcitationPattern, HarmonicSet, LoadCase, SignedPair};
use crate::model::SectorModel;

mod blocks;

/// The first-harmonic excitation and the static preload, on sector dofs.
#[derive(Clone, Debug, PartialEq)]
pub struct Forcing {
    /// Spatial pattern (unit amplitude).
    pub pattern: ExcitationPattern,
    /// Amplitude `f_ex`, N.
    pub amplitude: f64,
    /// Sector dofs (0-based) where it acts, with the same force on each.
    pub dofs: Vec<usize>,
    /// Static force on the same dofs of every sector (harmonic 0), N.
    pub static_force: f64,
}

/// From this many unknowns the physical full wheel keeps its Jacobian
/// structured (GMRES preconditioned in the wave's frame) instead of dense:
/// on the open fan (9072) a dense LU costs 10 s, the structured solve well
/// under one.
pub const STRUCTURED_UNKNOWNS: usize = 2000;

/// Cyclic coordinates on a basis, or the full wheel in physical coordinates.
#[derive(Clone, Debug)]
pub enum Formulation {
    /// Pairs of a spectral basis, in cyclic coordinates.
    Cyclic(SpectralBasis),
    /// All sectors assembled, no cyclic transform (the reference).
    Physical,
}

/// Everything a harmonic balance problem is built from.
#[derive(Clone, Debug)]
pub struct ProblemSpec<'a> {
    /// The sector model.
    pub model: &'a SectorModel,
    /// Contact dofs of a sector (0-based), normal toward the casing.
    pub contact_dofs: &'a [usize],
    /// The excitation, if any.
    pub forcing: Option<&'a Forcing>,
    /// The casing.
    pub casing: &'a Casing,
    /// The contact treatment.
    pub contact: ContactModel,
    /// Sliding friction at the contact dofs (one friction node per contact
    /// dof), if any.
    pub friction: Option<&'a SlidingFriction>,
    /// A static force on every dof of a sector (N, the same on every
    /// sector: nodal diameter 0, harmonic 0), if any: the preload.
    pub preload: Option<&'a [f64]>,
    /// `N_h`.
    pub harmonics: usize,
    /// `N_t`.
    pub time_samples: usize,
}

/// The most memory the dense storage of a problem may take, bytes (4 GB):
/// the matrices of the unknowns (`Z`, `∂Z/∂ω`, the Jacobian and its
/// factorization), the sector maps, the per-pair sector matrices and the
/// time samples of the AFT, estimated before any of them is allocated.
pub const MEMORY_LIMIT_BYTES: usize = 4_000_000_000;

impl ProblemSpec<'_> {
    /// The loads as pairs, for choosing or checking a basis.
    pub fn load_case(&self) -> LoadCase {
        LoadCase {
            sectors: self.model.sectors(),
            excitation: self.forcing.map(|f| f.pattern.clone()),
            casing_order: (self.casing.order > 0
                && self.casing.amplitudes.iter().any(|&p| p != 0.0))
            .then_some(self.casing.order),
        }
    }

    fn validate(&self) -> Result<(), HbmError> {
        let dofs = self.model.dofs_per_sector();
        let check = |key: &'static str, list: &[usize]| {
            if let Some(&bad) = list.iter().find(|&&d| d >= dofs) {
                return Err(HbmError::DofOutOfRange {
                    key,
                    dof: bad,
                    dofs,
                });
            }
            Ok(())
        };
        check("contact.dofs", self.contact_dofs)?;
        if let Some(forcing) = self.forcing {
            check("excitation.dofs", &forcing.dofs)?;
            forcing
                .pattern
                .validate(self.model.sectors())
                .map_err(HbmError::Load)?;
        }
        if self.contact_dofs.is_empty() {
            return Err(HbmError::NoContactDofs);
        }
        let mut sorted = self.contact_dofs.to_vec();
        sorted.sort_unstable();
        sorted.dedup();
        if sorted.len() != self.contact_dofs.len() {
            return Err(HbmError::RepeatedContactDof);
        }
        if self.casing.gaps.len() != self.contact_dofs.len()
            || self.casing.amplitudes.len() != self.contact_dofs.len()
        {
            return Err(HbmError::CasingLength {
                gaps: self.casing.gaps.len(),
                amplitudes: self.casing.amplitudes.len(),
                contact_dofs: self.contact_dofs.len(),
            });
        }
        if let Some(preload) = self.preload {
            if preload.len() != dofs || preload.iter().any(|v| !v.is_finite()) {
                return Err(HbmError::InvalidPreload {
                    values: preload.len(),
                    dofs,
                });
            }
        }
        if let Some(friction) = self.friction {
            self.validate_friction(friction)?;
        }
        if self.time_samples < HarmonicSet::up_to(self.harmonics).min_time_samples() {
            return Err(HbmError::TooFewTimeSamples {
                time_samples: self.time_samples,
                harmonics: self.harmonics,
            });
        }
        Ok(())
    }

    /// One friction node per contact dof, its tangential dofs in range and
    /// distinct from every other contact or tangential dof; no wall (its
    /// spring would also hold the tangential dofs).
    fn validate_friction(&self, friction: &SlidingFriction) -> Result<(), HbmError> {
        let invalid = |key, message: String| Err(HbmError::InvalidFriction { key, message });
        if friction.nodes().len() != self.contact_dofs.len() {
            return invalid(
                "contact.circumferential_dofs",
                format!(
                    "{} friction nodes for {} contact dofs: give one circumferential and one \
                     axial dof per contact dof",
                    friction.nodes().len(),
                    self.contact_dofs.len()
                ),
            );
        }
        let dofs = self.model.dofs_per_sector();
        let mut used: Vec<usize> = self.contact_dofs.to_vec();
        for node in friction.nodes() {
            for (key, dof) in [
                ("contact.circumferential_dofs", node.circumferential),
                ("contact.axial_dofs", node.axial),
            ] {
                if dof >= dofs {
                    return Err(HbmError::DofOutOfRange { key, dof, dofs });
                }
                if used.contains(&dof) {
                    return invalid(
                        key,
                        format!(
                            "dof {} is already a contact or tangential dof: each friction node \
                             needs its own circumferential and axial dofs",
                            dof + 1
                        ),
                    );
                }
                used.push(dof);
            }
        }
        if self.contact.law().wall_stiffness().is_some() {
            return invalid(
                "contact.wall_stiffness",
                "a flexible wall is not available with friction: leave wall_stiffness out \
                 (a rigid casing)"
                    .to_string(),
            );
        }
        Ok(())
    }

    /// The sector dofs the problem is condensed on: the contact dofs and,
    /// with friction, each node's circumferential and axial dofs after them.
    pub fn condensed_dofs(&self) -> Vec<usize> {
        let mut dofs = self.contact_dofs.to_vec();
        if let Some(friction) = self.friction {
            for node in friction.nodes() {
                dofs.extend([node.circumferential, node.axial]);
            }
        }
        dofs
    }

    /// Estimates the dense storage of the problem on `formulation` and
    /// refuses it beyond [`MEMORY_LIMIT_BYTES`] or the memory this process
    /// may still take ([`crate::memory::Budget`]), before anything is
    /// allocated, naming the key that weighs most.
    fn check_memory(&self, formulation: &Formulation) -> Result<(), HbmError> {
        let (parts, unknowns, sampled) = self.memory_parts(formulation);
        let rows = match formulation {
            Formulation::Cyclic(_) => self.model.dofs_per_sector(),
            Formulation::Physical => self.model.sectors() * self.model.dofs_per_sector(),
        };
        let budget = crate::memory::Budget::of_this_process((unknowns as usize).max(rows));
        let (limit, source) = if budget.bytes < MEMORY_LIMIT_BYTES as f64 {
            (budget.bytes, budget.source)
        } else {
            (
                MEMORY_LIMIT_BYTES as f64,
                format!(
                    "the {} GB a problem may hold (dense storage)",
                    MEMORY_LIMIT_BYTES as f64 / 1e9
                ),
            )
        };
        let total: f64 = parts.iter().map(|(_, bytes, _)| bytes).sum();
        if total > limit {
            let (what, _, key) =
                parts
                    .iter()
                    .cloned()
                    .fold(("", 0.0, ""), |a, b| if b.1 > a.1 { b } else { a });
            let value = match key {
                "harmonic_balance.time_samples" => self.time_samples,
                "model.sectors" => self.model.sectors(),
                _ => self.harmonics,
            };
            return Err(HbmError::TooLarge {
                key,
                value,
                what: format!(
                    "{what} ({unknowns} unknowns, {sampled} sampled sectors, {} time samples)",
                    self.time_samples
                ),
                gigabytes: total / 1e9,
                limit: source,
            });
        }
        Ok(())
    }

    /// The parts of the problem's dense storage on `formulation`: what,
    /// bytes and the key that sizes it most; with the unknowns and the
    /// sampled sectors.
    fn memory_parts(
        &self,
        formulation: &Formulation,
    ) -> (Vec<(&'static str, f64, &'static str)>, f64, f64) {
        let nc = self.condensed_dofs().len() as f64;
        let n = self.model.dofs_per_sector() as f64;
        let nt = self.time_samples as f64;
        let sectors = self.model.sectors() as f64;
        // Pairs per harmonic (the physical formulation: every sector).
        let pairs: Vec<f64> = match formulation {
            Formulation::Cyclic(basis) => basis
                .harmonic_set()
                .iter()
                .map(|k| basis.nodal_diameters(k).len() as f64)
                .collect(),
            Formulation::Physical => vec![sectors; HarmonicSet::up_to(self.harmonics).count()],
        };
        let unknowns = nc * pairs.iter().map(|p| 2.0 * p).sum::<f64>();
        let sampled = pairs.iter().cloned().fold(0.0, f64::max);
        let time_samples = "harmonic_balance.time_samples";
        // What sizes the unknowns: the harmonics, or on the full wheel the sectors.
        let harmonics = match formulation {
            Formulation::Cyclic(_) => "harmonic_balance.harmonics",
            Formulation::Physical => "model.sectors",
        };
        let block_matrices = match formulation {
            // M, K, C and the dynamic stiffness per pair, complex.
            Formulation::Cyclic(_) => (
                "the sector matrices of every pair",
                pairs.iter().sum::<f64>() * 4.0 * n * n * 16.0,
                harmonics,
            ),
            // The full wheel's M, K, C, real and their complex copies,
            // shared by every block.
            Formulation::Physical => (
                "the full wheel's matrices",
                3.0 * (sectors * n).powi(2) * (8.0 + 16.0),
                "model.sectors",
            ),
        };
        let parts = vec![
            // Z, ∂Z/∂ω, the Jacobian, its LU and a copy.
            (
                "the matrices of the unknowns",
                5.0 * unknowns * unknowns * 8.0,
                harmonics,
            ),
            // A map and its inverse per harmonic, complex.
            (
                "the sector maps",
                pairs.iter().map(|p| 2.0 * p * p * 16.0).sum::<f64>(),
                harmonics,
            ),
            block_matrices,
            // Samples, forces, derivatives and buffers per sampled sector,
            // the AFT's buffers and FFT plan.
            (
                "the time samples",
                6.0 * sampled * nc * nt * 8.0
                    + 6.0 * nt * 8.0
                    + crate::memory::fft_bytes(self.time_samples),
                time_samples,
            ),
        ];
        (parts, unknowns, sampled)
    }

    /// Builds the residual for `formulation`.
    pub fn build(&self, formulation: &Formulation) -> Result<HarmonicBalance, HbmError> {
        self.validate()?;
        self.check_memory(formulation)?;
        let n = self.model.sectors();
        let (layout, blocks) = match formulation {
            Formulation::Cyclic(basis) => {
                // docs/design.md §12: a mistuned wheel is not block-circulant.
                if self.model.is_mistuned() {
                    return Err(HbmError::MistunedReducedBasis {
                        kind: basis_name(basis.kind()).to_string(),
                    });
                }
                if basis.sectors() != n || basis.harmonics() != self.harmonics {
                    return Err(HbmError::BasisMismatch {
                        basis_sectors: basis.sectors(),
                        basis_harmonics: basis.harmonics(),
                        sectors: n,
                        harmonics: self.harmonics,
                    });
                }
                self.check_basis_holds_loads(basis)?;
                let layout =
                    Layout::cyclic(basis, self.condensed_dofs().len()).map_err(HbmError::Basis)?;
                let blocks = self.cyclic_blocks(&layout)?;
                (layout, blocks)
            }
            Formulation::Physical => {
                let layout = Layout::physical(n, self.harmonics, self.condensed_dofs().len());
                let blocks = self.physical_blocks(&layout)?;
                (layout, blocks)
            }
        };
        let law = self.contact.law();
        let linear = LinearPart::new(&layout, blocks).with_wall_stiffness(law.wall_stiffness());
        let mut force_scale = self
            .forcing
            .map_or(0.0, |f| f.amplitude.abs().max(f.static_force.abs()));
        if force_scale == 0.0 {
            force_scale = self.casing_force_scale()?;
        }
        if matches!(formulation, Formulation::Physical) {
            // Sector coordinates carry √N times the norm of pair coordinates.
            force_scale *= (n as f64).sqrt();
        }
        let problem = HarmonicBalance::new(
            layout,
            linear,
            law,
            self.casing.clone(),
            self.friction,
            self.time_samples,
            force_scale.max(f64::MIN_POSITIVE),
        );
        let unknowns = problem.layout().unknowns;
        Ok(match formulation {
            Formulation::Physical if unknowns >= STRUCTURED_UNKNOWNS => {
                problem.with_structured_jacobian(self.engine_order())
            }
            _ => problem,
        })
    }

    /// The nodal diameter of the load's largest pair on the first harmonic
    /// (the engine order of a traveling wave; 0 without a load).
    fn engine_order(&self) -> i64 {
        self.excitation_coefficients()
            .into_iter()
            .filter(|(pair, _)| pair.harmonic == 1)
            .max_by(|a, b| a.1.norm().total_cmp(&b.1.norm()))
            .map_or(0, |(pair, _)| pair.nodal_diameter)
    }

    /// The force scale of a casing-driven problem (no excitation): the
    /// static force that moves a contact dof by the casing's largest
    /// amplitude (or, for a circular casing, its largest gap), from the
    /// largest direct stiffness of the contact dofs in nodal diameter 0.
    fn casing_force_scale(&self) -> Result<f64, HbmError> {
        let largest = |values: &[f64]| values.iter().fold(0.0_f64, |m, v| m.max(v.abs()));
        let length = match largest(&self.casing.amplitudes) {
            p if p > 0.0 => p,
            _ => largest(&self.casing.gaps),
        };
        let stiffness = self
            .model
            .nodal_diameter_matrices(0)
            .map_err(HbmError::Model)?
            .stiffness;
        let direct = self
            .contact_dofs
            .iter()
            .fold(0.0_f64, |m, &d| m.max(stiffness[(d, d)].re.abs()));
        Ok(direct * length)
    }

    /// Every pair the loads generate (the symmetry rule) must be in the
    /// basis, or the reduced problem is not the full one restricted.
    fn check_basis_holds_loads(&self, basis: &SpectralBasis) -> Result<(), HbmError> {
        let required =
            SpectralBasis::symmetry(&self.load_case(), self.harmonics).map_err(HbmError::Basis)?;
        for k in required.harmonic_set() {
            for &s in required.nodal_diameters(k) {
                if !basis.nodal_diameters(k).contains(&s) {
                    return Err(HbmError::BasisMissesPair {
                        pair: SignedPair {
                            nodal_diameter: s,
                            harmonic: k as i64,
                        },
                        kind: format!("{:?}", basis.kind()),
                    });
                }
            }
        }
        Ok(())
    }
}

/// A basis kind as a case file names it (`basis.kind`).
fn basis_name(kind: crate::basis::BasisKind) -> &'static str {
    use crate::basis::BasisKind;
    match kind {
        BasisKind::Full => "full",
        BasisKind::NodalDiameter => "nodal_diameter",
        BasisKind::TravelingWave => "traveling_wave",
        BasisKind::Paper => "paper",
        BasisKind::Symmetry => "symmetry",
        BasisKind::Explicit => "explicit",
    }
}
