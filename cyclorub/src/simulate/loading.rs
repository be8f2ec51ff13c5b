//! What acts on the full wheel at each instant: the case's excitation on
//! every sector, and the casing's gap at every contact dof.
//!
//! Both are functions of the phase `θ` of the excitation (`θ = ωt` at a
//! fixed frequency, `θ = ∫ω dt` during a sweep): the excitation of sector
//! `j` (from 0) is `f_j(θ) = f_0 + 2 Re(X_j e^{iθ})` with
//! `X_j = f_ex Σ_s c_s e^{−isαj}` from the pattern's pairs (Eqs. 48, 75,
//! 86; the same coefficients as the harmonic balance's load), and the casing
//! rotates synchronously (Ω = ω), Eq. (74). With sliding friction (Eqs.
//! 83–84) each contact dof also has its friction node's tangential dofs.

use crate::contact::{Casing, SlidingFriction};
use crate::hbm::Forcing;
use faer::c64;

use super::SimulateError;

/// The loads of the full wheel: excitation, casing and contact dofs.
#[derive(Clone, Debug)]
pub struct WheelLoads {
    sectors: usize,
    dofs: usize,
    /// `X_j` per sector, with the excited dofs and the static force.
    excitation: Option<(Vec<c64>, Vec<usize>, f64)>,
    contact_dofs: Vec<usize>,
    casing: Casing,
    /// A static force on every dof of each sector (the preload), N.
    preload: Option<Vec<f64>>,
    /// Sliding friction at the contact dofs.
    friction: Option<SlidingFriction>,
}

impl WheelLoads {
    /// The loads of a wheel of `sectors` sectors with `dofs` dofs each:
    /// `forcing` (if any), the casing and the contact dofs (0-based).
    pub fn new(
        sectors: usize,
        dofs: usize,
        forcing: Option<&Forcing>,
        casing: Casing,
        contact_dofs: &[usize],
    ) -> Result<Self, SimulateError> {
        let out_of_range = |key: &'static str, list: &[usize]| {
            list.iter()
                .find(|&&d| d >= dofs)
                .map(|&d| SimulateError::DofOutOfRange {
                    key,
                    dof: d + 1,
                    dofs,
                })
        };
        if let Some(e) = out_of_range("contact.dofs", contact_dofs) {
            return Err(e);
        }
        if contact_dofs.is_empty() {
            return Err(SimulateError::Input(
                "contact.dofs is empty: at least one contact dof is needed".into(),
            ));
        }
        if !casing.fits(contact_dofs.len()) {
            return Err(SimulateError::Input(format!(
                "casing: {} gaps and {} amplitudes for {} contact dofs (give one value, or one per contact dof)",
                casing.gaps.len(),
                casing.amplitudes.len(),
                contact_dofs.len()
            )));
        }
        let excitation = match forcing {
            None => None,
            Some(f) => {
                if let Some(e) = out_of_range("excitation.dofs", &f.dofs) {
                    return Err(e);
                }
                f.pattern
                    .validate(sectors)
                    .map_err(|e| SimulateError::Input(format!("excitation: {e}")))?;
                let pairs = f.pattern.pair_coefficients(sectors);
                let alpha = 2.0 * std::f64::consts::PI / sectors as f64;
                let per_sector = (0..sectors)
                    .map(|j| {
                        pairs
                            .iter()
                            .map(|(p, (re, im))| {
                                c64::new(*re, *im)
                                    * f.amplitude
                                    * c64::cis(-(p.nodal_diameter as f64) * alpha * j as f64)
                            })
                            .sum()
                    })
                    .collect();
                Some((per_sector, f.dofs.clone(), f.static_force))
            }
        };
        Ok(Self {
            sectors,
            dofs,
            excitation,
            contact_dofs: contact_dofs.to_vec(),
            casing,
            preload: None,
            friction: None,
        })
    }

    /// Adds sliding friction at the contact dofs: one friction node per
    /// contact dof (its circumferential and axial dofs, 0-based, and its
    /// radius), the coefficient and the rotation. Each tangential dof must
    /// be in range and distinct from every contact and tangential dof, as
    /// the harmonic balance requires.
    pub fn with_friction(mut self, friction: SlidingFriction) -> Result<Self, SimulateError> {
        let nodes = friction.nodes();
        if nodes.len() != self.contact_dofs.len() {
            return Err(SimulateError::Input(format!(
                "friction: {} friction nodes for {} contact dofs; give one node (circumferential \
                 and axial dofs) per contact dof",
                nodes.len(),
                self.contact_dofs.len()
            )));
        }
        let mut used = self.contact_dofs.clone();
        for node in nodes {
            for (key, dof) in [
                ("contact.circumferential_dofs", node.circumferential),
                ("contact.axial_dofs", node.axial),
            ] {
                if dof >= self.dofs {
                    return Err(SimulateError::DofOutOfRange {
                        key,
                        dof: dof + 1,
                        dofs: self.dofs,
                    });
                }
                if used.contains(&dof) {
                    return Err(SimulateError::Input(format!(
                        "{key}: dof {} is already a contact or tangential dof; each friction \
                         node needs its own circumferential and axial dofs",
                        dof + 1
                    )));
                }
                used.push(dof);
            }
        }
        self.friction = Some(friction);
        Ok(self)
    }

    /// The sliding friction, if any.
    pub fn friction(&self) -> Option<&SlidingFriction> {
        self.friction.as_ref()
    }

    /// The full-wheel indices of the circumferential and axial dofs of the
    /// friction node of contact dof `contact` of `sector` (`None` without
    /// friction).
    pub fn friction_indices(&self, sector: usize, contact: usize) -> Option<[usize; 2]> {
        let node = self.friction.as_ref()?.nodes()[contact];
        let base = sector * self.dofs;
        Some([base + node.circumferential, base + node.axial])
    }

    /// Adds a static force on every dof of each sector (N, one per sector
    /// dof): the preload, applied alike on every sector at every instant.
    pub fn with_preload(mut self, forces: Vec<f64>) -> Result<Self, SimulateError> {
        if forces.len() != self.dofs || forces.iter().any(|f| !f.is_finite()) {
            return Err(SimulateError::Input(format!(
                "preload: {} forces for a sector of {} dofs; give one finite force (N) per dof",
                forces.len(),
                self.dofs
            )));
        }
        self.preload = Some(forces);
        Ok(self)
    }

    /// The contact dofs of a sector (0-based).
    pub fn contact_dofs(&self) -> &[usize] {
        &self.contact_dofs
    }

    /// The casing.
    pub fn casing(&self) -> &Casing {
        &self.casing
    }

    /// The index in a full-wheel vector of contact dof `contact` of
    /// `sector` (contact unknowns are sector-major: `sector · n_c + contact`).
    pub fn contact_index(&self, sector: usize, contact: usize) -> usize {
        sector * self.dofs + self.contact_dofs[contact]
    }

    /// The number of contact unknowns `N n_c`.
    pub fn contact_count(&self) -> usize {
        self.sectors * self.contact_dofs.len()
    }

    /// Writes the excitation at phase `θ` into `force` (`N n` long).
    pub fn force_at(&self, phase: f64, force: &mut [f64]) {
        force.iter_mut().for_each(|f| *f = 0.0);
        if let Some((per_sector, dofs, static_force)) = &self.excitation {
            let rotation = c64::cis(phase);
            for (j, x) in per_sector.iter().enumerate() {
                let value = static_force + 2.0 * (x * rotation).re;
                for &d in dofs {
                    force[j * self.dofs + d] += value;
                }
            }
        }
        if let Some(preload) = &self.preload {
            for sector in force.chunks_exact_mut(self.dofs) {
                for (f, p) in sector.iter_mut().zip(preload) {
                    *f += p;
                }
            }
        }
    }

    /// Writes the casing's gap at phase `θ` of every contact unknown
    /// (sector-major) into `gaps`.
    pub fn gaps_at(&self, phase: f64, gaps: &mut [f64]) {
        let contacts = self.contact_dofs.len();
        for j in 0..self.sectors {
            for c in 0..contacts {
                gaps[j * contacts + c] = self.casing.gap_at(self.sectors, j, c, phase);
            }
        }
    }
}
