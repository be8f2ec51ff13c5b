//! `cyclorub plan` (being written).

use super::CliError;

/// Arguments of `cyclorub plan`.
#[derive(clap::Args)]
pub struct PlanArgs {}

/// Runs `cyclorub plan`.
pub fn execute(_args: PlanArgs) -> Result<(), CliError> {
    Err(CliError::failure("plan is not available yet"))
}
