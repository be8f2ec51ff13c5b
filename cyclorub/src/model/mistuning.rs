//! Mistuning (issue 44, docs/design.md §12): no two blades alike.
//!
//! Sector `j` keeps the tuned sector's mass and damping, and its blade
//! stiffness is scaled by `1 + δ_j`: `K_j = K + δ_j K_blade`, with
//! `K_blade` the stiffness of the springs that join two blade dofs (on the
//! academic model, dofs 1, 2, 3 by default: the springs m1–m2 and m2–m3,
//! not the root spring m3–m4). Blade-alone frequencies move by about
//! `√(1 + δ_j)`. The wheel is then no longer block-circulant: no cyclic
//! basis holds it, and it is solved on the physical full wheel
//! ([`SectorModel::full_wheel`] adds the perturbation sector by sector).
//!
//! The damping stays the tuned wheel's (modal damping is computed on the
//! tuned nodal diameters): mistuning perturbs the stiffness only.

use super::academic::{LumpedSector, SpringLink};
use super::sector::SectorModel;
use super::ModelError;
use faer::{c64, Mat};
use std::sync::Arc;

/// How generated deviations are drawn.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum DeviationDistribution {
    /// Normal, mean 0 (Box–Muller).
    Normal,
    /// Uniform on `[−√3 σ, √3 σ]` (mean 0, standard deviation σ).
    Uniform,
}

/// The per-sector blade stiffness deviations and the blade stiffness they
/// scale.
#[derive(Clone, Debug)]
pub struct Mistuning {
    deviations: Vec<f64>,
    blade: BladeStiffness,
}

/// A finite-element sector's blade seen from its reduced model.
#[derive(Clone, Debug)]
pub struct ReducedBlade {
    /// For each nodal diameter `s = 0..=N/2`, the rows of its basis `V(s)`
    /// at the blade dofs (3 per blade node, in the set's order): the blade's
    /// displacement is `V(s) q` for the reduced coordinates `q` of diameter
    /// `s`, in the reduced model's frames (contact nodes turned where
    /// `contact_frame = "cylindrical"`).
    pub bases: Vec<Mat<c64>>,
    /// The sector stiffness entries `(a, b, k)` between two blade dofs
    /// (indices into the rows of `bases`; both triangles, each entry once).
    pub stiffness: Vec<(usize, usize, f64)>,
}

/// The blade stiffness that a deviation scales, as the full wheel sees it.
#[derive(Clone, Debug)]
enum BladeStiffness {
    /// One sector's own dofs: `δ_j K_blade` on the diagonal block `j`.
    Sector(Mat<f64>),
    /// A reduced model whose sector coordinates mix the sectors (Craig–
    /// Bampton per nodal diameter): `offsets[a N + b] = W_aᵀ K_blade W_b`,
    /// with `u_j = Σ_l W_{l−j} x_l` the blade displacement of sector `j`
    /// from the sector coordinates `x_l`, so that `δ_j K_blade` adds
    /// `δ_j offsets[(l−j) N + (m−j)]` to block `(l, m)` (offsets mod N).
    Reduced(Vec<Mat<f64>>),
}

impl Mistuning {
    /// Deviations `δ_j` (one per sector, each finite and `> −1`: a blade of
    /// stiffness `(1 + δ_j) K_blade` must keep a positive stiffness) of the
    /// blade stiffness `blade_stiffness` (one sector's, symmetric). `key`
    /// names the deviations in messages.
    pub fn new(
        deviations: Vec<f64>,
        blade_stiffness: Mat<f64>,
        key: &str,
    ) -> Result<Self, ModelError> {
        if let Some((j, d)) = deviations
            .iter()
            .enumerate()
            .find(|(_, d)| !(d.is_finite() && **d > -1.0))
        {
            return Err(ModelError::invalid(
                format!("{key}[{}]", j + 1),
                format!(
                    "{d} is not allowed: a deviation must be finite and > −1 (the blade \
                     stiffness is scaled by 1 + δ, which must stay positive)"
                ),
            ));
        }
        if blade_stiffness.nrows() != blade_stiffness.ncols() {
            return Err(ModelError::invalid(
                key,
                "the blade stiffness must be a square sector matrix",
            ));
        }
        Ok(Self {
            deviations,
            blade: BladeStiffness::Sector(blade_stiffness),
        })
    }

    /// Deviations `δ_j` of the blade of a sector reduced per nodal diameter
    /// (finite-element sectors): `blade` gives each diameter's basis rows
    /// at the blade dofs and the blade stiffness entries, which are scaled
    /// in physical coordinates and projected on the tuned sector's bases
    /// (the reduced wheel's coordinates do not change). The deviations are
    /// checked as by [`Mistuning::new`].
    pub fn reduced(
        deviations: Vec<f64>,
        blade: &ReducedBlade,
        key: &str,
    ) -> Result<Self, ModelError> {
        let n = deviations.len();
        let mut checked = Self::new(deviations, Mat::zeros(0, 0), key)?;
        if blade.bases.len() != n / 2 + 1 {
            return Err(ModelError::invalid(
                key,
                format!(
                    "the blade has bases for {} nodal diameters; {} sectors need {}",
                    blade.bases.len(),
                    n,
                    n / 2 + 1
                ),
            ));
        }
        checked.blade = BladeStiffness::Reduced(reduced_offsets(n, blade));
        Ok(checked)
    }

    /// `δ_j`, sector by sector (sector 1 first).
    pub fn deviations(&self) -> &[f64] {
        &self.deviations
    }

    /// The blade stiffness `K_blade` that `δ_j` scales on one sector's
    /// dofs, where the sector's dofs are its own (lumped models, inline
    /// matrices); `None` for a sector reduced per nodal diameter, whose
    /// blade moves with every sector's coordinates.
    pub fn blade_stiffness(&self) -> Option<&Mat<f64>> {
        match &self.blade {
            BladeStiffness::Sector(k) => Some(k),
            BladeStiffness::Reduced(_) => None,
        }
    }

    /// The size of the sector coordinates the blade stiffness acts on.
    fn sector_size(&self) -> usize {
        match &self.blade {
            BladeStiffness::Sector(k) => k.nrows(),
            BladeStiffness::Reduced(offsets) => offsets.first().map_or(0, |h| h.nrows()),
        }
    }

    /// Whether every deviation is 0 (the tuned wheel).
    pub fn is_zero(&self) -> bool {
        self.deviations.iter().all(|d| *d == 0.0)
    }
}

impl LumpedSector {
    /// The stiffness of the springs within a sector that join two of
    /// `blade_dofs` (0-based): the blade's own stiffness, which mistuning
    /// scales. Springs to the ground, to the next sector, or with one end
    /// off the blade (the root) are left out. `key` names `blade_dofs` in
    /// messages.
    pub fn blade_stiffness(&self, blade_dofs: &[usize], key: &str) -> Result<Mat<f64>, ModelError> {
        let n = self.masses.len();
        if blade_dofs.is_empty() {
            return Err(ModelError::invalid(
                key,
                "[] is not allowed: name the blade's dofs (1-based), e.g. [1, 2, 3]",
            ));
        }
        if let Some(&bad) = blade_dofs.iter().find(|&&d| d >= n) {
            return Err(ModelError::invalid(
                key,
                format!(
                    "dof {} is out of range: the sector has dofs 1..={n}",
                    bad + 1
                ),
            ));
        }
        let mut blade = Mat::<f64>::zeros(n, n);
        let mut springs = 0;
        for spring in &self.springs {
            if let SpringLink::Within(a, b) = spring.link {
                if blade_dofs.contains(&a) && blade_dofs.contains(&b) {
                    let k = spring.stiffness;
                    blade[(a, a)] += k;
                    blade[(b, b)] += k;
                    blade[(a, b)] -= k;
                    blade[(b, a)] -= k;
                    springs += 1;
                }
            }
        }
        if springs == 0 {
            return Err(ModelError::invalid(
                key,
                "no spring within a sector joins two of these dofs, so there is no blade \
                 stiffness to mistune; name at least two dofs joined by a spring",
            ));
        }
        Ok(blade)
    }
}

/// `count` deviations of standard deviation `standard_deviation`, drawn
/// from `distribution` by a generator seeded with `seed`: the same seed
/// gives the same pattern on every machine and every version (SplitMix64,
/// written here so that no crate update changes a stored study).
pub fn generate_deviations(
    count: usize,
    standard_deviation: f64,
    seed: u64,
    distribution: DeviationDistribution,
) -> Vec<f64> {
    let mut state = seed;
    // A uniform number in (0, 1): 53 random bits, never 0 (for the log).
    let mut uniform = move || {
        state = state.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = state;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^= z >> 31;
        ((z >> 11) as f64 + 0.5) / (1u64 << 53) as f64
    };
    (0..count)
        .map(|_| match distribution {
            DeviationDistribution::Normal => {
                // Box–Muller: one normal number per pair of uniform ones.
                let (u, v) = (uniform(), uniform());
                standard_deviation * (-2.0 * u.ln()).sqrt() * (2.0 * std::f64::consts::PI * v).cos()
            }
            DeviationDistribution::Uniform => {
                standard_deviation * 3f64.sqrt() * (2.0 * uniform() - 1.0)
            }
        })
        .collect()
}

impl SectorModel {
    /// The same wheel mistuned: sector `j`'s blade stiffness scaled by
    /// `1 + δ_j`. Refused unless there is one deviation per sector and the
    /// blade stiffness has a sector's size.
    pub fn with_mistuning(mut self, mistuning: Mistuning) -> Result<Self, ModelError> {
        if mistuning.deviations.len() != self.sectors() {
            return Err(ModelError::invalid(
                "mistuning.deviations",
                format!(
                    "{} values given: give one deviation per sector, as many as model.sectors = {}",
                    mistuning.deviations.len(),
                    self.sectors()
                ),
            ));
        }
        if mistuning.sector_size() != self.dofs_per_sector() {
            return Err(ModelError::invalid(
                "mistuning.blade_dofs",
                format!(
                    "the blade stiffness has {} rows, a sector {} dofs",
                    mistuning.sector_size(),
                    self.dofs_per_sector()
                ),
            ));
        }
        self.set_mistuning(Some(Arc::new(mistuning)));
        Ok(self)
    }

    /// Whether the wheel is mistuned (its sectors differ, even if by 0).
    pub fn is_mistuned(&self) -> bool {
        self.mistuning().is_some()
    }

    /// The same wheel tuned (the mistuning dropped).
    pub fn tuned(&self) -> Self {
        let mut tuned = self.clone();
        tuned.set_mistuning(None);
        tuned
    }
}

/// Adds `δ_j K_blade` to the diagonal block of every sector `j` of the
/// full-wheel stiffness `stiffness` (sector-major dofs).
pub(crate) fn add_blade_perturbation(stiffness: &mut Mat<f64>, mistuning: &Mistuning) {
    let offsets = match &mistuning.blade {
        BladeStiffness::Sector(blade) => {
            let n = blade.nrows();
            for (j, &delta) in mistuning.deviations.iter().enumerate() {
                if delta == 0.0 {
                    continue;
                }
                for a in 0..n {
                    for b in 0..n {
                        let k = blade[(a, b)];
                        if k != 0.0 {
                            stiffness[(j * n + a, j * n + b)] += delta * k;
                        }
                    }
                }
            }
            return;
        }
        BladeStiffness::Reduced(offsets) => offsets,
    };
    let sectors = mistuning.deviations.len();
    let n = mistuning.sector_size();
    if mistuning.is_zero() {
        return;
    }
    let mut perturbation = Mat::<f64>::zeros(sectors * n, sectors * n);
    for (j, &delta) in mistuning.deviations.iter().enumerate() {
        if delta == 0.0 {
            continue;
        }
        for l in 0..sectors {
            let a = (l + sectors - j) % sectors;
            for m in 0..sectors {
                let h = &offsets[a * sectors + (m + sectors - j) % sectors];
                for c in 0..n {
                    for r in 0..n {
                        perturbation[(l * n + r, m * n + c)] += delta * h[(r, c)];
                    }
                }
            }
        }
    }
    // Symmetric up to round-off: added exactly symmetric, as the wheel is.
    for c in 0..sectors * n {
        for r in 0..sectors * n {
            stiffness[(r, c)] += 0.5 * (perturbation[(r, c)] + perturbation[(c, r)]);
        }
    }
}

/// `W_aᵀ K_blade W_b` for every pair of sector offsets `a, b` (index
/// `a N + b`), with `W_d = (1/N) Σ_s V(s) e^{iαsd}` (real: `V(−s) =
/// conj V(s)`) the blade rows of the inverse DFT of the bases: the full
/// wheel's sector coordinates are `x_j = (1/√N) Σ_s e^{−iαsj} q_s`
/// (`matrices::assemble_from_nodal_diameters`), so the blade of sector `j`
/// moves by `u_j = Σ_l W_{l−j} x_l`.
fn reduced_offsets(sectors: usize, blade: &ReducedBlade) -> Vec<Mat<f64>> {
    use super::matrices::unit_phase;
    let (rows, cols) = (blade.bases[0].nrows(), blade.bases[0].ncols());
    let scale = 1.0 / sectors as f64;
    let w: Vec<Mat<f64>> = (0..sectors)
        .map(|d| {
            let mut out = Mat::<f64>::zeros(rows, cols);
            for s in 0..sectors {
                let (v, conjugate) = if 2 * s <= sectors {
                    (&blade.bases[s], false)
                } else {
                    (&blade.bases[sectors - s], true)
                };
                let phase = unit_phase((s * d) as i64, sectors);
                for c in 0..cols {
                    for r in 0..rows {
                        let x = if conjugate {
                            v[(r, c)].conj()
                        } else {
                            v[(r, c)]
                        };
                        out[(r, c)] += (x * phase).re * scale;
                    }
                }
            }
            out
        })
        .collect();
    // K_blade W_b from the entries.
    let kw: Vec<Mat<f64>> = w
        .iter()
        .map(|wb| {
            let mut out = Mat::<f64>::zeros(rows, cols);
            for &(a, b, k) in &blade.stiffness {
                for c in 0..cols {
                    out[(a, c)] += k * wb[(b, c)];
                }
            }
            out
        })
        .collect();
    (0..sectors * sectors)
        .map(|i| w[i / sectors].transpose() * &kw[i % sectors])
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    #[allow(clippy::float_cmp)] // sums of the Table 1 stiffnesses, exact in binary
    fn the_academic_blade_is_the_two_springs_above_the_root() {
        let blade = LumpedSector::academic()
            .blade_stiffness(&[0, 1, 2], "mistuning.blade_dofs")
            .unwrap();
        // k1 = 2e6 between m1 and m2, k2 = 1e6 between m2 and m3; k3 (m3–m4) left out.
        assert_eq!(blade[(0, 0)], 2e6);
        assert_eq!(blade[(1, 1)], 3e6);
        assert_eq!(blade[(2, 2)], 1e6);
        assert_eq!(blade[(1, 2)], -1e6);
        assert_eq!(blade[(3, 3)], 0.0);
    }

    #[test]
    fn generated_deviations_have_the_asked_moments_and_repeat() {
        for distribution in [
            DeviationDistribution::Normal,
            DeviationDistribution::Uniform,
        ] {
            let d = generate_deviations(200_000, 0.02, 7, distribution);
            let mean = d.iter().sum::<f64>() / d.len() as f64;
            let std = (d.iter().map(|x| (x - mean).powi(2)).sum::<f64>() / d.len() as f64).sqrt();
            assert!(mean.abs() < 2e-4, "{distribution:?}: mean {mean}");
            assert!((std - 0.02).abs() < 2e-4, "{distribution:?}: std {std}");
            assert_eq!(d[..10], generate_deviations(10, 0.02, 7, distribution)[..]);
        }
        assert_ne!(
            generate_deviations(3, 0.01, 1, DeviationDistribution::Normal),
            generate_deviations(3, 0.01, 2, DeviationDistribution::Normal)
        );
    }

    #[test]
    fn a_deviation_of_minus_one_is_refused() {
        let message = Mistuning::new(vec![0.0, -1.0], Mat::zeros(2, 2), "mistuning.deviations")
            .unwrap_err()
            .to_string();
        assert!(message.contains("mistuning.deviations[2]"), "{message}");
        assert!(message.contains("> −1"), "{message}");
    }
}
