//! `cyclorub modes`: natural frequencies per nodal diameter of a case's model.

use super::{outln, CliError};
use cyclorub::model::{ModelKind, ModelSpec, SectorModel};
use cyclorub::plot::frequency_versus_nodal_diameter;
use std::path::{Path, PathBuf};

/// Arguments of `cyclorub modes`.
#[derive(clap::Args)]
pub struct ModesArgs {
    /// The case file (TOML); only its `[model]` table is read. Without it,
    /// the paper's academic model with N = 24.
    pub case: Option<PathBuf>,
    /// Where to write the frequency versus nodal diameter plot (SVG);
    /// default `modes.svg` next to the case file (or in the current
    /// directory without a case file).
    #[arg(long, short)]
    pub output: Option<PathBuf>,
    /// Print `{ "sectors": N, "nodal_diameters": [ { "nd": d, "frequencies_hz": [...] } ] }`
    /// on standard output instead of the table.
    #[arg(long)]
    pub json: bool,
    /// Do not write the plot.
    #[arg(long)]
    pub no_plot: bool,
    /// Show only the first K mode families (table, plot and JSON); the table
    /// and plot show at most 10 unless this is given.
    #[arg(long, value_name = "K")]
    pub modes: Option<usize>,
}

/// The `--json` output.
#[derive(serde::Serialize)]
struct ModesJson {
    sectors: usize,
    nodal_diameters: Vec<NodalDiameterJson>,
}

/// One nodal diameter of the `--json` output.
#[derive(serde::Serialize)]
struct NodalDiameterJson {
    nd: usize,
    frequencies_hz: Vec<f64>,
}

/// The table and plot show at most this many mode families by default.
const DEFAULT_FAMILIES: usize = 10;

/// Runs `cyclorub modes`.
pub fn execute(args: ModesArgs) -> Result<(), CliError> {
    if args.modes == Some(0) {
        return Err(CliError::usage(
            "--modes 0: at least one mode family must be shown",
        ));
    }
    let (spec, case_dir) = match &args.case {
        Some(case) => {
            let spec = ModelSpec::from_case_file(case)?;
            let dir = case
                .parent()
                .map_or_else(|| PathBuf::from("."), Path::to_path_buf);
            (spec, dir)
        }
        None => (ModelSpec::default(), PathBuf::from(".")),
    };
    let model = spec.build(&case_dir)?;
    let frequencies = model.natural_frequencies()?;
    let shown = args
        .modes
        .unwrap_or(DEFAULT_FAMILIES)
        .min(model.dofs_per_sector());
    let description = describe(&spec, &model);

    if args.json {
        let limit = args.modes.unwrap_or(usize::MAX);
        let json = ModesJson {
            sectors: model.sectors(),
            nodal_diameters: frequencies
                .iter()
                .map(|(d, f)| NodalDiameterJson {
                    nd: *d,
                    frequencies_hz: f.iter().take(limit).copied().collect(),
                })
                .collect(),
        };
        let text = serde_json::to_string_pretty(&json)
            .map_err(|e| CliError::failure(format!("cannot format the JSON output: {e}")))?;
        outln!("{text}");
    } else {
        super::write_stdout(&table(
            &description,
            &frequencies,
            shown,
            model.dofs_per_sector(),
        ))?;
    }

    if !args.no_plot {
        let path = args.output.clone().unwrap_or_else(|| match &args.case {
            Some(_) => case_dir.join("modes.svg"),
            None => PathBuf::from("modes.svg"),
        });
        let title = format!("Natural frequencies, {description}");
        frequency_versus_nodal_diameter(&path, model.sectors(), &frequencies, Some(shown), &title)?;
        let line = format!("plot written to {}", path.display());
        if args.json {
            eprintln!("{line}");
        } else {
            outln!("{line}");
        }
    }
    Ok(())
}

fn describe(spec: &ModelSpec, model: &SectorModel) -> String {
    let kind = match spec.kind {
        ModelKind::Academic => "lumped (academic) model",
        ModelKind::Matrices => "inline matrices",
        ModelKind::MatrixMarket => "Matrix Market sector",
        ModelKind::FiniteElement => "finite-element sector, Craig–Bampton per nodal diameter",
    };
    let sectors = model.sectors();
    let dofs = model.dofs_per_sector();
    format!(
        "{kind}, N = {sectors} sector{}, {dofs} dof{} per sector",
        if sectors == 1 { "" } else { "s" },
        if dofs == 1 { "" } else { "s" }
    )
}

/// Rows: nodal diameter; columns: mode families; Hz.
fn table(
    description: &str,
    frequencies: &[(usize, Vec<f64>)],
    shown: usize,
    total: usize,
) -> String {
    let mut out = format!("Natural frequencies (Hz), {description}\n");
    if shown < total {
        out.push_str(&format!(
            "(first {shown} of {total} mode families; --modes K shows more)\n"
        ));
    }
    let width = frequencies
        .iter()
        .flat_map(|(_, f)| f.iter().take(shown))
        .map(|v| format!("{v:.3}").len())
        .max()
        .unwrap_or(8)
        .max(8);
    out.push_str(&format!("{:>4}", "ND"));
    for r in 0..shown {
        out.push_str(&format!("  {:>width$}", format!("mode {}", r + 1)));
    }
    out.push('\n');
    for (d, f) in frequencies {
        out.push_str(&format!("{d:>4}"));
        for v in f.iter().take(shown) {
            out.push_str(&format!("  {v:>width$.3}"));
        }
        out.push('\n');
    }
    out
}
