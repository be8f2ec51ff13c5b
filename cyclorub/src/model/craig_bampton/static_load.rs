//! The static response of the full finite-element sector to a load that is
//! the same on every sector (nodal diameter 0): the centrifugal preload of
//! a wheel spinning at a constant speed, and its body force `Ω² M r`.
//!
//! `K(0) q = T(0)ᵀ f` on the kept dofs (sparse Cholesky: the sector is
//! clamped), then `u = T(0) q` on every dof: a right boundary dof takes the
//! value of its left twin (turned by `2π/N` in a Cartesian boundary frame),
//! a clamped dof is 0.

use super::cache::{checksum, Reader};
use super::error::ReductionError;
use super::{InputDigest, ReductionCache, SparseSector};
use crate::model::Axis;
use faer::linalg::solvers::Solve;
use faer::{c64, Mat, Side};
use std::path::PathBuf;

/// The first line of a centrifugal cache file.
const MAGIC: &[u8] = b"cyclorub centrifugal displacement v1\n";

impl SparseSector {
    /// The static displacement (m, every dof of the sector) under the load
    /// `force` (N, one value per dof) applied alike on every sector.
    pub fn static_displacement(&self, force: &[f64]) -> Result<Vec<f64>, ReductionError> {
        let n = self.size();
        if force.len() != n {
            return Err(ReductionError::invalid(
                "static load",
                format!("{} values for a sector of {n} dofs", force.len()),
            ));
        }
        if let Some(d) = force.iter().position(|v| !v.is_finite()) {
            return Err(ReductionError::invalid(
                "static load",
                format!(
                    "the value of dof {} is {}, not a finite number",
                    d + 1,
                    force[d]
                ),
            ));
        }
        self.check()?;
        let dofs = self.cyclic_dofs(&[], "static load")?;
        let map = self.cyclic_map(0, &dofs);
        let matrices = self.nodal_diameter_matrices(0, &dofs)?;
        let factor = matrices.stiffness.sp_cholesky(Side::Lower).map_err(|e| {
            ReductionError::FullSectorNotPositiveDefinite {
                nodal_diameter: 0,
                detail: match e {
                    faer::sparse::linalg::LltError::Numeric(n) => format!(" ({n:?})"),
                    faer::sparse::linalg::LltError::Generic(g) => format!(" (faer: {g:?})"),
                },
            }
        })?;
        // T(0)ᵀ f: each dof's force goes to the kept dofs it is made of.
        let mut reduced = Mat::<c64>::zeros(dofs.dofs.len(), 1);
        for (d, row) in map.iter().enumerate() {
            for &(r, weight) in row {
                reduced[(r, 0)] += weight.conj() * force[d];
            }
        }
        let q = factor.solve(&reduced);
        let u: Vec<f64> = map
            .iter()
            .map(|row| row.iter().map(|&(r, weight)| (weight * q[(r, 0)]).re).sum())
            .collect();
        if let Some(d) = u.iter().position(|v| !v.is_finite()) {
            return Err(ReductionError::NonFiniteResult {
                nodal_diameter: 0,
                what: format!("the static displacement of dof {}", d + 1),
            });
        }
        Ok(u)
    }

    /// The centrifugal body force `Ω² M r⊥` (N, every dof): `r⊥` the
    /// position of each node away from `axis` (through the origin),
    /// `coordinates` one point per node (m), `speed` Ω in rad/s. The
    /// consistent mass spreads it exactly as the element's inertia does.
    pub fn centrifugal_force(
        &self,
        coordinates: &[[f64; 3]],
        axis: Axis,
        speed: f64,
    ) -> Result<Vec<f64>, ReductionError> {
        let n = self.size();
        if 3 * coordinates.len() != n {
            return Err(ReductionError::invalid(
                "centrifugal load",
                format!(
                    "{} nodes for a sector of {n} dofs (3 per node)",
                    coordinates.len()
                ),
            ));
        }
        let a = match axis {
            Axis::X => [1.0, 0.0, 0.0],
            Axis::Y => [0.0, 1.0, 0.0],
            Axis::Z => [0.0, 0.0, 1.0],
        };
        let away: Vec<f64> = coordinates
            .iter()
            .flat_map(|p| {
                let along = p[0] * a[0] + p[1] * a[1] + p[2] * a[2];
                [
                    p[0] - along * a[0],
                    p[1] - along * a[1],
                    p[2] - along * a[2],
                ]
            })
            .collect();
        let mut force = vec![0.0; n];
        let col_ptr = self.mass.symbolic().col_ptr();
        let rows = self.mass.symbolic().row_idx();
        let values = self.mass.val();
        let omega2 = speed * speed;
        for (j, &r) in away.iter().enumerate() {
            for p in col_ptr[j]..col_ptr[j + 1] {
                force[rows[p]] += omega2 * values[p] * r;
            }
        }
        Ok(force)
    }
}

impl ReductionCache {
    /// Where the static displacement under the centrifugal load at 1 rad/s
    /// of `digest` is kept (`centrifugal-<digest>.bin`): the response is
    /// linear in `Ω²`, so one file serves every speed.
    pub fn centrifugal_path(&self, digest: &InputDigest) -> PathBuf {
        self.dir.join(format!("centrifugal-{}.bin", digest.hex()))
    }

    /// The displacement of `digest` (`dofs` values), when the file is
    /// sound; otherwise why not.
    pub fn load_centrifugal(&self, digest: &InputDigest, dofs: usize) -> Result<Vec<f64>, String> {
        let path = self.centrifugal_path(digest);
        let bytes = std::fs::read(&path).map_err(|e| format!("{}: {e}", path.display()))?;
        let body = bytes
            .len()
            .checked_sub(16)
            .filter(|&n| n >= MAGIC.len() && bytes.starts_with(MAGIC))
            .ok_or_else(|| {
                format!(
                    "{}: not a centrifugal cache file of this version",
                    path.display()
                )
            })?;
        if checksum(&bytes[..body]) != bytes[body..] {
            return Err(format!("{}: the checksum does not match", path.display()));
        }
        let mut reader = Reader {
            bytes: &bytes[..body],
            at: MAGIC.len(),
        };
        let header = (reader.word()?, reader.word()?, reader.word()?);
        if header != (digest.fnv, digest.mix, dofs as u64) {
            return Err(format!(
                "{}: the file holds another input's displacement",
                path.display()
            ));
        }
        let values = (0..dofs)
            .map(|_| reader.finite())
            .collect::<Result<Vec<_>, _>>()?;
        if reader.at != body {
            return Err(format!("{}: the file has trailing bytes", path.display()));
        }
        Ok(values)
    }

    /// Writes the displacement of `digest` (through a temporary file and a
    /// rename, so that a reader never sees half a file).
    pub fn store_centrifugal(&self, digest: &InputDigest, values: &[f64]) -> std::io::Result<()> {
        let mut out = MAGIC.to_vec();
        for word in [digest.fnv, digest.mix, values.len() as u64]
            .into_iter()
            .chain(values.iter().map(|v| v.to_bits()))
        {
            out.extend_from_slice(&word.to_le_bytes());
        }
        let sum = checksum(&out);
        out.extend_from_slice(&sum);
        self.write_whole(&self.centrifugal_path(digest), out)
    }
}
