//! `cyclorub plot RESULTS_DIR [--sectors 1,5] [--point P | --at-hz F]
//! [--reference DIR] [--output DIR]`: redraws the figures of a results
//! folder from its `results.h5`.

use super::{outln, CliError};
use cyclorub::plot::{write_figures, FigureOptions, Reference};
use cyclorub::results::hdf5;
use std::path::PathBuf;

/// Arguments of `cyclorub plot`.
#[derive(clap::Args)]
pub struct PlotArgs {
    /// Results folder written by `cyclorub run`.
    results: PathBuf,
    /// Sectors (1-based, comma-separated) of the forced response curves
    /// (default: sector 1 and the sectors of largest and smallest peak).
    #[arg(long, value_delimiter = ',')]
    sectors: Option<Vec<usize>>,
    /// Point (index along the branch, as in branch.csv) of the cyclic
    /// component bar chart (default: the point of largest amplitude).
    #[arg(long, conflicts_with = "at_hz")]
    point: Option<usize>,
    /// Take the point nearest to this frequency (Hz) for the bar chart.
    #[arg(long)]
    at_hz: Option<f64>,
    /// Another results folder of the same case, drawn dashed as the reference.
    #[arg(long)]
    reference: Option<PathBuf>,
    /// Folder for the figures (default: RESULTS/plots).
    #[arg(long)]
    output: Option<PathBuf>,
}

/// Runs `cyclorub plot`.
pub fn execute(args: PlotArgs) -> Result<(), CliError> {
    let file = args.results.join(hdf5::FILE_NAME);
    if !file.is_file() {
        return Err(CliError::usage(format!(
            "{} has no {}: give a results folder written by `cyclorub run`",
            args.results.display(),
            hdf5::FILE_NAME
        )));
    }
    let data = hdf5::read(&file).map_err(|e| CliError::usage(e.to_string()))?;
    let point = match (args.point, args.at_hz) {
        (Some(p), _) => Some(p),
        (None, Some(f)) if f.is_finite() && f > 0.0 => data.nearest_point(f),
        (None, Some(f)) => {
            return Err(CliError::usage(format!(
                "--at-hz {f}: give a finite frequency > 0 Hz"
            )))
        }
        (None, None) => None,
    };
    let reference = match &args.reference {
        Some(dir) => {
            Some(Reference::read(dir).map_err(|e| CliError::usage(format!("--reference: {e}")))?)
        }
        None => None,
    };
    let options = FigureOptions {
        sectors: args.sectors.clone(),
        point,
        reference,
        relative_floor: 0.0,
    };
    let output = args
        .output
        .clone()
        .unwrap_or_else(|| args.results.join(cyclorub::run::FIGURES_FOLDER));
    let written = write_figures(&output, &data, &options)?;
    for path in written {
        outln!("wrote {}", path.display());
    }
    Ok(())
}
