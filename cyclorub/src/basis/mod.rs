//! Spectral bases: which (signed nodal diameter, harmonic) pairs are unknowns.
//!
//! A basis is a set of signed nodal diameters `S_k` on each harmonic
//! `k = 0..=N_h`, closed under conjugation (on `k = 0`, `s ∈ S_0 ⇔ −s ∈ S_0`).
//! Everything downstream (unknown layout, dynamic stiffness blocks, sector
//! sampling, sizes) is derived from it.

mod nodal_diameter;
mod paper;
mod sector_map;
mod symmetry;
mod traveling_wave;

pub use nodal_diameter::{
    combined_order, load_orders, paper_k, paper_nodal_diameters, parity_applies,
};
pub use paper::PaperRule;
pub use sector_map::{condition_number, condition_number_bound, sector_map, sector_map_inverse};
pub use symmetry::PairLattice;

use crate::cyclic::{fold_nodal_diameter, HarmonicSet, LoadError};
use serde::Serialize;

/// Errors building a basis.
#[derive(Debug, thiserror::Error, PartialEq)]
pub enum BasisError {
    /// The number of sectors must be at least 1.
    #[error("sectors = {0}: the number of sectors must be at least 1")]
    NoSectors(usize),
    /// There must be one set of nodal diameters per harmonic `0..=N_h`.
    #[error("expected {expected} harmonic sets (harmonics 0..={harmonics}), got {given}")]
    HarmonicCount {
        /// `N_h + 1`.
        expected: usize,
        /// `N_h`.
        harmonics: usize,
        /// Sets given.
        given: usize,
    },
    /// The set on harmonic 0 must hold `−s` with every `s` (a real static field).
    #[error("harmonic 0 holds nodal diameter {0} but not its opposite")]
    NotConjugateClosed(i64),
    /// The sector map of a set of diameters is singular (two diameters
    /// coincide modulo `N`) or its inverse is not finite.
    #[error("the sector map of nodal diameters {nodal_diameters:?} on {sectors} sectors is not invertible")]
    SingularSectorMap {
        /// Number of sectors `N`.
        sectors: usize,
        /// The signed diameters of the harmonic.
        nodal_diameters: Vec<i64>,
    },
    /// The load case is not valid for the wheel.
    #[error(transparent)]
    Load(#[from] LoadError),
    /// More pairs than a basis may hold.
    #[error(
        "N = {sectors} sectors and N_h = {harmonics} harmonics: a basis may hold up to \
         (N_h + 1)·N = {BASIS_MAX_PAIRS} pairs"
    )]
    TooLarge {
        /// Number of sectors `N`.
        sectors: usize,
        /// Number of harmonics `N_h`.
        harmonics: usize,
    },
}

/// The most pairs a basis may be built on, `(N_h + 1)·N` (the full basis):
/// ten million, beyond any wheel and harmonic count a harmonic balance
/// can solve (the dense problem holds far fewer unknowns), and small
/// enough that the sets of every rule fit in memory.
pub const BASIS_MAX_PAIRS: usize = 10_000_000;

/// At least one sector, and `(N_h + 1)·N` within [`BASIS_MAX_PAIRS`]: checked
/// by every rule before it builds its sets (and by a caller that wants to
/// know before it asks for one).
pub fn check_size(sectors: usize, harmonics: usize) -> Result<(), BasisError> {
    if sectors == 0 {
        return Err(BasisError::NoSectors(sectors));
    }
    match harmonics
        .checked_add(1)
        .and_then(|h| h.checked_mul(sectors))
    {
        Some(pairs) if pairs <= BASIS_MAX_PAIRS => Ok(()),
        _ => Err(BasisError::TooLarge { sectors, harmonics }),
    }
}

/// How a basis was built.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum BasisKind {
    /// Every pair on every harmonic.
    Full,
    /// The paper's nodal-diameter rule (Sec. 2.4), with the parity rule
    /// (Sec. 3.2.1) where it applies.
    NodalDiameter,
    /// The paper's traveling-wave hypothesis (Sec. 3.3).
    TravelingWave,
    /// The paper's own choice for a load case (Sec. 4.3).
    Paper,
    /// The symmetry rule (docs/design.md §3).
    Symmetry,
    /// Given explicitly.
    Explicit,
}

/// The signed pairs kept on each harmonic.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct SpectralBasis {
    kind: BasisKind,
    sectors: usize,
    /// `nodal_diameters[k]`: the signed nodal diameters of harmonic `k`,
    /// folded into `(−N/2, N/2]`, sorted ascending, without repeats.
    nodal_diameters: Vec<Vec<i64>>,
}

impl SpectralBasis {
    /// A basis from explicit sets, one per harmonic `0..=N_h`; the sets are
    /// folded, sorted and deduplicated; harmonic 0 must be conjugate-closed.
    pub fn new(
        kind: BasisKind,
        sectors: usize,
        nodal_diameters: Vec<Vec<i64>>,
    ) -> Result<Self, BasisError> {
        check_size(sectors, nodal_diameters.len().saturating_sub(1))?;
        let nodal_diameters: Vec<Vec<i64>> = nodal_diameters
            .into_iter()
            .map(|set| {
                let mut set: Vec<i64> = set
                    .into_iter()
                    .map(|s| fold_nodal_diameter(s, sectors))
                    .collect();
                // The rules produce sorted sets: skip the sort for them.
                if !set.windows(2).all(|w| w[0] < w[1]) {
                    set.sort_unstable();
                    set.dedup();
                }
                set
            })
            .collect();
        if nodal_diameters.is_empty() {
            return Err(BasisError::HarmonicCount {
                expected: 1,
                harmonics: 0,
                given: 0,
            });
        }
        for &s in &nodal_diameters[0] {
            if !nodal_diameters[0].contains(&fold_nodal_diameter(-s, sectors)) {
                return Err(BasisError::NotConjugateClosed(s));
            }
        }
        Ok(Self {
            kind,
            sectors,
            nodal_diameters,
        })
    }

    /// Every signed pair on every harmonic `0..=harmonics`.
    pub fn full(sectors: usize, harmonics: usize) -> Result<Self, BasisError> {
        check_size(sectors, harmonics)?;
        let half = sectors as i64 / 2;
        let all: Vec<i64> = (half + 1 - sectors as i64..=half).collect();
        let count = HarmonicSet::up_to(harmonics).count();
        Self::new(BasisKind::Full, sectors, vec![all; count])
    }

    /// The same sets, labelled as built by `kind`.
    pub(crate) fn with_kind(mut self, kind: BasisKind) -> Self {
        self.kind = kind;
        self
    }

    /// How the basis was built.
    pub fn kind(&self) -> BasisKind {
        self.kind
    }

    /// Number of sectors `N`.
    pub fn sectors(&self) -> usize {
        self.sectors
    }

    /// Highest harmonic `N_h`.
    pub fn harmonics(&self) -> usize {
        self.nodal_diameters.len() - 1
    }

    /// The harmonics the basis is laid on, `0..=N_h` (a harmonic without
    /// pairs stays in the set).
    pub fn harmonic_set(&self) -> HarmonicSet {
        HarmonicSet::up_to(self.harmonics())
    }

    /// The signed nodal diameters kept on harmonic `k` (empty above `N_h`).
    pub fn nodal_diameters(&self, harmonic: usize) -> &[i64] {
        self.nodal_diameters
            .get(harmonic)
            .map(Vec::as_slice)
            .unwrap_or(&[])
    }

    /// Real unknowns per contact dof: on `k = 0`, one per signed diameter
    /// (a `±s` pair holds one complex amplitude, `0` and `N/2` one real);
    /// on `k ≥ 1`, two (a complex amplitude) per signed diameter.
    pub fn real_unknowns_per_contact_dof(&self) -> usize {
        self.nodal_diameters[0].len()
            + self.nodal_diameters[1..]
                .iter()
                .map(|set| 2 * set.len())
                .sum::<usize>()
    }

    /// Real unknowns per contact dof of the full model: `N (2 N_h + 1)`.
    pub fn full_size_per_contact_dof(&self) -> usize {
        self.sectors * self.harmonic_set().coordinates()
    }

    /// Sectors sampled by the AFT-CP: `max_k |S_k|` (harmonic `k` uses the
    /// first `|S_k|` of them).
    pub fn sampled_sectors(&self) -> usize {
        self.nodal_diameters
            .iter()
            .map(Vec::len)
            .max()
            .unwrap_or(0)
            .max(1)
    }

    /// Reduction of the unknown count relative to the full model, in percent.
    pub fn reduction_percent(&self) -> f64 {
        100.0
            * (1.0
                - self.real_unknowns_per_contact_dof() as f64
                    / self.full_size_per_contact_dof() as f64)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn full_basis_has_the_full_size() {
        for n in 1..40 {
            let b = SpectralBasis::full(n, 10).unwrap();
            assert_eq!(b.real_unknowns_per_contact_dof(), n * 21);
            assert_eq!(b.sampled_sectors(), n);
        }
    }

    #[test]
    fn harmonic_zero_must_be_conjugate_closed() {
        let e = SpectralBasis::new(BasisKind::Explicit, 24, vec![vec![0, 2], vec![1]]);
        assert_eq!(e, Err(BasisError::NotConjugateClosed(2)));
    }
}
