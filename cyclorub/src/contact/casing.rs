//! The casing seen by the contact dofs: the gap `g0(t)` of Eq. (74).

use std::f64::consts::PI;

/// The casing seen by each contact dof: `g0_j(t) = c + p cos(h_c(ωt − α j))`
/// (Eq. 74, sectors `j = 1..N`, rotating synchronously, Ω = ω).
#[derive(Clone, Debug, PartialEq)]
pub struct Casing {
    /// Mean gap `c` per contact dof, m.
    pub gaps: Vec<f64>,
    /// Diametral order `h_c` (0: circular).
    pub order: usize,
    /// Amplitude `p` of the diametral shape per contact dof, m.
    pub amplitudes: Vec<f64>,
}

impl Casing {
    /// The gap `g0(τ_n) = c + p cos(h_c τ_n − h_c α (j + 1))`, `τ_n = 2π n / N_t`,
    /// of contact dof `contact` on sector `sector` (0-based `j`) of a wheel of
    /// `sectors` sectors. The one formula the residual and the recovery use.
    ///
    /// # Panics
    /// If `contact` is not below the number of gaps and amplitudes (the
    /// problem checks their lengths when it is built).
    pub fn gap_samples(
        &self,
        sectors: usize,
        sector: usize,
        contact: usize,
        time_samples: usize,
    ) -> Vec<f64> {
        (0..time_samples)
            .map(|n| {
                let tau = 2.0 * PI * n as f64 / time_samples as f64;
                self.gap_at(sectors, sector, contact, tau)
            })
            .collect()
    }

    /// The gap `g0 = c + p cos(h_c τ − h_c α (j + 1))` of contact dof
    /// `contact` on sector `sector` (0-based `j`) at the phase `τ = ωt` of
    /// the rotation (radians; a time integration passes the phase it has
    /// reached, a sweep included).
    ///
    /// # Panics
    /// If `contact` is not below the number of gaps and amplitudes.
    pub fn gap_at(&self, sectors: usize, sector: usize, contact: usize, phase: f64) -> f64 {
        let (gap, amplitude) = (self.gaps[contact], self.amplitudes[contact]);
        if self.order == 0 || amplitude == 0.0 {
            return gap + amplitude;
        }
        let alpha = 2.0 * PI / sectors as f64;
        let h_c = self.order as f64;
        gap + amplitude * (h_c * phase - h_c * alpha * (sector + 1) as f64).cos()
    }

    /// Whether there is one gap and one amplitude per contact dof.
    pub fn fits(&self, contact_dofs: usize) -> bool {
        self.gaps.len() == contact_dofs && self.amplitudes.len() == contact_dofs
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_diametral_casing_turns_one_sector_per_alpha() {
        let casing = Casing {
            gaps: vec![1e-3],
            order: 3,
            amplitudes: vec![5e-5],
        };
        let (n, n_t) = (24, 48);
        // Sector j + 1 sees at τ + α what sector j sees at τ: α = 2π/24 is
        // 2 of 48 samples.
        let first = casing.gap_samples(n, 0, 0, n_t);
        let second = casing.gap_samples(n, 1, 0, n_t);
        for i in 0..n_t {
            assert!((second[(i + 2) % n_t] - first[i]).abs() < 1e-15);
        }
        let circular = Casing { order: 0, ..casing };
        assert!(circular
            .gap_samples(n, 5, 0, n_t)
            .iter()
            .all(|&g| (g - 1.05e-3).abs() < 1e-18));
    }
}
