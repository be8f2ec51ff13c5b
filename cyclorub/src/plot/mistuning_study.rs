//! The distribution of a mistuning study's amplification factors (issue 44
//! item 5, docs/design.md §12): a histogram and the empirical cumulative
//! distribution side by side, with the tuned wheel's value 1 and
//! Whitehead's bound `(1 + √N)/2` marked.

use super::{palette, write_svg, PlotError};
use plotters::prelude::*;
use std::path::{Path, PathBuf};

/// Whitehead's bound on the amplification factor of a wheel of `sectors`
/// sectors: `(1 + √N)/2`, the largest a linear wheel's forced response can
/// reach in one sector against the tuned wheel's (Whitehead 1966).
pub fn whitehead_bound(sectors: usize) -> f64 {
    (1.0 + (sectors as f64).sqrt()) / 2.0
}

/// A histogram of the finite `values` in `bins` bins of equal width over
/// their range: `(left edges, width, counts)`; one value, or values all
/// alike, fill one bin of width 1 % of the value (or 0.01) centred on it.
pub fn histogram(values: &[f64], bins: usize) -> (Vec<f64>, f64, Vec<usize>) {
    let finite: Vec<f64> = values.iter().copied().filter(|v| v.is_finite()).collect();
    let bins = bins.max(1);
    let (low, high) = finite
        .iter()
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), &v| {
            (a.min(v), b.max(v))
        });
    if finite.is_empty() {
        return (Vec::new(), 0.0, Vec::new());
    }
    if high <= low {
        let width = (0.01 * low.abs()).max(0.01);
        return (vec![low - width / 2.0], width, vec![finite.len()]);
    }
    let width = (high - low) / bins as f64;
    let mut counts = vec![0; bins];
    for v in &finite {
        // The largest value falls in the last bin, not one past it.
        let bin = (((v - low) / width).floor() as usize).min(bins - 1);
        counts[bin] += 1;
    }
    let edges = (0..bins).map(|i| low + i as f64 * width).collect();
    (edges, width, counts)
}

/// The figure of the amplification factors `factors` (NaN left out) of a
/// study of a wheel of `sectors` sectors: histogram (left) and empirical
/// cumulative distribution (right), the tuned wheel's 1 and Whitehead's
/// bound drawn on both; returns the SVG text.
pub fn amplification_distribution_svg(
    factors: &[f64],
    sectors: usize,
    title: &str,
) -> Result<String, PlotError> {
    let what = "the amplification factors' distribution";
    let error = |e: &dyn std::fmt::Display| PlotError::Draw {
        what: what.into(),
        message: e.to_string(),
    };
    let mut values: Vec<f64> = factors.iter().copied().filter(|f| f.is_finite()).collect();
    if values.is_empty() {
        return Err(PlotError::Empty {
            what: what.into(),
            message: "no finite amplification factor".into(),
        });
    }
    values.sort_by(f64::total_cmp);
    let n = values.len();
    let bound = whitehead_bound(sectors);
    let (edges, width, counts) =
        histogram(&values, ((n as f64).sqrt().ceil() as usize).clamp(5, 40));
    let low = edges[0].min(1.0);
    let high = (edges[edges.len() - 1] + width).max(bound);
    let margin = 0.04 * (high - low);
    let (low, high) = (low - margin, high + margin);
    let tallest = counts.iter().copied().max().unwrap_or(1) as f64;
    let x_desc = "amplification factor (largest sector peak / tuned peak)";
    let marks = [
        (1.0, BLACK, "tuned wheel: 1".to_string()),
        (
            bound,
            RGBColor(214, 39, 40),
            format!("Whitehead's bound (1 + √N)/2 = {bound:.3}"),
        ),
    ];
    let mut svg = String::new();
    {
        let root = SVGBackend::with_string(&mut svg, (1200, 560)).into_drawing_area();
        root.fill(&WHITE).map_err(|e| error(&e))?;
        let root = root
            .titled(title, ("sans-serif", 22))
            .map_err(|e| error(&e))?;
        let panels = root.split_evenly((1, 2));
        // Left: the histogram.
        let top = 1.15 * tallest;
        let mut chart = ChartBuilder::on(&panels[0])
            .caption(format!("histogram of {n} patterns"), ("sans-serif", 18))
            .margin(12)
            .x_label_area_size(45)
            .y_label_area_size(60)
            .build_cartesian_2d(low..high, 0.0..top)
            .map_err(|e| error(&e))?;
        chart
            .configure_mesh()
            .x_desc(x_desc)
            .y_desc("patterns")
            // Whole patterns only: no label on a fractional tick.
            .y_label_formatter(&|y| {
                if (y - y.round()).abs() < 1e-9 {
                    format!("{}", y.round() as i64)
                } else {
                    String::new()
                }
            })
            .draw()
            .map_err(|e| error(&e))?;
        chart
            .draw_series(edges.iter().zip(&counts).map(|(&left, &count)| {
                Rectangle::new(
                    [(left, 0.0), (left + width, count as f64)],
                    palette(0).mix(0.75).filled(),
                )
            }))
            .map_err(|e| error(&e))?;
        // Each bin outlined, so that neighbours of one height stay apart.
        chart
            .draw_series(edges.iter().zip(&counts).filter(|(_, &c)| c > 0).map(
                |(&left, &count)| {
                    Rectangle::new(
                        [(left, 0.0), (left + width, count as f64)],
                        WHITE.stroke_width(1),
                    )
                },
            ))
            .map_err(|e| error(&e))?;
        for (x, colour, label) in &marks {
            chart
                .draw_series(DashedLineSeries::new(
                    vec![(*x, 0.0), (*x, top)],
                    8,
                    5,
                    colour.stroke_width(2),
                ))
                .map_err(|e| error(&e))?
                .label(label.clone())
                .legend(move |(x, y)| {
                    PathElement::new(vec![(x, y), (x + 20, y)], colour.stroke_width(2))
                });
        }
        chart
            .configure_series_labels()
            .background_style(WHITE.mix(0.85))
            .border_style(BLACK)
            .position(SeriesLabelPosition::UpperLeft)
            .draw()
            .map_err(|e| error(&e))?;
        // Right: the empirical cumulative distribution, a step per pattern.
        let mut chart = ChartBuilder::on(&panels[1])
            .caption("empirical cumulative distribution", ("sans-serif", 18))
            .margin(12)
            .x_label_area_size(45)
            .y_label_area_size(60)
            .build_cartesian_2d(low..high, 0.0..1.05)
            .map_err(|e| error(&e))?;
        chart
            .configure_mesh()
            .x_desc(x_desc)
            .y_desc("fraction of patterns ≤ x")
            .draw()
            .map_err(|e| error(&e))?;
        let mut steps = vec![(low, 0.0)];
        for (i, &v) in values.iter().enumerate() {
            steps.push((v, i as f64 / n as f64));
            steps.push((v, (i + 1) as f64 / n as f64));
        }
        steps.push((high, 1.0));
        chart
            .draw_series(LineSeries::new(steps, palette(0).stroke_width(2)))
            .map_err(|e| error(&e))?;
        for (x, colour, _) in &marks {
            chart
                .draw_series(DashedLineSeries::new(
                    vec![(*x, 0.0), (*x, 1.05)],
                    8,
                    5,
                    colour.stroke_width(2),
                ))
                .map_err(|e| error(&e))?;
        }
    }
    Ok(svg)
}

/// Writes [`amplification_distribution_svg`] to `path` (an SVG file),
/// with its PNG beside when `png`; returns the files written.
pub fn write_amplification_distribution(
    path: &Path,
    factors: &[f64],
    sectors: usize,
    png: bool,
) -> Result<Vec<PathBuf>, PlotError> {
    let count = factors.iter().filter(|f| f.is_finite()).count();
    let svg = amplification_distribution_svg(
        factors,
        sectors,
        &format!("Mistuning study: amplification factors of {count} patterns (N = {sectors})"),
    )?;
    if let Some(parent) = path.parent().filter(|p| !p.as_os_str().is_empty()) {
        std::fs::create_dir_all(parent).map_err(|source| PlotError::Write {
            path: parent.to_path_buf(),
            source,
        })?;
    }
    write_svg(path, &svg)?;
    let mut written = vec![path.to_path_buf()];
    if png {
        written.extend(super::png::write_pngs_beside(&written)?);
    }
    Ok(written)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_histogram_counts_every_value_once_in_its_bin() {
        let (edges, width, counts) = histogram(&[1.0, 1.1, 1.3, 1.3, 2.0, f64::NAN], 4);
        assert_eq!(counts, vec![2, 2, 0, 1]);
        assert!((width - 0.25).abs() < 1e-15);
        assert!((edges[1] - 1.25).abs() < 1e-15);
        let (_, _, one) = histogram(&[1.3, 1.3], 5);
        assert_eq!(one, vec![2]);
    }

    #[test]
    fn whiteheads_bound_and_the_marks_are_drawn() {
        assert!((whitehead_bound(24) - (1.0 + 24f64.sqrt()) / 2.0).abs() < 1e-15);
        assert!((whitehead_bound(4) - 1.5).abs() < 1e-15);
        let svg = amplification_distribution_svg(&[1.05, 1.2, 1.3], 6, "t").expect("svg");
        assert!(
            svg.contains("= 1.725"),
            "the bound's value is in the legend"
        );
        assert!(svg.contains("tuned wheel: 1"));
        assert!(matches!(
            amplification_distribution_svg(&[f64::NAN], 6, "t"),
            Err(PlotError::Empty { .. })
        ));
    }
}
