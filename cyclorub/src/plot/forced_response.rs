//! Forced response curves (as Figs. 5, 8, 11): amplitude versus frequency
//! for chosen sectors, the nonlinear branch solid where it is stable and
//! dashed where it is not (when the stability was checked), one small
//! hollow symbol per stability event (its shape the kind, its classes in a
//! label), the linear response dotted and, when a comparison run is given,
//! the reference dashed. When the nonlinear region is a small part of the
//! frequency range, a second panel below shows it alone
//! ([`nonlinear_region`]).

pub use super::curves::SectorCurves;
use super::event_symbols::{
    kind_name, label_offset, outline, outline_at, symbol_style, EventSymbol, SYMBOL_COLOUR,
    SYMBOL_SIZE,
};
use super::nonlinear_region::{clip_to, nonlinear_region, Region};
use super::{palette, PlotError};
use crate::stability::MarkerKind;
use plotters::coord::types::RangedCoordf64;
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

/// The words of a forced-response figure.
#[derive(Clone, Debug, PartialEq)]
pub struct Captions {
    /// The title.
    pub title: String,
    /// What the amplitude axis shows, with its unit (e.g. `amplitude of
    /// node 420, radial (m)`).
    pub amplitude_axis: String,
    /// The name of the reference run in the legend.
    pub reference: String,
}

impl Captions {
    /// A title, the amplitude axis `amplitude (m)` and the reference named
    /// `reference`.
    pub fn titled(title: &str) -> Self {
        Self {
            title: title.into(),
            amplitude_axis: "amplitude (m)".into(),
            reference: "reference".into(),
        }
    }
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

/// A panel's frame: its frequency and amplitude ranges.
#[derive(Clone, Copy, Debug, PartialEq)]
struct Frame {
    x: (f64, f64),
    y: (f64, f64),
}

/// The frame of the whole figure: every curve's frequencies, the
/// amplitudes of the nonlinear and reference curves (a linear peak far
/// above is cut). `None` when there is no finite point.
fn whole_frame(curves: &[SectorCurves]) -> Option<Frame> {
    let all = || {
        curves
            .iter()
            .flat_map(|c| c.nonlinear.iter().chain(&c.linear).chain(&c.reference))
            .filter(|(x, y)| x.is_finite() && y.is_finite())
    };
    all().next()?;
    let (x_min, x_max) = all().fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), &(x, _)| {
        (a.min(x), b.max(x))
    });
    let largest = |points: &mut dyn Iterator<Item = &(f64, f64)>| {
        points
            .map(|p| p.1)
            .filter(|y| y.is_finite())
            .fold(0.0_f64, f64::max)
    };
    let nonlinear_top = largest(
        &mut curves
            .iter()
            .flat_map(|c| c.nonlinear.iter().chain(&c.reference)),
    );
    let linear_top = largest(&mut curves.iter().flat_map(|c| &c.linear));
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
    Some(Frame {
        x: (x_min - pad, x_max + pad),
        y: (bottom, top),
    })
}

/// The frame of the zoomed panel on `region`: its window and the
/// amplitudes of the points that depart from the linear response, with
/// room above for the events' labels.
fn zoom_frame(region: &Region) -> Frame {
    let (low, high) = region.amplitude;
    let margin = (0.15 * (high - low)).max(0.01 * high.abs()).max(1e-30);
    let bottom = if low >= 0.0 {
        (low - margin).max(0.0)
    } else {
        low - margin
    };
    Frame {
        x: region.frequency,
        y: (bottom, high + 2.5 * margin),
    }
}

/// What one panel draws.
struct Panel<'a> {
    caption: String,
    frame: Frame,
    /// Whether the curves have legend entries here.
    curve_legend: bool,
    /// Where the legend goes.
    legend_at: SeriesLabelPosition,
    /// The events drawn in this panel.
    events: Vec<&'a EventSymbol>,
}

type Chart<'a, 'b> = ChartContext<'a, SVGBackend<'b>, Cartesian2d<RangedCoordf64, RangedCoordf64>>;

/// Whether the points of `piece` all fall on one pixel (a path of no
/// length: nothing to stroke, and a renderer warns about it).
fn within_a_pixel(chart: &Chart, piece: &[(f64, f64)]) -> bool {
    let first = piece.first().map(|p| chart.backend_coord(p));
    piece.iter().all(|p| Some(chart.backend_coord(p)) == first)
}

/// Draws the nonlinear branch of curve `c` (colour `color`): solid where
/// stable, dashed where not, clipped to `frame`.
fn draw_branch(
    chart: &mut Chart,
    c: &SectorCurves,
    color: RGBColor,
    frame: Frame,
    legend: bool,
) -> Result<(), PlotError> {
    let mut labelled = (!legend, !legend);
    // The runs are consecutive slices: `first` is where each starts.
    let mut first = 0;
    for run in split_at_breaks(&c.nonlinear, &c.breaks) {
        let states = c.unstable.get(first..first + run.len()).unwrap_or(&[]);
        first += run.len();
        for (segment, unstable) in stability_runs(run, states) {
            for piece in clip_to(&segment, frame.x, frame.y) {
                if within_a_pixel(chart, &piece) {
                    continue;
                }
                if unstable {
                    let series = chart
                        .draw_series(DashedLineSeries::new(piece, 7, 4, color.stroke_width(2)))
                        .map_err(draw_error)?;
                    if !labelled.1 {
                        labelled.1 = true;
                        series
                            .label(format!("{}, unstable", c.label))
                            .legend(move |(x, y)| {
                                DashedPathElement::new(
                                    vec![(x, y), (x + 24, y)],
                                    7,
                                    4,
                                    color.stroke_width(2),
                                )
                            });
                    }
                } else {
                    let series = chart
                        .draw_series(LineSeries::new(piece, color.stroke_width(2)))
                        .map_err(draw_error)?;
                    if !labelled.0 {
                        labelled.0 = true;
                        series.label(c.label.clone()).legend(move |(x, y)| {
                            PathElement::new(vec![(x, y), (x + 24, y)], color.stroke_width(2))
                        });
                    }
                }
            }
        }
    }
    Ok(())
}

/// Draws the linear response and the reference of curve `c`, clipped.
fn draw_others(
    chart: &mut Chart,
    c: &SectorCurves,
    color: RGBColor,
    frame: Frame,
    legend: bool,
    reference_label: &str,
) -> Result<(), PlotError> {
    for (run_index, run) in clip_to(&c.linear, frame.x, frame.y).into_iter().enumerate() {
        let series = chart
            .draw_series(DottedLineSeries::new(run, 0, 5, move |p| {
                Circle::new(p, 1, color.filled())
            }))
            .map_err(draw_error)?;
        if legend && run_index == 0 {
            series
                .label(format!("linear, {}", c.label))
                .legend(move |(x, y)| {
                    DottedPathElement::new(vec![(x, y), (x + 24, y)], 0, 5, move |p| {
                        Circle::new(p, 1, color.filled())
                    })
                });
        }
    }
    let light = color.mix(0.6);
    for (run_index, run) in clip_to(&c.reference, frame.x, frame.y)
        .into_iter()
        .enumerate()
    {
        let series = chart
            .draw_series(DashedLineSeries::new(run, 10, 5, light.stroke_width(2)))
            .map_err(draw_error)?;
        if legend && run_index == 0 {
            series
                .label(format!("{reference_label}, {}", c.label))
                .legend(move |(x, y)| {
                    DashedPathElement::new(vec![(x, y), (x + 24, y)], 10, 5, light.stroke_width(2))
                });
        }
    }
    Ok(())
}

/// Draws one panel into `area`.
fn draw_panel(
    area: &DrawingArea<SVGBackend, plotters::coord::Shift>,
    panel: &Panel,
    captions: &Captions,
    curves: &[SectorCurves],
) -> Result<(), PlotError> {
    let frame = panel.frame;
    let mut chart = ChartBuilder::on(area)
        .caption(&panel.caption, ("sans-serif", 20))
        .margin(15)
        .x_label_area_size(45)
        .y_label_area_size(90)
        .build_cartesian_2d(frame.x.0..frame.x.1, frame.y.0..frame.y.1)
        .map_err(draw_error)?;
    // Enough digits that neighbouring ticks differ on a zoomed panel.
    let span = (frame.y.1 - frame.y.0).abs();
    let scale = frame.y.0.abs().max(frame.y.1.abs());
    let digits = if span > 0.0 && scale > 0.0 {
        ((scale / span).log10().ceil().max(0.0) as usize + 1).min(6)
    } else {
        2
    };
    chart
        .configure_mesh()
        .x_desc("frequency (Hz)")
        .y_desc(&captions.amplitude_axis)
        .y_label_formatter(&|y| format!("{y:.digits$e}"))
        .x_label_formatter(&|x| format!("{x:.2}"))
        .draw()
        .map_err(draw_error)?;
    let mut labelled = false;
    for (i, c) in curves.iter().enumerate() {
        let color = palette(i);
        draw_others(
            &mut chart,
            c,
            color,
            frame,
            panel.curve_legend,
            &captions.reference,
        )?;
        if c.nonlinear.len() > 1 {
            draw_branch(&mut chart, c, color, frame, panel.curve_legend)?;
        } else if let Some(&p) = c.nonlinear.first() {
            let series = chart
                .draw_series(std::iter::once(Circle::new(p, 3, color.filled())))
                .map_err(draw_error)?;
            if panel.curve_legend {
                series
                    .label(c.label.clone())
                    .legend(move |(x, y)| Circle::new((x + 12, y), 3, color.filled()));
            }
        }
        labelled |= panel.curve_legend;
    }
    let mut named: Vec<MarkerKind> = Vec::new();
    for (i, &event) in panel.events.iter().enumerate() {
        let stagger = (i % 3) as i32;
        let series = chart
            .draw_series(std::iter::once(
                EmptyElement::at((event.frequency_hz, event.amplitude_m))
                    + PathElement::new(outline(event.kind, SYMBOL_SIZE), symbol_style())
                    + Text::new(
                        event.label.clone(),
                        label_offset(stagger),
                        ("sans-serif", 11).into_font().color(&SYMBOL_COLOUR),
                    ),
            ))
            .map_err(draw_error)?;
        if !named.contains(&event.kind) {
            named.push(event.kind);
            let kind = event.kind;
            series.label(kind_name(kind)).legend(move |(x, y)| {
                PathElement::new(outline_at(kind, (x + 12, y)), symbol_style())
            });
            labelled = true;
        }
    }
    if labelled {
        chart
            .configure_series_labels()
            .position(panel.legend_at.clone())
            .background_style(WHITE.mix(0.85))
            .border_style(BLACK.mix(0.4))
            .label_font(("sans-serif", 14))
            .draw()
            .map_err(draw_error)?;
    }
    Ok(())
}

/// Draws the curves of each sector (one colour per sector) and returns the
/// SVG text: the whole frequency range and, when the nonlinear region is a
/// small part of it, a second panel on that region. Each event is drawn
/// once: in the zoomed panel when it lies in its window, else in the first.
pub fn forced_response_svg(
    captions: &Captions,
    curves: &[SectorCurves],
) -> Result<String, PlotError> {
    let Some(whole) = whole_frame(curves) else {
        return Err(PlotError::Empty {
            what: WHAT.into(),
            message: "no point to draw".into(),
        });
    };
    let region = nonlinear_region(curves, whole.x.0, whole.x.1);
    let window = region.map(|r| r.frequency);
    let events: Vec<&EventSymbol> = curves
        .iter()
        .flat_map(|c| &c.markers)
        .filter(|e| e.frequency_hz.is_finite() && e.amplitude_m.is_finite())
        .collect();
    let zoomed =
        |e: &EventSymbol| window.is_some_and(|(low, high)| (low..=high).contains(&e.frequency_hz));
    let first = Panel {
        caption: captions.title.clone(),
        frame: whole,
        curve_legend: true,
        legend_at: SeriesLabelPosition::UpperLeft,
        events: events.iter().copied().filter(|e| !zoomed(e)).collect(),
    };
    let mut svg = String::new();
    {
        let size = if window.is_some() {
            (1000, 1150)
        } else {
            (1000, 650)
        };
        let root = SVGBackend::with_string(&mut svg, size).into_drawing_area();
        root.fill(&WHITE).map_err(draw_error)?;
        match region {
            Some(region) => {
                let (top, bottom) = root.split_vertically(620);
                draw_panel(&top, &first, captions, curves)?;
                let second = Panel {
                    caption: format!(
                        "Nonlinear region, {:.2}-{:.2} Hz",
                        region.frequency.0, region.frequency.1
                    ),
                    frame: zoom_frame(&region),
                    curve_legend: false,
                    legend_at: SeriesLabelPosition::LowerRight,
                    events: events.iter().copied().filter(|e| zoomed(e)).collect(),
                };
                draw_panel(&bottom, &second, captions, curves)?;
            }
            None => draw_panel(&root, &first, captions, curves)?,
        }
        root.present().map_err(draw_error)?;
    }
    Ok(svg)
}

/// Writes [`forced_response_svg`] to `path`.
pub fn forced_response(
    path: &Path,
    captions: &Captions,
    curves: &[SectorCurves],
) -> Result<(), PlotError> {
    let svg = forced_response_svg(captions, curves)?;
    super::write_svg(path, &svg)
}

#[cfg(test)]
mod tests {
    use super::*;

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
            forced_response_svg(&Captions::titled("gap"), &curves)
                .expect("drawn")
                .matches("<polyline")
                .count()
        };
        assert_eq!(polylines(vec![3]), polylines(Vec::new()) + 1);
    }
}
