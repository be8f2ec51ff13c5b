//! Reduced models cached on disk, keyed by a digest of the inputs, so that
//! a second run skips the reduction. A cache file is trusted only when its
//! header, its digest, its sizes and its checksum all match and every value
//! is finite; anything else (corrupt, truncated, stale, another version) is
//! recomputed and overwritten.

use super::{
    craig_bampton, CraigBamptonSettings, ReducedNodalDiameter, ReductionError, SparseSector,
};
use crate::model::BoundaryFrame;
use faer::{c64, Mat};
use std::path::{Path, PathBuf};

/// The first bytes of a cache file (the format's version at the end).
const MAGIC: &[u8] = b"cyclorub craig-bampton cache v1\n";

/// A 128-bit digest of the inputs of a reduction: two different 64-bit
/// hashes (FNV-1a, and a multiply–rotate hash) over the same bytes. Stable
/// across runs, platforms and compiler versions (unlike `std`'s hasher).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct InputDigest {
    pub(super) fnv: u64,
    pub(super) mix: u64,
}

impl Default for InputDigest {
    fn default() -> Self {
        Self {
            fnv: 0xcbf2_9ce4_8422_2325,
            mix: 0x9e37_79b9_7f4a_7c15,
        }
    }
}

impl InputDigest {
    /// An empty digest.
    pub fn new() -> Self {
        Self::default()
    }

    /// Adds bytes.
    pub fn bytes(&mut self, bytes: &[u8]) -> &mut Self {
        for &byte in bytes {
            self.fnv = (self.fnv ^ byte as u64).wrapping_mul(0x0000_0100_0000_01b3);
            self.mix = (self.mix.rotate_left(5) ^ byte as u64).wrapping_mul(0x517c_c1b7_2722_0a95);
        }
        self
    }

    /// Adds a length-prefixed byte string (so that `"ab" + "c"` and
    /// `"a" + "bc"` differ).
    pub fn field(&mut self, bytes: &[u8]) -> &mut Self {
        self.integer(bytes.len() as u64).bytes(bytes)
    }

    /// Adds an integer.
    pub fn integer(&mut self, value: u64) -> &mut Self {
        self.bytes(&value.to_le_bytes())
    }

    /// Adds a list of dofs.
    pub fn dofs(&mut self, dofs: &[usize]) -> &mut Self {
        self.integer(dofs.len() as u64);
        for &d in dofs {
            self.integer(d as u64);
        }
        self
    }

    /// The digest in hexadecimal (32 digits).
    pub fn hex(&self) -> String {
        format!("{:016x}{:016x}", self.fnv, self.mix)
    }

    /// The digest of everything a reduction depends on, from the sector in
    /// memory: matrices (structure and values), dof lists, boundary frame,
    /// number of sectors, and settings.
    pub fn of_reduction(sector: &SparseSector, settings: &CraigBamptonSettings) -> Self {
        let mut digest = Self::new();
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
            .dofs(&sector.right_boundary);
        digest.settings(sector.sectors, sector.boundary_frame, settings);
        digest.bytes(&sector.symmetry_tolerance.to_le_bytes());
        digest
    }

    /// Adds the number of sectors, the frame and the reduction settings.
    pub fn settings(
        &mut self,
        sectors: usize,
        frame: BoundaryFrame,
        settings: &CraigBamptonSettings,
    ) -> &mut Self {
        self.integer(sectors as u64)
            .field(format!("{frame:?}").as_bytes())
            .dofs(&settings.retained)
            .integer(settings.internal_modes as u64)
    }
}

/// How the reduced models were obtained.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum CacheOutcome {
    /// Read from the cache file.
    Hit(PathBuf),
    /// Computed (no usable cache file: the reason), and stored.
    Computed {
        /// The cache file.
        path: PathBuf,
        /// Why the cache was not used (missing, corrupt, stale).
        reason: String,
        /// Why the result could not be stored, if it could not.
        store_error: Option<String>,
    },
}

/// A folder of cached reduced models.
#[derive(Clone, Debug)]
pub struct ReductionCache {
    pub(super) dir: PathBuf,
}

impl ReductionCache {
    /// The cache in `dir` (created when first stored into).
    pub fn new(dir: impl Into<PathBuf>) -> Self {
        Self { dir: dir.into() }
    }

    /// The file of `digest`.
    pub fn path(&self, digest: &InputDigest) -> PathBuf {
        self.dir.join(format!("craig-bampton-{}.bin", digest.hex()))
    }

    /// The reduced models of `digest`, or why the file cannot be trusted.
    pub fn load(
        &self,
        digest: &InputDigest,
        sectors: usize,
        settings: &CraigBamptonSettings,
    ) -> Result<Vec<ReducedNodalDiameter>, String> {
        let path = self.path(digest);
        let bytes = std::fs::read(&path).map_err(|e| format!("{}: {e}", path.display()))?;
        decode(&bytes, digest, sectors, settings).map_err(|e| format!("{}: {e}", path.display()))
    }

    /// Writes the reduced models of `digest` (through a temporary file and
    /// a rename, so that a reader never sees half a file).
    pub fn store(
        &self,
        digest: &InputDigest,
        reduced: &[ReducedNodalDiameter],
    ) -> std::io::Result<()> {
        self.write_whole(&self.path(digest), encode(digest, reduced))
    }

    /// Writes `bytes` to `path` in the cache folder through a temporary
    /// file and a rename, so that a reader never sees half a file.
    pub(super) fn write_whole(&self, path: &Path, bytes: Vec<u8>) -> std::io::Result<()> {
        std::fs::create_dir_all(&self.dir)?;
        let temporary = path.with_extension(format!("tmp{}", std::process::id()));
        std::fs::write(&temporary, bytes)?;
        std::fs::rename(&temporary, path)
    }
}

/// [`craig_bampton`] through `cache`: read when the file of `digest` is
/// sound, computed and stored otherwise. `digest` must cover every input
/// ([`InputDigest::of_reduction`], or the input files' bytes and the
/// settings).
pub fn craig_bampton_cached(
    sector: &SparseSector,
    settings: &CraigBamptonSettings,
    cache: &ReductionCache,
    digest: &InputDigest,
) -> Result<(Vec<ReducedNodalDiameter>, CacheOutcome), ReductionError> {
    let path = cache.path(digest);
    let reason = match cache.load(digest, sector.sectors, settings) {
        Ok(reduced) => return Ok((reduced, CacheOutcome::Hit(path))),
        Err(reason) => reason,
    };
    let reduced = craig_bampton(sector, settings)?;
    let store_error = cache.store(digest, &reduced).err().map(|e| e.to_string());
    Ok((
        reduced,
        CacheOutcome::Computed {
            path,
            reason,
            store_error,
        },
    ))
}

/// The 128-bit digest of `bytes`, as the trailing checksum of a cache file.
pub(super) fn checksum(bytes: &[u8]) -> [u8; 16] {
    let mut digest = InputDigest::new();
    digest.bytes(bytes);
    let mut out = [0; 16];
    out[..8].copy_from_slice(&digest.fnv.to_le_bytes());
    out[8..].copy_from_slice(&digest.mix.to_le_bytes());
    out
}

fn encode(digest: &InputDigest, reduced: &[ReducedNodalDiameter]) -> Vec<u8> {
    let mut out = MAGIC.to_vec();
    put_words(&mut out, &[digest.fnv, digest.mix]);
    put_reduced(&mut out, reduced);
    let sum = checksum(&out);
    out.extend_from_slice(&sum);
    out
}

fn put_words(out: &mut Vec<u8>, words: &[u64]) {
    for v in words {
        out.extend_from_slice(&v.to_le_bytes());
    }
}

/// The reduced models' words: their count, then each diameter's sizes,
/// interface eigenvalues, mass and stiffness.
fn put_reduced(out: &mut Vec<u8>, reduced: &[ReducedNodalDiameter]) {
    let mut put = |v: u64| out.extend_from_slice(&v.to_le_bytes());
    put(reduced.len() as u64);
    for r in reduced {
        put(r.nodal_diameter as u64);
        put(r.stiffness.nrows() as u64);
        put(r.interface_eigenvalues.len() as u64);
        for &v in &r.interface_eigenvalues {
            put(v.to_bits());
        }
        for a in [&r.mass, &r.stiffness] {
            for j in 0..a.ncols() {
                for i in 0..a.nrows() {
                    put(a[(i, j)].re.to_bits());
                    put(a[(i, j)].im.to_bits());
                }
            }
        }
    }
}

/// Reads 8-byte little-endian words in order.
pub(super) struct Reader<'a> {
    pub(super) bytes: &'a [u8],
    pub(super) at: usize,
}

impl Reader<'_> {
    pub(super) fn word(&mut self) -> Result<u64, String> {
        let end = self.at + 8;
        let slice = self
            .bytes
            .get(self.at..end)
            .ok_or_else(|| "the file is truncated".to_string())?;
        self.at = end;
        let mut word = [0; 8];
        word.copy_from_slice(slice);
        Ok(u64::from_le_bytes(word))
    }

    pub(super) fn finite(&mut self) -> Result<f64, String> {
        let v = f64::from_bits(self.word()?);
        if v.is_finite() {
            Ok(v)
        } else {
            Err("a stored value is not finite".into())
        }
    }

    fn matrix(&mut self, size: usize) -> Result<Mat<c64>, String> {
        self.rectangle(size, size)
    }

    fn rectangle(&mut self, rows: usize, cols: usize) -> Result<Mat<c64>, String> {
        let mut a = Mat::<c64>::zeros(rows, cols);
        for j in 0..cols {
            for i in 0..rows {
                let re = self.finite()?;
                a[(i, j)] = c64::new(re, self.finite()?);
            }
        }
        Ok(a)
    }
}

fn decode(
    bytes: &[u8],
    digest: &InputDigest,
    sectors: usize,
    settings: &CraigBamptonSettings,
) -> Result<Vec<ReducedNodalDiameter>, String> {
    let body = bytes
        .len()
        .checked_sub(16)
        .filter(|&n| n >= MAGIC.len() && bytes.starts_with(MAGIC))
        .ok_or_else(|| "not a cache file of this version".to_string())?;
    if checksum(&bytes[..body]) != bytes[body..] {
        return Err("the checksum does not match: the file is corrupt".into());
    }
    let mut reader = Reader {
        bytes: &bytes[..body],
        at: MAGIC.len(),
    };
    if (reader.word()?, reader.word()?) != (digest.fnv, digest.mix) {
        return Err("the file holds another input's reduction".into());
    }
    let out = read_reduced(&mut reader, sectors, settings)?;
    if reader.at != body {
        return Err("the file has trailing bytes".into());
    }
    Ok(out)
}

/// The words of [`put_reduced`], checked against the sizes `sectors` and
/// `settings` give.
fn read_reduced(
    reader: &mut Reader<'_>,
    sectors: usize,
    settings: &CraigBamptonSettings,
) -> Result<Vec<ReducedNodalDiameter>, String> {
    let diameters = sectors / 2 + 1;
    if reader.word()? != diameters as u64 {
        return Err("the number of nodal diameters differs".into());
    }
    let size = settings.retained.len() + settings.internal_modes;
    let mut out = Vec::with_capacity(diameters);
    for s in 0..diameters {
        let expected = [s as u64, size as u64, settings.internal_modes as u64];
        for e in expected {
            if reader.word()? != e {
                return Err(format!("the sizes of nodal diameter {s} differ"));
            }
        }
        let values = (0..settings.internal_modes)
            .map(|_| reader.finite())
            .collect::<Result<Vec<_>, _>>()?;
        let mass = reader.matrix(size)?;
        let stiffness = reader.matrix(size)?;
        out.push(ReducedNodalDiameter {
            nodal_diameter: s as i64,
            mass,
            stiffness,
            interface_eigenvalues: values,
        });
    }
    Ok(out)
}

mod rows;
pub use rows::ReducedWithRows;

/// `dir/.cyclorub-cache`: the cache folder next to a case file.
pub fn cache_folder_next_to(case_dir: &Path) -> PathBuf {
    case_dir.join(".cyclorub-cache")
}
