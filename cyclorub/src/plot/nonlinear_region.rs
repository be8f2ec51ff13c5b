//! Where a forced response is nonlinear (the part a designer came for),
//! and the clipping of curves to a panel's frame.

use super::curves::SectorCurves;

/// A departure from the linear response larger than this fraction of the
/// curve's largest nonlinear amplitude counts as nonlinear.
pub const DEPARTURE: f64 = 0.02;

/// A zoomed panel is drawn only when the nonlinear region (padded) spans
/// less than this fraction of the whole frequency range.
const ZOOM_WORTH: f64 = 0.6;

/// The linear response `(Hz, m)` (by increasing frequency) at `f`,
/// interpolated linearly; `None` outside its range.
fn interpolate(linear: &[(f64, f64)], f: f64) -> Option<f64> {
    let after = linear.iter().position(|&(x, _)| x >= f)?;
    let (x1, y1) = linear[after];
    if after == 0 {
        return (x1 <= f).then_some(y1);
    }
    let (x0, y0) = linear[after - 1];
    if x1 - x0 <= 0.0 {
        return Some(y1);
    }
    Some(y0 + (f - x0) / (x1 - x0) * (y1 - y0))
}

/// Where a forced response is nonlinear.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Region {
    /// The frequency window, Hz (padded).
    pub frequency: (f64, f64),
    /// The smallest and largest amplitude of the points that depart, m.
    pub amplitude: (f64, f64),
}

/// The nonlinear region of `curves`: the points of a nonlinear branch that
/// depart from the linear response by more than [`DEPARTURE`] of the
/// branch's largest amplitude, their frequencies padded by a quarter of
/// their span on each side (at least 0.2 % of the frequency) and kept
/// within `(x_min, x_max)`. `None` when no curve departs, or when the
/// window would not be much narrower than `(x_min, x_max)` (the whole
/// figure then shows it well enough).
pub fn nonlinear_region(curves: &[SectorCurves], x_min: f64, x_max: f64) -> Option<Region> {
    let mut low = f64::INFINITY;
    let mut high = f64::NEG_INFINITY;
    let mut amplitude = (f64::INFINITY, f64::NEG_INFINITY);
    for curve in curves {
        let mut linear: Vec<(f64, f64)> = curve
            .linear
            .iter()
            .copied()
            .filter(|(x, y)| x.is_finite() && y.is_finite())
            .collect();
        linear.sort_by(|a, b| a.0.total_cmp(&b.0));
        let largest = curve
            .nonlinear
            .iter()
            .map(|p| p.1.abs())
            .filter(|y| y.is_finite())
            .fold(0.0_f64, f64::max);
        for &(f, a) in &curve.nonlinear {
            let Some(l) = interpolate(&linear, f) else {
                continue;
            };
            if (a - l).abs() > DEPARTURE * largest {
                low = low.min(f);
                high = high.max(f);
                amplitude = (amplitude.0.min(a), amplitude.1.max(a));
            }
        }
    }
    if low > high || low.is_nan() || high.is_nan() || x_max <= x_min || x_max.is_nan() {
        return None;
    }
    let pad = (0.25 * (high - low)).max(0.002 * high.abs());
    let window = ((low - pad).max(x_min), (high + pad).min(x_max));
    (window.1 - window.0 < ZOOM_WORTH * (x_max - x_min)).then_some(Region {
        frequency: window,
        amplitude,
    })
}

/// A segment clipped to a box.
struct Clipped {
    start: (f64, f64),
    end: (f64, f64),
    /// Whether the start was cut (the segment entered the box).
    cut_start: bool,
    /// Whether the end was cut (the segment left the box).
    cut_end: bool,
}

/// The part of the segment `a`–`b` inside the box (Liang–Barsky).
fn clip_segment(a: (f64, f64), b: (f64, f64), x: (f64, f64), y: (f64, f64)) -> Option<Clipped> {
    let (dx, dy) = (b.0 - a.0, b.1 - a.1);
    let (mut t0, mut t1) = (0.0_f64, 1.0_f64);
    for (p, q) in [
        (-dx, a.0 - x.0),
        (dx, x.1 - a.0),
        (-dy, a.1 - y.0),
        (dy, y.1 - a.1),
    ] {
        if p == 0.0 {
            if q < 0.0 {
                return None;
            }
        } else {
            let t = q / p;
            if p < 0.0 {
                t0 = t0.max(t);
            } else {
                t1 = t1.min(t);
            }
        }
    }
    if t0 > t1 {
        return None;
    }
    let at = |t: f64| (a.0 + t * dx, a.1 + t * dy);
    Some(Clipped {
        start: at(t0),
        end: at(t1),
        cut_start: t0 > 0.0,
        cut_end: t1 < 1.0,
    })
}

/// Splits a polyline into its runs inside the box `x` × `y`, the crossings
/// of the frame interpolated (a tall linear peak is cut at the top, a
/// curve at the sides of a zoomed panel). Runs of no length are dropped.
pub fn clip_to(points: &[(f64, f64)], x: (f64, f64), y: (f64, f64)) -> Vec<Vec<(f64, f64)>> {
    let mut runs: Vec<Vec<(f64, f64)>> = Vec::new();
    let mut open = false;
    for pair in points.windows(2) {
        let Some(piece) = clip_segment(pair[0], pair[1], x, y) else {
            open = false;
            continue;
        };
        match runs.last_mut() {
            Some(run) if open && !piece.cut_start => run.push(piece.end),
            _ => runs.push(vec![piece.start, piece.end]),
        }
        open = !piece.cut_end;
    }
    // A run that only touches the frame has no length: nothing to stroke.
    runs.retain(|run| run.iter().any(|p| *p != run[0]));
    runs
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn clipping_cuts_a_peak_at_the_frame() {
        let points = [(0.0, 0.0), (1.0, 2.0), (2.0, 0.0), (3.0, 0.5)];
        let runs = clip_to(&points, (-10.0, 10.0), (-1.0, 1.0));
        assert_eq!(runs.len(), 2);
        assert_eq!(runs[0], vec![(0.0, 0.0), (0.5, 1.0)]);
        assert_eq!(runs[1], vec![(1.5, 1.0), (2.0, 0.0), (3.0, 0.5)]);
        // At the sides too.
        let runs = clip_to(&points, (0.5, 2.5), (-1.0, 10.0));
        assert_eq!(
            runs,
            vec![vec![(0.5, 1.0), (1.0, 2.0), (2.0, 0.0), (2.5, 0.25)]]
        );
    }

    #[test]
    fn the_region_is_where_the_branch_leaves_the_linear_response() {
        let linear: Vec<(f64, f64)> = (0..=200)
            .map(|i| {
                let f = 100.0 + 0.1 * i as f64;
                (f, 1.0 / (1.0 + (f - 110.0).powi(2)))
            })
            .collect();
        // Capped at 0.5 between 109 and 111 Hz.
        let nonlinear: Vec<(f64, f64)> = linear.iter().map(|&(f, a)| (f, a.min(0.5))).collect();
        let curves = [SectorCurves {
            nonlinear,
            linear,
            ..SectorCurves::default()
        }];
        let region = nonlinear_region(&curves, 100.0, 120.0).expect("a region");
        let (low, high) = region.frequency;
        // The departing points are those on the cap.
        assert_eq!(region.amplitude, (0.5, 0.5));
        assert!(low > 108.0 && low < 109.1, "{low}");
        assert!(high > 110.9 && high < 112.0, "{high}");
        // A branch equal to the linear response has none.
        let linear_only = [SectorCurves {
            nonlinear: curves[0].linear.clone(),
            linear: curves[0].linear.clone(),
            ..SectorCurves::default()
        }];
        assert_eq!(nonlinear_region(&linear_only, 100.0, 120.0), None);
        // Nor one that departs everywhere (the whole figure shows it).
        assert_eq!(nonlinear_region(&curves, 108.0, 112.0), None);
    }
}
