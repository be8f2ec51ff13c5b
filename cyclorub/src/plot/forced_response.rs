//! Forced response curves (as Figs. 5, 8, 11): amplitude versus frequency
//! for chosen sectors, the nonlinear branch solid where it is stable and
//! dashed where it is not (when the stability was checked), its stability
//! markers, the linear response dotted and, when a comparison run is
//! given, the reference dashed and lighter.

use super::{palette, PlotError};
use crate::stability::MarkerKind;
use plotters::element::{DashedPathElement, DottedPathElement};
use plotters::prelude::*;
use std::path::Path;

const WHAT: &str = "the forced response plot";

fn draw_error(e: impl std::fmt::Display) -> PlotError {
    PlotError::Draw {
        what: WHAT.into(),
        message: e.to_string(),
    }
}

/// The curves of one sector.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct SectorCurves {
    /// Legend label of the nonlinear curve (e.g. `sector 3`).
    pub label: String,
    /// Nonlinear branch `(Hz, m)`, in branch order (turning points kept).
    pub nonlinear: Vec<(f64, f64)>,
    /// Where the nonlinear branch has gaps: the indices in `nonlinear` of
    /// the points not joined to the one before (a branch followed from both
    /// ends whose sweeps did not meet).
    pub breaks: Vec<usize>,
    /// Linear response `(Hz, m)`, by increasing frequency (may be empty).
    pub linear: Vec<(f64, f64)>,
    /// Reference branch `(Hz, m)` of a comparison run (may be empty).
    pub reference: Vec<(f64, f64)>,
    /// Per point of `nonlinear`: whether it is unstable (empty: not checked).
    pub unstable: Vec<bool>,
    /// Stability markers on this sector's curve: `(Hz, m, kind)`.
    pub markers: Vec<(f64, f64, MarkerKind)>,
}

/// The runs of equal stability in `points` (`unstable` per point, or
/// empty: all stable), each with its stability; consecutive runs share
/// their end point so that the curve is unbroken.
fn stability_runs(points: &[(f64, f64)], unstable: &[bool]) -> Vec<(Vec<(f64, f64)>, bool)> {
    let state = |i: usize| unstable.get(i).copied().unwrap_or(false);
    let mut runs: Vec<(Vec<(f64, f64)>, bool)> = Vec::new();
    for (i, &p) in points.iter().enumerate() {
        match runs.last_mut() {
            Some((run, s)) if *s == state(i) => run.push(p),
            Some((run, _)) => {
                let last = *run.last().unwrap_or(&p);
                runs.push((vec![last, p], state(i)));
            }
            None => runs.push((vec![p], state(i))),
        }
    }
    runs
}

/// The symbol and legend name of a marker kind.
fn marker_name(kind: MarkerKind) -> &'static str {
    match kind {
        MarkerKind::Fold => "fold",
        MarkerKind::BranchPoint => "branch point (symmetry breaking)",
        MarkerKind::RealCrossing => "fold or branch point",
        MarkerKind::PeriodDoubling => "period doubling",
        MarkerKind::NeimarkSacker => "Neimark-Sacker",
    }
}

/// Splits a polyline into the runs below `top`, with the crossings
/// interpolated, so that a tall linear peak is cut at the frame.
fn clip_above(points: &[(f64, f64)], top: f64) -> Vec<Vec<(f64, f64)>> {
    let mut runs = Vec::new();
    let mut run: Vec<(f64, f64)> = Vec::new();
    for (i, &(x, y)) in points.iter().enumerate() {
        let inside = y <= top;
        if i > 0 {
            let (px, py) = points[i - 1];
            let was_inside = py <= top;
            if inside != was_inside && (y - py).abs() > 0.0 {
                let t = (top - py) / (y - py);
                run.push((px + t * (x - px), top));
                if was_inside {
                    runs.push(std::mem::take(&mut run));
                }
            }
        }
        if inside {
            run.push((x, y));
        }
    }
    if !run.is_empty() {
        runs.push(run);
    }
    runs.retain(|r| r.len() > 1);
    runs
}

/// The runs of `points` between the `breaks` (indices of the points that
/// start a new run).
fn split_at_breaks<'a>(points: &'a [(f64, f64)], breaks: &[usize]) -> Vec<&'a [(f64, f64)]> {
    let mut runs = Vec::new();
    let mut start = 0;
    for &b in breaks {
        if b > start && b < points.len() {
            runs.push(&points[start..b]);
            start = b;
        }
    }
    runs.push(&points[start..]);
    runs
}

/// Draws the curves of each sector (one colour per sector) and returns the
/// SVG text. `reference_label` names the reference run in the legend.
pub fn forced_response_svg(
    title: &str,
    curves: &[SectorCurves],
    reference_label: &str,
) -> Result<String, PlotError> {
    let all = || {
        curves
            .iter()
            .flat_map(|c| c.nonlinear.iter().chain(&c.linear).chain(&c.reference))
            .filter(|(x, y)| x.is_finite() && y.is_finite())
    };
    if all().next().is_none() {
        return Err(PlotError::Empty {
            what: WHAT.into(),
            message: "no point to draw".into(),
        });
    }
    let (x_min, x_max) = all().fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), &(x, _)| {
        (a.min(x), b.max(x))
    });
    // The frame fits the nonlinear and reference curves; a linear peak above
    // is cut (it can be far above the gap).
    let nonlinear_top = curves
        .iter()
        .flat_map(|c| c.nonlinear.iter().chain(&c.reference))
        .map(|p| p.1)
        .filter(|y| y.is_finite())
        .fold(0.0_f64, f64::max);
    let linear_top = curves
        .iter()
        .flat_map(|c| &c.linear)
        .map(|p| p.1)
        .filter(|y| y.is_finite())
        .fold(0.0_f64, f64::max);
    let top = if nonlinear_top > 0.0 {
        1.15 * nonlinear_top.max(linear_top.min(2.0 * nonlinear_top))
    } else if linear_top > 0.0 {
        1.1 * linear_top
    } else {
        1.0
    };
    let bottom = all().map(|p| p.1).fold(0.0_f64, f64::min).min(0.0);
    let pad = if x_max > x_min {
        0.01 * (x_max - x_min)
    } else {
        1.0
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
            .build_cartesian_2d((x_min - pad)..(x_max + pad), bottom..top)
            .map_err(draw_error)?;
        chart
            .configure_mesh()
            .x_desc("frequency (Hz)")
            .y_desc("amplitude (m)")
            .y_label_formatter(&|y| format!("{y:.2e}"))
            .x_label_formatter(&|x| format!("{x:.2}"))
            .draw()
            .map_err(draw_error)?;
        for (i, c) in curves.iter().enumerate() {
            let color = palette(i);
            if c.nonlinear.len() > 1 {
                let mut labelled = (false, false);
                // The runs are consecutive slices: `first` is where each starts.
                let mut first = 0;
                for run in split_at_breaks(&c.nonlinear, &c.breaks) {
                    let states = c.unstable.get(first..first + run.len()).unwrap_or(&[]);
                    first += run.len();
                    for (segment, unstable) in stability_runs(run, states) {
                        if segment.len() < 2 {
                            continue;
                        }
                        if unstable {
                            let series = chart
                                .draw_series(DashedLineSeries::new(
                                    segment,
                                    6,
                                    4,
                                    color.stroke_width(2),
                                ))
                                .map_err(draw_error)?;
                            if !labelled.1 {
                                labelled.1 = true;
                                series.label(format!("{}, unstable", c.label)).legend(
                                    move |(x, y)| {
                                        DashedPathElement::new(
                                            vec![(x, y), (x + 24, y)],
                                            6,
                                            4,
                                            color.stroke_width(2),
                                        )
                                    },
                                );
                            }
                        } else {
                            let series = chart
                                .draw_series(LineSeries::new(segment, color.stroke_width(2)))
                                .map_err(draw_error)?;
                            if !labelled.0 {
                                labelled.0 = true;
                                series.label(c.label.clone()).legend(move |(x, y)| {
                                    PathElement::new(
                                        vec![(x, y), (x + 24, y)],
                                        color.stroke_width(2),
                                    )
                                });
                            }
                        }
                    }
                }
            } else if let Some(&p) = c.nonlinear.first() {
                chart
                    .draw_series(std::iter::once(Circle::new(p, 3, color.filled())))
                    .map_err(draw_error)?
                    .label(c.label.clone())
                    .legend(move |(x, y)| Circle::new((x + 12, y), 3, color.filled()));
            }
            for (run_index, run) in clip_above(&c.linear, top).into_iter().enumerate() {
                let series = chart
                    .draw_series(DottedLineSeries::new(run, 0, 5, move |p| {
                        Circle::new(p, 1, color.filled())
                    }))
                    .map_err(draw_error)?;
                if run_index == 0 {
                    series
                        .label(format!("linear, {}", c.label))
                        .legend(move |(x, y)| {
                            DottedPathElement::new(vec![(x, y), (x + 24, y)], 0, 5, move |p| {
                                Circle::new(p, 1, color.filled())
                            })
                        });
                }
            }
            if c.reference.len() > 1 {
                chart
                    .draw_series(DashedLineSeries::new(
                        c.reference.clone(),
                        8,
                        5,
                        color.stroke_width(2),
                    ))
                    .map_err(draw_error)?
                    .label(format!("{reference_label}, {}", c.label))
                    .legend(move |(x, y)| {
                        DashedPathElement::new(
                            vec![(x, y), (x + 24, y)],
                            8,
                            5,
                            color.stroke_width(2),
                        )
                    });
            }
        }
        let mut named: Vec<MarkerKind> = Vec::new();
        for &(x, y, kind) in curves.iter().flat_map(|c| &c.markers) {
            let black = BLACK.stroke_width(2);
            let series = match kind {
                MarkerKind::Fold | MarkerKind::RealCrossing => chart
                    .draw_series(std::iter::once(Cross::new((x, y), 6, black)))
                    .map_err(draw_error)?,
                MarkerKind::BranchPoint => chart
                    .draw_series(std::iter::once(TriangleMarker::new((x, y), 7, black)))
                    .map_err(draw_error)?,
                MarkerKind::PeriodDoubling | MarkerKind::NeimarkSacker => chart
                    .draw_series(std::iter::once(Circle::new((x, y), 6, black)))
                    .map_err(draw_error)?,
            };
            if !named.contains(&kind) {
                named.push(kind);
                series.label(marker_name(kind)).legend(move |(lx, ly)| {
                    let at = (lx + 12, ly);
                    match kind {
                        MarkerKind::Fold | MarkerKind::RealCrossing => {
                            Cross::new(at, 5, BLACK.stroke_width(2)).into_dyn()
                        }
                        MarkerKind::BranchPoint => {
                            TriangleMarker::new(at, 6, BLACK.stroke_width(2)).into_dyn()
                        }
                        _ => Circle::new(at, 5, BLACK.stroke_width(2)).into_dyn(),
                    }
                });
            }
        }
        chart
            .configure_series_labels()
            .position(SeriesLabelPosition::UpperLeft)
            .background_style(WHITE.mix(0.85))
            .border_style(BLACK.mix(0.4))
            .label_font(("sans-serif", 14))
            .draw()
            .map_err(draw_error)?;
        root.present().map_err(draw_error)?;
    }
    Ok(svg)
}

/// Writes [`forced_response_svg`] to `path`.
pub fn forced_response(
    path: &Path,
    title: &str,
    curves: &[SectorCurves],
    reference_label: &str,
) -> Result<(), PlotError> {
    let svg = forced_response_svg(title, curves, reference_label)?;
    super::write_svg(path, &svg)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn clipping_cuts_a_peak_at_the_frame() {
        let runs = clip_above(&[(0.0, 0.0), (1.0, 2.0), (2.0, 0.0), (3.0, 0.5)], 1.0);
        assert_eq!(runs.len(), 2);
        assert_eq!(runs[0], vec![(0.0, 0.0), (0.5, 1.0)]);
        assert_eq!(runs[1], vec![(1.5, 1.0), (2.0, 0.0), (3.0, 0.5)]);
    }

    #[test]
    fn a_branch_with_a_gap_is_drawn_in_two_lines() {
        let points = [(1.0, 1.0), (2.0, 2.0), (3.0, 1.5), (2.5, 3.0), (4.0, 1.0)];
        assert_eq!(
            split_at_breaks(&points, &[3]),
            vec![&points[..3], &points[3..]]
        );
        // Breaks at the ends or out of range split nothing.
        assert_eq!(split_at_breaks(&points, &[0, 5, 9]), vec![&points[..]]);
        let polylines = |breaks: Vec<usize>| {
            let curves = [SectorCurves {
                label: "sector 1".into(),
                nonlinear: points.to_vec(),
                breaks,
                ..SectorCurves::default()
            }];
            forced_response_svg("gap", &curves, "reference")
                .expect("drawn")
                .matches("<polyline")
                .count()
        };
        assert_eq!(polylines(vec![3]), polylines(Vec::new()) + 1);
    }
}
