//! The leading Floquet exponent of each symmetry class along the branch:
//! where a class's curve is above zero, perturbations of that nodal
//! diameter grow. Only the classes that ever grow are in colour, each with
//! its legend line; the others are grey, under one legend line. Where the
//! run converged its sizes at one point (`run.json` `stability.sizes`),
//! each class's converged leading real part is a hollow circle there.

use super::event_symbols::classes_label;
use super::{palette, PlotError};
use crate::results::data::ResultsData;
use crate::results::sizes::ConvergedSizes;
use crate::results::stability::StabilityData;
use plotters::element::DashedPathElement;
use plotters::prelude::*;
use std::path::Path;

const WHAT: &str = "the stability plot";

fn draw_error(e: impl std::fmt::Display) -> PlotError {
    PlotError::Draw {
        what: WHAT.into(),
        message: e.to_string(),
    }
}

/// The grey of the classes that never grow.
const NEVER_GROWS: RGBColor = RGBColor(175, 175, 175);

/// Whether class `sigma`'s curve `(Hz, largest Re λ)` ever grows: a marker
/// names the class, or its largest real part is past the markers'
/// hysteresis band (`1e-6 ω`) somewhere.
fn grows(sigma: i64, points: &[(f64, f64)], stability: &StabilityData) -> bool {
    stability
        .markers
        .iter()
        .any(|m| m.nodal_diameter == Some(sigma))
        || points
            .iter()
            .any(|&(f, re)| re > 1e-6 * 2.0 * std::f64::consts::PI * f)
}

/// Draws, against frequency, the largest real part of the exponents of
/// each class `σ ≥ 0` (a class and its conjugate `−σ` share it) at every
/// converged point, with the zero line; with `sizes`, each class's
/// converged leading real part at its point.
pub fn leading_exponents_svg(
    data: &ResultsData,
    stability: &StabilityData,
    title: &str,
    sizes: Option<&ConvergedSizes>,
) -> Result<String, PlotError> {
    let converged: Vec<usize> = (0..data.points.len().min(stability.stable.len()))
        .filter(|&i| data.points[i].converged)
        .collect();
    let curves: Vec<(i64, Vec<(f64, f64)>)> = stability
        .classes
        .iter()
        .enumerate()
        .filter(|(_, &sigma)| sigma >= 0)
        .map(|(column, &sigma)| {
            let values = stability.leading_of_class(column);
            let points = converged
                .iter()
                .map(|&i| (data.points[i].frequency_hz, values[i]))
                .filter(|(x, y)| x.is_finite() && y.is_finite())
                .collect();
            (sigma, points)
        })
        .collect();
    let all = || curves.iter().flat_map(|(_, c)| c.iter());
    if all().next().is_none() {
        return Err(PlotError::Empty {
            what: WHAT.into(),
            message: "no exponent to draw".into(),
        });
    }
    let (x_min, x_max) = all().fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), &(x, _)| {
        (a.min(x), b.max(x))
    });
    // The converged circles of the classes drawn (σ ≥ 0), at their point.
    let circles: Vec<(i64, f64, f64)> = sizes
        .map(|s| {
            s.classes
                .iter()
                .filter(|c| c.class >= 0 && c.finest_re.is_finite())
                .map(|c| (c.class, s.frequency_hz, c.finest_re))
                .collect()
        })
        .unwrap_or_default();
    let (y_min, y_max) = all()
        .copied()
        .chain(circles.iter().map(|&(_, x, y)| (x, y)))
        .fold((0.0_f64, 0.0_f64), |(a, b), (_, y)| (a.min(y), b.max(y)));
    // The legend in the upper corner away from the largest growth (the
    // curves' and circles' highest point), so it does not hide it.
    let highest_x = all()
        .copied()
        .chain(circles.iter().map(|&(_, x, y)| (x, y)))
        .max_by(|a, b| a.1.total_cmp(&b.1))
        .map_or(x_min, |(x, _)| x);
    let legend_corner = if highest_x < 0.5 * (x_min + x_max) {
        SeriesLabelPosition::UpperRight
    } else {
        SeriesLabelPosition::UpperLeft
    };
    let x_pad = if x_max > x_min {
        0.01 * (x_max - x_min)
    } else {
        1.0
    };
    let y_pad = if y_max > y_min {
        0.05 * (y_max - y_min)
    } else {
        1.0
    };
    let mut svg = String::new();
    {
        let root = SVGBackend::with_string(&mut svg, (1000, 650)).into_drawing_area();
        root.fill(&WHITE).map_err(draw_error)?;
        let mut chart = ChartBuilder::on(&root)
            .caption(title, ("sans-serif", 20))
            .margin(15)
            .x_label_area_size(45)
            .y_label_area_size(80)
            .build_cartesian_2d(
                (x_min - x_pad)..(x_max + x_pad),
                (y_min - y_pad)..(y_max + y_pad),
            )
            .map_err(draw_error)?;
        chart
            .configure_mesh()
            .x_desc("frequency (Hz)")
            .y_desc("largest Re λ (1/s): > 0 grows")
            .x_label_formatter(&|x| format!("{x:.2}"))
            .draw()
            .map_err(draw_error)?;
        chart
            .draw_series(DashedLineSeries::new(
                vec![(x_min - x_pad, 0.0), (x_max + x_pad, 0.0)],
                4,
                4,
                BLACK.stroke_width(1),
            ))
            .map_err(draw_error)?
            .label("Re λ = 0")
            .legend(|(x, y)| {
                DashedPathElement::new(vec![(x, y), (x + 24, y)], 4, 4, BLACK.stroke_width(1))
            });
        let (growing, quiet): (Vec<_>, Vec<_>) = curves
            .iter()
            .partition(|(sigma, points)| grows(*sigma, points, stability));
        let quiet_label = format!(
            "{}: never grow",
            classes_label(&quiet.iter().map(|(sigma, _)| *sigma).collect::<Vec<_>>())
        );
        for (i, (_, points)) in quiet.iter().enumerate() {
            let series = chart
                .draw_series(LineSeries::new(points.clone(), NEVER_GROWS.stroke_width(1)))
                .map_err(draw_error)?;
            if i == 0 {
                series.label(quiet_label.clone()).legend(|(x, y)| {
                    PathElement::new(vec![(x, y), (x + 24, y)], NEVER_GROWS.stroke_width(2))
                });
            }
        }
        for (i, (sigma, points)) in growing.iter().enumerate() {
            let color = palette(i);
            chart
                .draw_series(LineSeries::new(points.clone(), color.stroke_width(2)))
                .map_err(draw_error)?
                .label(format!("nodal diameter {sigma}"))
                .legend(move |(x, y)| {
                    PathElement::new(vec![(x, y), (x + 24, y)], color.stroke_width(2))
                });
        }
        if let Some(sizes) = sizes.filter(|_| !circles.is_empty()) {
            let color_of = |sigma: i64| {
                growing
                    .iter()
                    .position(|(s, _)| *s == sigma)
                    .map_or(NEVER_GROWS, palette)
            };
            chart
                .draw_series(
                    circles.iter().map(|&(sigma, x, y)| {
                        Circle::new((x, y), 5, color_of(sigma).stroke_width(2))
                    }),
                )
                .map_err(draw_error)?
                .label(format!(
                    "converged at point {} (H = {}; the curves: H = {})",
                    sizes.point,
                    sizes.finest_harmonics(),
                    stability.harmonics
                ))
                .legend(|(x, y)| Circle::new((x + 12, y), 5, BLACK.stroke_width(2)));
        }
        chart
            .configure_series_labels()
            .position(legend_corner)
            .background_style(WHITE.mix(0.85))
            .border_style(BLACK.mix(0.4))
            .label_font(("sans-serif", 12))
            .draw()
            .map_err(draw_error)?;
        root.present().map_err(draw_error)?;
    }
    Ok(svg)
}

/// Writes [`leading_exponents_svg`] to `path`.
pub fn leading_exponents(
    path: &Path,
    data: &ResultsData,
    stability: &StabilityData,
    title: &str,
    sizes: Option<&ConvergedSizes>,
) -> Result<(), PlotError> {
    let svg = leading_exponents_svg(data, stability, title, sizes)?;
    super::write_svg(path, &svg)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_class_grows_past_the_band_only() {
        let stability = StabilityData {
            harmonics: 3,
            classes: vec![0, 1],
            stable: Vec::new(),
            unstable_exponents: Vec::new(),
            leading_re: Vec::new(),
            leading_im: Vec::new(),
            off_contact_bound: Vec::new(),
            markers: Vec::new(),
        };
        // 1e-6 ω at 100 Hz is 6.3e-4 1/s.
        let quiet = [(100.0, -3.0), (101.0, 1e-4), (102.0, -1.0)];
        let growing = [(100.0, -3.0), (101.0, 2.0), (102.0, -1.0)];
        assert!(!grows(0, &quiet, &stability));
        assert!(grows(1, &growing, &stability));
    }
}
