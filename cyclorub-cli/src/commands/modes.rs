//! `cyclorub modes`: natural frequencies per nodal diameter of a case's model;
//! on a finite-element case, the full sector's beside the Craig–Bampton
//! model's, with their relative differences; on a mistuned case (its
//! `[mistuning]` applied), the mistuned wheel's modes after them.

use super::{outln, CliError};
use cyclorub::model::{ModelKind, ModelSpec, SectorModel};
use cyclorub::plot::{
    frequency_versus_nodal_diameter, frequency_versus_nodal_diameter_compared, ComparedFrequencies,
};
use std::path::{Path, PathBuf};

/// Arguments of `cyclorub modes`.
#[derive(clap::Args)]
pub struct ModesArgs {
    /// The case file (TOML); its `[model]` table is read, and its
    /// `[mistuning]` when it has one: the tuned wheel's frequencies per
    /// nodal diameter are then followed by the mistuned wheel's modes (the
    /// assembled full wheel with the blade deviations, solved densely:
    /// frequency, most active sector, localization, nodal-diameter
    /// content; `--json`: `mistuned_wheel_modes`). Without a case file,
    /// the paper's academic model with N = 24.
    pub case: Option<PathBuf>,
    /// Where to write the frequency versus nodal diameter plot (SVG);
    /// default `modes.svg` next to the case file (or in the current
    /// directory without a case file).
    #[arg(long, short)]
    pub output: Option<PathBuf>,
    /// Print `{ "sectors": N, "nodal_diameters": [ { "nd": d, "frequencies_hz": [...] } ] }`
    /// on standard output instead of the table. On a finite-element case each
    /// diameter also has `full_sector_frequencies_hz` (the first K, default 10)
    /// and `relative_differences` ((Craig–Bampton − full) / full, mode by mode).
    #[arg(long)]
    pub json: bool,
    /// Do not write the plot.
    #[arg(long)]
    pub no_plot: bool,
    /// Show only the first K mode families (table, plot and JSON); the table
    /// and plot show at most 10 unless this is given.
    #[arg(long, value_name = "K")]
    pub modes: Option<usize>,
    /// On a finite-element case, show only the Craig–Bampton model's
    /// frequencies: skip the full sector's (a sparse eigen solution per
    /// nodal diameter, cached in .cyclorub-cache next to the case file).
    #[arg(long)]
    pub no_full_sector: bool,
}

/// The `--json` output.
#[derive(serde::Serialize)]
struct ModesJson {
    sectors: usize,
    nodal_diameters: Vec<NodalDiameterJson>,
    /// A mistuned case: the mistuned wheel's modes.
    #[serde(skip_serializing_if = "Option::is_none")]
    mistuned_wheel_modes: Option<Vec<WheelModeJson>>,
}

/// One mode of the mistuned wheel in the `--json` output.
#[derive(serde::Serialize)]
struct WheelModeJson {
    frequency_hz: f64,
    /// 1-based.
    most_active_sector: usize,
    /// The most active sector's share of the kinetic energy.
    localization: f64,
    /// Energy share per sector, sector 1 first.
    sector_shares: Vec<f64>,
    /// Energy share per nodal diameter 0..=N/2.
    nodal_diameter_shares: Vec<f64>,
}

/// One nodal diameter of the `--json` output.
#[derive(serde::Serialize)]
struct NodalDiameterJson {
    nd: usize,
    frequencies_hz: Vec<f64>,
    /// Finite-element cases: the full sector's frequencies.
    #[serde(skip_serializing_if = "Option::is_none")]
    full_sector_frequencies_hz: Option<Vec<f64>>,
    /// Finite-element cases: (Craig–Bampton − full) / full, mode by mode.
    #[serde(skip_serializing_if = "Option::is_none")]
    relative_differences: Option<Vec<f64>>,
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
    // A mistuned case (issue 44): the tuned wheel's modes per diameter,
    // then the mistuned wheel's (dense, on the assembled full wheel).
    let mistuned_case = args
        .case
        .as_deref()
        .and_then(|case| cyclorub::case::Case::from_file(case).ok())
        .filter(|case| case.mistuning.is_set());
    let wheel_modes = match &mistuned_case {
        Some(case) => {
            let wheel = case
                .mistuned(model.clone(), &case_dir)
                .map_err(|e| CliError::usage(e.to_string()))?;
            let families = args.modes.unwrap_or(DEFAULT_FAMILIES);
            let count = families.saturating_mul(wheel.sectors());
            Some(wheel.wheel_modes(count)?)
        }
        None => None,
    };
    let frequencies = model.natural_frequencies()?;
    let shown = args
        .modes
        .unwrap_or(DEFAULT_FAMILIES)
        .min(model.dofs_per_sector());
    let description = describe(&spec, &model);
    // A finite-element case's reduced model is checked against the full
    // sector it comes from: its lowest `shown` frequencies per diameter.
    let full = if spec.kind == ModelKind::FiniteElement && !args.no_full_sector {
        Some(spec.full_sector_frequencies(&case_dir, shown)?)
    } else {
        None
    };

    if args.json {
        let limit = args.modes.unwrap_or(usize::MAX);
        let json = ModesJson {
            sectors: model.sectors(),
            nodal_diameters: frequencies
                .iter()
                .enumerate()
                .map(|(i, (d, f))| {
                    let full = full.as_ref().map(|full| full[i].1.clone());
                    NodalDiameterJson {
                        nd: *d,
                        frequencies_hz: f.iter().take(limit).copied().collect(),
                        relative_differences: full.as_ref().map(|g| relative_differences(f, g)),
                        full_sector_frequencies_hz: full,
                    }
                })
                .collect(),
            mistuned_wheel_modes: wheel_modes.as_ref().map(|modes| {
                modes
                    .iter()
                    .map(|mode| {
                        let (sector, share) = mode.localization();
                        WheelModeJson {
                            frequency_hz: mode.frequency_hz,
                            most_active_sector: sector + 1,
                            localization: share,
                            sector_shares: mode.sector_shares.clone(),
                            nodal_diameter_shares: mode.nodal_diameter_shares.clone(),
                        }
                    })
                    .collect()
            }),
        };
        let text = serde_json::to_string_pretty(&json)
            .map_err(|e| CliError::failure(format!("cannot format the JSON output: {e}")))?;
        outln!("{text}");
    } else {
        let mut text = match &full {
            Some(full) => comparison_table(&description, &frequencies, full),
            None => table(&description, &frequencies, shown, model.dofs_per_sector()),
        };
        if let Some(modes) = &wheel_modes {
            text.insert_str(0, "The tuned wheel, per nodal diameter:\n");
            text.push_str(&wheel_table(modes));
        }
        super::write_stdout(&text)?;
    }

    if !args.no_plot {
        let path = args.output.clone().unwrap_or_else(|| match &args.case {
            Some(_) => case_dir.join("modes.svg"),
            None => PathBuf::from("modes.svg"),
        });
        // A mistuned case: the plot is the tuned wheel's, per diameter.
        let tuned = if wheel_modes.is_some() {
            ", the tuned wheel"
        } else {
            ""
        };
        let title = format!("Natural frequencies, {description}{tuned}");
        match &full {
            Some(full) => frequency_versus_nodal_diameter_compared(
                &path,
                model.sectors(),
                &frequencies,
                &ComparedFrequencies {
                    lines_label: "Craig–Bampton (lines)",
                    markers: full,
                    markers_label: "full sector (open circles)",
                },
                Some(shown),
                &title,
            )?,
            None => frequency_versus_nodal_diameter(
                &path,
                model.sectors(),
                &frequencies,
                Some(shown),
                &title,
            )?,
        }
        let line = format!("plot written to {}", path.display());
        if args.json {
            eprintln!("{line}");
        } else {
            outln!("{line}");
        }
    }
    Ok(())
}

/// `(reduced − full) / full` for the modes both have, matched by index
/// (both ascending).
fn relative_differences(reduced: &[f64], full: &[f64]) -> Vec<f64> {
    reduced.iter().zip(full).map(|(r, f)| (r - f) / f).collect()
}

/// Rows: nodal diameter and mode; columns: the full sector's frequency,
/// the Craig–Bampton model's, and their relative difference.
fn comparison_table(
    description: &str,
    reduced: &[(usize, Vec<f64>)],
    full: &[(usize, Vec<f64>)],
) -> String {
    let mut out = format!("Natural frequencies (Hz), {description}\n");
    let count = full.iter().map(|(_, f)| f.len()).max().unwrap_or(0);
    out.push_str(&format!(
        "The full sector (all dofs but the clamped ones, sparse) against its Craig–Bampton model, \
         first {count} modes per nodal diameter (--modes K shows more);\n\
         relative difference = (Craig–Bampton − full) / full\n"
    ));
    let width = reduced
        .iter()
        .chain(full)
        .flat_map(|(_, f)| f.iter().take(count))
        .map(|v| format!("{v:.3}").len())
        .max()
        .unwrap_or(8)
        .max(13);
    out.push_str(&format!(
        "{:>4}  {:>4}  {:>width$}  {:>width$}  {:>19}\n",
        "ND", "mode", "full sector", "Craig–Bampton", "relative difference"
    ));
    for ((d, r), (_, f)) in reduced.iter().zip(full) {
        for (mode, (rv, fv)) in r.iter().zip(f).enumerate() {
            let difference = (rv - fv) / fv;
            out.push_str(&format!(
                "{d:>4}  {:>4}  {fv:>width$.3}  {rv:>width$.3}  {difference:>19.2e}\n",
                mode + 1
            ));
        }
    }
    out
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

/// The mistuned wheel's modes: frequency, localization (the most active
/// sector and its share of the kinetic energy) and the two largest
/// nodal-diameter shares.
fn wheel_table(modes: &[cyclorub::model::WheelMode]) -> String {
    let mut out = String::from(
        "\nThe mistuned wheel ([mistuning]), the assembled full wheel solved densely:\n\
         localization = the most active sector's share of the mode's kinetic energy \
         (1/N: spread evenly, 1: one sector alone);\n\
         nodal-diameter content = shares of the energy per nodal diameter (ND) of the \
         spatial DFT over the sectors, the two largest\n",
    );
    out.push_str(&format!(
        "{:>5}  {:>12}  {:>6}  {:>12}  {:>14}  {:>14}\n",
        "mode", "frequency Hz", "sector", "localization", "largest ND", "second ND"
    ));
    for (i, mode) in modes.iter().enumerate() {
        let (sector, share) = mode.localization();
        let mut diameters: Vec<(usize, f64)> = mode
            .nodal_diameter_shares
            .iter()
            .copied()
            .enumerate()
            .collect();
        diameters.sort_by(|a, b| b.1.total_cmp(&a.1));
        let shown = |k: usize| {
            diameters
                .get(k)
                .map_or_else(String::new, |(d, s)| format!("ND {d}: {s:.3}"))
        };
        out.push_str(&format!(
            "{:>5}  {:>12.3}  {:>6}  {share:>12.3}  {:>14}  {:>14}\n",
            i + 1,
            mode.frequency_hz,
            sector + 1,
            shown(0),
            shown(1)
        ));
    }
    out
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
