//! `cyclorub run` (being written).

use super::CliError;

/// Arguments of `cyclorub run`.
#[derive(clap::Args)]
pub struct RunArgs {}

/// Runs `cyclorub run`.
pub fn execute(_args: RunArgs) -> Result<(), CliError> {
    Err(CliError::failure("run is not available yet"))
}
