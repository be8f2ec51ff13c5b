//! One module per subcommand. Library errors become messages as they are:
//! the library words them and says which are bad input ([`Classified`]).

pub mod branches;
mod branches_files;
pub mod compare;
pub mod init;
pub mod mesh;
pub mod modes;
pub mod plan;
pub mod plot;
pub mod recover;
pub mod reproduce;
mod results_folder;
pub mod run;
mod run_sizes;
pub mod simulate;
mod simulate_sources;
pub mod stability;
pub mod study;

/// `println!` that returns a [`CliError`] (exit 1) when standard output
/// cannot be written (a full disk, `> /dev/full`) instead of panicking;
/// a closed pipe still ends the process quietly (SIGPIPE, see `main`).
macro_rules! outln {
    ($($arg:tt)*) => {
        $crate::commands::write_stdout(&format!("{}\n", format_args!($($arg)*)))?
    };
}
pub(crate) use outln;

/// Writes `text` to standard output and flushes it; a failure is an
/// error to report, not a panic.
pub fn write_stdout(text: &str) -> Result<(), CliError> {
    use std::io::Write as _;
    let mut out = std::io::stdout().lock();
    out.write_all(text.as_bytes())
        .and_then(|()| out.flush())
        .map_err(|e| CliError::failure(format!("cannot write to standard output: {e}")))
}

/// A library error that says whether it is bad input (its
/// `is_input_error`): bad input exits with 2, anything else with 1.
pub trait Classified: std::fmt::Display {
    /// Whether the error is in what the user gave.
    fn is_input_error(&self) -> bool;
}

macro_rules! classified {
    ($($error:ty),* $(,)?) => {
        $(impl Classified for $error {
            fn is_input_error(&self) -> bool {
                <$error>::is_input_error(self)
            }
        })*
    };
}

classified!(
    cyclorub::run::RunError,
    cyclorub::model::ModelError,
    cyclorub::mesh::MeshError,
    cyclorub::results::ResultsError,
    cyclorub::results::output_folder::OutputFolderError,
    cyclorub::plot::PlotError,
    cyclorub::simulate::SimulateError,
    cyclorub::branches::BranchError,
    cyclorub_app::plan::PlanError,
    cyclorub_app::reproduce::ReproduceError,
);

impl<E: Classified> From<E> for CliError {
    fn from(error: E) -> Self {
        if error.is_input_error() {
            Self::usage(error.to_string())
        } else {
            Self::failure(error.to_string())
        }
    }
}

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
