//! Writing a results folder: the one place the bindings call the
//! library's writer, so that a change of its signature (the streaming
//! writer of issue 19) is adapted here only.

use crate::errors::Result;
use cyclorub::forced_response::Solution;
use cyclorub::results::output_folder::check_run_folder;
use std::path::Path;

/// Writes the folder `cyclorub run` writes for `solution` into `directory`
/// (made if needed). A folder that holds another run is refused unless
/// `overwrite` (then that run's files are removed first), as is a file or
/// a path under a file.
pub fn write_folder(solution: &Solution, directory: &Path, overwrite: bool) -> Result<()> {
    // Worded for Python (`overwrite=True`, not the command's flags).
    check_run_folder(directory, "directory", overwrite, "overwrite=True")?;
    cyclorub::run::prepare_output_folder(directory, overwrite)?;
    cyclorub::run::write(solution, directory)?;
    Ok(())
}
