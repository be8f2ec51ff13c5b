//! The static response of a sector model to a load that is the same on
//! every sector: nodal diameter 0 at rest, `K(0) u = f`.

use super::SectorModel;
use crate::model::ModelError;
use faer::linalg::solvers::Solve;
use faer::Mat;

impl SectorModel {
    /// The static displacement (m, per dof of a sector) under `force` (N
    /// per dof) applied alike on every sector; `key` names the load in
    /// errors.
    pub fn static_response(&self, force: &[f64], key: &str) -> Result<Vec<f64>, ModelError> {
        let dofs = self.dofs_per_sector();
        if force.len() != dofs {
            return Err(ModelError::invalid(
                key.to_string(),
                format!("{} values for a sector of {dofs} dofs", force.len()),
            ));
        }
        let stiffness = self.stiffness.at_real(0, self.sectors);
        let rhs = Mat::from_fn(dofs, 1, |r, _| force[r]);
        let u = stiffness.partial_piv_lu().solve(&rhs);
        let u: Vec<f64> = (0..dofs).map(|r| u[(r, 0)]).collect();
        // A wheel free to turn or translate has no static response.
        let residual = (0..dofs)
            .map(|r| {
                let row: f64 = (0..dofs).map(|c| stiffness[(r, c)] * u[c]).sum();
                (row - force[r]).abs()
            })
            .fold(0.0_f64, f64::max);
        let scale = force.iter().fold(0.0_f64, |m, f| m.max(f.abs()));
        if u.iter().any(|v| !v.is_finite()) || residual > 1e-8 * scale.max(f64::MIN_POSITIVE) {
            return Err(ModelError::invalid(
                key.to_string(),
                "the sector's stiffness at nodal diameter 0 is singular: the wheel is not held \
                 (clamp it, or ground a dof), so a static load has no static response",
            ));
        }
        Ok(u)
    }
}
