//! What every CLI test file runs the binary with.

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

/// Runs the `cyclorub` binary built for the tests with `args` (log level
/// `warn`), waiting for its output.
pub fn cyclorub(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_cyclorub"))
        .args(args)
        .env("RUST_LOG", "warn")
        .output()
        .expect("the cyclorub binary runs")
}

/// A run's standard output then its standard error, as text.
pub fn text(output: &Output) -> String {
    format!(
        "{}{}",
        String::from_utf8_lossy(&output.stdout),
        String::from_utf8_lossy(&output.stderr)
    )
}

/// The HDF5 C library's reading of a results file through h5py: the
/// library's tests' helper, shared.
#[path = "../../cyclorub/tests/common/h5py.rs"]
pub mod h5py;

/// A test's scratch folder: removed when the test passes (the guard is
/// dropped without a panic), kept when it fails, as the evidence.
pub struct Scratch(PathBuf);

impl std::ops::Deref for Scratch {
    type Target = Path;
    fn deref(&self) -> &Path {
        &self.0
    }
}

impl AsRef<Path> for Scratch {
    fn as_ref(&self) -> &Path {
        &self.0
    }
}

impl Drop for Scratch {
    fn drop(&mut self) {
        if !std::thread::panicking() {
            let _ = std::fs::remove_dir_all(&self.0);
        }
    }
}

/// A fresh, empty `cyclorub-{kind}-{pid}-{name}` folder in the system's
/// temporary folder, removed when the test passes.
pub fn scratch(kind: &str, name: &str) -> Scratch {
    let dir = std::env::temp_dir().join(format!("cyclorub-{kind}-{}-{name}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).expect("the scratch folder is made");
    Scratch(dir)
}
