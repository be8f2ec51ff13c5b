//! The branch between two of its points, parametrized by the fraction of
//! the chord joining them (docs/design.md §10, "Located"): Newton on the
//! harmonic balance closed by the plane orthogonal to the chord.

use super::locate_error::LocateError;
use crate::continuation::{Evaluation, NewtonSettings, Point, Problem, ScalingSettings};
use crate::hbm::HarmonicBalance;
use faer::linalg::solvers::{PartialPivLu, Solve};
use faer::Mat;

/// The bracket's width in frequency (Hz) below which a crossing is located
/// (with its real part within the growth tolerance).
pub const BRACKET_HZ: f64 = 1e-4;

/// The bracket's width as a fraction of the chord below which a crossing
/// is located whatever its width in frequency.
pub const BRACKET_FRACTION: f64 = 1e-6;

/// The bracket's largest width (fraction of the chord) to count as
/// located in frequency: near a fold the frequency is flat along the
/// branch, its two ends may be at one frequency with the turn beyond them
/// (its frequency within `c w²` of theirs for a bracket `w` wide, `c` the
/// frequency's fall over the chord: a few mHz on the default branch).
pub(super) const FOLD_FRACTION: f64 = 1e-2;

/// How far beside a marker's point (a fraction of the chord) locating
/// probes, where two trials have not moved that end and the real part
/// elsewhere is already the far point's: where the continuation placed the
/// point on a change of contact (a kink, located to about
/// [`BRACKET_FRACTION`]), the change lies within this of it (measured
/// within 1e-6 of the chord on the six-sector DLFT wheel).
pub(super) const PROBE: f64 = 4.0 * BRACKET_FRACTION;

/// The share of the change of the real part between a marker's two points
/// that a bracket closed to [`BRACKET_FRACTION`] of the chord must still
/// hold for the exponent to jump inside it (a smooth crossing, even a
/// fold's square root, holds a share of order `√BRACKET_FRACTION` there).
pub(super) const JUMP_SHARE: f64 = 0.5;

/// The largest multiplier angle (rad) at the located point of a real
/// crossing: a real multiplier's is at round-off of the location (measured
/// below 1e-6 on the 8-sector case), a slowly modulated complex pair's stays
/// finite (above 1e-2 there).
pub const REAL_AT_LOCATION: f64 = 1e-3;

/// A marker's two points, `index` and the next, of the branch `points`.
pub(super) fn marker_points(
    points: &[Point],
    index: usize,
) -> Result<(&Point, &Point), LocateError> {
    match (points.get(index), points.get(index + 1)) {
        (Some(a), Some(b)) => Ok((a, b)),
        _ => Err(LocateError::Points {
            index,
            next: index + 1,
            points: points.len(),
        }),
    }
}

/// How locating measures a chord, for the planes square to it on which
/// it solves its trial points.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum ChordMetric {
    /// The branch's continuation's metric: displacements in `length_scale`
    /// (m; weighted by the problem's norm weights), the frequency in
    /// `frequency_span` (rad/s). In it the continuation's step between two
    /// points turned little, and a fold between them leaves the planes
    /// across the branch; in [`Self::Alike`] a fold's tangent turns nearly
    /// square to the chord (the default branch's fold at 129.99 Hz: the
    /// tangent's two parts cancel to a tenth in the plane's normal, and
    /// Newton from the chord's point 2 % from a point does not converge).
    Continuation {
        /// The continuation's length scale (m).
        length_scale: f64,
        /// The width of the frequencies' range (rad/s).
        frequency_span: f64,
    },
    /// The chord's unknowns and frequency parts each divided by its squared
    /// length, so that both count alike. Under a law with pieces (DLFT) or
    /// kinks (the plain penalty) the continuation places its points on the
    /// changes of contact, and there this metric keeps a jump's bracket
    /// beside its point where the continuation's cuts the two sheets of a
    /// kinked fold mid-chord (measured on the six-sector DLFT wheel: trial
    /// points 2e-7 of the chord apart, 0.016 Hz apart).
    Alike,
}

impl ChordMetric {
    /// The continuation's metric for `length_scale` (m) and the frequency
    /// range `(start, end)` (rad/s), floored as the continuation floors a
    /// range ([`ScalingSettings::min_range_fraction`]).
    pub fn continuation(length_scale: f64, (start, end): (f64, f64)) -> Self {
        let floor = ScalingSettings::default().min_range_fraction * start.abs().max(end.abs());
        let span = (end - start).abs().max(floor);
        Self::Continuation {
            length_scale,
            frequency_span: if span.is_finite() && span > 0.0 {
                span
            } else {
                1.0
            },
        }
    }

    /// The metrics locating tries, in order, under a smooth law or not:
    /// `continuation` first under a smooth law, [`Self::Alike`] first
    /// under one with pieces or kinks.
    pub fn in_order(continuation: Self, smooth: bool) -> [Self; 2] {
        if smooth {
            [continuation, Self::Alike]
        } else {
            [Self::Alike, continuation]
        }
    }
}

/// The chord between two points of a branch and the plane orthogonal to it
/// at a fraction `s` in a [`ChordMetric`]: `n · (z − z(s)) = 0`,
/// `z = (x, ω)`.
pub(super) struct Chord {
    xa: Vec<f64>,
    dx: Vec<f64>,
    wa: f64,
    dw: f64,
    normal_x: Vec<f64>,
    normal_w: f64,
}

impl Chord {
    pub(super) fn new(
        problem: &HarmonicBalance,
        a: &Point,
        b: &Point,
        metric: ChordMetric,
    ) -> Self {
        let weights = problem.norm_weights();
        let dx: Vec<f64> = b
            .unknowns
            .iter()
            .zip(&a.unknowns)
            .map(|(p, q)| p - q)
            .collect();
        let dw = b.omega - a.omega;
        let (unknowns_square, frequency_square) = match metric {
            ChordMetric::Continuation {
                length_scale,
                frequency_span,
            } => (length_scale * length_scale, frequency_span * frequency_span),
            ChordMetric::Alike => (
                dx.iter().zip(&weights).map(|(d, w)| w * d * d).sum(),
                dw * dw,
            ),
        };
        let normal_x = if unknowns_square > 0.0 {
            dx.iter()
                .zip(&weights)
                .map(|(d, w)| w * d / unknowns_square)
                .collect()
        } else {
            vec![0.0; dx.len()]
        };
        let normal_w = if frequency_square > 0.0 {
            dw / frequency_square
        } else {
            0.0
        };
        Self {
            xa: a.unknowns.clone(),
            dx,
            wa: a.omega,
            dw,
            normal_x,
            normal_w,
        }
    }

    /// The branch's point on the plane at `s`, by Newton from the chord's
    /// point there (or from `start`, a solution at another fraction, moved
    /// along the chord); `(unknowns, ω)`.
    pub(super) fn solve(
        &self,
        problem: &mut HarmonicBalance,
        s: f64,
        start: Option<(f64, &[f64])>,
        newton: &NewtonSettings,
    ) -> Result<(Vec<f64>, f64), LocateError> {
        let on_chord: Vec<f64> = self
            .xa
            .iter()
            .zip(&self.dx)
            .map(|(x, d)| x + s * d)
            .collect();
        let omega_s = self.wa + s * self.dw;
        let mut x = match start {
            // A neighbouring solution moved along the chord: nearer the
            // branch than the chord itself where the branch bends.
            Some((f, y)) if (f - s).abs() < 0.5 => y
                .iter()
                .zip(&self.dx)
                .map(|(y, d)| y + (s - f) * d)
                .collect(),
            _ => on_chord.clone(),
        };
        let mut omega = omega_s;
        let n = x.len();
        let scale = problem.force_scale();
        let mut evaluation = Evaluation::default();
        let mut residual = f64::INFINITY;
        for _ in 0..newton.max_iterations + 5 {
            problem
                .evaluate(&x, omega, true, &mut evaluation)
                .map_err(|e| LocateError::Evaluation(e.to_string()))?;
            if evaluation.structured.is_some() || evaluation.jacobian.nrows() != n {
                return Err(LocateError::Structured { unknowns: n });
            }
            let previous = residual;
            residual = evaluation
                .residual
                .iter()
                .map(|r| r * r)
                .sum::<f64>()
                .sqrt()
                / scale;
            // Converged well below the tolerance, or at it once Newton
            // stops gaining (round-off).
            if residual <= 1e-2 * newton.tolerance
                || (residual <= newton.tolerance && residual > 0.25 * previous)
            {
                return Ok((x, omega));
            }
            let plane: f64 = x
                .iter()
                .zip(&on_chord)
                .zip(&self.normal_x)
                .map(|((x, c), n)| (x - c) * n)
                .sum::<f64>()
                + (omega - omega_s) * self.normal_w;
            // The plane's row scaled like the Jacobian's rows.
            let largest = (0..n)
                .flat_map(|c| evaluation.jacobian.col_as_slice(c).iter())
                .fold(0.0_f64, |m, v| m.max(v.abs()))
                .max(f64::MIN_POSITIVE);
            let row = self
                .normal_x
                .iter()
                .chain(std::iter::once(&self.normal_w))
                .fold(0.0_f64, |m, v| m.max(v.abs()))
                .max(f64::MIN_POSITIVE);
            let k = largest / row;
            let matrix = Mat::from_fn(n + 1, n + 1, |r, c| match (r < n, c < n) {
                (true, true) => evaluation.jacobian[(r, c)],
                (true, false) => evaluation.derivative_omega[r],
                (false, true) => k * self.normal_x[c],
                (false, false) => k * self.normal_w,
            });
            let rhs = Mat::from_fn(n + 1, 1, |r, _| {
                if r < n {
                    -evaluation.residual[r]
                } else {
                    -k * plane
                }
            });
            let step = PartialPivLu::new(matrix.as_ref()).solve(&rhs);
            if (0..=n).any(|r| !step[(r, 0)].is_finite()) {
                break;
            }
            // Backtracking: the step halved while it does not lower the
            // residual (a stiff contact law overshoots), the last taken.
            let mut fraction = 1.0;
            let mut trial = x.clone();
            for halving in 0..=newton.max_halvings {
                for (i, t) in trial.iter_mut().enumerate() {
                    *t = x[i] + fraction * step[(i, 0)];
                }
                let w = omega + fraction * step[(n, 0)];
                let lower = match problem.evaluate(&trial, w, false, &mut evaluation) {
                    Ok(()) => {
                        let r = evaluation
                            .residual
                            .iter()
                            .map(|r| r * r)
                            .sum::<f64>()
                            .sqrt();
                        r / scale < residual
                    }
                    Err(_) => false,
                };
                if lower || halving == newton.max_halvings {
                    break;
                }
                fraction *= 0.5;
            }
            x = trial;
            omega += fraction * step[(n, 0)];
        }
        Err(LocateError::Newton {
            fraction: s,
            residual,
        })
    }
}

impl Chord {
    /// [`Self::solve`], and where Newton does not converge there from the
    /// chord (a branch bending away from it: a sharp fold), the same
    /// fraction reached in [`WALK`] steps (then four times as many) from
    /// the nearer of the bracket's `ends` (fractions and solutions), each
    /// step from the last (the walk's solves count as the one trial).
    pub(super) fn solve_or_walk(
        &self,
        problem: &mut HarmonicBalance,
        s: f64,
        start: Option<(f64, &[f64])>,
        ends: [(f64, &[f64]); 2],
        newton: &NewtonSettings,
    ) -> Result<(Vec<f64>, f64), LocateError> {
        let failed = match self.solve(problem, s, start, newton) {
            Err(error @ LocateError::Newton { .. }) => error,
            solved => return solved,
        };
        let end = if s - ends[0].0 <= ends[1].0 - s {
            ends[0]
        } else {
            ends[1]
        };
        'walks: for steps in [WALK, 4 * WALK] {
            let (mut fraction, mut x) = (end.0, end.1.to_vec());
            let mut omega = f64::NAN;
            for k in 1..=steps {
                let f = if k == steps {
                    s
                } else {
                    end.0 + (s - end.0) * k as f64 / steps as f64
                };
                match self.solve(problem, f, Some((fraction, &x)), newton) {
                    Ok((next, w)) => (fraction, x, omega) = (f, next, w),
                    Err(LocateError::Newton { .. }) => continue 'walks,
                    Err(error) => return Err(error),
                }
            }
            return Ok((x, omega));
        }
        Err(failed)
    }
}

/// Steps of [`Chord::solve_or_walk`]'s first walk.
const WALK: usize = 4;

/// Whether the contact changes between the solutions `(a, omega_a)` and
/// `(b, omega_b)` of `problem`: never under a smooth law; under a law that
/// names its pieces (DLFT: the contact state at every sampled instant),
/// where the pieces differ; under one that does not (the plain penalty),
/// taken as changing.
pub(super) fn contact_changes(
    problem: &mut HarmonicBalance,
    a: &[f64],
    omega_a: f64,
    b: &[f64],
    omega_b: f64,
) -> bool {
    if problem.is_smooth() {
        return false;
    }
    match (problem.piece(a, omega_a), problem.piece(b, omega_b)) {
        (Ok(Some(p)), Ok(Some(q))) => p != q,
        (Ok(None), Ok(None)) => true,
        _ => false,
    }
}
