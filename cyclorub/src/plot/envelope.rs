//! The envelope of a time integration: the per-period maximum of the
//! observed dof, one curve per sector, against time (fixed frequency) or
//! against the instantaneous frequency (sweep), with the harmonic balance
//! branch of the same case dashed when given.

use super::{palette, PlotError};
use plotters::prelude::*;

const WHAT: &str = "the envelope plot";

fn draw_error(e: impl std::fmt::Display) -> PlotError {
    PlotError::Draw {
        what: WHAT.into(),
        message: e.to_string(),
    }
}

/// Draws `curves[j] = [(x, max)]` per sector (sector `j + 1`) with the
/// axis label `x_label`, and `reference` (`(x, amplitude)`, may be empty)
/// dashed; returns the SVG text. More than 12 sectors are drawn without a
/// legend entry each.
pub fn envelope_svg(
    title: &str,
    x_label: &str,
    curves: &[Vec<(f64, f64)>],
    reference: &[(f64, f64)],
) -> Result<String, PlotError> {
    let all = || {
        curves
            .iter()
            .flatten()
            .chain(reference)
            .filter(|(x, y)| x.is_finite() && y.is_finite())
    };
    if all().next().is_none() {
        return Err(PlotError::Empty {
            what: WHAT.into(),
            message: "no period to draw".into(),
        });
    }
    let (x_min, x_max) = all().fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), &(x, _)| {
        (a.min(x), b.max(x))
    });
    let (y_min, y_max) = all().fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), &(_, y)| {
        (a.min(y), b.max(y))
    });
    let pad_x = if x_max > x_min {
        0.01 * (x_max - x_min)
    } else {
        1.0
    };
    let pad_y = if y_max > y_min {
        0.05 * (y_max - y_min)
    } else {
        0.05 * y_max.abs().max(1e-12)
    };
    let mut svg = String::new();
    {
        let root = SVGBackend::with_string(&mut svg, (1000, 650)).into_drawing_area();
        root.fill(&WHITE).map_err(draw_error)?;
        let mut chart = ChartBuilder::on(&root)
            .caption(title, ("sans-serif", 22))
            .margin(15)
            .x_label_area_size(45)
            .y_label_area_size(90)
            .build_cartesian_2d(
                (x_min - pad_x)..(x_max + pad_x),
                (y_min - pad_y)..(y_max + pad_y),
            )
            .map_err(draw_error)?;
        chart
            .configure_mesh()
            .x_desc(x_label)
            .y_desc("largest displacement over the period (m)")
            .y_label_formatter(&|y| format!("{y:.3e}"))
            .draw()
            .map_err(draw_error)?;
        let labelled = curves.len() <= 12;
        for (j, curve) in curves.iter().enumerate() {
            let color = palette(j);
            // One period integrated: a dot per sector (a line of one point
            // is no line, and a rasterizer warns about it).
            let series = if curve.len() < 2 {
                chart
                    .draw_series(curve.iter().map(|&p| Circle::new(p, 3, color.filled())))
                    .map_err(draw_error)?
            } else {
                chart
                    .draw_series(LineSeries::new(curve.clone(), color.stroke_width(1)))
                    .map_err(draw_error)?
            };
            if labelled {
                series
                    .label(format!("sector {}", j + 1))
                    .legend(move |(x, y)| {
                        PathElement::new(vec![(x, y), (x + 24, y)], color.stroke_width(2))
                    });
            }
        }
        if reference.len() > 1 {
            chart
                .draw_series(DashedLineSeries::new(
                    reference.to_vec(),
                    8,
                    5,
                    BLACK.stroke_width(2),
                ))
                .map_err(draw_error)?
                .label("harmonic balance")
                .legend(|(x, y)| {
                    PathElement::new(vec![(x, y), (x + 24, y)], BLACK.stroke_width(2))
                });
        }
        chart
            .configure_series_labels()
            .background_style(WHITE.mix(0.85))
            .border_style(BLACK)
            .position(SeriesLabelPosition::UpperRight)
            .draw()
            .map_err(draw_error)?;
        root.present().map_err(draw_error)?;
    }
    Ok(svg)
}

#[cfg(test)]
mod tests {
    use super::envelope_svg;

    /// Polylines of fewer than two points in `svg`.
    fn lone_polylines(svg: &str) -> usize {
        svg.split("points=\"")
            .skip(1)
            .filter_map(|rest| rest.split('"').next())
            .filter(|points| points.split_whitespace().count() < 2)
            .count()
    }

    #[test]
    fn one_period_is_drawn_as_dots_and_more_as_lines() {
        let one: Vec<Vec<(f64, f64)>> = (0..3).map(|j| vec![(1.0, 1e-3 * j as f64)]).collect();
        let svg = envelope_svg("one period", "period", &one, &[]).unwrap();
        assert_eq!(lone_polylines(&svg), 0);
        assert!(svg.matches("<circle").count() >= 3, "{svg}");
        let two: Vec<Vec<(f64, f64)>> = (0..3)
            .map(|j| vec![(1.0, 1e-3 * j as f64), (2.0, 2e-3 * j as f64)])
            .collect();
        let svg = envelope_svg("two periods", "period", &two, &[]).unwrap();
        assert_eq!(lone_polylines(&svg), 0);
        assert!(svg.matches("<polyline").count() >= 3);
    }
}
