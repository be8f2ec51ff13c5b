//! Pseudo-arc-length continuation (DESIGN.md §7): tangent predictor,
//! corrector on the hyperplane orthogonal to the tangent, step halved on
//! failure and grown after easy steps, in scaled unknowns
//! (`x` by a length, `ω` by the frequency range).

use super::newton::{newton, NewtonSettings};
use super::{hertz, norm, Branch, Evaluation, Point, Problem, Progress, StopReason};
use faer::linalg::solvers::Solve;
use faer::Mat;

/// Arc-length settings (frequencies in rad/s).
#[derive(Clone, Copy, Debug)]
pub struct ArcLengthSettings {
    /// Start frequency.
    pub start: f64,
    /// End frequency (below `start` to go down).
    pub end: f64,
    /// First step, scaled arc length.
    pub initial_step: f64,
    /// Smallest step before giving up.
    pub min_step: f64,
    /// Largest step.
    pub max_step: f64,
    /// Length by which displacements are scaled (e.g. the gap), m.
    pub length_scale: f64,
    /// Corrector settings.
    pub newton: NewtonSettings,
    /// Cap on points.
    pub max_points: usize,
}

/// Consecutive tangents further apart than this (cosine) reject the step:
/// a guard against jumping between close branches.
const MIN_TANGENT_COSINE: f64 = 0.5;
/// Steps converging within this many iterations grow the next step.
const EASY_ITERATIONS: usize = 3;
/// A corrector that moves further than this fraction of the step from the
/// prediction has likely converged onto another part of the curve: reject.
const MAX_CORRECTION_RATIO: f64 = 0.5;
const GROWTH: f64 = 1.5;

struct Scaling {
    /// `z̄ = D z`: per-unknown factors, then the frequency's.
    factors: Vec<f64>,
}

impl Scaling {
    fn scaled(&self, x: &[f64], omega: f64) -> Vec<f64> {
        let n = x.len();
        let mut z: Vec<f64> = x.iter().zip(&self.factors).map(|(v, d)| v * d).collect();
        z.push(omega * self.factors[n]);
        z
    }

    fn unscaled(&self, z: &[f64]) -> (Vec<f64>, f64) {
        let n = z.len() - 1;
        let x = (0..n).map(|i| z[i] / self.factors[i]).collect();
        (x, z[n] / self.factors[n])
    }
}

/// The augmented matrix `[[J D⁻¹ / F], [tᵀ]]`.
fn augmented(evaluation: &Evaluation, scaling: &Scaling, force: f64, tangent: &[f64]) -> Mat<f64> {
    let n = evaluation.residual.len();
    Mat::from_fn(n + 1, n + 1, |r, c| {
        if r == n {
            tangent[c]
        } else if c == n {
            evaluation.derivative_omega[r] / scaling.factors[n] / force
        } else {
            evaluation.jacobian[(r, c)] / scaling.factors[c] / force
        }
    })
}

/// The unit tangent at the point of `evaluation`, oriented like `previous`.
fn tangent(
    evaluation: &Evaluation,
    scaling: &Scaling,
    force: f64,
    previous: &[f64],
) -> Option<Vec<f64>> {
    let n = evaluation.residual.len();
    let a = augmented(evaluation, scaling, force, previous);
    let rhs = Mat::from_fn(n + 1, 1, |r, _| if r == n { 1.0 } else { 0.0 });
    let t = a.partial_piv_lu().solve(&rhs);
    let t: Vec<f64> = (0..=n).map(|r| t[(r, 0)]).collect();
    let length = norm(&t);
    (length.is_finite() && length > 0.0).then(|| t.iter().map(|v| v / length).collect())
}

/// Continues from `guess` (an approximate solution at `settings.start`) to
/// `settings.end`, calling `observer` on each accepted point. Never fails:
/// the branch holds every point computed and says why it stopped.
pub fn continue_branch<P: Problem>(
    problem: &mut P,
    guess: Vec<f64>,
    settings: &ArcLengthSettings,
    mut observer: impl FnMut(&Point, &Progress),
) -> Branch {
    let n = problem.unknowns();
    let force = problem.force_scale();
    let direction = if settings.end >= settings.start {
        1.0
    } else {
        -1.0
    };
    let mut factors: Vec<f64> = problem
        .norm_weights()
        .iter()
        .map(|w| w.sqrt() / settings.length_scale)
        .collect();
    // The frequency is measured in units of the range: the whole sweep is
    // one unit of arc length, comparable with a displacement of one gap.
    let range = (settings.end - settings.start).abs();
    factors.push(
        1.0 / range
            .max(1e-6 * settings.start.abs())
            .max(f64::MIN_POSITIVE),
    );
    let scaling = Scaling { factors };
    let mut evaluation = Evaluation::default();
    let mut points: Vec<Point> = Vec::new();
    let mut total = 0;
    let stop_with = |points: Vec<Point>, stop: StopReason, total: usize| Branch {
        points,
        stop,
        total_iterations: total,
    };

    // First point at fixed frequency.
    let mut x = guess;
    let (converged, iterations, residual_norm) = match newton(
        problem,
        &mut x,
        settings.start,
        &settings.newton,
        &mut evaluation,
    ) {
        Ok(result) => result,
        Err(error) => {
            return stop_with(
                points,
                StopReason::EvaluationError {
                    frequency_hz: hertz(settings.start),
                    message: error.to_string(),
                },
                total,
            )
        }
    };
    total += iterations;
    if !converged {
        return stop_with(
            points,
            StopReason::NewtonFailure {
                frequency_hz: hertz(settings.start),
                residual_norm,
            },
            total,
        );
    }
    let first = Point {
        omega: settings.start,
        unknowns: x.clone(),
        iterations,
        residual_norm,
        converged: true,
    };
    observer(
        &first,
        &Progress {
            points: 1,
            frequency_hz: hertz(settings.start),
            step: settings.initial_step,
        },
    );
    points.push(first);

    let mut seed = vec![0.0; n + 1];
    seed[n] = direction;
    let Some(mut current_tangent) = tangent(&evaluation, &scaling, force, &seed) else {
        return stop_with(
            points,
            StopReason::EvaluationError {
                frequency_hz: hertz(settings.start),
                message: "the tangent could not be computed (singular augmented Jacobian)".into(),
            },
            total,
        );
    };
    let mut z = scaling.scaled(&x, settings.start);
    let mut step = settings.initial_step.min(settings.max_step);

    loop {
        if points.len() >= settings.max_points {
            return stop_with(
                points,
                StopReason::PointCap {
                    max_points: settings.max_points,
                },
                total,
            );
        }
        let predicted: Vec<f64> = z
            .iter()
            .zip(&current_tangent)
            .map(|(a, t)| a + step * t)
            .collect();
        let mut candidate = predicted.clone();
        let mut accepted = None;
        for iteration in 0..=settings.newton.max_iterations {
            let (xc, omega) = scaling.unscaled(&candidate);
            if let Err(error) = problem.evaluate(&xc, omega, true, &mut evaluation) {
                // An evaluation failure (e.g. at a singular frequency) is a
                // failed step, not the end: retry with a smaller step.
                tracing::debug!("evaluation failed at {:.4} Hz: {error}", hertz(omega));
                break;
            }
            let residual = norm(&evaluation.residual) / force;
            if !residual.is_finite() {
                break;
            }
            if residual <= settings.newton.tolerance {
                accepted = Some((iteration, residual));
                break;
            }
            if iteration == settings.newton.max_iterations {
                break;
            }
            let a = augmented(&evaluation, &scaling, force, &current_tangent);
            let constraint: f64 = candidate
                .iter()
                .zip(&predicted)
                .zip(&current_tangent)
                .map(|((c, p), t)| (c - p) * t)
                .sum();
            let rhs = Mat::from_fn(n + 1, 1, |r, _| {
                if r == n {
                    -constraint
                } else {
                    -evaluation.residual[r] / force
                }
            });
            let delta = a.partial_piv_lu().solve(&rhs);
            if (0..=n).any(|r| !delta[(r, 0)].is_finite()) {
                break;
            }
            for (r, c) in candidate.iter_mut().enumerate() {
                *c += delta[(r, 0)];
            }
        }
        let spent = accepted.map_or(settings.newton.max_iterations, |(i, _)| i);
        total += spent;
        let next_tangent =
            accepted.and_then(|_| tangent(&evaluation, &scaling, force, &current_tangent));
        let correction = candidate
            .iter()
            .zip(&predicted)
            .map(|(a, b)| (a - b) * (a - b))
            .sum::<f64>()
            .sqrt();
        let turning_too_fast = (next_tangent.as_ref().is_some_and(|t| {
            let cosine: f64 = t.iter().zip(&current_tangent).map(|(a, b)| a * b).sum();
            cosine < MIN_TANGENT_COSINE
        }) || correction > MAX_CORRECTION_RATIO * step)
            && step > 2.0 * settings.min_step;
        let (Some((iterations, residual_norm)), Some(next_tangent), false) =
            (accepted, next_tangent, turning_too_fast)
        else {
            step *= 0.5;
            if step < settings.min_step {
                let (_, omega) = scaling.unscaled(&z);
                return stop_with(
                    points,
                    StopReason::StepUnderflow {
                        frequency_hz: hertz(omega),
                        step,
                    },
                    total,
                );
            }
            continue;
        };
        let (xc, omega) = scaling.unscaled(&candidate);
        let previous = points.last().map(|p| (p.omega, p.unknowns.clone()));
        if (omega - settings.end) * direction >= 0.0 {
            // Crossed the end: solve exactly at the end frequency from the
            // linear interpolation between the last two points.
            if let Some((previous_omega, previous_x)) = previous {
                let weight = (settings.end - previous_omega) / (omega - previous_omega);
                let mut x_end: Vec<f64> = previous_x
                    .iter()
                    .zip(&xc)
                    .map(|(a, b)| a + weight * (b - a))
                    .collect();
                if let Ok((true, end_iterations, end_residual)) = newton(
                    problem,
                    &mut x_end,
                    settings.end,
                    &settings.newton,
                    &mut evaluation,
                ) {
                    total += end_iterations;
                    let point = Point {
                        omega: settings.end,
                        unknowns: x_end,
                        iterations: end_iterations,
                        residual_norm: end_residual,
                        converged: true,
                    };
                    observer(
                        &point,
                        &Progress {
                            points: points.len() + 1,
                            frequency_hz: hertz(settings.end),
                            step,
                        },
                    );
                    points.push(point);
                    return stop_with(points, StopReason::EndReached, total);
                }
            }
            // The exact end failed: keep the point past it.
            let point = Point {
                omega,
                unknowns: xc,
                iterations,
                residual_norm,
                converged: true,
            };
            points.push(point);
            return stop_with(points, StopReason::EndReached, total);
        }
        let point = Point {
            omega,
            unknowns: xc,
            iterations,
            residual_norm,
            converged: true,
        };
        observer(
            &point,
            &Progress {
                points: points.len() + 1,
                frequency_hz: hertz(omega),
                step,
            },
        );
        points.push(point);
        z = candidate;
        current_tangent = next_tangent;
        if iterations <= EASY_ITERATIONS {
            step = (step * GROWTH).min(settings.max_step);
        }
    }
}
