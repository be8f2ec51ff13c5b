//! What `run.json` records of the basis a branch was solved on.

use serde::Serialize;

/// One harmonic's signed nodal diameters.
#[derive(Clone, Debug, Serialize)]
pub struct HarmonicRecord {
    /// Harmonic `k`.
    pub k: usize,
    /// Signed nodal diameters kept.
    pub signed_nodal_diameters: Vec<i64>,
}

/// The basis actually solved on.
#[derive(Clone, Debug, Serialize)]
pub struct BasisRecord {
    /// `symmetry`, `paper`, `nodal_diameter`, `full` or `physical`.
    pub kind: String,
    /// Real unknowns solved for.
    pub unknowns: usize,
    /// Sectors sampled by the AFT.
    pub sampled_sectors: usize,
    /// Real unknowns of the full model, `N n_c (2 N_h + 1)`.
    pub full_unknowns: usize,
    /// `100 (1 − unknowns / full_unknowns)`.
    pub reduction_percent: f64,
    /// Per harmonic (cyclic bases only).
    pub harmonics: Vec<HarmonicRecord>,
}
