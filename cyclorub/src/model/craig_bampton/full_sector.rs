//! The lowest natural frequencies of the full finite-element sector (every
//! dof kept but the clamped ones, no reduction) per nodal diameter: the
//! reference that the Craig–Bampton models are compared with
//! (`cyclorub modes` on a finite-element case), and their cache file.
//!
//! Per diameter `s = 0..=N/2`: the sparse `K(s)`, `M(s)` of
//! [`SparseSector::nodal_diameter_matrices`] on all kept dofs, the sparse
//! Cholesky factor of `K(s)` (positive definite: the sector is clamped),
//! and the subspace iteration of the fixed-interface modes. Nothing dense
//! of the sector's size is formed: the dense blocks are `n × max(2m, m+8)`
//! for `m` frequencies.

use super::cache::{checksum, Reader};
use super::error::ReductionError;
use super::subspace::lowest_modes;
use super::{InputDigest, ReductionCache, SparseSector};
use faer::Side;
use rayon::prelude::*;
use std::path::PathBuf;

/// The first bytes of a full-sector cache file (the format's version at the end).
const MAGIC: &[u8] = b"cyclorub full-sector frequencies v1\n";

/// The lowest `count` natural frequencies (Hz, ascending) of the full
/// sector for every unsigned nodal diameter `0..=N/2`, as
/// `(diameter, frequencies)` in diameter order: the shape of
/// `SectorModel::natural_frequencies`, so that both can be matched mode by
/// mode. Diameters are solved in parallel; a line per diameter is logged
/// (tracing, level info) as it finishes.
pub fn full_sector_frequencies(
    sector: &SparseSector,
    count: usize,
) -> Result<Vec<(usize, Vec<f64>)>, ReductionError> {
    sector.check()?;
    let dofs = sector.cyclic_dofs(&[], "full sector dofs")?;
    let kept = dofs.dofs.len();
    if count == 0 || count > kept {
        return Err(ReductionError::invalid(
            "full-sector modes",
            format!(
                "{count} is not allowed: between 1 and the {kept} kept dofs of the sector \
                 (all dofs but the clamped and right boundary ones)"
            ),
        ));
    }
    let diameters = sector.sectors / 2 + 1;
    tracing::info!(
        "full sector: the lowest {count} frequencies of each of {diameters} nodal diameters \
         ({kept} dofs, sparse)"
    );
    (0..diameters)
        .into_par_iter()
        .map(|d| {
            let started = std::time::Instant::now();
            let s = d as i64;
            let matrices = sector.nodal_diameter_matrices(s, &dofs)?;
            let factor = matrices.stiffness.sp_cholesky(Side::Lower).map_err(|e| {
                ReductionError::FullSectorNotPositiveDefinite {
                    nodal_diameter: s,
                    detail: match e {
                        faer::sparse::linalg::LltError::Numeric(n) => format!(" ({n:?})"),
                        faer::sparse::linalg::LltError::Generic(g) => format!(" (faer: {g:?})"),
                    },
                }
            })?;
            // K(s), M(s) are exactly real at diameters 0 and N/2 (phases ±1).
            let real = d == 0 || 2 * d == sector.sectors;
            let (values, _) = lowest_modes(&factor, &matrices.mass, count, s, real)?;
            let hertz = values
                .iter()
                .map(|&v| {
                    if v.is_finite() && v > 0.0 {
                        Ok(v.sqrt() / (2.0 * std::f64::consts::PI))
                    } else {
                        Err(ReductionError::NonFiniteResult {
                            nodal_diameter: s,
                            what: format!("the full sector's eigenvalue {v:e} (rad/s)²"),
                        })
                    }
                })
                .collect::<Result<Vec<f64>, _>>()?;
            tracing::info!(
                "full sector, nodal diameter {d}: {:.3?} Hz ({:.1} s)",
                hertz,
                started.elapsed().as_secs_f64()
            );
            Ok((d, hertz))
        })
        .collect()
}

impl InputDigest {
    /// The digest of everything the full sector's frequencies depend on,
    /// from the sector in memory: matrices (structure and values), dof
    /// lists, boundary frame, number of sectors and symmetry tolerance
    /// (not the count: a cache file holding more frequencies serves fewer).
    pub fn of_full_sector(sector: &SparseSector) -> Self {
        let mut digest = Self::new();
        digest.field(b"cyclorub full sector v1");
        for a in [&sector.mass, &sector.stiffness] {
            digest.integer(a.nrows() as u64).integer(a.ncols() as u64);
            digest.dofs(a.symbolic().col_ptr());
            digest.dofs(a.symbolic().row_idx());
            for v in a.val() {
                digest.bytes(&v.to_le_bytes());
            }
        }
        digest
            .dofs(&sector.clamped)
            .dofs(&sector.left_boundary)
            .dofs(&sector.right_boundary)
            .integer(sector.sectors as u64)
            .field(format!("{:?}", sector.boundary_frame).as_bytes())
            .bytes(&sector.symmetry_tolerance.to_le_bytes());
        digest
    }
}

impl ReductionCache {
    /// The full-sector frequencies file of `digest` (one file per input,
    /// whatever the count: it holds the count it was computed with).
    pub fn full_sector_path(&self, digest: &InputDigest) -> PathBuf {
        self.dir.join(format!("full-sector-{}.bin", digest.hex()))
    }

    /// The lowest `count` full-sector frequencies of `digest` per diameter
    /// `0..=sectors/2`, when the file is sound and holds at least `count`;
    /// otherwise why not.
    pub fn load_full_sector(
        &self,
        digest: &InputDigest,
        sectors: usize,
        count: usize,
    ) -> Result<Vec<(usize, Vec<f64>)>, String> {
        let path = self.full_sector_path(digest);
        let bytes = std::fs::read(&path).map_err(|e| format!("{}: {e}", path.display()))?;
        decode(&bytes, digest, sectors, count).map_err(|e| format!("{}: {e}", path.display()))
    }

    /// Writes the full-sector frequencies of `digest` (through a temporary
    /// file and a rename, so that a reader never sees half a file).
    pub fn store_full_sector(
        &self,
        digest: &InputDigest,
        frequencies: &[(usize, Vec<f64>)],
    ) -> std::io::Result<()> {
        self.write_whole(&self.full_sector_path(digest), encode(digest, frequencies))
    }
}

/// Magic, digest, diameters, count, then per diameter its number and
/// `count` frequencies (f64 bits), and the checksum of all that.
fn encode(digest: &InputDigest, frequencies: &[(usize, Vec<f64>)]) -> Vec<u8> {
    let count = frequencies.iter().map(|(_, f)| f.len()).min().unwrap_or(0);
    let mut out = MAGIC.to_vec();
    let mut put = |v: u64| out.extend_from_slice(&v.to_le_bytes());
    put(digest.fnv);
    put(digest.mix);
    put(frequencies.len() as u64);
    put(count as u64);
    for (d, f) in frequencies {
        put(*d as u64);
        for &v in &f[..count] {
            put(v.to_bits());
        }
    }
    let sum = checksum(&out);
    out.extend_from_slice(&sum);
    out
}

fn decode(
    bytes: &[u8],
    digest: &InputDigest,
    sectors: usize,
    count: usize,
) -> Result<Vec<(usize, Vec<f64>)>, String> {
    let body = bytes
        .len()
        .checked_sub(16)
        .filter(|&n| n >= MAGIC.len() && bytes.starts_with(MAGIC))
        .ok_or_else(|| "not a full-sector cache file of this version".to_string())?;
    if checksum(&bytes[..body]) != bytes[body..] {
        return Err("the checksum does not match: the file is corrupt".into());
    }
    let mut reader = Reader {
        bytes: &bytes[..body],
        at: MAGIC.len(),
    };
    if (reader.word()?, reader.word()?) != (digest.fnv, digest.mix) {
        return Err("the file holds another input's frequencies".into());
    }
    let diameters = sectors / 2 + 1;
    if reader.word()? != diameters as u64 {
        return Err("the number of nodal diameters differs".into());
    }
    let stored = usize::try_from(reader.word()?).map_err(|e| e.to_string())?;
    if stored < count {
        return Err(format!(
            "it holds {stored} frequencies per diameter, {count} are asked for"
        ));
    }
    let mut out = Vec::with_capacity(diameters);
    for d in 0..diameters {
        if reader.word()? != d as u64 {
            return Err(format!("the entry of nodal diameter {d} is out of place"));
        }
        let mut f = (0..stored)
            .map(|_| reader.finite())
            .collect::<Result<Vec<_>, _>>()?;
        if f.windows(2).any(|w| w[0] > w[1]) || f.first().is_some_and(|&v| v <= 0.0) {
            return Err(format!(
                "the frequencies of nodal diameter {d} are not positive and ascending"
            ));
        }
        f.truncate(count);
        out.push((d, f));
    }
    if reader.at != body {
        return Err("the file has trailing bytes".into());
    }
    Ok(out)
}
