//! Cyclic components of a response (Figs. 6, 7, 9, 10, 12 and 20 of the
//! paper): the spatial DFT, harmonic by harmonic, of one dof's harmonic
//! coefficients on all `N` sectors, split into forward and backward waves.
//!
//! With `X_{j,k}` the coefficient of harmonic `k` on sector `j` (0-based,
//! `u_j = a0_j + Σ_k 2 Re(X_{j,k} e^{ikωt})`), the signed pair `(s, k)`,
//! the wave `e^{i(kωt − sαj)}`, has the coefficient
//! `c_{s,k} = (1/N) Σ_j X_{j,k} e^{isαj}`, so `X_{j,k} = Σ_s c_{s,k} e^{−isαj}`.
//!
//! On `k ≥ 1` the pair and its conjugate make the traveling wave
//! `2|c_{s,k}| cos(kωt − sαj + φ)`: its amplitude `2|c_{s,k}|` is the
//! forward component of nodal diameter `s` if `0 < s < N/2`, the backward
//! component of `|s|` if `s < 0`. On `k = 0` the field is static and real,
//! `c_{−s} = conj(c_s)`: the pattern of diameter `d` has amplitude `2|c_d|`,
//! shown as `|c_d|` forward and `|c_{−d}|` backward. Diameters `0` and `N/2`
//! are standing patterns: their amplitude is shown half forward and half
//! backward, as the paper does. So on every harmonic, forward + backward of
//! diameter `d` is the amplitude of that diameter's pattern, and a standing
//! wave `A cos(dαj) cos(kωt)` shows `A/2` forward and `A/2` backward.

use super::ResultsError;
use crate::cyclic::HarmonicSet;
use faer::c64;
use std::f64::consts::PI;

/// Forward and backward amplitudes per harmonic and nodal diameter.
#[derive(Clone, Debug, PartialEq)]
pub struct CyclicComponents {
    /// Number of sectors `N`.
    pub sectors: usize,
    /// `N_h`.
    pub harmonics: usize,
    /// `forward[k][d]`, `k = 0..=N_h`, `d = 0..=N/2` (floor), in the unit
    /// of the coordinates (m for a displacement).
    pub forward: Vec<Vec<f64>>,
    /// `backward[k][d]`, same shape.
    pub backward: Vec<Vec<f64>>,
}

impl CyclicComponents {
    /// The components of a field given by its real harmonic coordinates on
    /// every sector: `coordinates[j]` is sector `j` (0-based, all `N` of
    /// them), each `[a0, Re X1, Im X1, …]` of length `2 N_h + 1`.
    pub fn from_sector_coordinates(coordinates: &[Vec<f64>]) -> Result<Self, ResultsError> {
        let n = coordinates.len();
        if n == 0 {
            return Err(ResultsError::Input(
                "cyclic components need the coordinates of every sector; none given".into(),
            ));
        }
        let size = coordinates[0].len();
        let set = HarmonicSet::from_coordinates(size);
        let Some(set) = set.filter(|_| coordinates.iter().all(|c| c.len() == size)) else {
            return Err(ResultsError::Input(format!(
                "every sector needs 2 N_h + 1 harmonic coordinates (odd, the same for all); got lengths {:?}",
                coordinates.iter().map(Vec::len).collect::<Vec<_>>()
            )));
        };
        let m = n / 2;
        let twiddles = twiddles(n);
        let mut forward = vec![vec![0.0; m + 1]; set.count()];
        let mut backward = vec![vec![0.0; m + 1]; set.count()];
        for k in set {
            let value = |j: usize| coefficient(&coordinates[j], k);
            let c = spatial_dft(n, &twiddles, value);
            let scale = if k == 0 { 1.0 } else { 2.0 };
            for d in 0..=m {
                if d == 0 || 2 * d == n {
                    let half = 0.5 * scale * c[d].norm();
                    forward[k][d] = half;
                    backward[k][d] = half;
                } else {
                    forward[k][d] = scale * c[d].norm();
                    backward[k][d] = scale * c[n - d].norm();
                }
            }
        }
        Ok(Self {
            sectors: n,
            harmonics: set.highest(),
            forward,
            backward,
        })
    }

    /// Number of nodal diameters shown, `N/2 + 1` (floor).
    pub fn diameters(&self) -> usize {
        self.sectors / 2 + 1
    }

    /// The largest component of all.
    pub fn max(&self) -> f64 {
        self.forward
            .iter()
            .chain(&self.backward)
            .flatten()
            .fold(0.0_f64, |m, &v| m.max(v))
    }

    /// The nodal diameters whose largest component (over harmonics and
    /// directions) exceeds `relative` times [`Self::max`].
    pub fn significant_diameters(&self, relative: f64) -> Vec<usize> {
        let threshold = relative * self.max();
        (0..self.diameters())
            .filter(|&d| {
                HarmonicSet::up_to(self.harmonics)
                    .iter()
                    .any(|k| self.forward[k][d] > threshold || self.backward[k][d] > threshold)
            })
            .collect()
    }
}

/// The energy `|c_{s,k}|²` of every signed pair `(s, k)` of one or more
/// fields given on all `N` sectors (summed over the fields, e.g. every dof
/// of a sector): the measure of what a solution holds outside a basis.
///
/// On `k ≥ 1` the pair `(s, k)` stands for itself and its conjugate
/// `(−s, −k)`; on `k = 0` both `c_s` and `c_{−s}` are counted, so a basis
/// closed under conjugation keeps or drops them together.
#[derive(Clone, Debug, PartialEq)]
pub struct PairEnergies {
    /// Number of sectors `N`.
    pub sectors: usize,
    /// `N_h`.
    pub harmonics: usize,
    /// `energy[k][s mod N]`, in the unit of the coordinates squared.
    pub energy: Vec<Vec<f64>>,
}

impl PairEnergies {
    /// No energy yet, for fields of `sectors` sectors and `harmonics` harmonics.
    pub fn new(sectors: usize, harmonics: usize) -> Self {
        Self {
            sectors,
            harmonics,
            energy: vec![vec![0.0; sectors]; HarmonicSet::up_to(harmonics).count()],
        }
    }

    /// Adds the energy of one field, given as in
    /// [`CyclicComponents::from_sector_coordinates`].
    pub fn add_field(&mut self, coordinates: &[Vec<f64>]) -> Result<(), ResultsError> {
        let set = HarmonicSet::up_to(self.harmonics);
        let expected = set.coordinates();
        if coordinates.len() != self.sectors || coordinates.iter().any(|c| c.len() != expected) {
            return Err(ResultsError::Input(format!(
                "pair energies need {} sectors of {expected} harmonic coordinates; got {} sectors of lengths {:?}",
                self.sectors,
                coordinates.len(),
                coordinates.iter().map(Vec::len).collect::<Vec<_>>()
            )));
        }
        let twiddles = twiddles(self.sectors);
        for k in set {
            let value = |j: usize| coefficient(&coordinates[j], k);
            for (e, c) in self.energy[k]
                .iter_mut()
                .zip(spatial_dft(self.sectors, &twiddles, value))
            {
                *e += c.norm_sqr();
            }
        }
        Ok(())
    }

    /// The energy of every pair.
    pub fn total(&self) -> f64 {
        self.energy.iter().flatten().sum()
    }

    /// The energy of the pairs `(s, k)` that `kept(k, s)` rejects, `s`
    /// folded into `(−N/2, N/2]`.
    pub fn outside(&self, kept: impl Fn(usize, i64) -> bool) -> f64 {
        let mut sum = 0.0;
        for (k, row) in self.energy.iter().enumerate() {
            for (s, e) in row.iter().enumerate() {
                if !kept(
                    k,
                    crate::cyclic::fold_nodal_diameter(s as i64, self.sectors),
                ) {
                    sum += e;
                }
            }
        }
        sum
    }
}

/// The complex coefficient `X_k` of harmonic `k` in one sector's coordinates.
fn coefficient(coordinates: &[f64], harmonic: usize) -> c64 {
    let (re, im) = HarmonicSet::coefficient(coordinates, harmonic);
    c64::new(re, im)
}

/// `c_s = (1/N) Σ_j v(j) e^{isαj}` for `s = 0..N` (index `s mod N`), with
/// angles reduced through integers.
fn spatial_dft(n: usize, twiddles: &[c64], value: impl Fn(usize) -> c64) -> Vec<c64> {
    let values: Vec<c64> = (0..n).map(value).collect();
    (0..n)
        .map(|s| {
            values
                .iter()
                .enumerate()
                .map(|(j, v)| v * twiddles[(s * j) % n])
                .sum::<c64>()
                / n as f64
        })
        .collect()
}

/// `e^{iαm}`, `m = 0..n`, `α = 2π/n`: the factors of [`spatial_dft`],
/// computed once per field (the sines and cosines were most of the cost
/// of a long branch's output).
fn twiddles(n: usize) -> Vec<c64> {
    let alpha = 2.0 * PI / n as f64;
    (0..n).map(|m| c64::cis(alpha * m as f64)).collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Coordinates of `Σ (amplitude, s, k, phase)` traveling waves
    /// `A cos(kωt − sαj + φ)` on `n` sectors with `harmonics` harmonics.
    fn waves(n: usize, harmonics: usize, list: &[(f64, i64, usize, f64)]) -> Vec<Vec<f64>> {
        let alpha = 2.0 * PI / n as f64;
        (0..n)
            .map(|j| {
                let mut c = vec![0.0; 2 * harmonics + 1];
                for &(a, s, k, phi) in list {
                    let angle = phi - s as f64 * alpha * j as f64;
                    if k == 0 {
                        c[0] += a * angle.cos();
                    } else {
                        // A cos(θ) = 2 Re(A/2 e^{iθ}).
                        c[2 * k - 1] += 0.5 * a * angle.cos();
                        c[2 * k] += 0.5 * a * angle.sin();
                    }
                }
                c
            })
            .collect()
    }

    #[test]
    fn a_static_pattern_splits_half_and_half() {
        let c =
            CyclicComponents::from_sector_coordinates(&waves(8, 1, &[(2.0, 3, 0, 0.4)])).unwrap();
        assert!((c.forward[0][3] - 1.0).abs() < 1e-14);
        assert!((c.backward[0][3] - 1.0).abs() < 1e-14);
        let c =
            CyclicComponents::from_sector_coordinates(&waves(8, 1, &[(2.0, 0, 0, 0.0)])).unwrap();
        assert!((c.forward[0][0] - 1.0).abs() < 1e-14 && (c.backward[0][0] - 1.0).abs() < 1e-14);
    }

    #[test]
    fn pair_energies_hold_each_wave_on_its_own_pair() {
        // Two traveling waves and a static pattern on 9 sectors.
        let n = 9;
        let field = waves(
            n,
            3,
            &[(2.0, -2, 1, 0.3), (0.5, 4, 3, -1.0), (1.0, 3, 0, 0.2)],
        );
        let mut energies = PairEnergies::new(n, 3);
        energies.add_field(&field).unwrap();
        // A cos(kωt − sαj + φ) = 2 Re(A/2 e^{iφ} e^{i(kωt − sαj)}): |c| = A/2.
        assert!((energies.energy[1][n - 2] - 1.0).abs() < 1e-13);
        assert!((energies.energy[3][4] - 0.0625).abs() < 1e-14);
        // A static cos pattern of diameter 3 splits over c_3 and c_{−3}.
        assert!((energies.energy[0][3] - 0.25).abs() < 1e-14);
        assert!((energies.energy[0][n - 3] - 0.25).abs() < 1e-14);
        let kept = |k: usize, s: i64| matches!((k, s), (1, -2) | (3, 4) | (0, 3) | (0, -3));
        assert!(energies.outside(kept) < 1e-28 * energies.total());
        assert!((energies.outside(|k, _| k != 3) - 0.0625).abs() < 1e-14);
        // Parseval: Σ_s |c_s|² = (1/N) Σ_j |X_j|² on every harmonic.
        let direct: f64 = field
            .iter()
            .map(|c| {
                c[0] * c[0]
                    + (1..=3)
                        .map(|k| c[2 * k - 1].powi(2) + c[2 * k].powi(2))
                        .sum::<f64>()
            })
            .sum::<f64>()
            / n as f64;
        assert!((energies.total() - direct).abs() < 1e-13);
        assert!(energies.add_field(&field[1..]).is_err());
    }

    #[test]
    fn bad_shapes_are_refused() {
        assert!(CyclicComponents::from_sector_coordinates(&[]).is_err());
        assert!(CyclicComponents::from_sector_coordinates(&[vec![0.0; 3], vec![0.0; 5]]).is_err());
        assert!(CyclicComponents::from_sector_coordinates(&[vec![0.0; 4]]).is_err());
    }
}
