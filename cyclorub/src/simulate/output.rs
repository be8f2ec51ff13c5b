//! The files of a time integration: `simulation.csv` (per period: the
//! largest displacement of the observed dof per sector), `simulation.json`
//! (what was run and how it ended), `simulation.h5` (feature `hdf5`: the
//! envelope, the Poincaré section and every step of the last periods) and
//! the figures (feature `plot`): `plots/envelope.svg` (per-period maximum
//! per sector), `plots/time_history.svg` (the last periods of the plotted
//! sectors), `plots/spectrum.svg` (their amplitude spectrum) and
//! `plots/waterfall.svg` (every sector's spectrum as a colour map).
//!
//! Sectors are 1-based in the files' headers and text, 0-based along the
//! HDF5 arrays' axes.

use super::run::SimulationOutcome;
use super::SimulateError;
use serde::Serialize;
use std::fmt::Write as _;
use std::path::{Path, PathBuf};

/// The files a simulation folder holds, with and without the features.
pub const SIMULATION_FILES: &[&str] = &[
    "simulation.csv",
    #[cfg(feature = "hdf5")]
    "simulation.h5",
    #[cfg(feature = "plot")]
    "plots/envelope.svg",
    #[cfg(feature = "plot")]
    "plots/time_history.svg",
    #[cfg(feature = "plot")]
    "plots/spectrum.svg",
    #[cfg(feature = "plot")]
    "plots/waterfall.svg",
    "simulation.json",
];

/// What `simulation.json` records.
#[derive(Clone, Debug, Serialize)]
pub struct SimulationRecord {
    /// The case file.
    pub case: String,
    /// `fixed` or `sweep`.
    pub mode: String,
    /// Excitation frequency (fixed) or start and end (sweep), Hz.
    pub frequency_hz: Vec<f64>,
    /// Sweep rate, Hz/s (sweep only).
    pub rate_hz_per_s: Option<f64>,
    /// Where it started: `rest`, or the results folder and point.
    pub start: String,
    /// The perturbation, as given.
    pub perturbation: Option<String>,
    /// The scheme.
    pub scheme: String,
    /// The dispersion correction applied (`Ω/Ω_w`, see
    /// [`super::wheel::dispersion_ratio`]): at a fixed frequency with the
    /// implicit scheme, unless switched off.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub dispersion_ratio: Option<f64>,
    /// Time step, s.
    pub step_s: f64,
    /// What the wheel settled to (fixed frequency).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub attractor: Option<super::Attractor>,
    /// With `--reference` at a fixed frequency: the branch's amplitudes
    /// there, one per sheet, m.
    #[serde(skip_serializing_if = "Vec::is_empty")]
    pub reference_amplitudes_m: Vec<f64>,
    /// Steps per excitation period integrated.
    pub steps_per_period: usize,
    /// The steps per period asked for, when the explicit scheme needed more
    /// to be stable (it then takes the bound's count, a multiple of the
    /// sectors).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub steps_raised_from: Option<usize>,
    /// Periods integrated.
    pub periods: usize,
    /// How it ended, in words.
    pub ending: String,
    /// Steady-state tolerance (relative distance of the state a period apart).
    pub steady_tolerance: Option<f64>,
    /// Spread of the per-period maxima across sectors over the last 10
    /// periods, relative.
    pub modulation_across_sectors: f64,
    /// Spread of the per-period maxima over the last 10 periods, relative;
    /// `None` (null) when one period was integrated: nothing to compare.
    pub modulation_over_periods: Option<f64>,
    /// Steps, Newton iterations, halvings.
    pub steps: u64,
    /// Newton iterations.
    pub newton_iterations: u64,
    /// Step halvings.
    pub halvings: u64,
    /// Wall-clock time, s.
    pub wall_seconds: f64,
    /// Steps per second.
    pub steps_per_second: f64,
    /// The observed dof, 1-based.
    pub observed_dof: usize,
    /// The observed dof as the user knows it (`node 420, radial`, `m1, the
    /// blade tip`: [`crate::results::data::observed_name`]), in the figures.
    pub observed_name: String,
    /// The sectors (1-based) of the time-history and spectrum figures.
    pub plotted_sectors: Vec<usize>,
    /// The formats of the figures (`[output] figures`: a PNG at 300 dpi
    /// beside each SVG when it holds `png`).
    pub figures: Vec<crate::case::FigureFormat>,
}

/// The sectors (1-based) the time-history and spectrum figures show when
/// none are asked for: sector 1 and the sectors of the largest and the
/// smallest maximum over the last period (the extremes of a localized or
/// modulated response), in order, without repeats.
pub fn default_plotted_sectors(outcome: &SimulationOutcome) -> Vec<usize> {
    let mut sectors = vec![1];
    if let Some(last) = outcome.periods.last() {
        let extreme = |better: fn(f64, f64) -> bool| {
            (0..last.maxima.len()).reduce(|a, b| {
                if better(last.maxima[b], last.maxima[a]) {
                    b
                } else {
                    a
                }
            })
        };
        for j in [extreme(|a, b| a > b), extreme(|a, b| a < b)]
            .into_iter()
            .flatten()
        {
            sectors.push(j + 1);
        }
    }
    sectors.sort_unstable();
    sectors.dedup();
    sectors
}

/// Times the highest excitation frequency up to which the spectrum
/// figures go: the harmonics a harmonic balance of `N_h = 10` holds.
#[cfg(feature = "plot")]
const SPECTRUM_HARMONICS: f64 = 10.5;

fn io(path: &Path) -> impl FnOnce(std::io::Error) -> SimulateError + '_ {
    move |e| SimulateError::Write {
        path: path.to_path_buf(),
        message: e.to_string(),
    }
}

/// Writes the folder `output`; returns the paths written. `reference`
/// (`(frequency or time, amplitude)`, may be empty) is drawn dashed on the
/// envelope: the harmonic balance branch of the same case for a sweep.
pub fn write(
    output: &Path,
    outcome: &SimulationOutcome,
    record: &SimulationRecord,
    reference: &[(f64, f64)],
) -> Result<Vec<PathBuf>, SimulateError> {
    std::fs::create_dir_all(output).map_err(io(output))?;
    // Only the figures draw the reference.
    #[cfg(not(feature = "plot"))]
    let _ = reference;
    let mut written = Vec::new();
    let path = output.join("simulation.csv");
    std::fs::write(&path, csv(outcome)).map_err(io(&path))?;
    written.push(path);
    #[cfg(feature = "hdf5")]
    {
        let path = output.join("simulation.h5");
        super::hdf5::write(&path, outcome, record.observed_dof)?;
        written.push(path);
    }
    #[cfg(feature = "plot")]
    {
        let folder = output.join("plots");
        std::fs::create_dir_all(&folder).map_err(io(&folder))?;
        let path = folder.join("envelope.svg");
        let sectors = outcome.periods.first().map_or(0, |p| p.maxima.len());
        let sweep = record.mode == "sweep";
        let curves: Vec<Vec<(f64, f64)>> = (0..sectors)
            .map(|j| {
                outcome
                    .periods
                    .iter()
                    .map(|p| {
                        let x = if sweep { p.frequency_hz } else { p.end_time };
                        (x, p.maxima[j])
                    })
                    .collect()
            })
            .collect();
        let title = format!(
            "Envelope per sector, {} ({})",
            record.observed_name, record.start
        );
        let x_label = if sweep {
            "instantaneous frequency (Hz)"
        } else {
            "time (s)"
        };
        let svg = crate::plot::envelope_svg(&title, x_label, &curves, reference).map_err(|e| {
            SimulateError::Write {
                path: path.clone(),
                message: e.to_string(),
            }
        })?;
        std::fs::write(&path, svg).map_err(io(&path))?;
        written.push(path);
        written.extend(write_history_figures(&folder, outcome, record)?);
        if record.figures.contains(&crate::case::FigureFormat::Png) {
            let svgs: Vec<PathBuf> = written
                .iter()
                .filter(|p| p.extension().is_some_and(|e| e == "svg"))
                .cloned()
                .collect();
            let pngs =
                crate::plot::png::write_pngs_beside(&svgs).map_err(|e| SimulateError::Write {
                    path: folder.clone(),
                    message: e.to_string(),
                })?;
            written.extend(pngs);
        }
    }
    let path = output.join("simulation.json");
    let text = serde_json::to_string_pretty(record).map_err(|e| SimulateError::Write {
        path: path.clone(),
        message: e.to_string(),
    })?;
    std::fs::write(&path, text + "\n").map_err(io(&path))?;
    written.push(path);
    Ok(written)
}

/// The time history, spectrum and waterfall of the recorded last periods
/// (none when no step was recorded).
#[cfg(feature = "plot")]
fn write_history_figures(
    folder: &Path,
    outcome: &SimulationOutcome,
    record: &SimulationRecord,
) -> Result<Vec<PathBuf>, SimulateError> {
    use super::spectrum::Window;
    let history = &outcome.history;
    let sectors = outcome.periods.first().map_or(0, |p| p.maxima.len());
    if history.time.len() < 2 || sectors == 0 {
        return Ok(Vec::new());
    }
    let shown: Vec<usize> = record
        .plotted_sectors
        .iter()
        .copied()
        .filter(|&j| (1..=sectors).contains(&j))
        .collect();
    let series = |j: usize| -> Vec<f64> {
        (0..history.time.len())
            .map(|i| history.observed_displacement[i * sectors + j - 1])
            .collect()
    };
    let sweep = record.mode == "sweep";
    // Whole periods at a fixed frequency: the rectangular window is exact.
    let window = if sweep {
        Window::Hann
    } else {
        Window::Rectangular
    };
    let spectra = history.observed_spectra(sectors, outcome.step, window);
    let highest = record.frequency_hz.iter().fold(0.0_f64, |m, f| m.max(*f));
    let max_hz = SPECTRUM_HARMONICS * highest;
    let recorded = format!(
        "last {:.3} s, {}",
        history.time.len() as f64 * outcome.step,
        record.observed_name
    );
    let curves: Vec<(usize, Vec<f64>)> = shown.iter().map(|&j| (j, series(j))).collect();
    let spectrum_curves: Vec<(usize, Vec<f64>)> = shown
        .iter()
        .map(|&j| (j, spectra.amplitude[j - 1].clone()))
        .collect();
    let window_text = if sweep {
        "Hann window"
    } else {
        "whole periods"
    };
    let figures = [
        (
            "time_history.svg",
            crate::plot::simulation::time_history_svg(
                &format!("Time history ({recorded})"),
                &history.time,
                &curves,
            ),
        ),
        (
            "spectrum.svg",
            crate::plot::simulation::spectrum_svg(
                &format!("Amplitude spectrum ({recorded}, {window_text})"),
                &spectra.frequency_hz,
                &spectrum_curves,
                max_hz,
                (!sweep).then_some(highest),
            ),
        ),
        (
            "waterfall.svg",
            crate::plot::simulation::waterfall_svg(
                &format!("Spectrum of every sector ({recorded}, {window_text})"),
                &spectra.frequency_hz,
                &spectra.amplitude,
                max_hz,
            ),
        ),
    ];
    let mut written = Vec::new();
    for (name, svg) in figures {
        let path = folder.join(name);
        let svg = svg.map_err(|e| SimulateError::Write {
            path: path.clone(),
            message: e.to_string(),
        })?;
        std::fs::write(&path, svg).map_err(io(&path))?;
        written.push(path);
    }
    Ok(written)
}

/// `simulation.csv`: one row per period.
pub fn csv(outcome: &SimulationOutcome) -> String {
    let sectors = outcome.periods.first().map_or(0, |p| p.maxima.len());
    let mut text = String::from("period,end_time_s,frequency_hz");
    for j in 1..=sectors {
        let _ = write!(text, ",max_sector_{j}");
    }
    text.push_str(
        ",peak_contact_force_n,poincare_distance,input_work_j,damping_work_j,contact_work_j\n",
    );
    for p in &outcome.periods {
        let _ = write!(
            text,
            "{},{:.12e},{:.9e}",
            p.period, p.end_time, p.frequency_hz
        );
        for m in &p.maxima {
            let _ = write!(text, ",{m:.12e}");
        }
        let force = p.peak_force.iter().fold(0.0_f64, |a, f| a.max(*f));
        let _ = writeln!(
            text,
            ",{force:.6e},{:.3e},{:.9e},{:.9e},{:.9e}",
            p.poincare_distance, p.energy.input, p.energy.damping, p.energy.contact
        );
    }
    text
}
