//! The figures of a time integration beside its envelope: the time history
//! of chosen sectors over the last periods, their amplitude spectrum, and
//! the waterfall of every sector's spectrum (a colour map, sector against
//! frequency), where a response localized on a few blades or modulated by
//! another nodal diameter shows at a glance.

use super::{palette, PlotError};
use plotters::prelude::*;

fn draw_error(what: &'static str) -> impl Fn(String) -> PlotError {
    move |message| PlotError::Draw {
        what: what.into(),
        message,
    }
}

fn empty(what: &str, message: &str) -> PlotError {
    PlotError::Empty {
        what: what.into(),
        message: message.into(),
    }
}

/// Range of finite values, padded by `fraction` of its width (or of its
/// magnitude when flat).
fn padded(values: impl Iterator<Item = f64>, fraction: f64) -> Option<(f64, f64)> {
    let (low, high) = values
        .filter(|v| v.is_finite())
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), v| {
            (a.min(v), b.max(v))
        });
    if low > high {
        return None;
    }
    let pad = if high > low {
        fraction * (high - low)
    } else {
        fraction * high.abs().max(1e-12)
    };
    Some((low - pad, high + pad))
}

/// The displacement of the observed dof against time, one curve per
/// `(sector (1-based), samples)` in `curves`, sampled at `time`.
pub fn time_history_svg(
    title: &str,
    time: &[f64],
    curves: &[(usize, Vec<f64>)],
) -> Result<String, PlotError> {
    const WHAT: &str = "the time history plot";
    let error = draw_error(WHAT);
    let (t_min, t_max) =
        padded(time.iter().copied(), 0.0).ok_or_else(|| empty(WHAT, "no step recorded"))?;
    let (y_min, y_max) = padded(curves.iter().flat_map(|(_, c)| c.iter().copied()), 0.05)
        .ok_or_else(|| empty(WHAT, "no sector to draw"))?;
    let mut svg = String::new();
    {
        let root = SVGBackend::with_string(&mut svg, (1000, 600)).into_drawing_area();
        root.fill(&WHITE).map_err(|e| error(e.to_string()))?;
        let mut chart = ChartBuilder::on(&root)
            .caption(title, ("sans-serif", 22))
            .margin(15)
            .x_label_area_size(45)
            .y_label_area_size(90)
            .build_cartesian_2d(t_min..t_max.max(t_min + 1e-12), y_min..y_max)
            .map_err(|e| error(e.to_string()))?;
        chart
            .configure_mesh()
            .x_desc("time (s)")
            .y_desc("displacement toward the casing (m)")
            .y_label_formatter(&|y| format!("{y:.3e}"))
            .draw()
            .map_err(|e| error(e.to_string()))?;
        for (slot, (sector, samples)) in curves.iter().enumerate() {
            let color = palette(slot);
            chart
                .draw_series(LineSeries::new(
                    time.iter().copied().zip(samples.iter().copied()),
                    color.stroke_width(1),
                ))
                .map_err(|e| error(e.to_string()))?
                .label(format!("sector {sector}"))
                .legend(move |(x, y)| {
                    PathElement::new(vec![(x, y), (x + 24, y)], color.stroke_width(2))
                });
        }
        chart
            .configure_series_labels()
            .background_style(WHITE.mix(0.85))
            .border_style(BLACK)
            .position(SeriesLabelPosition::UpperRight)
            .draw()
            .map_err(|e| error(e.to_string()))?;
        root.present().map_err(|e| error(e.to_string()))?;
    }
    Ok(svg)
}

/// Decades below the largest amplitude that the spectrum figures show.
pub const SPECTRUM_DECADES: f64 = 6.0;

/// The amplitude spectra `(sector (1-based), amplitudes)` on the bins
/// `frequency_hz`, up to `max_hz`, on a log scale, with the multiples of
/// `excitation_hz` (when given) as light vertical lines.
pub fn spectrum_svg(
    title: &str,
    frequency_hz: &[f64],
    curves: &[(usize, Vec<f64>)],
    max_hz: f64,
    excitation_hz: Option<f64>,
) -> Result<String, PlotError> {
    const WHAT: &str = "the spectrum plot";
    let error = draw_error(WHAT);
    let bins = frequency_hz.iter().take_while(|f| **f <= max_hz).count();
    let top = curves
        .iter()
        .flat_map(|(_, a)| a.iter().take(bins).copied())
        .filter(|a| a.is_finite())
        .fold(0.0_f64, f64::max);
    if bins < 2 || top <= 0.0 {
        return Err(empty(WHAT, "no spectrum to draw (too few steps recorded)"));
    }
    let floor = top * 10f64.powf(-SPECTRUM_DECADES);
    let x_max = frequency_hz[bins - 1];
    let mut svg = String::new();
    {
        let root = SVGBackend::with_string(&mut svg, (1000, 600)).into_drawing_area();
        root.fill(&WHITE).map_err(|e| error(e.to_string()))?;
        let mut chart = ChartBuilder::on(&root)
            .caption(title, ("sans-serif", 22))
            .margin(15)
            .x_label_area_size(45)
            .y_label_area_size(90)
            .build_cartesian_2d(0.0..x_max, (floor..top * 2.0).log_scale())
            .map_err(|e| error(e.to_string()))?;
        chart
            .configure_mesh()
            .x_desc("frequency (Hz)")
            .y_desc("amplitude (m)")
            .y_label_formatter(&|y| format!("{y:.0e}"))
            .draw()
            .map_err(|e| error(e.to_string()))?;
        if let Some(f) = excitation_hz.filter(|f| *f > 0.0) {
            let count = (x_max / f).floor() as usize;
            chart
                .draw_series((1..=count).map(|k| {
                    let x = k as f64 * f;
                    PathElement::new(vec![(x, floor), (x, top * 2.0)], BLACK.mix(0.15))
                }))
                .map_err(|e| error(e.to_string()))?;
        }
        for (slot, (sector, amplitude)) in curves.iter().enumerate() {
            let color = palette(slot);
            chart
                .draw_series(LineSeries::new(
                    frequency_hz
                        .iter()
                        .zip(amplitude)
                        .take(bins)
                        .map(|(&f, &a)| (f, a.max(floor))),
                    color.stroke_width(1),
                ))
                .map_err(|e| error(e.to_string()))?
                .label(format!("sector {sector}"))
                .legend(move |(x, y)| {
                    PathElement::new(vec![(x, y), (x + 24, y)], color.stroke_width(2))
                });
        }
        chart
            .configure_series_labels()
            .background_style(WHITE.mix(0.85))
            .border_style(BLACK)
            .position(SeriesLabelPosition::UpperRight)
            .draw()
            .map_err(|e| error(e.to_string()))?;
        root.present().map_err(|e| error(e.to_string()))?;
    }
    Ok(svg)
}

/// The colour of `level` in `[0, 1]` (0: faint, 1: strong), through dark
/// blue, teal, green and yellow (after viridis).
fn colour_map(level: f64) -> RGBColor {
    const STOPS: [(f64, [f64; 3]); 5] = [
        (0.0, [68.0, 1.0, 84.0]),
        (0.25, [59.0, 82.0, 139.0]),
        (0.5, [33.0, 145.0, 140.0]),
        (0.75, [94.0, 201.0, 98.0]),
        (1.0, [253.0, 231.0, 37.0]),
    ];
    let level = if level.is_nan() {
        0.0
    } else {
        level.clamp(0.0, 1.0)
    };
    let upper = STOPS.iter().position(|s| s.0 >= level).unwrap_or(4).max(1);
    let (a, ca) = STOPS[upper - 1];
    let (b, cb) = STOPS[upper];
    let w = (level - a) / (b - a);
    let c = |i: usize| (ca[i] + w * (cb[i] - ca[i])).round() as u8;
    RGBColor(c(0), c(1), c(2))
}

/// The waterfall over sectors: `amplitude[sector][bin]` on the bins
/// `frequency_hz` up to `max_hz` as a colour map (sector against
/// frequency), in decibels below the largest amplitude of all sectors,
/// over [`SPECTRUM_DECADES`] decades, with its colour bar.
pub fn waterfall_svg(
    title: &str,
    frequency_hz: &[f64],
    amplitude: &[Vec<f64>],
    max_hz: f64,
) -> Result<String, PlotError> {
    const WHAT: &str = "the waterfall plot";
    let error = draw_error(WHAT);
    let bins = frequency_hz.iter().take_while(|f| **f <= max_hz).count();
    let top = amplitude
        .iter()
        .flat_map(|a| a.iter().take(bins).copied())
        .filter(|a| a.is_finite())
        .fold(0.0_f64, f64::max);
    if bins < 2 || top <= 0.0 || amplitude.is_empty() {
        return Err(empty(WHAT, "no spectrum to draw (too few steps recorded)"));
    }
    let range_db = 20.0 * SPECTRUM_DECADES;
    let level = |a: f64| {
        let db = 20.0 * (a.max(f64::MIN_POSITIVE) / top).log10();
        1.0 + db.max(-range_db) / range_db
    };
    let resolution = frequency_hz[1] - frequency_hz[0];
    let x_max = frequency_hz[bins - 1] + 0.5 * resolution;
    let sectors = amplitude.len();
    let mut svg = String::new();
    {
        let root = SVGBackend::with_string(&mut svg, (1000, 650)).into_drawing_area();
        root.fill(&WHITE).map_err(|e| error(e.to_string()))?;
        let root = root
            .titled(title, ("sans-serif", 22))
            .map_err(|e| error(e.to_string()))?;
        let (main, bar) = root.split_horizontally(880);
        let mut chart = ChartBuilder::on(&main)
            .margin(15)
            .x_label_area_size(45)
            .y_label_area_size(60)
            .build_cartesian_2d(-0.5 * resolution..x_max, 0.5..(sectors as f64 + 0.5))
            .map_err(|e| error(e.to_string()))?;
        chart
            .configure_mesh()
            .x_desc("frequency (Hz)")
            .y_desc("sector")
            .y_label_formatter(&|y| {
                if (y - y.round()).abs() < 1e-9 {
                    format!("{}", y.round() as i64)
                } else {
                    String::new()
                }
            })
            .disable_mesh()
            .draw()
            .map_err(|e| error(e.to_string()))?;
        let cells = amplitude.iter().enumerate().flat_map(|(j, row)| {
            row.iter().take(bins).enumerate().map(move |(k, &a)| {
                let f = frequency_hz[k];
                let y = (j + 1) as f64;
                Rectangle::new(
                    [
                        (f - 0.5 * resolution, y - 0.5),
                        (f + 0.5 * resolution, y + 0.5),
                    ],
                    colour_map(level(a)).filled(),
                )
            })
        });
        chart.draw_series(cells).map_err(|e| error(e.to_string()))?;
        let mut scale = ChartBuilder::on(&bar)
            .margin_top(15)
            .margin_bottom(60)
            .margin_right(10)
            .y_label_area_size(55)
            .build_cartesian_2d(0.0..1.0, -range_db..0.0)
            .map_err(|e| error(e.to_string()))?;
        scale
            .configure_mesh()
            .disable_x_axis()
            .disable_mesh()
            .y_desc("dB re largest")
            .draw()
            .map_err(|e| error(e.to_string()))?;
        let steps = 60;
        scale
            .draw_series((0..steps).map(|i| {
                let low = -range_db + range_db * i as f64 / steps as f64;
                let high = low + range_db / steps as f64;
                Rectangle::new(
                    [(0.0, low), (1.0, high)],
                    colour_map(1.0 + (0.5 * (low + high)) / range_db).filled(),
                )
            }))
            .map_err(|e| error(e.to_string()))?;
        root.present().map_err(|e| error(e.to_string()))?;
    }
    Ok(svg)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_colour_map_runs_from_its_first_stop_to_its_last() {
        assert_eq!(colour_map(0.0), RGBColor(68, 1, 84));
        assert_eq!(colour_map(1.0), RGBColor(253, 231, 37));
        assert_eq!(colour_map(0.5), RGBColor(33, 145, 140));
        assert_eq!(colour_map(-3.0), colour_map(0.0));
        assert_eq!(colour_map(f64::NAN), colour_map(0.0));
    }

    #[test]
    fn figures_are_drawn_and_empty_data_is_refused() {
        let time: Vec<f64> = (0..64).map(|i| i as f64 * 1e-3).collect();
        let wave: Vec<f64> = time.iter().map(|t| (100.0 * t).sin()).collect();
        let svg = time_history_svg("t", &time, &[(3, wave.clone())]).unwrap();
        assert!(svg.contains("sector 3"));
        let frequency: Vec<f64> = (0..33).map(|k| k as f64 * 15.625).collect();
        let amplitude: Vec<f64> = (0..33).map(|k| 1.0 / (1.0 + k as f64)).collect();
        let svg = spectrum_svg(
            "s",
            &frequency,
            &[(1, amplitude.clone())],
            300.0,
            Some(15.625),
        )
        .unwrap();
        assert!(svg.contains("sector 1"));
        let svg = waterfall_svg("w", &frequency, &[amplitude.clone(), amplitude], 300.0).unwrap();
        assert!(svg.contains("dB re largest"));
        assert!(time_history_svg("t", &[], &[]).is_err());
        assert!(spectrum_svg("s", &frequency, &[(1, vec![0.0; 33])], 300.0, None).is_err());
        assert!(waterfall_svg("w", &frequency, &[], 300.0).is_err());
    }
}
