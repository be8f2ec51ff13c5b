//! The figure of a symmetric branch and the branches that bifurcate from
//! it (docs/design.md §11): against frequency, the largest amplitude over
//! the sectors of each branch (for a bifurcated branch, also the smallest,
//! thin: how far its sectors are from moving alike), solid where the point
//! is stable and dashed where it is not.

use super::{palette, PlotError};
use plotters::prelude::*;

/// The figure's file name in the branches folder.
pub const BRANCHES: &str = "branches.svg";

/// One point of a curve of the figure.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CurvePoint {
    /// Frequency, Hz.
    pub frequency_hz: f64,
    /// The largest amplitude over the sectors, m.
    pub largest_m: f64,
    /// The smallest amplitude over the sectors, m.
    pub smallest_m: f64,
    /// Whether the point is stable (`None`: not checked, drawn solid).
    pub stable: Option<bool>,
}

/// One branch of the figure.
#[derive(Clone, Debug, PartialEq)]
pub struct BranchCurve {
    /// The legend's text.
    pub label: String,
    /// The points in branch order.
    pub points: Vec<CurvePoint>,
    /// Whether to draw the smallest amplitude too (bifurcated branches).
    pub spread: bool,
}

/// The SVG of `curves` (the first one in black: the symmetric branch).
pub fn branches_svg(
    curves: &[BranchCurve],
    title: &str,
    observed: &str,
) -> Result<String, PlotError> {
    let what = "the bifurcated branches";
    let error = |e: &dyn std::fmt::Display| PlotError::Draw {
        what: what.into(),
        message: e.to_string(),
    };
    let all = curves
        .iter()
        .flat_map(|c| c.points.iter())
        .filter(|p| p.largest_m.is_finite());
    let (low, high, top) = all.fold(
        (f64::INFINITY, f64::NEG_INFINITY, 0.0_f64),
        |(a, b, t), p| {
            (
                a.min(p.frequency_hz),
                b.max(p.frequency_hz),
                t.max(p.largest_m),
            )
        },
    );
    if !(low.is_finite() && high.is_finite()) {
        return Err(PlotError::Empty {
            what: what.into(),
            message: "no point".into(),
        });
    }
    let (low, high) = if high > low {
        (low, high)
    } else {
        (low - 1.0, high + 1.0)
    };
    let top = if top > 0.0 { 1.08 * top } else { 1.0 };
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
            .y_desc(format!("amplitude of {observed} over the sectors (m)"))
            .y_label_formatter(&|y| format!("{y:.2e}"))
            .draw()
            .map_err(|e| error(&e))?;
        for (index, curve) in curves.iter().enumerate() {
            let colour = if index == 0 {
                BLACK
            } else {
                palette(index - 1)
            };
            let mut legend = true;
            for (value, thin) in [(0_usize, false), (1, true)] {
                if thin && !curve.spread {
                    continue;
                }
                let y = |p: &CurvePoint| {
                    if value == 0 {
                        p.largest_m
                    } else {
                        p.smallest_m
                    }
                };
                // Pieces of equal stability, each sharing its end point with the next.
                let mut start = 0;
                while start + 1 < curve.points.len() {
                    let stable = curve.points[start].stable.unwrap_or(true);
                    let mut end = start + 1;
                    while end + 1 < curve.points.len()
                        && curve.points[end].stable.unwrap_or(true) == stable
                    {
                        end += 1;
                    }
                    let piece: Vec<(f64, f64)> = curve.points[start..=end]
                        .iter()
                        .map(|p| (p.frequency_hz, y(p)))
                        .filter(|(_, a)| a.is_finite())
                        .collect();
                    let style = colour.stroke_width(if thin { 1 } else { 2 });
                    let drawn = if stable {
                        chart
                            .draw_series(LineSeries::new(piece, style))
                            .map_err(|e| error(&e))?
                    } else {
                        chart
                            .draw_series(DashedLineSeries::new(piece, 6, 4, style))
                            .map_err(|e| error(&e))?
                    };
                    if legend {
                        drawn.label(curve.label.clone()).legend(move |(x, y)| {
                            PathElement::new(vec![(x, y), (x + 20, y)], colour.stroke_width(2))
                        });
                        legend = false;
                    }
                    start = end;
                }
            }
        }
        chart
            .configure_series_labels()
            .background_style(WHITE.mix(0.85))
            .border_style(BLACK)
            .position(SeriesLabelPosition::UpperLeft)
            .draw()
            .map_err(|e| error(&e))?;
    }
    Ok(svg)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn stable_and_unstable_pieces_are_drawn_solid_and_dashed() {
        let point = |f: f64, stable: bool| CurvePoint {
            frequency_hz: f,
            largest_m: 1e-3 * f,
            smallest_m: 0.5e-3 * f,
            stable: Some(stable),
        };
        let curves = vec![
            BranchCurve {
                label: "symmetric".into(),
                points: vec![point(1.0, true), point(2.0, true), point(3.0, false)],
                spread: false,
            },
            BranchCurve {
                label: "class 1".into(),
                points: vec![point(1.5, false), point(2.5, false)],
                spread: true,
            },
        ];
        let svg = branches_svg(&curves, "t", "dof 1").unwrap();
        assert!(svg.contains("symmetric") && svg.contains("class 1"));
        // Dashed pieces are drawn as many short segments: more polylines
        // than the three solid and dashed runs alone would give.
        assert!(svg.matches("<polyline").count() > 4, "{svg}");
        let empty = branches_svg(&[], "t", "dof 1");
        assert!(matches!(empty, Err(PlotError::Empty { .. })));
    }
}
