//! `cyclorub plot RESULTS_DIR [--sectors 1,5] [--point P | --at-hz F]
//! [--reference DIR] [--output DIR]`: redraws the figures of a results
//! folder from its `results.h5`.

use super::{outln, CliError};
use cyclorub::plot::{write_figures, FigureOptions, Reference};
use cyclorub::results::hdf5;
use cyclorub::results::output_folder::check_output_folder;
use cyclorub_app::compare::same_case;
use std::path::{Path, PathBuf};

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
    /// Another results folder of the same case, drawn dashed as the
    /// reference; for a mistuned run, also the tuned wheel (the same case
    /// without [mistuning]).
    #[arg(long)]
    reference: Option<PathBuf>,
    /// Folder for the figures (default: RESULTS/plots).
    #[arg(long)]
    output: Option<PathBuf>,
}

/// Runs `cyclorub plot`.
pub fn execute(args: PlotArgs) -> Result<(), CliError> {
    if let Some(output) = &args.output {
        // Worded as run's and simulate's.
        check_output_folder(output, "--output")?;
    }
    let file = args.results.join(hdf5::FILE_NAME);
    if !file.is_file() {
        return Err(CliError::usage(format!(
            "{} has no {}: give a results folder written by `cyclorub run`",
            args.results.display(),
            hdf5::FILE_NAME
        )));
    }
    let data = hdf5::read(&file).map_err(|e| CliError::usage(e.to_string()))?;
    if data.points.is_empty() {
        return Err(CliError::usage(format!(
            "{} holds 0 points (a run stopped or killed before its first point): nothing to plot",
            file.display()
        )));
    }
    let point = match (args.point, args.at_hz) {
        (Some(p), _) => Some(p),
        // Within the branch's range, the nearest point; beyond it refused
        // with the range (as `stability` and `recover` do).
        (None, Some(f)) if f.is_finite() && f > 0.0 => {
            Some(super::results_folder::choose_point(&data, None, Some(f))?.0)
        }
        (None, Some(f)) => {
            return Err(CliError::usage(format!(
                "--at-hz {f}: give a finite frequency > 0 Hz"
            )))
        }
        (None, None) => None,
    };
    let reference = match &args.reference {
        Some(dir) => {
            let tuned = same_case_as(&data.case_json, dir)?;
            let mut reference =
                Reference::read(dir).map_err(|e| CliError::usage(format!("--reference: {e}")))?;
            if tuned {
                // The mistuned run's own amplification factor is read
                // against this wheel: said in the legend.
                reference.label = reference.label.replacen("reference", "tuned wheel", 1);
                outln!(
                    "--reference {}: the tuned wheel (the same case without [mistuning]), drawn dashed",
                    dir.display()
                );
            }
            Some(reference)
        }
        None => None,
    };
    let options = FigureOptions {
        sectors: args.sectors.clone(),
        point,
        reference,
        relative_floor: 0.0,
        png: cyclorub::plot::figures::png_asked(&data),
        sizes: cyclorub::results::sizes::read(&args.results),
    };
    let output = args
        .output
        .clone()
        .unwrap_or_else(|| args.results.join(cyclorub::run::FIGURES_FOLDER));
    let mut written = write_figures(&output, &data, &options)?;
    // A mistuned run: its fan of sector curves and its bars of sector
    // peaks, the peaks as run.json records them.
    if let Some((peaks, tuned)) = mistuning_record(&args.results, data.sectors) {
        written.extend(cyclorub::plot::mistuning::write_mistuning_figures(
            &output,
            &data,
            &peaks,
            tuned,
            options.png,
        )?);
    }
    for path in written {
        outln!("wrote {}", path.display());
    }
    Ok(())
}

/// The sector peaks and the tuned peak (m) that run.json records of a
/// mistuned run of `sectors` sectors; `None` for a tuned run or a folder
/// without a readable run.json (then the figures it would give are not
/// drawn, with a warning when the record is there but unreadable).
fn mistuning_record(results: &Path, sectors: usize) -> Option<(Vec<f64>, Option<f64>)> {
    let path = results.join("run.json");
    let text = std::fs::read_to_string(&path).ok()?;
    let record = match cyclorub::results::folder::RunFile::parse(&path, &text) {
        Ok(run) => run.mistuning?,
        Err(e) => {
            tracing::warn!("{e}: the mistuning figures are not redrawn");
            return None;
        }
    };
    if record.sector_peaks_m.len() == sectors {
        Some((record.sector_peaks_m, record.tuned_peak_m))
    } else {
        tracing::warn!(
            "run.json's mistuning record has {} sector peaks for {sectors} sectors: the \
             mistuning figures are not redrawn",
            record.sector_peaks_m.len()
        );
        None
    }
}

/// Whether a case (JSON) has a `[mistuning]` (a non-empty table).
fn mistuned(case: &serde_json::Value) -> bool {
    match case.get("mistuning") {
        None | Some(serde_json::Value::Null) => false,
        Some(serde_json::Value::Object(table)) => table.values().any(|v| !v.is_null()),
        Some(_) => true,
    }
}

/// Refuses a reference folder of another case, as `cyclorub compare` does
/// ([`same_case`]): `ours` is results.h5's case (JSON), the reference's is
/// in its run.json. One difference is allowed: a mistuned run's reference
/// may be the tuned wheel (the same case without `[mistuning]`, what its
/// amplification factor is read against); `Ok(true)` then. A folder
/// without a readable run.json (a branch.csv from elsewhere) cannot be
/// checked: drawn, with a warning that says so.
fn same_case_as(ours: &str, dir: &Path) -> Result<bool, CliError> {
    let flag = format!("--reference {}", dir.display());
    let ours: serde_json::Value = serde_json::from_str(ours)
        .map_err(|e| CliError::usage(format!("the results' case: {e}")))?;
    let path = dir.join("run.json");
    let theirs = std::fs::read_to_string(&path)
        .map_err(|e| e.to_string())
        .and_then(|text| {
            serde_json::from_str::<serde_json::Value>(&text).map_err(|e| e.to_string())
        })
        .and_then(|run| {
            run.get("case")
                .cloned()
                .ok_or_else(|| "it records no case".to_string())
        });
    match theirs {
        Ok(mut theirs) => {
            let tuned_reference = mistuned(&ours) && !mistuned(&theirs);
            if mistuned(&theirs) && !mistuned(&ours) {
                return Err(CliError::usage(format!(
                    "{flag}: the reference is a mistuned wheel ([mistuning]) and these results \
                     are of the tuned one; draw the mistuned run with the tuned one as its \
                     reference (cyclorub plot MISTUNED --reference TUNED)"
                )));
            }
            let mut ours = ours;
            if tuned_reference {
                // Compared without the mistuning: the rest must agree.
                for case in [&mut ours, &mut theirs] {
                    if let Some(table) = case.as_object_mut() {
                        table.remove("mistuning");
                    }
                }
            }
            same_case(&ours, &theirs)
                .map(|()| tuned_reference)
                .map_err(|why| CliError::usage(format!("{flag}: {why}")))
        }
        Err(why) => {
            tracing::warn!(
                "{flag}: {} cannot tell its case ({why}): drawn without checking that it is a run of the same case",
                path.display()
            );
            Ok(false)
        }
    }
}
