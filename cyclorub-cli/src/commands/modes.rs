//! `cyclorub modes` (being written).

use super::CliError;

/// Arguments of `cyclorub modes`.
#[derive(clap::Args)]
pub struct ModesArgs {}

/// Runs `cyclorub modes`.
pub fn execute(_args: ModesArgs) -> Result<(), CliError> {
    Err(CliError::failure("modes is not available yet"))
}
