//! `cyclorub init` (being written).

use super::CliError;

/// Arguments of `cyclorub init`.
#[derive(clap::Args)]
pub struct InitArgs {}

/// Runs `cyclorub init`.
pub fn execute(_args: InitArgs) -> Result<(), CliError> {
    Err(CliError::failure("init is not available yet"))
}
