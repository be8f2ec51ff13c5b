//! Writing a results folder: the one place the bindings call the
//! library's writer, so that a change of its signature (the streaming
//! writer of issue 19) is adapted here only.

use crate::errors::Result;
use cyclorub::forced_response::Solution;
use std::path::Path;

/// Writes the folder `cyclorub run` writes for `solution` into `directory`
/// (made if needed).
pub fn write_folder(solution: &Solution, directory: &Path) -> Result<()> {
    cyclorub::run::prepare_output_folder(directory)?;
    cyclorub::run::write(solution, directory)?;
    Ok(())
}
