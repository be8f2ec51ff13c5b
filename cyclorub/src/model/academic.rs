//! Lumped sectors (masses and springs) and the paper's academic model
//! (Sec. 4.1, Table 1).
//!
//! The topology of the academic model is our reading of the paper's missing
//! Fig. 3 (docs/design.md §4), kept here and only here:
//! in each sector `m1–k1–m2–k2–m3–k3–m4`, `m4–k4–ground`, `m4–k5–m5`, and
//! `m5ʲ–k5–m4ʲ⁺¹` to the next sector. Contact and excitation act on `m1`.

use super::damping::Damping;
use super::sector::{BlockCirculantSector, SectorModel};
use super::ModelError;
use faer::Mat;

/// Masses of Table 1 (kg): `m1..m5`.
pub const ACADEMIC_MASSES: [f64; 5] = [0.2, 0.3, 0.4, 1.2, 1.2];

/// Stiffnesses of Table 1 (N/m): `k1..k5`.
pub const ACADEMIC_STIFFNESSES: [f64; 5] = [2e6, 1e6, 40e6, 0.6e6, 50e6];

/// The dof of the academic model where contact and excitation act (`m1`, 0-based).
pub const ACADEMIC_CONTACT_DOF: usize = 0;

/// What a spring connects (0-based dofs of a sector).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum SpringLink {
    /// Dof `.0` to dof `.1` of the same sector.
    Within(usize, usize),
    /// Dof `.0` of sector `j` to dof `.1` of sector `j+1`.
    NextSector(usize, usize),
    /// Dof `.0` to the ground.
    Ground(usize),
}

/// A linear spring of a lumped sector.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Spring {
    /// What it connects.
    pub link: SpringLink,
    /// Its stiffness (N/m).
    pub stiffness: f64,
}

/// A lumped sector: one mass per dof and a list of springs.
#[derive(Clone, Debug, PartialEq)]
pub struct LumpedSector {
    /// Mass of each dof (kg).
    pub masses: Vec<f64>,
    /// The springs.
    pub springs: Vec<Spring>,
}

impl LumpedSector {
    /// The paper's academic sector (Table 1, topology of docs/design.md §4).
    pub fn academic() -> Self {
        let k = ACADEMIC_STIFFNESSES;
        Self {
            masses: ACADEMIC_MASSES.to_vec(),
            springs: academic_springs(&k),
        }
    }

    /// Checks the values and assembles the block-circulant form.
    /// `key` prefixes error messages (e.g. `model`); dofs in messages are 1-based.
    pub(crate) fn to_block_circulant(&self, key: &str) -> Result<BlockCirculantSector, ModelError> {
        let n = self.masses.len();
        if n == 0 {
            return Err(ModelError::invalid(
                format!("{key}.masses"),
                "the list is empty: a sector needs at least one mass",
            ));
        }
        super::sector::check_sector_dofs(n, format!("{key}.masses"))?;
        for (i, &m) in self.masses.iter().enumerate() {
            if !(m.is_finite() && m > 0.0) {
                return Err(ModelError::invalid(
                    format!("{key}.masses[{}]", i + 1),
                    format!("{m} is not allowed: masses must be finite and > 0 (kg)"),
                ));
            }
        }
        let mut stiffness = Mat::<f64>::zeros(n, n);
        let mut coupling = Mat::<f64>::zeros(n, n);
        for (i, spring) in self.springs.iter().enumerate() {
            let at = format!("{key}.springs[{}]", i + 1);
            let k = spring.stiffness;
            if !(k.is_finite() && k >= 0.0) {
                return Err(ModelError::invalid(
                    format!("{at}.stiffness"),
                    format!("{k} is not allowed: stiffnesses must be finite and ≥ 0 (N/m)"),
                ));
            }
            let dofs: Vec<usize> = match spring.link {
                SpringLink::Within(a, b) | SpringLink::NextSector(a, b) => vec![a, b],
                SpringLink::Ground(a) => vec![a],
            };
            for &d in &dofs {
                if d >= n {
                    return Err(ModelError::invalid(
                        format!("{at}.dofs"),
                        format!(
                            "dof {} is out of range: the sector has dofs 1..={n} (one per mass)",
                            d + 1
                        ),
                    ));
                }
            }
            match spring.link {
                SpringLink::Within(a, b) => {
                    if a == b {
                        return Err(ModelError::invalid(
                            format!("{at}.dofs"),
                            format!(
                                "a spring within a sector joins two different dofs, not dof {} to itself \
                                 (use link = \"ground\" for a spring to the ground)",
                                a + 1
                            ),
                        ));
                    }
                    stiffness[(a, a)] += k;
                    stiffness[(b, b)] += k;
                    stiffness[(a, b)] -= k;
                    stiffness[(b, a)] -= k;
                }
                SpringLink::NextSector(a, b) => {
                    stiffness[(a, a)] += k;
                    stiffness[(b, b)] += k;
                    coupling[(a, b)] -= k;
                }
                SpringLink::Ground(a) => stiffness[(a, a)] += k,
            }
        }
        let masses = &self.masses;
        Ok(BlockCirculantSector {
            mass: Mat::from_fn(n, n, |i, j| if i == j { masses[i] } else { 0.0 }),
            stiffness,
            mass_coupling: None,
            stiffness_coupling: Some(coupling),
        })
    }
}

/// The academic topology with stiffnesses `k1..k5`.
pub(crate) fn academic_springs(k: &[f64; 5]) -> Vec<Spring> {
    vec![
        Spring {
            link: SpringLink::Within(0, 1),
            stiffness: k[0],
        },
        Spring {
            link: SpringLink::Within(1, 2),
            stiffness: k[1],
        },
        Spring {
            link: SpringLink::Within(2, 3),
            stiffness: k[2],
        },
        Spring {
            link: SpringLink::Ground(3),
            stiffness: k[3],
        },
        Spring {
            link: SpringLink::Within(3, 4),
            stiffness: k[4],
        },
        Spring {
            link: SpringLink::NextSector(4, 3),
            stiffness: k[4],
        },
    ]
}

impl SectorModel {
    /// A lumped sector (masses and springs), `sectors` sectors, with `damping`.
    /// Dofs are labelled `m1`, `m2`, ….
    pub fn lumped(
        sectors: usize,
        sector: &LumpedSector,
        damping: Damping,
    ) -> Result<Self, ModelError> {
        let blocks = sector.to_block_circulant("sector")?;
        let labels = (1..=sector.masses.len()).map(|i| format!("m{i}")).collect();
        SectorModel::block_circulant(sectors, blocks, damping)?.with_dof_labels(labels)
    }

    /// The paper's academic model with `sectors` sectors and `ξ = 1e-3` on
    /// all modes.
    pub fn academic(sectors: usize) -> Result<Self, ModelError> {
        SectorModel::lumped(sectors, &LumpedSector::academic(), Damping::default())
    }
}
