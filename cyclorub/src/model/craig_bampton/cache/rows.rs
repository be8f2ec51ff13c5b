//! The reduced models together with the rows of each diameter's basis at
//! chosen dofs (a blade's, for mistuning), cached in one file so that the
//! model and its rows always come from one computation; trusted as the
//! reduced models' own file is (header, digest, sizes, checksum, finite
//! values).

use super::{checksum, put_reduced, put_words, read_reduced, InputDigest, Reader, ReductionCache};
use crate::model::craig_bampton::{CraigBamptonSettings, ReducedNodalDiameter};
use faer::{c64, Mat};
use std::path::PathBuf;

/// The first bytes of a rows cache file (the format's version at the end).
const MAGIC_ROWS: &[u8] = b"cyclorub craig-bampton rows cache v1\n";

/// Each nodal diameter's reduced model and its basis rows.
pub type ReducedWithRows = Vec<(ReducedNodalDiameter, Mat<c64>)>;

impl ReductionCache {
    /// The rows file of `digest`.
    pub fn rows_path(&self, digest: &InputDigest) -> PathBuf {
        self.dir
            .join(format!("craig-bampton-rows-{}.bin", digest.hex()))
    }

    /// The reduced models and basis rows of `digest` (`rows` rows each), or
    /// why the file cannot be trusted.
    pub fn load_with_rows(
        &self,
        digest: &InputDigest,
        sectors: usize,
        settings: &CraigBamptonSettings,
        rows: usize,
    ) -> Result<ReducedWithRows, String> {
        let path = self.rows_path(digest);
        let bytes = std::fs::read(&path).map_err(|e| format!("{}: {e}", path.display()))?;
        decode(&bytes, digest, sectors, settings, rows)
            .map_err(|e| format!("{}: {e}", path.display()))
    }

    /// Writes the reduced models and basis rows of `digest` (through a
    /// temporary file and a rename).
    pub fn store_with_rows(
        &self,
        digest: &InputDigest,
        reduced: &[(ReducedNodalDiameter, Mat<c64>)],
    ) -> std::io::Result<()> {
        self.write_whole(&self.rows_path(digest), encode(digest, reduced))
    }
}

fn encode(digest: &InputDigest, reduced: &[(ReducedNodalDiameter, Mat<c64>)]) -> Vec<u8> {
    let mut out = MAGIC_ROWS.to_vec();
    put_words(&mut out, &[digest.fnv, digest.mix]);
    let models: Vec<ReducedNodalDiameter> = reduced.iter().map(|(r, _)| r.clone()).collect();
    put_reduced(&mut out, &models);
    for (_, rows) in reduced {
        put_words(&mut out, &[rows.nrows() as u64, rows.ncols() as u64]);
        for j in 0..rows.ncols() {
            for i in 0..rows.nrows() {
                put_words(
                    &mut out,
                    &[rows[(i, j)].re.to_bits(), rows[(i, j)].im.to_bits()],
                );
            }
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
    settings: &CraigBamptonSettings,
    rows: usize,
) -> Result<ReducedWithRows, String> {
    let body = bytes
        .len()
        .checked_sub(16)
        .filter(|&n| n >= MAGIC_ROWS.len() && bytes.starts_with(MAGIC_ROWS))
        .ok_or_else(|| "not a rows cache file of this version".to_string())?;
    if checksum(&bytes[..body]) != bytes[body..] {
        return Err("the checksum does not match: the file is corrupt".into());
    }
    let mut reader = Reader {
        bytes: &bytes[..body],
        at: MAGIC_ROWS.len(),
    };
    if (reader.word()?, reader.word()?) != (digest.fnv, digest.mix) {
        return Err("the file holds another input's reduction".into());
    }
    let models = read_reduced(&mut reader, sectors, settings)?;
    let mut out = Vec::with_capacity(models.len());
    for (s, model) in models.into_iter().enumerate() {
        let cols = model.stiffness.ncols() as u64;
        if (reader.word()?, reader.word()?) != (rows as u64, cols) {
            return Err(format!(
                "the basis rows of nodal diameter {s} have other sizes"
            ));
        }
        let basis_rows = reader.rectangle(rows, cols as usize)?;
        out.push((model, basis_rows));
    }
    if reader.at != body {
        return Err("the file has trailing bytes".into());
    }
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn reduced(seed: f64) -> ReducedWithRows {
        (0..3)
            .map(|s| {
                let m =
                    |k: f64| Mat::from_fn(4, 4, |i, j| c64::new(seed + k + (i * 4 + j) as f64, k));
                (
                    ReducedNodalDiameter {
                        nodal_diameter: s,
                        mass: m(1.0),
                        stiffness: m(2.0),
                        interface_eigenvalues: vec![3.0, 4.0],
                    },
                    Mat::from_fn(5, 4, |i, j| c64::new(seed * (i + j) as f64, -(s as f64))),
                )
            })
            .collect()
    }

    /// A stored file reads back the same models and rows; another digest,
    /// other sizes, a flipped byte or a truncation are refused.
    #[test]
    fn reduced_models_with_their_rows_read_back_and_a_damaged_file_is_refused() {
        let dir = std::env::temp_dir().join(format!("cyclorub-rows-cache-{}", std::process::id()));
        let cache = ReductionCache::new(&dir);
        let mut digest = InputDigest::new();
        digest.field(b"test");
        let settings = CraigBamptonSettings {
            retained: vec![0, 1],
            internal_modes: 2,
        };
        let stored = reduced(0.5);
        cache
            .store_with_rows(&digest, &stored)
            .expect("a writable folder");
        let read = cache
            .load_with_rows(&digest, 5, &settings, 5)
            .expect("the file just written");
        assert_eq!(read.len(), stored.len());
        for ((a, ra), (b, rb)) in read.iter().zip(&stored) {
            assert_eq!(a.nodal_diameter, b.nodal_diameter);
            assert!(a.mass == b.mass && a.stiffness == b.stiffness && ra == rb);
            assert_eq!(a.interface_eigenvalues, b.interface_eigenvalues);
        }
        let mut other = digest;
        other.field(b"other");
        assert!(cache.load_with_rows(&other, 5, &settings, 5).is_err());
        assert!(cache.load_with_rows(&digest, 5, &settings, 6).is_err());
        let path = cache.rows_path(&digest);
        let mut bytes = std::fs::read(&path).expect("the file");
        let middle = bytes.len() / 2;
        bytes[middle] ^= 1;
        std::fs::write(&path, &bytes).expect("a writable file");
        let error = cache.load_with_rows(&digest, 5, &settings, 5).unwrap_err();
        assert!(error.contains("corrupt"), "{error}");
        std::fs::write(&path, &bytes[..middle]).expect("a writable file");
        assert!(cache.load_with_rows(&digest, 5, &settings, 5).is_err());
        let _ = std::fs::remove_dir_all(&dir);
    }
}
