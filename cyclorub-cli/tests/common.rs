//! What every CLI test file runs the binary with.

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
