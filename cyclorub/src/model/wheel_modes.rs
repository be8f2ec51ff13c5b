//! The modes of the whole wheel (issue 44 item 3, docs/design.md §12): of a
//! mistuned wheel, whose sectors differ, no nodal diameter holds a mode, so
//! the assembled full wheel `K φ = ω² M φ` is solved densely (Cholesky
//! `M = L Lᵀ`, then the symmetric eigenproblem of `L⁻¹ K L⁻ᵀ` by QR, whose
//! vectors stay accurate above 128 rows, see [`self_adjoint_eigen_by_qr`]).
//!
//! Each mode is described the way mistuning studies do:
//! - its **localization**: the share of the mode's kinetic energy held by
//!   the most active sector (`1/N` for a traveling wave, up to `2/N` for a
//!   tuned standing wave, up to 1 for a mode confined to one blade);
//! - its **nodal-diameter content**: the spatial DFT of the shape over the
//!   sectors, `Φ̂_s = Σ_j φ_j e^{−i s α j}`, as the share of the energy per
//!   unsigned nodal diameter `d = |s|` (a tuned mode has all of it on one).
//!
//! Both measure sector `j`'s motion with the sector's own mass block
//! `M_jj` (the same for every sector: mistuning scales stiffness only), so
//! that the shares add up to 1 exactly (Parseval).

use super::eigen::self_adjoint_eigen_by_qr;
use super::sector::SectorModel;
use super::ModelError;
use faer::{Mat, Side};
use std::f64::consts::PI;

/// One mode of the whole wheel.
#[derive(Clone, Debug)]
pub struct WheelMode {
    /// Natural frequency, Hz.
    pub frequency_hz: f64,
    /// The shape, mass-normalized (`φᵀ M φ = 1`), sector-major: dof `d` of
    /// sector `j` (0-based) at `j·dofs_per_sector + d`.
    pub shape: Vec<f64>,
    /// Share of the kinetic energy per sector (sector 1 first; sums to 1).
    pub sector_shares: Vec<f64>,
    /// Share of the energy per unsigned nodal diameter `0..=N/2` (sums to 1).
    pub nodal_diameter_shares: Vec<f64>,
}

impl WheelMode {
    /// The most active sector (0-based) and its share of the energy: the
    /// mode's localization.
    pub fn localization(&self) -> (usize, f64) {
        largest(&self.sector_shares)
    }

    /// The nodal diameter holding the largest share of the energy, and
    /// that share.
    pub fn dominant_nodal_diameter(&self) -> (usize, f64) {
        largest(&self.nodal_diameter_shares)
    }
}

/// The index and value of the largest entry (`(0, 0)` when empty).
fn largest(values: &[f64]) -> (usize, f64) {
    values.iter().copied().enumerate().fold(
        (0, 0.0),
        |best, (i, v)| if v > best.1 { (i, v) } else { best },
    )
}

impl SectorModel {
    /// The lowest `count` modes (all of them if `count` is larger) of the
    /// assembled full wheel, mistuning included (see the module's header).
    /// Dense: at most [`super::FULL_WHEEL_MAX_DOFS`] rows.
    pub fn wheel_modes(&self, count: usize) -> Result<Vec<WheelMode>, ModelError> {
        let wheel = self.full_wheel()?;
        let (mass, stiffness) = (&wheel.mass, &wheel.stiffness);
        let size = mass.nrows();
        let llt = mass
            .llt(Side::Lower)
            .map_err(|_| ModelError::MassNotPositiveDefinite {
                what: "full wheel mass".into(),
                nodal_diameter: None,
            })?;
        let l = llt.L();
        // A = L⁻¹ K L⁻ᵀ, symmetrized against round-off.
        let mut y = stiffness.clone();
        l.solve_lower_triangular_in_place(y.as_mut());
        let mut a: Mat<f64> = y.transpose().to_owned();
        l.solve_lower_triangular_in_place(a.as_mut());
        let a = Mat::from_fn(size, size, |i, j| 0.5 * (a[(i, j)] + a[(j, i)]));
        if (0..size).any(|i| (0..size).any(|j| !a[(i, j)].is_finite())) {
            return Err(ModelError::WheelEigen {
                message: "the stiffness holds non-finite values after the mass factorization"
                    .into(),
            });
        }
        let (values, mut shapes) =
            self_adjoint_eigen_by_qr(a.as_ref()).map_err(|_| ModelError::WheelEigen {
                message: "the symmetric eigenvalue solver did not converge".into(),
            })?;
        // Φ = L⁻ᵀ U: mass-normalized shapes.
        l.transpose()
            .solve_upper_triangular_in_place(shapes.as_mut());
        let scale = values.iter().fold(0.0_f64, |m, v| m.max(v.abs()));
        let sectors = self.sectors();
        let dofs = self.dofs_per_sector();
        let sector_mass = Mat::from_fn(dofs, dofs, |a, b| mass[(a, b)]);
        values
            .iter()
            .take(count)
            .enumerate()
            .map(|(m, &value)| {
                // Round-off negatives (rigid modes) are 0; a clearly
                // negative eigenvalue is an unstable stiffness.
                if !value.is_finite() || value < -1e-9 * scale {
                    return Err(ModelError::WheelEigen {
                        message: format!(
                            "eigenvalue {value:e} (rad/s)²: the stiffness is not positive \
                             semidefinite"
                        ),
                    });
                }
                let shape: Vec<f64> = (0..size).map(|r| shapes[(r, m)]).collect();
                let (sector_shares, nodal_diameter_shares) =
                    energy_shares(&shape, &sector_mass, sectors);
                Ok(WheelMode {
                    frequency_hz: value.max(0.0).sqrt() / (2.0 * PI),
                    shape,
                    sector_shares,
                    nodal_diameter_shares,
                })
            })
            .collect()
    }
}

/// The shares of `shape`'s energy `Σ_j φ_jᵀ M_s φ_j` (`M_s` a sector's mass
/// block) per sector, and per unsigned nodal diameter of its spatial DFT
/// (Parseval: `Σ_j ‖φ_j‖² = (1/N) Σ_s ‖Φ̂_s‖²` in the `M_s` norm).
fn energy_shares(shape: &[f64], sector_mass: &Mat<f64>, sectors: usize) -> (Vec<f64>, Vec<f64>) {
    let dofs = sector_mass.nrows();
    let norm = |re: &[f64], im: &[f64]| -> f64 {
        let mut sum = 0.0;
        for a in 0..dofs {
            for b in 0..dofs {
                let m = sector_mass[(a, b)];
                if m != 0.0 {
                    sum += m * (re[a] * re[b] + im[a] * im[b]);
                }
            }
        }
        sum
    };
    let zeros = vec![0.0; dofs];
    let per_sector: Vec<f64> = shape.chunks(dofs).map(|phi| norm(phi, &zeros)).collect();
    let total: f64 = per_sector.iter().sum();
    let alpha = 2.0 * PI / sectors as f64;
    let mut per_diameter = vec![0.0; sectors / 2 + 1];
    for s in 0..sectors {
        let (mut re, mut im) = (vec![0.0; dofs], vec![0.0; dofs]);
        for (j, phi) in shape.chunks(dofs).enumerate() {
            // exp(−i s α j), with s j reduced modulo N for accuracy.
            let angle = alpha * ((s * j) % sectors) as f64;
            let (sin, cos) = angle.sin_cos();
            for d in 0..dofs {
                re[d] += phi[d] * cos;
                im[d] -= phi[d] * sin;
            }
        }
        let diameter = s.min(sectors - s);
        per_diameter[diameter] += norm(&re, &im) / sectors as f64;
    }
    let share = |v: Vec<f64>| v.into_iter().map(|e| e / total).collect();
    (share(per_sector), share(per_diameter))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The tuned academic wheel: every mode lies on one nodal diameter, at
    /// that diameter's frequency, and is spread over the sectors (a tuned
    /// standing wave holds at most 2/N per sector).
    #[test]
    fn a_tuned_wheel_has_one_nodal_diameter_per_mode() {
        let model = SectorModel::academic(6).unwrap();
        let per_diameter = model.natural_frequencies().unwrap();
        let modes = model.wheel_modes(usize::MAX).unwrap();
        assert_eq!(modes.len(), 30);
        for mode in &modes {
            let (d, share) = mode.dominant_nodal_diameter();
            assert!((share - 1.0).abs() < 1e-10, "{mode:?}");
            let nearest = per_diameter[d]
                .1
                .iter()
                .map(|f| (f - mode.frequency_hz).abs())
                .fold(f64::INFINITY, f64::min);
            assert!(nearest < 1e-9 * mode.frequency_hz, "{mode:?}");
            let (_, localization) = mode.localization();
            assert!(localization <= 2.0 / 6.0 + 1e-10, "{mode:?}");
            let sum: f64 = mode.sector_shares.iter().sum();
            assert!((sum - 1.0).abs() < 1e-12);
        }
    }
}
