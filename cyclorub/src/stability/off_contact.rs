//! Points of weak contact: the linear wheel's exponents, with a bound.
//!
//! With damping diagonal in the undamped modes (modal ratios, Rayleigh),
//! the linear wheel's exponents are `ν = −ξω ± iω√(1 − ξ²)` of every mode
//! of every diameter, and the contact stiffness `d(t)` moves them by at
//! most `|Δλ| ≤ 2 max_t |d| · max_s Σ_c (M(s)⁻¹)_cc / min_r |ν⁺_r − ν⁻_r|`
//! (Bauer–Fike in the modal basis, where the perturbation is
//! `(ν⁺ − ν⁻)⁻¹ Φᴴ D Φ` and `Φ Φᴴ = M⁻¹`; the truncated multiplication by
//! `d` has norm at most `max |d|`). Where that bound is small against the
//! damping rates, a point is given the linear exponents and the bound,
//! which costs nothing; elsewhere Hill's method runs.

use super::classes::SymmetryClass;
use super::spectrum::{ClassSpectrum, Exponent};
use super::StabilityError;
use crate::model::SectorModel;
use faer::linalg::solvers::Solve;
use faer::{c64, Mat, Side};

/// The linear exponents per class and the bound's factor.
#[derive(Clone, Debug)]
pub struct OffContact {
    /// The classes' linear spectra, in the classes' order.
    spectra: Vec<ClassSpectrum>,
    /// `|Δλ| ≤ factor · max |d|`, (rad/s) per (N/m).
    factor: f64,
    /// The smallest damping rate `min |Re ν|`, 1/s.
    slowest_decay: f64,
}

/// The undamped modes of one diameter with their modal damping, or `None`
/// when the damping is not diagonal in them.
struct ModalData {
    exponents: Vec<c64>,
    separation: f64,
    contact_flexibility: f64,
}

fn modal_data(
    model: &SectorModel,
    nodal_diameter: i64,
    contact_dofs: &[usize],
) -> Result<Option<ModalData>, StabilityError> {
    let m = model.nodal_diameter_matrices(nodal_diameter)?;
    let n = m.mass.nrows();
    let what = || StabilityError::SingularMass {
        what: format!("nodal diameter {nodal_diameter}"),
    };
    let llt = m.mass.llt(Side::Lower).map_err(|_| what())?;
    let l = llt.L();
    // A = L⁻¹ X L⁻ᴴ for X = K, C.
    let reduce = |x: &Mat<c64>| {
        let mut y = x.clone();
        l.solve_lower_triangular_in_place(y.as_mut());
        let mut a: Mat<c64> = y.adjoint().to_owned();
        l.solve_lower_triangular_in_place(a.as_mut());
        Mat::from_fn(n, n, |i, j| (a[(i, j)] + a[(j, i)].conj()) * 0.5)
    };
    // QR, not faer's divide and conquer (inaccurate from 128 rows on:
    // `model::eigen::self_adjoint_eigen_by_qr`).
    let (values, u) = crate::model::self_adjoint_eigen_by_qr(reduce(&m.stiffness).as_ref())
        .map_err(|_| StabilityError::Eigen {
            message: format!("the modes of nodal diameter {nodal_diameter}"),
        })?;
    let u = u.as_ref();
    let modal_damping = u.adjoint() * reduce(&m.damping) * u;
    let largest = (0..n)
        .map(|r| modal_damping[(r, r)].norm())
        .fold(0.0, f64::max);
    let off_diagonal = (0..n)
        .flat_map(|r| (0..n).filter(move |&c| c != r).map(move |c| (r, c)))
        .map(|(r, c)| modal_damping[(r, c)].norm())
        .fold(0.0, f64::max);
    if off_diagonal > 1e-9 * largest.max(f64::MIN_POSITIVE) {
        return Ok(None);
    }
    let mut exponents = Vec::with_capacity(2 * n);
    let mut separation = f64::INFINITY;
    for r in 0..n {
        let omega_squared = values[r].max(0.0);
        let rate = 0.5 * modal_damping[(r, r)].re;
        let discriminant = rate * rate - omega_squared;
        let root = c64::new(0.0, 0.0)
            + if discriminant < 0.0 {
                c64::new(0.0, (-discriminant).sqrt())
            } else {
                c64::new(discriminant.sqrt(), 0.0)
            };
        exponents.push(c64::new(-rate, 0.0) + root);
        exponents.push(c64::new(-rate, 0.0) - root);
        separation = separation.min(2.0 * root.norm());
    }
    let mass_inverse = llt.solve(Mat::<c64>::identity(n, n));
    let contact_flexibility = contact_dofs.iter().map(|&c| mass_inverse[(c, c)].re).sum();
    Ok(Some(ModalData {
        exponents,
        separation,
        contact_flexibility,
    }))
}

impl OffContact {
    /// The linear spectra of `classes` (their pairs on harmonic 0), or `None`
    /// when the damping is not modal or a mode is undamped or critically
    /// damped (no bound, or no margin).
    pub fn new(
        model: &SectorModel,
        classes: &[SymmetryClass],
        contact_dofs: &[usize],
    ) -> Result<Option<Self>, StabilityError> {
        let mut spectra = Vec::with_capacity(classes.len());
        let mut factor = 0.0_f64;
        let mut slowest_decay = f64::INFINITY;
        for class in classes {
            let mut exponents = Vec::new();
            for pair in class.pairs.iter().filter(|p| p.harmonic == 0) {
                let Some(data) = modal_data(model, pair.nodal_diameter, contact_dofs)? else {
                    return Ok(None);
                };
                if data.separation <= 0.0 {
                    return Ok(None);
                }
                factor = factor.max(2.0 * data.contact_flexibility / data.separation);
                for e in &data.exponents {
                    slowest_decay = slowest_decay.min(-e.re);
                }
                exponents.extend(data.exponents.iter().map(|&e| Exponent::new(e)));
            }
            exponents.sort_by(|a, b| b.re.total_cmp(&a.re));
            spectra.push(ClassSpectrum {
                nodal_diameter: class.nodal_diameter,
                exponents,
                truncation: 0.0,
                dense: false,
            });
        }
        if !(slowest_decay > 0.0 && factor.is_finite()) {
            return Ok(None);
        }
        Ok(Some(Self {
            spectra,
            factor,
            slowest_decay,
        }))
    }

    /// How far at most (rad/s) a contact of peak stiffness
    /// `peak_contact_stiffness` (N/m) moves the linear exponents.
    pub fn bound(&self, peak_contact_stiffness: f64) -> f64 {
        self.factor * peak_contact_stiffness
    }

    /// The linear spectra and the bound on how far the contact moves them,
    /// when the bound is within 1 % of the slowest damping rate (so that
    /// the exponents are the linear ones to that and the verdict is sure).
    pub fn spectra(&self, peak_contact_stiffness: f64) -> Option<(&[ClassSpectrum], f64)> {
        let bound = self.factor * peak_contact_stiffness;
        (bound <= 1e-2 * self.slowest_decay).then_some((&self.spectra, bound))
    }
}
