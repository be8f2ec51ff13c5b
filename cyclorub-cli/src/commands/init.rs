//! `cyclorub init`: print a commented case file to start from, the paper's
//! default case, one of its academic studies or one of its Sec. 5 studies
//! on the open fan.

use super::CliError;
use cyclorub_app::template::{default_template, example_template, listing};

/// Arguments of `cyclorub init`.
#[derive(clap::Args)]
pub struct InitArgs {
    /// Print the case file of one of the paper's studies (academic, or on
    /// the open fan) instead of the default case (`--list` shows their
    /// names).
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
            Some(name) => match example_template(name) {
                Some(text) => text,
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
