//! Result files: `branch.csv` (one row per point), `observed_harmonics.csv`
//! (on demand: the observed dof's harmonic coefficients per point and
//! sector) and
//! `run.json` (the resolved case, basis sizes, timings, stop reason); and
//! beyond them what a person needs to judge a run: [`recovery`] of any dof
//! on any sector, [`components`] (cyclic, forward and backward), the
//! self-describing HDF5 file (`hdf5`, feature `hdf5`) built from [`data`],
//! and the reading of a results folder ([`folder`]).

pub mod bifurcated;
pub mod components;
pub mod data;
pub mod folder;
#[cfg(feature = "hdf5")]
pub mod hdf5;
mod mode;
pub mod output_folder;
pub mod peak;
pub mod recovery;
pub mod sizes;
pub mod stability;
pub mod stream;
pub mod summary;

pub use mode::RunMode;
use serde::Serialize;
use std::fs::File;
use std::io::{BufWriter, Write};
use std::path::{Path, PathBuf};

/// Errors writing results.
#[derive(Debug, thiserror::Error)]
pub enum ResultsError {
    /// A file or folder could not be written.
    #[error("cannot write {path}: {source}")]
    Io {
        /// The path.
        path: PathBuf,
        /// Why.
        source: std::io::Error,
    },
    /// A results file could not be read or has not the expected content.
    #[error("cannot read {path}: {message}")]
    Read {
        /// The path.
        path: PathBuf,
        /// What is wrong.
        message: String,
    },
    /// The HDF5 file could not be written or opened.
    #[error("HDF5 file {path}: {message}")]
    Hdf5 {
        /// The path.
        path: PathBuf,
        /// The HDF5 library's message.
        message: String,
    },
    /// Arguments that do not fit the problem (a sector or dof out of range,
    /// arrays of the wrong length).
    #[error("{0}")]
    Input(String),
    /// The harmonic balance problem failed during recovery.
    #[error(transparent)]
    Hbm(#[from] crate::hbm::HbmError),
}

impl ResultsError {
    /// Whether the error is in what the user gave (a results folder that
    /// cannot be read or does not fit, arguments out of range), as opposed
    /// to a failure while writing or recovering.
    pub fn is_input_error(&self) -> bool {
        matches!(self, Self::Read { .. } | Self::Input(_))
    }
}

fn io(path: &Path) -> impl FnOnce(std::io::Error) -> ResultsError + '_ {
    move |source| ResultsError::Io {
        path: path.to_path_buf(),
        source,
    }
}

/// One row of `branch.csv`.
#[derive(Clone, Debug, Serialize)]
pub struct BranchRow {
    /// Point index along the branch, from 0.
    pub point: usize,
    /// Frequency, Hz.
    pub frequency_hz: f64,
    /// Maximum over the period of the observed displacement, per reported sector, m.
    pub amplitudes: Vec<f64>,
    /// Newton iterations.
    pub iterations: usize,
    /// `‖R‖ / f_ex`.
    pub residual_norm: f64,
    /// Whether Newton converged.
    pub converged: bool,
    /// Whether the point is stable and how many exponents grow (when the
    /// stability check ran; see [`crate::stability`]).
    pub stability: Option<(bool, usize)>,
}

/// Writes `branch.csv` and, when asked, `observed_harmonics.csv` in a
/// results folder.
pub struct BranchFiles {
    branch: BufWriter<File>,
    harmonics: Option<BufWriter<File>>,
    directory: PathBuf,
    stability: bool,
}

impl BranchFiles {
    /// Creates the folder and the files with their headers; `sectors` are
    /// the reported sectors (1-based), `harmonics` is `N_h`; with
    /// `stability`, `branch.csv` ends with `stable,unstable_exponents`;
    /// `observed_harmonics.csv` only with `harmonics_csv`.
    pub fn create(
        directory: &Path,
        sectors: &[usize],
        harmonics: usize,
        stability: bool,
        harmonics_csv: bool,
    ) -> Result<Self, ResultsError> {
        std::fs::create_dir_all(directory).map_err(io(directory))?;
        let path = directory.join("branch.csv");
        let mut branch = BufWriter::new(File::create(&path).map_err(io(&path))?);
        let mut header = String::from("point,frequency_hz");
        for s in sectors {
            header.push_str(&format!(",amplitude_sector_{s}"));
        }
        header.push_str(",iterations,residual_norm,converged");
        if stability {
            header.push_str(",stable,unstable_exponents");
        }
        writeln!(branch, "{header}").map_err(io(&path))?;
        let file = if harmonics_csv {
            let path = directory.join("observed_harmonics.csv");
            let mut file = BufWriter::new(File::create(&path).map_err(io(&path))?);
            let mut header = String::from("point,frequency_hz,sector,a0");
            for k in 1..=harmonics {
                header.push_str(&format!(",re_{k},im_{k}"));
            }
            writeln!(file, "{header}").map_err(io(&path))?;
            Some(file)
        } else {
            None
        };
        Ok(Self {
            branch,
            harmonics: file,
            directory: directory.to_path_buf(),
            stability,
        })
    }

    /// Appends one point and flushes both files (see [`Self::write`]).
    pub fn push<C: AsRef<[f64]>>(
        &mut self,
        row: &BranchRow,
        sectors: &[usize],
        coordinates: &[C],
    ) -> Result<(), ResultsError> {
        self.write(row, sectors, coordinates)?;
        self.flush()
    }

    /// Writes what the buffers hold to both files.
    pub fn flush(&mut self) -> Result<(), ResultsError> {
        let path = self.directory.join("branch.csv");
        self.branch.flush().map_err(io(&path))?;
        let path = self.directory.join("observed_harmonics.csv");
        match &mut self.harmonics {
            Some(file) => file.flush().map_err(io(&path)),
            None => Ok(()),
        }
    }

    /// Appends one point, buffered: its row and (when the file is written)
    /// the observed dof's coordinates (`[a0, Re X1, Im X1, …]`, `u = a0 + Σ 2 Re(X_k e^{ikωt})`)
    /// per sector.
    pub fn write<C: AsRef<[f64]>>(
        &mut self,
        row: &BranchRow,
        sectors: &[usize],
        coordinates: &[C],
    ) -> Result<(), ResultsError> {
        let path = self.directory.join("branch.csv");
        // Straight into the buffered files: no string per line or value.
        let write_row = |out: &mut BufWriter<File>| -> std::io::Result<()> {
            write!(out, "{},{:.12e}", row.point, row.frequency_hz)?;
            for a in &row.amplitudes {
                write!(out, ",{a:.12e}")?;
            }
            write!(
                out,
                ",{},{:.6e},{}",
                row.iterations, row.residual_norm, row.converged
            )?;
            if self.stability {
                match row.stability {
                    Some((stable, unstable)) => write!(out, ",{},{unstable}", u8::from(stable))?,
                    None => write!(out, ",,")?,
                }
            }
            writeln!(out)
        };
        write_row(&mut self.branch).map_err(io(&path))?;
        let path = self.directory.join("observed_harmonics.csv");
        let write_harmonics = |out: &mut BufWriter<File>| -> std::io::Result<()> {
            for (sector, c) in sectors.iter().zip(coordinates) {
                write!(out, "{},{:.12e},{sector}", row.point, row.frequency_hz)?;
                for v in c.as_ref() {
                    write!(out, ",{v:.15e}")?;
                }
                writeln!(out)?;
            }
            Ok(())
        };
        match &mut self.harmonics {
            Some(file) => write_harmonics(file).map_err(io(&path)),
            None => Ok(()),
        }
    }
}

/// Writes `value` as pretty JSON to `directory/name`.
pub fn write_json(
    directory: &Path,
    name: &str,
    value: &impl Serialize,
) -> Result<PathBuf, ResultsError> {
    let path = directory.join(name);
    let text = serde_json::to_string_pretty(value).map_err(|e| ResultsError::Io {
        path: path.clone(),
        source: std::io::Error::other(e),
    })?;
    std::fs::write(&path, text + "\n").map_err(io(&path))?;
    Ok(path)
}
