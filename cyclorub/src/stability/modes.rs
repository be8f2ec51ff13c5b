//! Floquet modes: an exponent of one class with its Hill eigenvector,
//! mapped to the full wheel as a perturbation of the periodic point at
//! `t = 0` (phase 0, the instant the harmonic balance point's state is
//! rebuilt at, see `simulate::start::from_harmonic_balance`).
//!
//! Hill's eigenvector of `λ` holds amplitudes `Q_{s,k}` on the class's
//! pairs. The linearized dynamics then has the solution
//! `y_j(t) = e^{λt} Σ_{(s,k)} Q_{s,k} e^{ikωt} e^{−isαj}` on sector `j`
//! (0-based, docs/design.md §2: the pair `(s, k)` is the wave
//! `e^{i(kωt − sα(j−1))}` of sectors numbered from 1), and so has its real
//! part: starting the wheel from `Re(e^{iφ} y(0))`, `Re(e^{iφ} ẏ(0))`,
//! the perturbation evolves as `Re(e^{iφ} y(t))`, multiplied by `e^{λT}`
//! every period `T = 2π/ω`. Each copy `λ + imω` of an exponent gives the
//! same `y(t)`: the mode does not depend on which copy was picked.

use super::spectrum::Exponent;
use faer::c64;
use std::f64::consts::PI;

/// A Floquet exponent of one class and its mode on the full wheel at
/// `t = 0`, complex, sector-major (`[j · n + r]` for sector `j`, 0-based,
/// and sector dof `r`).
#[derive(Clone, Debug, PartialEq)]
pub struct FloquetMode {
    /// The class's nodal diameter `σ` (0 on the whole wheel).
    pub nodal_diameter: i64,
    /// `λ`, rad/s (the copy centred on the harmonics kept).
    pub exponent: Exponent,
    /// Angular frequency of the point, rad/s.
    pub omega: f64,
    /// The share of the eigenvector's weight on the highest harmonics
    /// kept: small (below 1e-3, say) when the truncation holds the mode.
    pub truncation: f64,
    /// `y(0)`, scaled so that its largest component is 1 (real).
    pub displacement: Vec<c64>,
    /// `ẏ(0)`, with the same scale, 1/s.
    pub velocity: Vec<c64>,
}

impl FloquetMode {
    /// The multiplier `e^{λT}` over one period `T = 2π/ω`.
    pub fn multiplier(&self) -> c64 {
        self.exponent.multiplier(self.omega)
    }

    /// The real perturbation `(Re(e^{iφ} y(0)), Re(e^{iφ} ẏ(0)))` of phase
    /// `phase` (rad). The ones of phases 0 and `π/2` evolve as the real
    /// and imaginary parts of `e^{λt}` times one mode: the root of the sum
    /// of their squared norms grows exactly as `|e^{λt}|` at period ends,
    /// with no beat between `λ` and its conjugate.
    pub fn real_state(&self, phase: f64) -> (Vec<f64>, Vec<f64>) {
        let turn = c64::cis(phase);
        let real = |v: &[c64]| v.iter().map(|z| (turn * z).re).collect();
        (real(&self.displacement), real(&self.velocity))
    }
}

/// The mode at `t = 0` of amplitudes `q` on `pairs` (one group of `dofs`
/// sector dofs per pair `(s, k)`, in order) for the exponent `lambda` at
/// `omega`, on a wheel of `sectors` sectors: `(y(0), ẏ(0))`, unscaled.
pub(super) fn sector_mode(
    q: &[c64],
    pairs: &[(i64, i64)],
    dofs: usize,
    sectors: usize,
    lambda: c64,
    omega: f64,
) -> (Vec<c64>, Vec<c64>) {
    let alpha = 2.0 * PI / sectors as f64;
    let mut displacement = vec![c64::new(0.0, 0.0); sectors * dofs];
    let mut velocity = displacement.clone();
    for (g, &(s, k)) in pairs.iter().enumerate() {
        let rate = lambda + c64::new(0.0, k as f64 * omega);
        for j in 0..sectors {
            // e^{−isαj}, the phase reduced modulo N first for accuracy.
            let wave = c64::cis(-alpha * (s * j as i64).rem_euclid(sectors as i64) as f64);
            for r in 0..dofs {
                let y = q[g * dofs + r] * wave;
                displacement[j * dofs + r] += y;
                velocity[j * dofs + r] += rate * y;
            }
        }
    }
    (displacement, velocity)
}

/// The mode at `t = 0` of amplitudes `q` on harmonics `harmonics` of the
/// whole wheel's `size` dofs (one group per harmonic): `(y(0), ẏ(0))`.
pub(super) fn wheel_mode(
    q: &[c64],
    harmonics: &[i64],
    size: usize,
    lambda: c64,
    omega: f64,
) -> (Vec<c64>, Vec<c64>) {
    let mut displacement = vec![c64::new(0.0, 0.0); size];
    let mut velocity = displacement.clone();
    for (g, &k) in harmonics.iter().enumerate() {
        let rate = lambda + c64::new(0.0, k as f64 * omega);
        for i in 0..size {
            displacement[i] += q[g * size + i];
            velocity[i] += rate * q[g * size + i];
        }
    }
    (displacement, velocity)
}

/// Scales `(y, ẏ)` so that the largest component of `y` is 1 (real);
/// `None` when `y` is zero.
pub(super) fn normalized(mut y: Vec<c64>, mut v: Vec<c64>) -> Option<(Vec<c64>, Vec<c64>)> {
    let largest = y
        .iter()
        .copied()
        .max_by(|a, b| a.norm_sqr().total_cmp(&b.norm_sqr()))?;
    if largest.norm_sqr() == 0.0 || !largest.norm_sqr().is_finite() {
        return None;
    }
    let scale = largest.inv();
    y.iter_mut().for_each(|z| *z *= scale);
    v.iter_mut().for_each(|z| *z *= scale);
    Some((y, v))
}
