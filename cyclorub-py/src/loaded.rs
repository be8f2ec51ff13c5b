//! A results folder read back for `cyclorub.load`, through the library's
//! one reader of a results folder (`ResultsFolder::read_with_results_file`,
//! issue 41 item 4): `run.json` typed, `results.h5` whole. The CLI and the
//! app read folders through the same reader.

use crate::errors::{Error, Result};
use cyclorub::case::BasisChoice;
use cyclorub::results::data::ResultsData;
use cyclorub::results::folder::{ResultsFolder, RunFile};
use std::path::{Path, PathBuf};

/// What a loaded result keeps of its folder.
pub struct LoadedFolder {
    /// The folder.
    pub directory: PathBuf,
    /// Its `run.json`, typed.
    pub record: RunFile,
    /// The basis its branch was solved on (`run.json`'s basis kind).
    pub basis: BasisChoice,
}

/// Reads the results folder `directory` (written by `cyclorub run` or
/// `Result.save`): what the result keeps of it, and everything its
/// `results.h5` holds.
pub fn read(directory: &Path) -> Result<(LoadedFolder, ResultsData)> {
    let folder = ResultsFolder::read_with_results_file(directory)?;
    let basis = folder.record.basis_choice(&directory.join("run.json"))?;
    let data = folder.data.ok_or_else(|| {
        Error::internal(format!(
            "{}: results.h5 was not read (please report it)",
            directory.display()
        ))
    })?;
    Ok((
        LoadedFolder {
            directory: folder.path,
            record: folder.record,
            basis,
        },
        data,
    ))
}
