//! Hill's method on one block of perturbation pairs: the quadratic
//! eigenproblem in the exponent, linearized, solved densely, and the
//! physical exponents picked among its eigenvalues.
//!
//! A perturbation `y(t) = e^{λt} Σ q_g e^{i k_g ω t}` over groups `g` (a
//! pair `(s, k)` of a sector, or a harmonic of the whole wheel) obeys
//! `[(λ + i k ω)² M + (λ + i k ω) C + K] q_g + Σ_h D_{gh} q_h = 0`, with
//! `D` the contact stiffness's Fourier coefficients (friction adds
//! `Σ_h E_{gh} (λ + i k_h ω) q_h`, `E` its velocity terms). With `μ = λ/ω` and
//! the state `[q; μ q]` this is `μ z = A z`,
//! `A = [[0, I], [k² I − M⁻¹(i k C/ω + K/ω²) − M⁻¹ D/ω², −2 i k I − M⁻¹ C/ω]]`
//! per group. Of its eigenvalues, each physical exponent appears once per
//! shift `λ + i m ω`, which moves the eigenvector's centre (the signed mean
//! harmonic of `|q|²`) by one harmonic: the physical copy is the one centred
//! in `(−1/2, 1/2]`. In the untruncated problem a class holds
//! `2 · dofs · |P₀|` of them. Truncated, a family whose eigenvectors reach
//! the highest harmonics kept may be counted in a neighbouring class, or in
//! none, its copies' centres no longer a whole harmonic apart (on the
//! default case's contact plateau, `H = 10`, 6 of the 240 families are
//! lost): `ClassSpectrum::truncation` says how far the vectors reach.

use super::StabilityError;
use faer::linalg::solvers::Solve;
use faer::{c64, Mat, Side};
use std::sync::Arc;

/// A set of local matrices (a sector's at one signed diameter, or the
/// whole wheel's) with `M⁻¹K` and `M⁻¹C`.
#[derive(Clone, Debug)]
pub struct LocalDynamics {
    mass: Mat<c64>,
    stiffness: Mat<c64>,
    damping: Mat<c64>,
    mass_inverse: Mat<c64>,
    mass_inverse_stiffness: Mat<c64>,
    mass_inverse_damping: Mat<c64>,
    /// The exponents (rad/s) and unit mode shapes of `M q̈ + C q̇ + K q = 0`,
    /// computed once when first asked.
    exponents: std::sync::OnceLock<Result<Vec<LinearExponent>, String>>,
}

impl LocalDynamics {
    /// From Hermitian positive definite `mass` and any `stiffness`, `damping`;
    /// `what` names the matrices in the error.
    pub fn new(
        mass: &Mat<c64>,
        stiffness: &Mat<c64>,
        damping: &Mat<c64>,
        what: &str,
    ) -> Result<Self, StabilityError> {
        let llt = mass
            .llt(Side::Lower)
            .map_err(|_| StabilityError::SingularMass {
                what: what.to_string(),
            })?;
        let n = mass.nrows();
        let mass_inverse = llt.solve(Mat::<c64>::identity(n, n));
        Ok(Self {
            mass_inverse_stiffness: &mass_inverse * stiffness,
            mass_inverse_damping: &mass_inverse * damping,
            mass_inverse,
            mass: mass.clone(),
            stiffness: stiffness.clone(),
            damping: damping.clone(),
            exponents: std::sync::OnceLock::new(),
        })
    }

    /// The exponents `p` (rad/s) of `M q̈ + C q̇ + K q = 0` with their unit
    /// mode shapes `q`, from the first-order form (computed once).
    pub fn exponents(&self) -> Result<&[LinearExponent], StabilityError> {
        self.exponents
            .get_or_init(|| self.first_order_exponents())
            .as_deref()
            .map_err(|message| StabilityError::Eigen {
                message: message.clone(),
            })
    }

    fn first_order_exponents(&self) -> Result<Vec<LinearExponent>, String> {
        let n = self.dofs();
        let zero = c64::new(0.0, 0.0);
        let a = Mat::<c64>::from_fn(2 * n, 2 * n, |r, c| match (r < n, c < n) {
            (true, true) => zero,
            (true, false) if c - n == r => c64::new(1.0, 0.0),
            (true, false) => zero,
            (false, true) => -self.mass_inverse_stiffness[(r - n, c)],
            (false, false) => -self.mass_inverse_damping[(r - n, c - n)],
        });
        let eigen = a
            .eigen()
            .map_err(|e| format!("the linear exponents of a group: {e:?}"))?;
        (0..2 * n)
            .map(|i| {
                let p = eigen.S()[i];
                let mode: Vec<c64> = (0..n).map(|r| eigen.U()[(r, i)]).collect();
                let size = mode.iter().map(|z| z.norm_sqr()).sum::<f64>().sqrt();
                if !(p.re.is_finite() && p.im.is_finite() && size > 0.0 && size.is_finite()) {
                    return Err("the linear exponents of a group are not finite".to_string());
                }
                Ok((p, mode.into_iter().map(|z| z / size).collect()))
            })
            .collect()
    }

    /// Dofs.
    pub fn dofs(&self) -> usize {
        self.mass_inverse.nrows()
    }

    /// `M`.
    pub fn mass(&self) -> &Mat<c64> {
        &self.mass
    }

    /// `K`.
    pub fn stiffness(&self) -> &Mat<c64> {
        &self.stiffness
    }

    /// `C`.
    pub fn damping(&self) -> &Mat<c64> {
        &self.damping
    }

    /// `M⁻¹`.
    pub fn mass_inverse(&self) -> &Mat<c64> {
        &self.mass_inverse
    }

    /// `M⁻¹K`.
    pub fn mass_inverse_stiffness(&self) -> &Mat<c64> {
        &self.mass_inverse_stiffness
    }

    /// `M⁻¹C`.
    pub fn mass_inverse_damping(&self) -> &Mat<c64> {
        &self.mass_inverse_damping
    }
}

/// A linear exponent (rad/s) with its unit mode shape.
pub type LinearExponent = (c64, Vec<c64>);

/// One group of a block: harmonic `k` on a set of local dofs.
#[derive(Clone, Debug)]
pub struct Group {
    /// The harmonic `k`.
    pub harmonic: i64,
    /// The local dynamics.
    pub dynamics: Arc<LocalDynamics>,
}

/// An exponent picked as physical, with what its eigenvector says.
#[derive(Clone, Copy, Debug)]
pub struct Picked {
    /// `λ`, rad/s.
    pub exponent: c64,
    /// Signed mean harmonic of the eigenvector (in units of the harmonic step).
    pub centre: f64,
    /// Share of the eigenvector's weight on the highest harmonics `|k| = H`.
    pub edge: f64,
}

/// Where each group's dofs start in the block, and the block's dofs.
pub fn group_offsets(groups: &[Group]) -> (Vec<usize>, usize) {
    let mut next = 0;
    let offsets = groups
        .iter()
        .map(|g| {
            let at = next;
            next += g.dynamics.dofs();
            at
        })
        .collect();
    (offsets, next)
}

/// The block's Hill matrix `A` (module doc), dense: `2m × 2m` for the
/// groups' `m` dofs; `damping` the contact's velocity terms `E` (friction),
/// entered as `−M⁻¹ E (μ + i k_h)/ω` on the state `[q; μq]` of the column's
/// group `h`.
pub fn hill_matrix(
    groups: &[Group],
    coupling: &[(usize, usize, c64)],
    damping: &[(usize, usize, c64)],
    omega: f64,
) -> Mat<c64> {
    let (offsets, m) = group_offsets(groups);
    let mut a = Mat::<c64>::zeros(2 * m, 2 * m);
    let (w1, w2) = (1.0 / omega, 1.0 / (omega * omega));
    for (group, &offset) in groups.iter().zip(&offsets) {
        let d = group.dynamics.as_ref();
        let n = d.dofs();
        let k = group.harmonic as f64;
        let ik = c64::new(0.0, k);
        for r in 0..n {
            a[(offset + r, m + offset + r)] = c64::new(1.0, 0.0);
            for c in 0..n {
                let mut lower = -(ik * d.mass_inverse_damping[(r, c)] * w1
                    + d.mass_inverse_stiffness[(r, c)] * w2);
                let mut right = -d.mass_inverse_damping[(r, c)] * w1;
                if r == c {
                    lower += c64::new(k * k, 0.0);
                    right -= ik * 2.0;
                }
                a[(m + offset + r, offset + c)] = lower;
                a[(m + offset + r, m + offset + c)] = right;
            }
        }
    }
    // −M⁻¹ D / ω²: each entry D_{qc} reaches the rows of q's group.
    let group_of: Vec<usize> = (0..groups.len())
        .flat_map(|g| std::iter::repeat_n(g, groups[g].dynamics.dofs()))
        .collect();
    for &(q, col, value) in coupling {
        let g = group_of[q];
        let (offset, d) = (offsets[g], groups[g].dynamics.as_ref());
        for r in 0..d.dofs() {
            a[(m + offset + r, col)] -= d.mass_inverse[(r, q - offset)] * value * w2;
        }
    }
    // −M⁻¹ E (μ + i k_h) / ω: on the column's velocity state and, through
    // i k_h, on its displacement.
    for &(q, col, value) in damping {
        let g = group_of[q];
        let (offset, d) = (offsets[g], groups[g].dynamics.as_ref());
        let ik = c64::new(0.0, groups[group_of[col]].harmonic as f64);
        for r in 0..d.dofs() {
            let term = d.mass_inverse[(r, q - offset)] * value * w1;
            a[(m + offset + r, m + col)] -= term;
            a[(m + offset + r, col)] -= term * ik;
        }
    }
    a
}

/// The physical exponents of one block: `groups` in order (their dofs
/// concatenated), `coupling` the contact stiffness between the groups'
/// dofs as entries `(row, column, N/m)` (repeats add up), `damping` its
/// velocity terms likewise (N·s/m, friction), `omega` rad/s, `step` the
/// harmonic step of the groups.
pub fn physical_exponents(
    groups: &[Group],
    coupling: &[(usize, usize, c64)],
    damping: &[(usize, usize, c64)],
    omega: f64,
    step: i64,
) -> Result<Vec<Picked>, StabilityError> {
    Ok(
        physical_modes(groups, coupling, damping, omega, step, false)?
            .into_iter()
            .map(|(p, _)| p)
            .collect(),
    )
}

/// [`physical_exponents`] with, when `vectors` is set, each exponent's
/// amplitudes `q` (the first half of the eigenvector `[q; μq]`, in the
/// groups' order, unit norm over the whole eigenvector; empty otherwise).
pub fn physical_modes(
    groups: &[Group],
    coupling: &[(usize, usize, c64)],
    damping: &[(usize, usize, c64)],
    omega: f64,
    step: i64,
    vectors: bool,
) -> Result<Vec<(Picked, Vec<c64>)>, StabilityError> {
    let (offsets, m) = group_offsets(groups);
    let a = hill_matrix(groups, coupling, damping, omega);
    let eigen = a.eigen().map_err(|e| StabilityError::Eigen {
        message: format!("{e:?}"),
    })?;
    let (values, eigenvectors) = (eigen.S(), eigen.U());
    let highest = groups.iter().map(|g| g.harmonic.abs()).max().unwrap_or(0);
    let step = step.max(1) as f64;
    let mut candidates: Vec<(Picked, usize)> = (0..2 * m)
        .map(|i| {
            let mut total = 0.0;
            let mut moment = 0.0;
            let mut edge = 0.0;
            for (group, &offset) in groups.iter().zip(&offsets) {
                let weight: f64 = (0..group.dynamics.dofs())
                    .map(|r| eigenvectors[(offset + r, i)].norm_sqr())
                    .sum();
                total += weight;
                moment += weight * group.harmonic as f64 / step;
                if group.harmonic.abs() == highest && highest > 0 {
                    edge += weight;
                }
            }
            let total = if total > 0.0 {
                total
            } else {
                f64::MIN_POSITIVE
            };
            let picked = Picked {
                exponent: values[i] * omega,
                centre: moment / total,
                edge: edge / total,
            };
            (picked, i)
        })
        .collect();
    if candidates.iter().any(|(p, _)| {
        !(p.exponent.re.is_finite() && p.exponent.im.is_finite() && p.centre.is_finite())
    }) {
        return Err(StabilityError::Eigen {
            message: "the eigenvalue solver returned values that are not finite".into(),
        });
    }
    // Shifting λ by iω moves the centre by one harmonic step: each family
    // has one copy centred in (−1/2, 1/2], a rule of the eigenvector alone,
    // so that a class's pick is the whole wheel's restricted to it.
    candidates.retain(|(p, _)| p.centre > -0.5 && p.centre <= 0.5);
    candidates.sort_by(|(p, _), (q, _)| q.exponent.re.total_cmp(&p.exponent.re));
    Ok(candidates
        .into_iter()
        .map(|(p, i)| {
            let q = if vectors {
                (0..m).map(|r| eigenvectors[(r, i)]).collect()
            } else {
                Vec::new()
            };
            (p, q)
        })
        .collect())
}
