//! The paper's own choice of basis for a load case (Sec. 4.3, 5.3, 5.4, C).

use super::nodal_diameter::{combined_order, load_orders, paper_k};
use super::{BasisError, BasisKind, SpectralBasis};
use crate::cyclic::{ExcitationPattern, LoadCase};
use serde::Serialize;

/// Which of its rules the paper applies to a load case.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
#[serde(tag = "rule", rename_all = "snake_case")]
pub enum PaperRule {
    /// One traveling excitation and a circular casing: the traveling-wave
    /// hypothesis (Sec. 3.3).
    TravelingWave {
        /// Engine order `h`.
        engine_order: usize,
    },
    /// The nodal-diameter rule (Sec. 2.4) on the gcd of the excited orders,
    /// with the parity rule (Sec. 3.2.1) when `parity` is true.
    NodalDiameter {
        /// The combined order `h` (gcd of the excited orders).
        engine_order: usize,
        /// `K` of Eq. (33) for `h`.
        k: usize,
        /// Whether the parity rule is used (it applies and the load is a
        /// single order on harmonic 1 with a circular casing).
        parity: bool,
    },
}

impl PaperRule {
    /// The paper's rule for a load: the traveling-wave hypothesis for a
    /// single traveling excitation (no casing order); the nodal-diameter
    /// rule with the parity rule where it applies for one excited order
    /// (standing, mixed); the gcd rule without parity for combined loads
    /// (excitation and casing, Eq. 82 and Eq. 107) and for per-sector
    /// excitations.
    pub fn for_load(load: &LoadCase) -> Result<Self, BasisError> {
        let (orders, parity_allowed) = load_orders(load)?;
        if let (Some(ExcitationPattern::Traveling { engine_order }), true) =
            (&load.excitation, parity_allowed)
        {
            return Ok(Self::TravelingWave {
                engine_order: *engine_order,
            });
        }
        let h = combined_order(&orders);
        Ok(Self::NodalDiameter {
            engine_order: h,
            k: paper_k(load.sectors, h),
            parity: parity_allowed && super::nodal_diameter::parity_applies(load.sectors, h),
        })
    }

    /// `K` of Eq. (33) where the nodal-diameter rule is used.
    pub fn k(&self) -> Option<usize> {
        match self {
            Self::TravelingWave { .. } => None,
            Self::NodalDiameter { k, .. } => Some(*k),
        }
    }
}

impl SpectralBasis {
    /// The paper's own choice of basis for a load case ([`PaperRule::for_load`]):
    /// e.g. Eq. (76) for a traveling `h = 1` on 24 sectors, Eq. (78) for a
    /// standing `h = 1`, Eq. (82) for `h = 6` with a casing `h_c = 8`.
    pub fn paper(load: &LoadCase, harmonics: usize) -> Result<Self, BasisError> {
        let basis = match PaperRule::for_load(load)? {
            PaperRule::TravelingWave { engine_order } => {
                Self::traveling_wave(load.sectors, harmonics, engine_order)?
            }
            PaperRule::NodalDiameter {
                engine_order,
                parity,
                ..
            } => Self::nodal_diameter_rule(load.sectors, harmonics, &[engine_order], parity)?,
        };
        Ok(basis.with_kind(BasisKind::Paper))
    }
}
