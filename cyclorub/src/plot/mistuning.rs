//! The figures of a mistuned wheel (issue 44): every sector's amplitude
//! against frequency (the fan of curves a mistuned wheel is known by) and
//! a bar chart of each sector's peak, with the tuned wheel's peak as a
//! dashed line.

use super::{palette, write_svg, PlotError};
use crate::results::data::ResultsData;
use plotters::prelude::*;
use std::path::{Path, PathBuf};

/// Every sector's amplitude against frequency.
pub const SECTOR_AMPLITUDES: &str = "sector_amplitudes.svg";
/// Each sector's peak.
pub const SECTOR_PEAKS: &str = "sector_peaks.svg";

fn draw_error(what: &str) -> impl Fn(&dyn std::fmt::Display) -> PlotError + '_ {
    move |e| PlotError::Draw {
        what: what.into(),
        message: e.to_string(),
    }
}

/// The fan of curves: the observed dof's amplitude (toward the casing) of
/// every sector along the converged points of `data`, one colour per
/// sector; returns the SVG text.
pub fn sector_amplitudes_svg(data: &ResultsData, title: &str) -> Result<String, PlotError> {
    let what = "the sector amplitudes";
    let error = draw_error(what);
    let points: Vec<_> = data.points.iter().filter(|p| p.converged).collect();
    if points.is_empty() || data.sectors == 0 {
        return Err(PlotError::Empty {
            what: what.into(),
            message: "no converged point".into(),
        });
    }
    let (low, high) = points
        .iter()
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), p| {
            (a.min(p.frequency_hz), b.max(p.frequency_hz))
        });
    let (low, high) = if high > low {
        (low, high)
    } else {
        (low - 1.0, high + 1.0)
    };
    let top = points
        .iter()
        .flat_map(|p| p.amplitude.iter())
        .fold(0.0_f64, |m, &a| if a.is_finite() { m.max(a) } else { m });
    let top = if top > 0.0 { 1.08 * top } else { 1.0 };
    let breaks = data.converged_breaks();
    let mut svg = String::new();
    {
        let root = SVGBackend::with_string(&mut svg, (900, 600)).into_drawing_area();
        root.fill(&WHITE).map_err(|e| error(&e))?;
        let mut chart = ChartBuilder::on(&root)
            .caption(title, ("sans-serif", 22))
            .margin(15)
            .x_label_area_size(45)
            .y_label_area_size(85)
            .build_cartesian_2d(low..high, 0.0..top)
            .map_err(|e| error(&e))?;
        chart
            .configure_mesh()
            .x_desc("frequency (Hz)")
            .y_desc(format!("amplitude of {} (m)", data.observed_name))
            .y_label_formatter(&|y| format!("{y:.2e}"))
            .draw()
            .map_err(|e| error(&e))?;
        for j in 0..data.sectors {
            let colour = palette(j);
            // One line per piece between the branch's gaps.
            let mut piece: Vec<(f64, f64)> = Vec::new();
            for (i, p) in points.iter().enumerate() {
                if let Some(&a) = p.amplitude.get(j) {
                    piece.push((p.frequency_hz, a));
                }
                if breaks.contains(&(i + 1)) || i + 1 == points.len() {
                    chart
                        .draw_series(LineSeries::new(
                            std::mem::take(&mut piece),
                            colour.stroke_width(1),
                        ))
                        .map_err(|e| error(&e))?;
                }
            }
        }
    }
    Ok(svg)
}

/// The bar chart of each sector's peak (m), with the tuned wheel's peak
/// `tuned` as a dashed line when known; returns the SVG text.
pub fn sector_peaks_svg(
    peaks: &[f64],
    tuned: Option<f64>,
    amplitude_axis: &str,
    title: &str,
) -> Result<String, PlotError> {
    let what = "the sector peaks";
    let error = draw_error(what);
    let n = peaks.len();
    if n == 0 || peaks.iter().all(|p| !p.is_finite()) {
        return Err(PlotError::Empty {
            what: what.into(),
            message: "no sector peak".into(),
        });
    }
    let top =
        peaks
            .iter()
            .chain(tuned.iter())
            .fold(0.0_f64, |m, &a| if a.is_finite() { m.max(a) } else { m });
    let top = if top > 0.0 { 1.12 * top } else { 1.0 };
    let mut svg = String::new();
    {
        let root = SVGBackend::with_string(&mut svg, (900, 600)).into_drawing_area();
        root.fill(&WHITE).map_err(|e| error(&e))?;
        let mut chart = ChartBuilder::on(&root)
            .caption(title, ("sans-serif", 22))
            .margin(15)
            .x_label_area_size(45)
            .y_label_area_size(85)
            .build_cartesian_2d(0.5..(n as f64 + 0.5), 0.0..top)
            .map_err(|e| error(&e))?;
        chart
            .configure_mesh()
            .x_desc("sector")
            .y_desc(amplitude_axis)
            .x_labels(n.min(24))
            .x_label_formatter(&|x| {
                if (x - x.round()).abs() < 1e-9 && *x >= 1.0 {
                    format!("{}", x.round() as i64)
                } else {
                    String::new()
                }
            })
            .y_label_formatter(&|y| format!("{y:.2e}"))
            .draw()
            .map_err(|e| error(&e))?;
        chart
            .draw_series(
                peaks
                    .iter()
                    .enumerate()
                    .filter(|(_, p)| p.is_finite())
                    .map(|(j, &p)| {
                        let x = j as f64 + 1.0;
                        Rectangle::new([(x - 0.35, 0.0), (x + 0.35, p)], palette(j).filled())
                    }),
            )
            .map_err(|e| error(&e))?;
        if let Some(tuned) = tuned.filter(|t| t.is_finite()) {
            chart
                .draw_series(DashedLineSeries::new(
                    vec![(0.5, tuned), (n as f64 + 0.5, tuned)],
                    8,
                    5,
                    BLACK.stroke_width(2),
                ))
                .map_err(|e| error(&e))?
                .label(format!("tuned peak {tuned:.3e} m"))
                .legend(|(x, y)| {
                    PathElement::new(vec![(x, y), (x + 20, y)], BLACK.stroke_width(2))
                });
            chart
                .configure_series_labels()
                .background_style(WHITE.mix(0.8))
                .border_style(BLACK)
                .position(SeriesLabelPosition::UpperRight)
                .draw()
                .map_err(|e| error(&e))?;
        }
    }
    Ok(svg)
}

/// Writes both figures of a mistuned run into `directory` (with PNGs
/// beside when `png`) and returns the files written.
pub fn write_mistuning_figures(
    directory: &Path,
    data: &ResultsData,
    peaks: &[f64],
    tuned: Option<f64>,
    png: bool,
) -> Result<Vec<PathBuf>, PlotError> {
    std::fs::create_dir_all(directory).map_err(|source| PlotError::Write {
        path: directory.to_path_buf(),
        source,
    })?;
    let dof = &data.observed_name;
    let n = data.sectors;
    let mut written = Vec::new();
    // A run with nothing to draw (no converged point, no sector peak) keeps
    // its other results: the figure is skipped and said so.
    let skipped = |figure: &str, result: Result<String, PlotError>| match result {
        Err(PlotError::Empty { message, .. }) => {
            tracing::warn!("{figure} not drawn: {message}");
            Ok(None)
        }
        other => other.map(Some),
    };
    let fan = skipped(
        SECTOR_AMPLITUDES,
        sector_amplitudes_svg(
            data,
            &format!("Mistuned wheel: amplitude of {dof} in every sector (N = {n})"),
        ),
    )?;
    let bars = skipped(
        SECTOR_PEAKS,
        sector_peaks_svg(
            peaks,
            tuned,
            &format!("peak amplitude of {dof} (m)"),
            &format!("Mistuned wheel: peak per sector of {dof} (N = {n})"),
        ),
    )?;
    for (name, svg) in [(SECTOR_AMPLITUDES, fan), (SECTOR_PEAKS, bars)] {
        let Some(svg) = svg else { continue };
        let path = directory.join(name);
        write_svg(&path, &svg)?;
        written.push(path);
    }
    if png {
        let pngs = super::png::write_pngs_beside(&written)?;
        written.extend(pngs);
    }
    Ok(written)
}
