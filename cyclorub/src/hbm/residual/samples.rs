//! The contact state at every sampled instant of one point, for results.

use super::{form_law_variable, ContactSamples, HarmonicBalance};
use crate::hbm::HbmError;

impl HarmonicBalance {
    /// The contact state at `(x, omega)` at every sampled instant: the
    /// penetration, the force and, for a law that reads the linear residual,
    /// its input before correction.
    pub fn contact_samples(&mut self, x: &[f64], omega: f64) -> Result<ContactSamples, HbmError> {
        self.linear.update(&self.layout, omega)?;
        let size = self.layout.coordinates();
        let input = self.law.input();
        // `v` as the residual forms it, from the dense `Z` just updated.
        let mut residual = vec![0.0; x.len()];
        self.linear.multiply(&self.layout, x, false, &mut residual);
        for (r, f) in residual.iter_mut().zip(&self.linear.load) {
            *r -= f;
        }
        let mut v = vec![0.0; x.len()];
        form_law_variable(input.penetration, input.residual, x, &residual, &mut v);
        let mut coordinates = vec![0.0; self.layout.sector_coordinates()];
        self.to_sectors(x, &mut coordinates);
        let mut read = vec![0.0; self.layout.sector_coordinates()];
        self.to_sectors(&v, &mut read);
        let n_t = self.aft.time_samples();
        let (mut penetration, mut force, mut multiplier) = (vec![], vec![], vec![]);
        let mut samples = vec![0.0; n_t];
        for (index, gap) in self.gap_samples.iter().enumerate() {
            let band = self.normal_band(index);
            let range = band..band + size;
            self.aft.to_time(&coordinates[range.clone()], &mut samples);
            penetration.push(samples.iter().zip(gap).map(|(x, g)| x - g).collect());
            self.aft.to_time(&read[range], &mut samples);
            let mut f = vec![0.0; n_t];
            self.law.apply(&samples, gap, &mut f, None, None);
            force.push(f);
            if input.reads_residual() {
                multiplier.push(
                    samples
                        .iter()
                        .zip(gap)
                        .map(|(v, g)| v - input.penetration * g)
                        .collect(),
                );
            }
        }
        Ok(ContactSamples {
            sampled_sectors: self.layout.sampled_sectors,
            contact_dofs: self.normal_dofs,
            penetration,
            force,
            multiplier: input.reads_residual().then_some(multiplier),
        })
    }
}
