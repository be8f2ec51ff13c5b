//! Craig–Bampton reduction per nodal diameter of a sparse finite-element
//! sector (the paper's Sec. 5.1: 11 retained nodes, 20 internal modes).
//!
//! For each nodal diameter `s`, the kept dofs of the sector (all but the
//! clamped and right boundary ones, [`SparseSector`]) carry the sparse
//! complex Hermitian `K(s) = T(s)ᴴ K T(s)` and `M(s)`. They split into the
//! **retained** dofs `B` (all dofs of the contact, excitation and
//! observation nodes) and the interior `I`. The reduction basis is
//!
//! ```text
//! u_B = q_B,   u_I = Ψ q_B + Φ η,   Ψ = −K_II⁻¹ K_IB,
//! ```
//!
//! `Ψ` the static constraint modes, `Φ` the lowest `m` fixed-interface modes
//! of `(K_II(s), M_II(s))`, mass-normalized. The reduced `K_r(s)`, `M_r(s)`
//! (dense Hermitian, `b + m` square) are `Vᴴ K(s) V`, `Vᴴ M(s) V`; their
//! coordinates are the retained dofs first, in the order given
//! ([`CraigBamptonSettings::retained`]), then the modal coordinates `η` in
//! ascending frequency. The static response at the retained dofs is that of
//! the full sector exactly (`K_r`'s retained block is the Schur complement).
//!
//! **Eigensolver.** Subspace iteration with a Rayleigh–Ritz step per
//! iteration (block `max(2m, m + 8)`), shift-invert at zero through faer's
//! sparse supernodal Cholesky of the complex Hermitian `K_II(s)`, the same
//! factor that gives `Ψ`: one factorization per diameter serves both. faer
//! factors complex Hermitian matrices directly, so the real symmetric pencil
//! of twice the size (whose eigenvalues come in pairs) is not needed. The
//! wanted eigenvalues are the lowest of a pencil whose `K_II` is positive
//! definite (the sector is clamped, or held by its retained dofs), which
//! subspace iteration finds robustly and simply; block Lanczos would take
//! fewer solves but needs reorthogonalization and restarts.

mod cache;
mod cyclic;
mod error;
mod full_sector;
mod static_load;
mod subspace;

pub use cache::{
    cache_folder_next_to, craig_bampton_cached, CacheOutcome, InputDigest, ReducedWithRows,
    ReductionCache,
};
pub use cyclic::{CyclicDofs, SparseNodalDiameter, SparseSector};
pub use error::{ReductionError, SectorMatrix};
pub use full_sector::full_sector_frequencies;

use crate::model::{Damping, ModelError, SectorModel};
use faer::sparse::{SparseColMat, Triplet};
use faer::{c64, Mat, Side};
use rayon::prelude::*;
use subspace::{hermitian_part, lowest_modes, sparse_times};

/// What the reduction keeps.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct CraigBamptonSettings {
    /// The retained dofs (0-based sector dofs; none clamped, none on the
    /// right cyclic boundary): the first coordinates of the reduced model,
    /// in this order.
    pub retained: Vec<usize>,
    /// The number `m` of fixed-interface modes kept per nodal diameter.
    pub internal_modes: usize,
}

/// The reduced matrices of one nodal diameter.
#[derive(Clone, Debug)]
pub struct ReducedNodalDiameter {
    /// The signed nodal diameter `s`.
    pub nodal_diameter: i64,
    /// `M_r(s)`: retained dofs first, then modal coordinates.
    pub mass: Mat<c64>,
    /// `K_r(s)`: retained dofs first, then modal coordinates.
    pub stiffness: Mat<c64>,
    /// The eigenvalues `ω²` ((rad/s)², ascending) of the kept fixed-interface modes.
    pub interface_eigenvalues: Vec<f64>,
}

/// Reduces `sector` for every nodal diameter `s = 0..=N/2` (in parallel).
pub fn craig_bampton(
    sector: &SparseSector,
    settings: &CraigBamptonSettings,
) -> Result<Vec<ReducedNodalDiameter>, ReductionError> {
    sector.check()?;
    let dofs = sector.cyclic_dofs(&settings.retained, "retained dofs")?;
    check_modes(&dofs, settings)?;
    (0..=sector.sectors as i64 / 2)
        .into_par_iter()
        .map(|s| reduce_checked(sector, &dofs, settings.internal_modes, s))
        .collect()
}

/// Reduces `sector` for the signed nodal diameter `s` only.
pub fn craig_bampton_nodal_diameter(
    sector: &SparseSector,
    settings: &CraigBamptonSettings,
    nodal_diameter: i64,
) -> Result<ReducedNodalDiameter, ReductionError> {
    sector.check()?;
    let dofs = sector.cyclic_dofs(&settings.retained, "retained dofs")?;
    check_modes(&dofs, settings)?;
    reduce_checked(sector, &dofs, settings.internal_modes, nodal_diameter)
}

/// The reduced sector as a [`SectorModel`] of `sectors` sectors, with
/// `damping` (modal ratios apply by mode index to the reduced model's modes
/// of each diameter: the paper's 1e-3 on the first five, 5e-3 beyond).
/// Its dofs are the reduced coordinates: the retained dofs first, in the
/// order of [`CraigBamptonSettings::retained`], labelled `dof d` with `d`
/// the 1-based sector dof, then the modal coordinates, labelled `mode r`.
pub fn reduced_sector_model(
    sectors: usize,
    settings: &CraigBamptonSettings,
    reduced: &[ReducedNodalDiameter],
    damping: Damping,
) -> Result<SectorModel, ModelError> {
    for (s, r) in reduced.iter().enumerate() {
        if r.nodal_diameter != s as i64 {
            return Err(ModelError::invalid(
                "reduced models",
                format!(
                    "entry {} is nodal diameter {}; give the diameters 0..=N/2 in order",
                    s + 1,
                    r.nodal_diameter
                ),
            ));
        }
    }
    let mass = reduced.iter().map(|r| r.mass.clone()).collect();
    let stiffness = reduced.iter().map(|r| r.stiffness.clone()).collect();
    let labels = settings
        .retained
        .iter()
        .map(|d| format!("dof {}", d + 1))
        .chain((1..=settings.internal_modes).map(|r| format!("mode {r}")))
        .collect();
    SectorModel::per_nodal_diameter(sectors, mass, stiffness, damping)?.with_dof_labels(labels)
}

fn check_modes(dofs: &CyclicDofs, settings: &CraigBamptonSettings) -> Result<(), ReductionError> {
    let interior = dofs.dofs.len() - dofs.first;
    if settings.internal_modes > interior {
        return Err(ReductionError::invalid(
            "internal modes",
            format!(
                "{} is too many: the sector has {interior} interior dofs (kept dofs that are not retained)",
                settings.internal_modes
            ),
        ));
    }
    Ok(())
}

/// The blocks of a Hermitian matrix (both triangles stored) split at
/// `b`: dense `A_BB`, dense `A_IB`, sparse `A_II`.
struct Blocks {
    boundary: Mat<c64>,
    coupling: Mat<c64>,
    interior: SparseColMat<usize, c64>,
}

fn split(
    a: &SparseColMat<usize, c64>,
    b: usize,
    s: i64,
    what: &str,
) -> Result<Blocks, ReductionError> {
    let n = a.nrows();
    let col_ptr = a.symbolic().col_ptr();
    let rows = a.symbolic().row_idx();
    let values = a.val();
    let mut boundary = Mat::<c64>::zeros(b, b);
    let mut coupling = Mat::<c64>::zeros(n - b, b);
    let mut triplets = Vec::with_capacity(values.len());
    for j in 0..n {
        for p in col_ptr[j]..col_ptr[j + 1] {
            let (i, v) = (rows[p], values[p]);
            match (i < b, j < b) {
                (true, true) => boundary[(i, j)] += v,
                (false, true) => coupling[(i - b, j)] += v,
                (false, false) => triplets.push(Triplet::new(i - b, j - b, v)),
                // The Hermitian twin of the coupling.
                (true, false) => {}
            }
        }
    }
    let interior = SparseColMat::try_new_from_triplets(n - b, n - b, &triplets).map_err(|e| {
        ReductionError::Sparse {
            nodal_diameter: s,
            what: format!("the interior block of {what}(s)"),
            message: format!("{e:?}"),
        }
    })?;
    Ok(Blocks {
        boundary,
        coupling,
        interior,
    })
}

/// `Vᴴ A V` for `V = [[I_b, 0], [V_I]]`, `V_I = [Ψ Φ]`.
fn project(a: &Blocks, v: &Mat<c64>) -> Mat<c64> {
    let b = a.boundary.nrows();
    let mut out = v.adjoint() * sparse_times(&a.interior, v);
    let g = a.coupling.adjoint() * v;
    for j in 0..out.ncols() {
        for i in 0..b {
            out[(i, j)] += g[(i, j)];
            out[(j, i)] += g[(i, j)].conj();
        }
    }
    for j in 0..b {
        for i in 0..b {
            out[(i, j)] += a.boundary[(i, j)];
        }
    }
    hermitian_part(&out)
}

fn all_finite(a: &Mat<c64>) -> bool {
    (0..a.ncols())
        .all(|j| (0..a.nrows()).all(|i| a[(i, j)].re.is_finite() && a[(i, j)].im.is_finite()))
}

fn reduce_checked(
    sector: &SparseSector,
    dofs: &CyclicDofs,
    modes: usize,
    s: i64,
) -> Result<ReducedNodalDiameter, ReductionError> {
    reduce_with_basis(sector, dofs, modes, s).map(|(reduced, _)| reduced)
}

/// Reduces `sector` on nodal diameter `s` in the paper's basis
/// (`craig_bampton`) and returns the interior rows `V_I = [Ψ Φ]` too
/// (rows in [`CyclicDofs`] order after the retained ones).
fn reduce_with_basis(
    sector: &SparseSector,
    dofs: &CyclicDofs,
    modes: usize,
    s: i64,
) -> Result<(ReducedNodalDiameter, Mat<c64>), ReductionError> {
    let started = std::time::Instant::now();
    let matrices = sector.nodal_diameter_matrices(s, dofs)?;
    let b = dofs.first;
    let stiffness = split(&matrices.stiffness, b, s, "K")?;
    let mass = split(&matrices.mass, b, s, "M")?;
    let factor = stiffness.interior.sp_cholesky(Side::Lower).map_err(|e| {
        ReductionError::NotPositiveDefinite {
            matrix: error::SectorMatrix::Stiffness,
            nodal_diameter: s,
            detail: match e {
                faer::sparse::linalg::LltError::Numeric(n) => format!(" ({n:?})"),
                faer::sparse::linalg::LltError::Generic(g) => format!(" (faer: {g:?})"),
            },
        }
    })?;
    let factored = started.elapsed();
    // Ψ = −K_II⁻¹ K_IB.
    let mut psi = Mat::from_fn(stiffness.coupling.nrows(), b, |i, j| {
        -stiffness.coupling[(i, j)]
    });
    {
        use faer::linalg::solvers::Solve;
        factor.solve_in_place(psi.as_mut());
    }
    // K(s), M(s) are exactly real at diameters 0 and N/2 (phases ±1).
    let real = s == 0 || 2 * s.unsigned_abs() as usize == sector.sectors;
    let (values, phi) = lowest_modes(&factor, &mass.interior, modes, s, real)?;
    tracing::debug!(
        "nodal diameter {s}: K(s), M(s) and the factor of K_II in {:.2?}, then constraint and \
         {modes} fixed-interface modes in {:.2?}",
        factored,
        started.elapsed() - factored
    );
    let interior = psi.nrows();
    let v = Mat::from_fn(interior, b + modes, |i, j| {
        if j < b {
            psi[(i, j)]
        } else {
            phi[(i, j - b)]
        }
    });
    if !all_finite(&v) {
        return Err(ReductionError::NonFiniteResult {
            nodal_diameter: s,
            what: "the Craig–Bampton basis".into(),
        });
    }
    let reduced_stiffness = project(&stiffness, &v);
    let reduced_mass = project(&mass, &v);
    for (a, what) in [
        (&reduced_stiffness, "the reduced stiffness"),
        (&reduced_mass, "the reduced mass"),
    ] {
        if !all_finite(a) {
            return Err(ReductionError::NonFiniteResult {
                nodal_diameter: s,
                what: what.into(),
            });
        }
    }
    Ok((
        ReducedNodalDiameter {
            nodal_diameter: s,
            mass: reduced_mass,
            stiffness: reduced_stiffness,
            interface_eigenvalues: values,
        },
        v,
    ))
}

/// The reduction of [`craig_bampton`] for every nodal diameter `s =
/// 0..=N/2` (in parallel), each with the rows of its basis `V(s)` at the
/// sector dofs `rows` (0-based; each kept: neither clamped nor on the
/// right cyclic boundary): `u_rows = V_rows(s) q` for the reduced
/// coordinates `q` of diameter `s` (retained dofs first, then modal
/// coordinates). Mistuning (issue 44) projects a blade's stiffness with
/// them. `what` names the list in errors.
pub fn craig_bampton_with_rows(
    sector: &SparseSector,
    settings: &CraigBamptonSettings,
    rows: &[usize],
    what: &str,
) -> Result<Vec<(ReducedNodalDiameter, Mat<c64>)>, ReductionError> {
    sector.check()?;
    let dofs = sector.cyclic_dofs(&settings.retained, "retained dofs")?;
    check_modes(&dofs, settings)?;
    let kept = rows
        .iter()
        .enumerate()
        .map(|(i, &d)| {
            dofs.row_of(d).ok_or_else(|| {
                ReductionError::invalid(
                    format!("{what}[{}]", i + 1),
                    format!(
                        "dof {} is clamped, on the right cyclic boundary or out of range: \
                         only the sector's kept dofs have rows in the reduced basis",
                        d + 1
                    ),
                )
            })
        })
        .collect::<Result<Vec<usize>, _>>()?;
    let b = dofs.first;
    (0..=sector.sectors as i64 / 2)
        .into_par_iter()
        .map(|s| {
            let (reduced, v) = reduce_with_basis(sector, &dofs, settings.internal_modes, s)?;
            let columns = b + settings.internal_modes;
            let basis = Mat::from_fn(kept.len(), columns, |i, j| {
                let r = kept[i];
                if r < b {
                    c64::new(if r == j { 1.0 } else { 0.0 }, 0.0)
                } else {
                    v[(r - b, j)]
                }
            });
            Ok((reduced, basis))
        })
        .collect()
}
