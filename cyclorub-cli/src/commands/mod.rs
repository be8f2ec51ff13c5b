//! One module per subcommand; each turns library errors into messages.

pub mod compare;
pub mod init;
pub mod modes;
pub mod plan;
pub mod plot;
pub mod reproduce;
pub mod run;

/// A failure to report: the message and the process exit code.
#[derive(Debug)]
pub struct CliError {
    /// What went wrong, naming the argument or key and what is allowed.
    pub message: String,
    /// 2 for bad input (as clap), 1 for a failure during the work.
    pub exit_code: u8,
}

impl CliError {
    /// Bad input: exit code 2.
    pub fn usage(message: impl Into<String>) -> Self {
        Self {
            message: message.into(),
            exit_code: 2,
        }
    }

    /// A failure while working: exit code 1.
    pub fn failure(message: impl Into<String>) -> Self {
        Self {
            message: message.into(),
            exit_code: 1,
        }
    }
}
