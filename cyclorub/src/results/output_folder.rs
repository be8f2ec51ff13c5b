//! The folder a command writes into (`run`, `simulate` and `plot`'s
//! `--output`, the Python package's `save`): checked before any work, with
//! one wording for every caller, so that `/dev/full` or a path under a file
//! is said as such, not as the operating system's "File exists" or "Not a
//! directory" once the work is done.

use std::path::{Path, PathBuf};

/// Why a folder cannot be written into.
#[derive(Debug, thiserror::Error)]
pub enum OutputFolderError {
    /// The name is empty.
    #[error("the results folder ({named}) cannot be used: the name is empty; name a folder")]
    Empty {
        /// How the caller names the folder (`--output`, `directory` …).
        named: String,
    },
    /// The path, or a folder above it, is a file.
    #[error(
        "the results folder {} ({named}) cannot be used: {}",
        path.display(),
        file_message(path, file)
    )]
    File {
        /// The folder asked for.
        path: PathBuf,
        /// The file: the path itself or a folder above it.
        file: PathBuf,
        /// How the caller names the folder.
        named: String,
    },
    /// The folder holds another run's results and overwriting was not
    /// asked for.
    #[error(
        "the results folder {} ({named}) cannot be used: it holds the results of another run; \
         name another folder, or replace them ({overwrite})",
        path.display()
    )]
    HoldsARun {
        /// The folder.
        path: PathBuf,
        /// How the caller names the folder.
        named: String,
        /// How the caller asks for overwriting (`--overwrite`,
        /// `overwrite=True`).
        overwrite: String,
    },
}

fn file_message(path: &Path, file: &Path) -> String {
    if file == path {
        "it is a file, not a folder".into()
    } else {
        format!("{} is a file, not a folder", file.display())
    }
}

impl OutputFolderError {
    /// Always bad input: the caller named the folder.
    pub fn is_input_error(&self) -> bool {
        true
    }
}

/// Refuses an output folder `path` that cannot be a folder: an empty name,
/// a path that is a file (`/dev/full`), a path under a file. `named` says
/// how the caller names it in messages (`--output`, `output.directory or
/// --output`, `directory`). The folder is not made.
pub fn check_output_folder(path: &Path, named: &str) -> Result<(), OutputFolderError> {
    if path.as_os_str().is_empty() {
        return Err(OutputFolderError::Empty {
            named: named.into(),
        });
    }
    // The path itself, then each folder above it that exists.
    for at in path.ancestors().filter(|a| !a.as_os_str().is_empty()) {
        if at.exists() {
            if at.is_dir() {
                return Ok(());
            }
            return Err(OutputFolderError::File {
                path: path.to_path_buf(),
                file: at.to_path_buf(),
                named: named.into(),
            });
        }
    }
    Ok(())
}

/// [`check_output_folder`], then refuses a folder that holds another run's
/// results (its `run.json` or `branch.csv`) unless `overwrite`; `switch`
/// names how the caller asks for overwriting (`--overwrite`,
/// `overwrite=True`).
pub fn check_run_folder(
    path: &Path,
    named: &str,
    overwrite: bool,
    switch: &str,
) -> Result<(), OutputFolderError> {
    check_output_folder(path, named)?;
    let holds_a_run = ["run.json", "branch.csv"]
        .iter()
        .any(|name| path.join(name).exists());
    if holds_a_run && !overwrite {
        return Err(OutputFolderError::HoldsARun {
            path: path.to_path_buf(),
            named: named.into(),
            overwrite: switch.into(),
        });
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_file_and_a_path_under_a_file_are_named() {
        let dir =
            std::env::temp_dir().join(format!("cyclorub-output-folder-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let file = dir.join("a_file");
        std::fs::write(&file, "").unwrap();
        let message = check_output_folder(&file, "--output")
            .unwrap_err()
            .to_string();
        assert!(message.ends_with("it is a file, not a folder"), "{message}");
        let under = file.join("results");
        let message = check_output_folder(&under, "--output")
            .unwrap_err()
            .to_string();
        assert!(
            message.contains("a_file is a file, not a folder"),
            "{message}"
        );
        assert!(check_output_folder(&dir.join("new/deeper"), "--output").is_ok());
        std::fs::write(dir.join("run.json"), "{}").unwrap();
        let message = check_run_folder(&dir, "directory", false, "overwrite=True")
            .unwrap_err()
            .to_string();
        assert!(message.contains("(overwrite=True)"), "{message}");
        assert!(check_run_folder(&dir, "directory", true, "overwrite=True").is_ok());
        let _ = std::fs::remove_dir_all(&dir);
    }
}
