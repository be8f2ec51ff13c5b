//! `cyclorub init`: print a commented case file to start from, the paper's
//! default case or one of its academic studies.

use super::CliError;
use cyclorub_app::template::{default_template, listing, Example};

/// Arguments of `cyclorub init`.
#[derive(clap::Args)]
pub struct InitArgs {
    /// Print the case file of one of the paper's academic studies instead of
    /// the default case (`--list` shows their names).
    #[arg(long, value_name = "NAME", conflicts_with = "list")]
    pub example: Option<String>,
    /// List the examples (name, then what it is) and exit.
    #[arg(long)]
    pub list: bool,
}

/// Runs `cyclorub init`: the case file (or the list) on standard output.
pub fn execute(args: InitArgs) -> Result<(), CliError> {
    let text = if args.list {
        listing()
    } else {
        match args.example.as_deref() {
            None => default_template(),
            Some(name) => match Example::find(name) {
                Some(example) => example.template(),
                None => {
                    return Err(CliError::usage(format!(
                        "--example {name}: no such example; the examples are:\n{}",
                        listing().trim_end()
                    )))
                }
            },
        }
    };
    super::write_stdout(&text)
}
