//! What the stability check says of one point: the physical exponents of
//! every symmetry class.

use faer::c64;
use serde::{Deserialize, Serialize};
use std::f64::consts::PI;

/// One Floquet exponent `λ` (rad/s): the perturbation grows as `e^{Re λ t}`
/// and turns at `Im λ`; its multiplier over a period `T` is `e^{λT}`.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct Exponent {
    /// `Re λ`, 1/s.
    pub re: f64,
    /// `Im λ`, rad/s.
    pub im: f64,
}

impl Exponent {
    /// From a complex value.
    pub fn new(value: c64) -> Self {
        Self {
            re: value.re,
            im: value.im,
        }
    }

    /// As a complex value.
    pub fn value(&self) -> c64 {
        c64::new(self.re, self.im)
    }

    /// The Floquet multiplier `e^{λT}` over the period `T = 2π/ω`.
    pub fn multiplier(&self, omega: f64) -> c64 {
        let period = 2.0 * PI / omega;
        c64::cis(self.im * period) * (self.re * period).exp()
    }
}

/// The physical exponents of one symmetry class at one point.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct ClassSpectrum {
    /// The class's nodal diameter `σ` (see [`super::SymmetryClass`]); 0
    /// is the reduced problem's own class. For the whole wheel in
    /// physical coordinates, the single class is labelled 0.
    pub nodal_diameter: i64,
    /// Its exponents, largest real part first: `2 · dofs · |P₀|` of them
    /// when the truncation places every family (see `stability::hill`), all
    /// classes together `2 · dofs · N`.
    pub exponents: Vec<Exponent>,
    /// The largest share of an exponent's eigenvector on the highest
    /// harmonics kept: small (say below 1e-3) when the truncation holds it.
    /// Small is necessary, not sufficient: on the soft N = 6 case of
    /// `tests/simulate_floquet_growth.rs` with `N_h = 12`, class 2's leading
    /// real part goes +5.8, +12.9, +15.1, +15.7 1/s at H = 12, 16, 24, 40
    /// with this share below 2e-5 throughout; raise H to see convergence.
    pub truncation: f64,
    /// Whether the dense eigenproblem gave these exponents (the whole
    /// wheel's, or a class the targeted solver could not vouch for).
    pub dense: bool,
}

impl ClassSpectrum {
    /// The exponent of largest real part.
    pub fn leading(&self) -> Option<Exponent> {
        self.exponents.first().copied()
    }

    /// How many exponents have a real part above `tolerance` (1/s).
    pub fn unstable(&self, tolerance: f64) -> usize {
        self.exponents.iter().filter(|e| e.re > tolerance).count()
    }
}

/// The stability of one point: every class's exponents.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct PointStability {
    /// Angular frequency of the point, rad/s.
    pub omega: f64,
    /// Every class, in increasing nodal diameter.
    pub classes: Vec<ClassSpectrum>,
    /// A real part above this counts as growth, 1/s.
    pub tolerance: f64,
    /// The largest contact stiffness over the period and the wheel, N/m.
    pub peak_contact_stiffness: f64,
    /// When the contact is weak enough for the linear wheel's exponents to
    /// hold (see `stability::off_contact`): how far at most (rad/s) the
    /// contact moves them. `None`: solved by Hill's method.
    pub off_contact_bound: Option<f64>,
}

impl PointStability {
    /// Whether no exponent grows.
    pub fn stable(&self) -> bool {
        self.unstable_exponents() == 0
    }

    /// How many exponents of the whole wheel grow (each of a conjugate
    /// pair counted, as in the full wheel's spectrum).
    pub fn unstable_exponents(&self) -> usize {
        self.classes
            .iter()
            .map(|c| c.unstable(self.tolerance))
            .sum()
    }

    /// The class and exponent of largest real part.
    pub fn leading(&self) -> Option<(i64, Exponent)> {
        self.classes
            .iter()
            .filter_map(|c| c.leading().map(|e| (c.nodal_diameter, e)))
            .max_by(|a, b| a.1.re.total_cmp(&b.1.re))
    }

    /// The classes with a growing exponent.
    pub fn unstable_classes(&self) -> Vec<i64> {
        self.classes
            .iter()
            .filter(|c| c.unstable(self.tolerance) > 0)
            .map(|c| c.nodal_diameter)
            .collect()
    }

    /// The class of nodal diameter `sigma`.
    pub fn class(&self, sigma: i64) -> Option<&ClassSpectrum> {
        self.classes.iter().find(|c| c.nodal_diameter == sigma)
    }

    /// Every exponent of the wheel, largest real part first.
    pub fn all_exponents(&self) -> Vec<Exponent> {
        let mut all: Vec<Exponent> = self
            .classes
            .iter()
            .flat_map(|c| c.exponents.iter().copied())
            .collect();
        all.sort_by(|a, b| b.re.total_cmp(&a.re));
        all
    }
}
