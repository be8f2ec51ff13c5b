//! The frequency versus nodal diameter diagram: one line per mode family,
//! optionally a second model's frequencies as open circles beside them.

use super::PlotError;
use plotters::prelude::*;
use std::path::Path;

const WHAT: &str = "the frequency versus nodal diameter plot";

/// Colours of the mode families (the "tab10" palette), reused cyclically.
const COLOURS: [RGBColor; 10] = [
    RGBColor(31, 119, 180),
    RGBColor(255, 127, 14),
    RGBColor(44, 160, 44),
    RGBColor(214, 39, 40),
    RGBColor(148, 103, 189),
    RGBColor(140, 86, 75),
    RGBColor(227, 119, 194),
    RGBColor(127, 127, 127),
    RGBColor(188, 189, 34),
    RGBColor(23, 190, 207),
];

fn draw_error(e: impl std::fmt::Display) -> PlotError {
    PlotError::Draw {
        what: WHAT.into(),
        message: e.to_string(),
    }
}

/// A second model's frequencies drawn beside the lines of the first, as
/// open circles of the same family colours, with a legend naming both
/// (e.g. the full finite-element sector beside its Craig–Bampton model).
#[derive(Clone, Copy, Debug)]
pub struct ComparedFrequencies<'a> {
    /// Legend entry of the lines (e.g. `Craig–Bampton`).
    pub lines_label: &'a str,
    /// The frequencies (Hz) drawn as open circles, as `(diameter,
    /// frequencies)` like the lines', matched family by family (index).
    pub markers: &'a [(usize, Vec<f64>)],
    /// Legend entry of the open circles (e.g. `full sector`).
    pub markers_label: &'a str,
}

/// Draws the natural frequencies (Hz) of each nodal diameter `0..=N/2`, as
/// given by `SectorModel::natural_frequencies`, one line per mode family
/// (the `r`-th frequency of every diameter), and returns the SVG text.
/// `families` limits the number of families drawn (`None`: all).
pub fn frequency_versus_nodal_diameter_svg(
    sectors: usize,
    frequencies: &[(usize, Vec<f64>)],
    families: Option<usize>,
    title: &str,
) -> Result<String, PlotError> {
    draw(sectors, frequencies, None, families, title)
}

/// [`frequency_versus_nodal_diameter_svg`] with `compared`'s frequencies
/// as open circles beside the lines and a legend of both.
pub fn frequency_versus_nodal_diameter_compared_svg(
    sectors: usize,
    frequencies: &[(usize, Vec<f64>)],
    compared: &ComparedFrequencies,
    families: Option<usize>,
    title: &str,
) -> Result<String, PlotError> {
    draw(sectors, frequencies, Some(compared), families, title)
}

fn draw(
    sectors: usize,
    frequencies: &[(usize, Vec<f64>)],
    compared: Option<&ComparedFrequencies>,
    families: Option<usize>,
    title: &str,
) -> Result<String, PlotError> {
    let count = frequencies.iter().map(|(_, f)| f.len()).max().unwrap_or(0);
    let count = families.map_or(count, |k| k.min(count));
    if frequencies.is_empty() || count == 0 {
        return Err(PlotError::Empty {
            what: WHAT.into(),
            message: "no frequencies".into(),
        });
    }
    let markers: &[(usize, Vec<f64>)] = compared.map_or(&[], |c| c.markers);
    let top = frequencies
        .iter()
        .chain(markers)
        .flat_map(|(_, f)| f.iter().take(count))
        .fold(0.0_f64, |m, &f| m.max(f));
    let top = if top > 0.0 { top * 1.08 } else { 1.0 };
    let last_nd = frequencies.iter().map(|(d, _)| *d).max().unwrap_or(0);
    // Room on the right for the family labels.
    let label_room = 0.12 * (last_nd as f64 + 1.0) + 0.6;
    let mut svg = String::new();
    {
        let root = SVGBackend::with_string(&mut svg, (900, 600)).into_drawing_area();
        root.fill(&WHITE).map_err(draw_error)?;
        let mut chart = ChartBuilder::on(&root)
            .caption(title, ("sans-serif", 22))
            .margin(15)
            .x_label_area_size(45)
            .y_label_area_size(75)
            .build_cartesian_2d(-0.5..(last_nd as f64 + 0.5 + label_room), 0.0..top)
            .map_err(draw_error)?;
        chart
            .configure_mesh()
            .x_desc(format!("nodal diameter (N = {sectors})"))
            .y_desc("frequency (Hz)")
            .x_labels((last_nd + 1).min(24))
            .y_label_formatter(&|y| format!("{y:.0}"))
            .x_label_formatter(&|x| {
                if (x - x.round()).abs() < 1e-9 && *x >= 0.0 && *x <= last_nd as f64 {
                    format!("{}", x.round() as i64)
                } else {
                    String::new()
                }
            })
            .draw()
            .map_err(draw_error)?;
        for r in 0..count {
            let color = COLOURS[r % COLOURS.len()];
            let points: Vec<(f64, f64)> = frequencies
                .iter()
                .filter_map(|(d, f)| f.get(r).map(|&v| (*d as f64, v)))
                .collect();
            chart
                .draw_series(LineSeries::new(points.clone(), color.stroke_width(2)))
                .map_err(draw_error)?;
            if let Some(&(x, y)) = points.last() {
                if count <= 12 {
                    chart
                        .draw_series(std::iter::once(Text::new(
                            format!("mode {}", r + 1),
                            (x + 0.15, y),
                            ("sans-serif", 14).into_font().color(&color),
                        )))
                        .map_err(draw_error)?;
                }
            }
            chart
                .draw_series(
                    points
                        .into_iter()
                        .map(|p| Circle::new(p, 3, color.filled())),
                )
                .map_err(draw_error)?;
            let open: Vec<(f64, f64)> = markers
                .iter()
                .filter_map(|(d, f)| f.get(r).map(|&v| (*d as f64, v)))
                .collect();
            chart
                .draw_series(
                    open.into_iter()
                        .map(|p| Circle::new(p, 6, color.stroke_width(2))),
                )
                .map_err(draw_error)?;
        }
        if let Some(compared) = compared {
            // The legend's entries, in black: a line with its dot, an open circle.
            chart
                .draw_series(std::iter::empty::<Circle<(f64, f64), i32>>())
                .map_err(draw_error)?
                .label(compared.lines_label)
                .legend(|(x, y)| {
                    EmptyElement::at((x, y))
                        + PathElement::new(vec![(-8, 0), (8, 0)], BLACK.stroke_width(2))
                        + Circle::new((0, 0), 3, BLACK.filled())
                });
            chart
                .draw_series(std::iter::empty::<Circle<(f64, f64), i32>>())
                .map_err(draw_error)?
                .label(compared.markers_label)
                .legend(|(x, y)| Circle::new((x, y), 6, BLACK.stroke_width(2)));
            chart
                .configure_series_labels()
                .position(SeriesLabelPosition::LowerLeft)
                .background_style(WHITE.mix(0.9))
                .border_style(BLACK)
                .label_font(("sans-serif", 15))
                .draw()
                .map_err(draw_error)?;
        }
        root.present().map_err(draw_error)?;
    }
    Ok(svg)
}

/// Writes [`frequency_versus_nodal_diameter_svg`] to `path`.
pub fn frequency_versus_nodal_diameter(
    path: &Path,
    sectors: usize,
    frequencies: &[(usize, Vec<f64>)],
    families: Option<usize>,
    title: &str,
) -> Result<(), PlotError> {
    let svg = frequency_versus_nodal_diameter_svg(sectors, frequencies, families, title)?;
    write(path, svg)
}

/// Writes [`frequency_versus_nodal_diameter_compared_svg`] to `path`.
pub fn frequency_versus_nodal_diameter_compared(
    path: &Path,
    sectors: usize,
    frequencies: &[(usize, Vec<f64>)],
    compared: &ComparedFrequencies,
    families: Option<usize>,
    title: &str,
) -> Result<(), PlotError> {
    let svg = frequency_versus_nodal_diameter_compared_svg(
        sectors,
        frequencies,
        compared,
        families,
        title,
    )?;
    write(path, svg)
}

fn write(path: &Path, svg: String) -> Result<(), PlotError> {
    super::write_svg(path, &svg)
}
