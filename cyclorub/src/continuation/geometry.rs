//! The space continuation works in: scaled unknowns `z = D [x; ω]`, and the
//! distances between points and segments of a branch there.

use super::{Problem, Settings};

/// The scaling `z = D [x; ω]` of the unknowns and the frequency.
#[derive(Clone, Debug)]
pub(crate) struct Scaling {
    /// `z̄ = D z`: per-unknown factors, then the frequency's.
    factors: Vec<f64>,
}

impl Scaling {
    /// Unknowns by `settings.length_scale` (weighted by the problem's norm
    /// weights), the frequency in units of the range: the whole sweep is
    /// one unit of arc length, comparable with a displacement of one length
    /// scale. The same for both ends of a range. A range narrower than
    /// `scaling.min_range_fraction` of the frequency counts as that wide, so
    /// that a degenerate range still scales finitely.
    pub(crate) fn new<P: Problem>(problem: &P, all: &Settings) -> Self {
        let settings = &all.arc_length;
        let mut factors: Vec<f64> = problem
            .norm_weights()
            .iter()
            .map(|w| w.sqrt() / settings.length_scale)
            .collect();
        let range = (settings.end - settings.start).abs();
        factors.push(
            1.0 / range
                .max(all.scaling.min_range_fraction * settings.start.abs().max(settings.end.abs()))
                .max(f64::MIN_POSITIVE),
        );
        Self { factors }
    }

    /// No scaling, for tests: `unknowns` factors of 1 and the frequency's.
    #[cfg(test)]
    pub(crate) fn identity(unknowns: usize) -> Self {
        Self::from_factors(vec![1.0; unknowns + 1])
    }

    /// Given factors, for tests.
    #[cfg(test)]
    pub(crate) fn from_factors(factors: Vec<f64>) -> Self {
        Self { factors }
    }

    /// `z` of `(x, ω)`.
    pub(crate) fn scaled(&self, x: &[f64], omega: f64) -> Vec<f64> {
        self.scaled_iter(x, omega).collect()
    }

    /// The coordinates of `z` of `(x, ω)` one by one, without a copy.
    pub(crate) fn scaled_iter<'a>(
        &'a self,
        x: &'a [f64],
        omega: f64,
    ) -> impl Iterator<Item = f64> + Clone + 'a {
        let n = x.len();
        x.iter()
            .zip(&self.factors)
            .map(|(v, d)| v * d)
            .chain(std::iter::once(omega * self.factors[n]))
    }

    /// `(x, ω)` of `z`.
    pub(crate) fn unscaled(&self, z: &[f64]) -> (Vec<f64>, f64) {
        let n = z.len() - 1;
        let x = (0..n).map(|i| z[i] / self.factors[i]).collect();
        (x, z[n] / self.factors[n])
    }

    /// The factors: per unknown, then the frequency's.
    pub(crate) fn factors(&self) -> &[f64] {
        &self.factors
    }
}

/// `a + length · direction`.
pub(crate) fn along(a: &[f64], direction: &[f64], length: f64) -> Vec<f64> {
    a.iter()
        .zip(direction)
        .map(|(a, t)| a + length * t)
        .collect()
}

/// `aᵀ b`.
pub(crate) fn dot(a: &[f64], b: &[f64]) -> f64 {
    a.iter().zip(b).map(|(a, b)| a * b).sum()
}

/// `‖a − b‖`.
pub(crate) fn distance(a: &[f64], b: &[f64]) -> f64 {
    a.iter()
        .zip(b)
        .map(|(a, b)| (a - b) * (a - b))
        .sum::<f64>()
        .sqrt()
}

/// Distance from `point` to the segment `[a, b]`, and the segment's length.
/// The ends are given coordinate by coordinate, so that stored points can
/// be scaled on the fly (see [`Scaling::scaled_iter`]). The distance is
/// summed from the offsets to the closest point of the segment, not from
/// the expansion `|ah|² − 2t ah·ab + t²|ab|²`, which cancels to nothing
/// for a point on a long segment.
pub(crate) fn segment_distance(
    point: &[f64],
    a: impl Iterator<Item = f64> + Clone,
    b: impl Iterator<Item = f64> + Clone,
) -> (f64, f64) {
    let (mut length2, mut along) = (0.0, 0.0);
    for ((c, a), b) in point.iter().zip(a.clone()).zip(b.clone()) {
        let d = b - a;
        length2 += d * d;
        along += (c - a) * d;
    }
    let t = (along / length2.max(f64::MIN_POSITIVE)).clamp(0.0, 1.0);
    let distance = point
        .iter()
        .zip(a)
        .zip(b)
        .map(|((c, a), b)| (c - a - t * (b - a)).powi(2))
        .sum::<f64>()
        .sqrt();
    (distance, length2.sqrt())
}

/// The cosine between the segment `[a, b]` (of length `length`) and the
/// unit vector `tangent`.
pub(crate) fn segment_cosine(a: &[f64], b: &[f64], length: f64, tangent: &[f64]) -> f64 {
    b.iter()
        .zip(a)
        .zip(tangent)
        .map(|((b, a), t)| (b - a) * t)
        .sum::<f64>()
        / length.max(f64::MIN_POSITIVE)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn distance_to(point: &[f64], a: &[f64], b: &[f64]) -> (f64, f64) {
        segment_distance(point, a.iter().copied(), b.iter().copied())
    }

    #[test]
    fn the_distance_to_a_segment_is_measured_across_it_and_at_its_ends() {
        let (a, b) = ([0.0, 0.0], [2.0, 0.0]);
        let (across, length) = distance_to(&[1.0, 3.0], &a, &b);
        assert!((across - 3.0).abs() < 1e-14 && (length - 2.0).abs() < 1e-14);
        assert!((distance_to(&[5.0, 4.0], &a, &b).0 - 5.0).abs() < 1e-14);
        assert!((distance_to(&[-3.0, -4.0], &a, &b).0 - 5.0).abs() < 1e-14);
        // A segment of zero length: the distance to its point.
        assert!((distance_to(&[3.0, 4.0], &a, &a).0 - 5.0).abs() < 1e-14);
    }

    #[test]
    fn a_point_close_to_a_long_segment_keeps_its_distance() {
        // 1e-9 off a segment a thousand long, far from its ends: the
        // expanded form loses every digit (|ah|² ~ 1e5, d² ~ 1e-18).
        let (a, b) = ([0.0, 0.0], [1000.0, 0.0]);
        let (d, _) = distance_to(&[300.0, 1e-9], &a, &b);
        assert!((d - 1e-9).abs() < 1e-20, "{d}");
    }

    #[test]
    fn scaled_points_give_the_distance_in_scaled_units() {
        let scaling = Scaling::from_factors(vec![2.0, 0.5]);
        // Scaled: a = (0, 0), b = (2, 0).
        let (x_a, x_b) = ([0.0], [1.0]);
        let (d, length) = segment_distance(
            &[1.0, 3.0],
            scaling.scaled_iter(&x_a, 0.0),
            scaling.scaled_iter(&x_b, 0.0),
        );
        assert!((d - 3.0).abs() < 1e-14 && (length - 2.0).abs() < 1e-14);
        assert_eq!(scaling.scaled(&x_b, 4.0), vec![2.0, 2.0]);
        assert_eq!(scaling.unscaled(&[2.0, 2.0]), (vec![1.0], 4.0));
    }
}
