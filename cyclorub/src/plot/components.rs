//! Cyclic components: bar charts per harmonic and nodal diameter at one
//! point, forward and backward (as Figs. 6, 7, 9, 10, 12), and the
//! components of one harmonic along a branch (as Fig. 20). Log scales.

use super::{palette, PlotError};
use crate::results::components::CyclicComponents;
use plotters::element::DashedPathElement;
use plotters::prelude::*;
use std::path::Path;

fn draw_error(what: &'static str) -> impl Fn(String) -> PlotError {
    move |message| PlotError::Draw {
        what: what.into(),
        message,
    }
}

/// Rounds the log axis to whole decades around `[low, high]`.
fn decades(low: f64, high: f64) -> (f64, f64) {
    let lo = 10f64.powf(low.log10().floor());
    let hi = 10f64.powf(high.log10().ceil());
    (lo, if hi > lo { hi } else { lo * 10.0 })
}

const BARS: &str = "the cyclic component bar chart";

/// Bar charts of the forward (top) and backward (bottom) components on
/// every harmonic, one colour per nodal diameter, log scale. Diameters
/// whose components all stay below `relative_floor` times the largest are
/// left out (so are bars below it). Returns the SVG text.
pub fn cyclic_components_svg(
    components: &CyclicComponents,
    title: &str,
    relative_floor: f64,
) -> Result<String, PlotError> {
    let largest = components.max();
    if !(largest > 0.0 && largest.is_finite()) {
        return Err(PlotError::Empty {
            what: BARS.into(),
            message: "every component is zero".into(),
        });
    }
    let floor = largest * relative_floor;
    let shown = components.significant_diameters(relative_floor);
    let smallest = components
        .forward
        .iter()
        .chain(&components.backward)
        .flatten()
        .cloned()
        .filter(|&v| v > floor)
        .fold(largest, f64::min);
    let (low, high) = decades(smallest.max(floor), largest * 1.5);
    let harmonics = components.harmonics;
    let width = 0.8 / shown.len().max(1) as f64;
    let error = draw_error(BARS);
    let mut svg = String::new();
    {
        let root = SVGBackend::with_string(&mut svg, (1100, 850)).into_drawing_area();
        root.fill(&WHITE).map_err(|e| error(e.to_string()))?;
        let root = root
            .titled(title, ("sans-serif", 22))
            .map_err(|e| error(e.to_string()))?;
        let panels = root.split_evenly((2, 1));
        for (panel, (name, values)) in panels.iter().zip([
            ("forward", &components.forward),
            ("backward", &components.backward),
        ]) {
            let mut chart = ChartBuilder::on(panel)
                .caption(
                    format!("{name} components (N = {})", components.sectors),
                    ("sans-serif", 18),
                )
                .margin(10)
                .x_label_area_size(40)
                .y_label_area_size(80)
                .build_cartesian_2d(-0.5..(harmonics as f64 + 0.5), (low..high).log_scale())
                .map_err(|e| error(e.to_string()))?;
            chart
                .configure_mesh()
                .x_desc("harmonic k")
                .y_desc("amplitude (m)")
                .x_labels(harmonics + 1)
                .x_label_formatter(&|x| {
                    if (x - x.round()).abs() < 1e-9 && *x >= 0.0 {
                        format!("{}", x.round() as i64)
                    } else {
                        String::new()
                    }
                })
                .y_label_formatter(&|y| format!("{y:.0e}"))
                .disable_x_mesh()
                .draw()
                .map_err(|e| error(e.to_string()))?;
            for (slot, &d) in shown.iter().enumerate() {
                let color = palette(d);
                let bars: Vec<Rectangle<(f64, f64)>> = (0..=harmonics)
                    .filter(|&k| values[k][d] > floor)
                    .map(|k| {
                        let x0 = k as f64 - 0.4 + slot as f64 * width;
                        Rectangle::new([(x0, low), (x0 + width, values[k][d])], color.filled())
                    })
                    .collect();
                let series = chart.draw_series(bars).map_err(|e| error(e.to_string()))?;
                if name == "forward" {
                    series.label(format!("ND {d}")).legend(move |(x, y)| {
                        Rectangle::new([(x, y - 5), (x + 14, y + 5)], color.filled())
                    });
                }
            }
            if name == "forward" {
                chart
                    .configure_series_labels()
                    .position(SeriesLabelPosition::UpperRight)
                    .background_style(WHITE.mix(0.85))
                    .border_style(BLACK.mix(0.4))
                    .label_font(("sans-serif", 14))
                    .draw()
                    .map_err(|e| error(e.to_string()))?;
            }
        }
        root.present().map_err(|e| error(e.to_string()))?;
    }
    Ok(svg)
}

/// Writes [`cyclic_components_svg`] to `path`.
pub fn cyclic_components(
    path: &Path,
    components: &CyclicComponents,
    title: &str,
    relative_floor: f64,
) -> Result<(), PlotError> {
    let svg = cyclic_components_svg(components, title, relative_floor)?;
    super::write_svg(path, &svg)
}

const ALONG: &str = "the branch cyclic component plot";

/// The components of harmonic `harmonic` along a branch (frequencies in
/// Hz, one set of components per point, in branch order): per nodal
/// diameter, forward solid and backward dashed, log scale. Diameters below
/// `relative_floor` times the largest component are left out, and at most
/// `max_diameters` of the largest are drawn. Returns the SVG text.
pub fn branch_components_svg(
    frequencies_hz: &[f64],
    components: &[CyclicComponents],
    harmonic: usize,
    title: &str,
    relative_floor: f64,
    max_diameters: usize,
) -> Result<String, PlotError> {
    let error = draw_error(ALONG);
    let count = frequencies_hz.len().min(components.len());
    if count == 0 || components.iter().any(|c| c.harmonics < harmonic) {
        return Err(PlotError::Empty {
            what: ALONG.into(),
            message: format!("no point, or no harmonic {harmonic}"),
        });
    }
    let diameters = components[0].diameters();
    let largest_of = |d: usize| {
        components[..count]
            .iter()
            .map(|c| c.forward[harmonic][d].max(c.backward[harmonic][d]))
            .fold(0.0_f64, f64::max)
    };
    let largest = (0..diameters).map(largest_of).fold(0.0_f64, f64::max);
    if !(largest > 0.0 && largest.is_finite()) {
        return Err(PlotError::Empty {
            what: ALONG.into(),
            message: format!("harmonic {harmonic} is zero along the branch"),
        });
    }
    let floor = largest * relative_floor;
    let mut shown: Vec<usize> = (0..diameters).filter(|&d| largest_of(d) > floor).collect();
    shown.sort_by(|&a, &b| largest_of(b).total_cmp(&largest_of(a)));
    shown.truncate(max_diameters.max(1));
    shown.sort_unstable();
    let smallest = shown
        .iter()
        .flat_map(|&d| {
            components[..count]
                .iter()
                .flat_map(move |c| [c.forward[harmonic][d], c.backward[harmonic][d]])
        })
        .filter(|&v| v > floor)
        .fold(largest, f64::min);
    let (low, high) = decades(smallest.max(floor), largest * 1.5);
    let (x_min, x_max) = frequencies_hz[..count]
        .iter()
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), &f| {
            (a.min(f), b.max(f))
        });
    let pad = if x_max > x_min {
        0.01 * (x_max - x_min)
    } else {
        1.0
    };
    let mut svg = String::new();
    {
        let root = SVGBackend::with_string(&mut svg, (1000, 650)).into_drawing_area();
        root.fill(&WHITE).map_err(|e| error(e.to_string()))?;
        let mut chart = ChartBuilder::on(&root)
            .caption(title, ("sans-serif", 22))
            .margin(15)
            .x_label_area_size(45)
            .y_label_area_size(80)
            .build_cartesian_2d((x_min - pad)..(x_max + pad), (low..high).log_scale())
            .map_err(|e| error(e.to_string()))?;
        chart
            .configure_mesh()
            .x_desc("frequency (Hz)")
            .y_desc(format!("harmonic {harmonic} component (m)"))
            .x_label_formatter(&|x| format!("{x:.2}"))
            .y_label_formatter(&|y| format!("{y:.0e}"))
            .draw()
            .map_err(|e| error(e.to_string()))?;
        for &d in &shown {
            let color = palette(d);
            for backward in [false, true] {
                let values: Vec<(f64, f64)> = frequencies_hz[..count]
                    .iter()
                    .zip(&components[..count])
                    .map(|(&f, c)| {
                        let v = if backward {
                            c.backward[harmonic][d]
                        } else {
                            c.forward[harmonic][d]
                        };
                        (f, v)
                    })
                    .collect();
                if values.iter().all(|p| p.1 <= floor) {
                    continue;
                }
                let points: Vec<(f64, f64)> =
                    values.into_iter().map(|(f, v)| (f, v.max(low))).collect();
                if backward {
                    chart
                        .draw_series(DashedLineSeries::new(points, 8, 5, color.stroke_width(2)))
                        .map_err(|e| error(e.to_string()))?
                        .label(format!("ND {d} backward"))
                        .legend(move |(x, y)| {
                            DashedPathElement::new(
                                vec![(x, y), (x + 24, y)],
                                8,
                                5,
                                color.stroke_width(2),
                            )
                        });
                } else {
                    chart
                        .draw_series(LineSeries::new(points, color.stroke_width(2)))
                        .map_err(|e| error(e.to_string()))?
                        .label(format!("ND {d} forward"))
                        .legend(move |(x, y)| {
                            PathElement::new(vec![(x, y), (x + 24, y)], color.stroke_width(2))
                        });
                }
            }
        }
        chart
            .configure_series_labels()
            .position(SeriesLabelPosition::UpperLeft)
            .background_style(WHITE.mix(0.85))
            .border_style(BLACK.mix(0.4))
            .label_font(("sans-serif", 14))
            .draw()
            .map_err(|e| error(e.to_string()))?;
        root.present().map_err(|e| error(e.to_string()))?;
    }
    Ok(svg)
}

/// Writes [`branch_components_svg`] to `path`.
pub fn branch_components(
    path: &Path,
    frequencies_hz: &[f64],
    components: &[CyclicComponents],
    harmonic: usize,
    title: &str,
    relative_floor: f64,
    max_diameters: usize,
) -> Result<(), PlotError> {
    let svg = branch_components_svg(
        frequencies_hz,
        components,
        harmonic,
        title,
        relative_floor,
        max_diameters,
    )?;
    super::write_svg(path, &svg)
}
