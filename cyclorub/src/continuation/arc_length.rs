//! Pseudo-arc-length continuation (DESIGN.md §7): tangent predictor,
//! corrector on the hyperplane orthogonal to the tangent, step halved on
//! failure and grown after easy steps, in scaled unknowns
//! (`x` by a length, `ω` by the frequency range).
//!
//! On a smooth residual ([`Problem::is_smooth`]) a step is refused when the
//! tangent turns by more than 11° or the corrector moves by more than a
//! tenth of the step, and halved until it passes: every fold is resolved
//! however sharp, and the corrector cannot reach another sheet of the
//! branch close by (the regularized law's folds have radii ~ γ/κ and come
//! in nearly coincident pairs on the deformed-casing cases). A step is
//! also refused when it reverses the branch's orientation (the sign of
//! `det [J; tᵀ]`, kept along a branch through its folds), unless it is
//! far shorter than the last easy one ([`BRANCH_POINT_STEP`]): a longer
//! one went back along the branch or onto a close sheet that turns the
//! tangent too little to be seen otherwise; a short one crosses a branch
//! point (logged).
//!
//! Nonsmooth residuals (DLFT-HBM, whose contact state changes one sampled
//! instant at a time, so that the branch is a chain of smooth *pieces*
//! joined at *kinks*):
//!
//! - the corrector backtracks on the residual norm and gives up as soon as
//!   the Newton direction stops descending, instead of wandering through
//!   far contact states;
//! - when the problem tells its pieces ([`Problem::piece`]), every step
//!   keeps the smooth limits, which follow the branch through its folds:
//!   near a fold tip the other sheet is as close as the step, and with lax
//!   limits (60°, half the step) the N = 45 deformed-casing branch slipped
//!   back onto the sheet it came along and returned to its start. Past a
//!   kink the tangent turns by a fixed angle however short the step, up
//!   to a reversal of the frequency (a nonsmooth fold), so that halving
//!   only creeps toward it: once a short step (up to
//!   [`PIECEWISE_FINE_STEP`]) fails, or the step has collapsed far below
//!   the last easy one, the kink ahead is located by bisection along the
//!   tangent and the branch turns there onto the next piece, along the
//!   null vector of the Jacobian on that piece, the way that keeps the
//!   sign of `det [J; tᵀ]` (the branch's orientation, which a regular
//!   branch keeps through kinks as through smooth folds: this is the way
//!   into the next piece), turning again at once when several instants
//!   switch together. Turning at kinks while the steps were long chose the
//!   wrong way at the N = 24 deformed-casing case's two nearly coincident
//!   folds (218.7 Hz), and the branch went back to its start;
//! - without pieces (the plain penalty law, γ = 0), a kink is recognized
//!   when a converged step that turned too far turns as far again at half
//!   the step, or when the step has been halved well below the last easy
//!   one, and the way on is the side where the residual stays small; a
//!   step back onto the branch already travelled (near a recent segment
//!   and against it) is refused; and when the step has shrunk far below
//!   the last easy one, longer steps are tried along the tangent to pass
//!   over small nonsmooth structures;
//! - on a piecewise branch the step is capped at [`PIECEWISE_MAX_STEP`];
//! - on any residual, a step that lands on a sheet travelled long before
//!   (see `clearance`: much further along the branch than across, and far
//!   closer to the step's end than its length and than its start was) is
//!   refused, and a kink step whose told way lands there tries the other
//!   way; a branch that runs beside an old sheet, however close, keeps its
//!   distance and goes on;
//! - the branch stops when it comes back to a point it has passed (a closed
//!   loop) and when it turns back past its start frequency (it would go on
//!   toward ω ≤ 0).
//!
//! Measured on the paper's academic cases (`N_h = 10`, `N_t` = 10000 or
//! a multiple of N near it, reduced bases, `cargo test --release -p
//! cyclorub --test dlft_hbm -- --ignored`): all eight cases with a circular
//! casing run to the end of their range with either law. With a deformed
//! casing, N = 24 (h = 6, h_c = 8) reaches its end with both laws: through
//! 20 turning points with R-HBM (γ = 2.5 N), the same ones for largest
//! steps 0.1, 0.05 and 0.01, and through 18 with DLFT, the same for
//! largest steps 0.03 and 0.01 (before, both jumped between sheets near
//! 218.6 Hz and cycled or went back to the start). N = 45 (h = 12,
//! h_c = 3, `N_t` = 9990) snakes between 211 and 223 Hz with either law,
//! its response localizing on a few blades sheet after sheet (the same
//! folds, to 1e-4 Hz, at `N_t` = 19980: they are not a sampling
//! artifact). R-HBM: the sweep from the start ran 80000 points (53 min in
//! release, up to 222.57 Hz) without stopping; the branch is longer.
//! DLFT: within one contact state the residual is affine in the unknowns,
//! so the solution at a frequency is unique and a branch that comes back
//! onto a piece it travelled before must follow it. The sweep from the
//! start does so at 221.29 Hz: from its point 5935 it closes onto its
//! trail of points 5847–5890 running the same way and goes round a loop of
//! 145 points, where the closed-loop check stops it (the same junction, to
//! 3e-4 Hz, at `N_t` = 19980, and with every kink turned by the pieces
//! instead of the orientation); the sweep back from the end
//! ([`super::continue_from_both_ends`]) stops where every way on lands on
//! its old sheets (220.4848 Hz after 5112 points; 218.88 Hz at `N_t` =
//! 19980), leaving a gap. Before steps landing on old sheets were refused,
//! both sweeps went back along their trails for hundreds of points. The
//! loop is a neck of the solution set, not a long step's jump: with the
//! largest step 0.003 the sweep follows the same folds (to the spacing of
//! its points) and stalls at 221.2879 Hz; round the loop the second pass
//! runs 1e-6 to 4e-5 (scaled) beside the first and comes within 1.7e-8 of
//! it at 221.2874 Hz (its Newton residuals are ~1e-11, so the two passes
//! are distinct solutions). Newton from 48 directions around that point,
//! at radii 1e-5 to 1e-3 and a radius above and below in frequency, finds
//! no solution off the trail closer than 4e-3 (an experiment, not kept:
//! following that one stalled 400 points later at 220.93 Hz). With the
//! closed-loop check made 1e4 times stricter the sweep goes round the same
//! loop again and again (221.27 to 221.45 Hz, about 90 points a turn).

use super::clearance::Clearance;
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
/// The same two limits on a smooth residual (11°, a tenth of the step):
/// the regularized law's folds can be sharp (radius ~ γ/κ) with another
/// sheet close by, which the lax limits let the corrector jump onto.
const SMOOTH_MIN_TANGENT_COSINE: f64 = 0.98;
const SMOOTH_MAX_CORRECTION_RATIO: f64 = 0.1;
/// Steps converging within this many iterations grow the next step.
const EASY_ITERATIONS: usize = 3;
/// A corrector that moves further than this fraction of the step from the
/// prediction has likely converged onto another part of the curve: reject.
const MAX_CORRECTION_RATIO: f64 = 0.5;
const GROWTH: f64 = 1.5;
/// A step rejected for turning, then rejected again at half the step with
/// at least this fraction of the turn, has crossed a corner (a smooth turn
/// halves with the step).
const CORNER_PERSISTENCE: f64 = 0.6;
/// A step halved to this fraction of the last step that went through at
/// once means the branch is creeping toward a kink.
const KINK_CASCADE: f64 = 1.0 / 8.0;
/// The residual on one side of a kink must be this much smaller than on the
/// other to tell which way the branch goes on.
const KINK_SIDE_RATIO: f64 = 0.1;
/// A point closer to a travelled segment than this fraction of the
/// segment's length, plus this fraction of the step, is on it.
const RETRACE_SEGMENT_FRACTION: f64 = 0.25;
const RETRACE_FRACTION: f64 = 0.05;
/// Running against a travelled segment at least this steeply (cosine) is
/// going back.
const RETRACE_COSINE: f64 = 0.8;
/// On a piecewise residual, a long step halved to this fraction of the
/// last one that went through at once has met a kink: it is located and
/// turned.
const PIECEWISE_KINK_CASCADE: f64 = 1.0 / 256.0;
/// A refused step on a piecewise residual up to this length (scaled) looks
/// for a kink ahead and turns it; longer ones are only halved (turning
/// kinks at long steps chose the wrong way at the N = 24 deformed-casing
/// case's nearly coincident folds).
const PIECEWISE_FINE_STEP: f64 = 1e-3;
/// The largest step on a piecewise-smooth branch (scaled arc length: 3 %
/// of the frequency range or of the length scale). Longer steps across
/// many kinks were seen to land on a nearby sheet near resonance peaks.
const PIECEWISE_MAX_STEP: f64 = 0.03;
/// A step halved to this fraction of the last easy one tries a leap.
const LEAP_CASCADE: f64 = 1.0 / 64.0;
/// Recent points kept to recognize going back.
const TRAIL: usize = 64;
/// Kinks met one right after the other (within this fraction of the
/// step) are turned at once, up to this many.
const KINK_NEAR: f64 = 1e-3;
const MAX_PIVOTS: usize = 16;
/// A kink is located to this fraction of the step.
const KINK_RESOLUTION: f64 = 1e-6;
/// Distances (in units of the located kink's width) at which the pieces on
/// either side of it are compared.
const KINK_SIDE_SCALES: [f64; 4] = [4.0, 64.0, 1024.0, 16384.0];
/// How far out (in units of the distance within which the kink lies) the
/// residual is compared on either side of it.
const KINK_TEST_DISTANCE: f64 = 16.0;
/// A way on past a kink may not go back along the way in more steeply
/// than this (cosine of the angle with the reversed tangent).
const MAX_KINK_REVERSAL: f64 = 0.9;
/// Halvings of a Newton correction before the corrector gives up.
const MAX_BACKTRACKS: usize = 4;
/// A step may reverse the branch's orientation (cross a branch point) only
/// when it is this much shorter than the last good step: longer ones that
/// reverse it have gone back along the branch or onto a nearby sheet (the
/// N = 45 deformed-casing branch, at 221.4 Hz with R-HBM, onto a closed
/// curve it then went round for ever).
const BRANCH_POINT_STEP: f64 = 1.0 / 1024.0;

/// The equation that closes the corrector's system.
#[derive(Clone, Copy)]
enum Constraint<'a> {
    /// `tᵀ (z − predicted) = 0`: the plane through the prediction.
    Plane {
        tangent: &'a [f64],
        predicted: &'a [f64],
    },
}

impl Constraint<'_> {
    /// Value and gradient.
    fn at(&self, z: &[f64]) -> (f64, Vec<f64>) {
        match *self {
            Constraint::Plane { tangent, predicted } => (
                z.iter()
                    .zip(predicted)
                    .zip(tangent)
                    .map(|((c, p), t)| (c - p) * t)
                    .sum(),
                tangent.to_vec(),
            ),
        }
    }
}

/// An accepted step.
struct Step {
    candidate: Vec<f64>,
    iterations: usize,
    residual_norm: f64,
    tangent: Vec<f64>,
    /// The sign of `det [J D⁻¹ / F; tᵀ]` there (see `oriented_null_vector`).
    orientation: f64,
}

pub(super) struct Scaling {
    /// `z̄ = D z`: per-unknown factors, then the frequency's.
    factors: Vec<f64>,
}

impl Scaling {
    /// Unknowns by `settings.length_scale` (weighted by the problem's norm
    /// weights), the frequency in units of the range: the whole sweep is
    /// one unit of arc length, comparable with a displacement of one gap.
    /// The same for both ends of a range.
    pub(super) fn new<P: Problem>(problem: &P, settings: &ArcLengthSettings) -> Self {
        let mut factors: Vec<f64> = problem
            .norm_weights()
            .iter()
            .map(|w| w.sqrt() / settings.length_scale)
            .collect();
        let range = (settings.end - settings.start).abs();
        factors.push(
            1.0 / range
                .max(1e-6 * settings.start.abs().max(settings.end.abs()))
                .max(f64::MIN_POSITIVE),
        );
        Self { factors }
    }

    pub(super) fn scaled(&self, x: &[f64], omega: f64) -> Vec<f64> {
        let n = x.len();
        let mut z: Vec<f64> = x.iter().zip(&self.factors).map(|(v, d)| v * d).collect();
        z.push(omega * self.factors[n]);
        z
    }

    /// The factors: per unknown, then the frequency's.
    pub(super) fn factors(&self) -> &[f64] {
        &self.factors
    }

    /// No scaling, for tests: `unknowns` factors of 1 and the frequency's.
    #[cfg(test)]
    pub(super) fn identity(unknowns: usize) -> Self {
        Self {
            factors: vec![1.0; unknowns + 1],
        }
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
    oriented_null_vector(evaluation, scaling, force, previous).map(|(t, _)| t)
}

/// The unit tangent `t` at the point of `evaluation`, oriented like
/// `previous`, and its orientation: the sign of `det [J D⁻¹ / F; tᵀ]`.
///
/// The orientation is kept along a regular branch, through smooth folds
/// and through the kinks of a piecewise-smooth one alike (for a kink: the
/// null vectors of the Jacobians on either side, each scaled to cross the
/// switching surface at unit speed, are joined by those of the Jacobians
/// in between, which are all regular on a regular branch), so it tells
/// the way on past a kink without looking at the pieces around it.
fn oriented_null_vector(
    evaluation: &Evaluation,
    scaling: &Scaling,
    force: f64,
    previous: &[f64],
) -> Option<(Vec<f64>, f64)> {
    let n = evaluation.residual.len();
    let a = augmented(evaluation, scaling, force, previous);
    let rhs = Mat::from_fn(n + 1, 1, |r, _| if r == n { 1.0 } else { 0.0 });
    let lu = a.partial_piv_lu();
    let t = lu.solve(&rhs);
    let t: Vec<f64> = (0..=n).map(|r| t[(r, 0)]).collect();
    let length = norm(&t);
    if !(length.is_finite() && length > 0.0) {
        return None;
    }
    // `[J; pᵀ] t = e` gives `det [J; tᵀ] = det [J; pᵀ] · |t|` for the unit
    // `t` returned (determinant lemma, with `pᵀ t = 1`): the sign of
    // `det [J; pᵀ]` from its factors.
    let diagonal_sign = (0..=n).fold(1.0, |sign, i| sign * lu.U()[(i, i)].signum());
    Some((
        t.iter().map(|v| v / length).collect(),
        if permutation_is_odd(lu.P().arrays().0) {
            -diagonal_sign
        } else {
            diagonal_sign
        },
    ))
}

/// Whether a permutation, given by its forward array, is odd (an odd
/// number of transpositions: `n − cycles`).
fn permutation_is_odd(forward: &[usize]) -> bool {
    let mut seen = vec![false; forward.len()];
    let mut transpositions = 0;
    for start in 0..forward.len() {
        let mut length = 0;
        let mut i = start;
        while !seen[i] {
            seen[i] = true;
            i = forward[i];
            length += 1;
        }
        transpositions += length.max(1) - 1;
    }
    transpositions % 2 == 1
}

/// Relative distance below which a new point is the same as an earlier one.
const SAME_POINT: f64 = 1e-7;

/// A point repeats an earlier one only if it is also closer to it than
/// this fraction of the step (scaled): steps near the sharpest folds of the
/// regularized law are shorter than [`SAME_POINT`], and the sheet beyond
/// such a fold passed that close to an earlier point (N = 45 deformed
/// casing, 221.4 Hz) without repeating it.
const SAME_POINT_STEP_FRACTION: f64 = 1e-2;

/// The index of an earlier point (not one of the last two) that `point`
/// repeats, to [`SAME_POINT`] relative in frequency and unknowns and to
/// [`SAME_POINT_STEP_FRACTION`] of `step` (scaled by `scaling`): the
/// continuation has come back on its own trail (a closed curve, or a cycle
/// through corners of a nonsmooth branch) and would go round forever.
fn revisited_point(points: &[Point], point: &Point, scaling: &Scaling, step: f64) -> Option<usize> {
    let scale = point
        .unknowns
        .iter()
        .fold(0.0_f64, |m, v| m.max(v.abs()))
        .max(f64::MIN_POSITIVE);
    let here = scaling.scaled(&point.unknowns, point.omega);
    let earlier = points.len().checked_sub(2)?;
    points[..earlier].iter().position(|p| {
        (p.omega - point.omega).abs() <= SAME_POINT * point.omega.abs()
            && p.unknowns
                .iter()
                .zip(&point.unknowns)
                .all(|(a, b)| (a - b).abs() <= SAME_POINT * scale)
            && scaling
                .scaled(&p.unknowns, p.omega)
                .iter()
                .zip(&here)
                .map(|(a, b)| (a - b) * (a - b))
                .sum::<f64>()
                .sqrt()
                <= SAME_POINT_STEP_FRACTION * step
    })
}

/// Continues from `guess` (an approximate solution at `settings.start`) to
/// `settings.end`, calling `observer` on each accepted point. Never fails:
/// the branch holds every point computed and says why it stopped.
pub fn continue_branch<P: Problem>(
    problem: &mut P,
    guess: Vec<f64>,
    settings: &ArcLengthSettings,
    observer: impl FnMut(&Point, &Progress),
) -> Branch {
    follow(problem, guess, settings, observer, None).0
}

/// Asked at every accepted point, in scaled unknowns with the unit tangent
/// there: the index of a point of another branch that this one has joined.
pub(super) type Meeting<'a> = &'a mut dyn FnMut(&[f64], &[f64]) -> Option<usize>;

/// [`continue_branch`], which also stops where `meeting` says the branch
/// has joined another (returning what `meeting` said; the stop is then
/// `EndReached`, to be replaced by the caller).
pub(super) fn follow<P: Problem>(
    problem: &mut P,
    guess: Vec<f64>,
    settings: &ArcLengthSettings,
    mut observer: impl FnMut(&Point, &Progress),
    mut meeting: Option<Meeting<'_>>,
) -> (Branch, Option<usize>) {
    let n = problem.unknowns();
    let force = problem.force_scale();
    let direction = if settings.end >= settings.start {
        1.0
    } else {
        -1.0
    };
    let scaling = Scaling::new(problem, settings);
    let mut evaluation = Evaluation::default();
    let mut points: Vec<Point> = Vec::new();
    let mut total = 0;
    let stop_with = |points: Vec<Point>, stop: StopReason, total: usize| {
        (
            Branch {
                points,
                stop,
                total_iterations: total,
                sweeps: None,
            },
            None,
        )
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
    let Some((mut current_tangent, mut orientation)) =
        oriented_null_vector(&evaluation, &scaling, force, &seed)
    else {
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
    // Whether the residual tells its smooth pieces (then kinks are located exactly).
    let piecewise = matches!(problem.piece(&x, settings.start), Ok(Some(_)));
    // Long steps across many kinks may land on a nearby sheet of a
    // piecewise-smooth branch (seen with DLFT near resonance peaks).
    let max_step = if piecewise {
        settings.max_step.min(PIECEWISE_MAX_STEP)
    } else {
        settings.max_step
    };
    step = step.min(max_step);
    // A smooth residual (R-HBM with γ > 0) resolves every turn of its
    // branch with a short enough step: no corner heuristics, and tighter
    // turns so that the corrector cannot reach a nearby sheet. A residual
    // that tells its pieces (DLFT) is followed the same way, its kinks
    // being turned exactly only when the step has collapsed at one.
    let smooth = !piecewise && problem.is_smooth();
    let tight = smooth || piecewise;
    // The turn limits: tight on a smooth or piecewise residual, even for
    // short steps (near a fold tip the other sheet is as close as the
    // step, and lax limits let the N = 45 deformed-casing DLFT branch
    // slip back onto the sheet it came along); a kink that turns a step
    // too far is located and turned exactly instead.
    let (min_cosine, max_correction) = if tight {
        (SMOOTH_MIN_TANGENT_COSINE, SMOOTH_MAX_CORRECTION_RATIO)
    } else {
        (MIN_TANGENT_COSINE, MAX_CORRECTION_RATIO)
    };
    // The turn of the last step rejected for turning, and the failures, from z.
    let mut last_turn: Option<f64> = None;
    let mut failures = 0;
    // The last step that went through at the first attempt.
    let mut good_step = step;
    // The arc length travelled, to tell a step that lands on a sheet
    // travelled long before (see `clearance`).
    let mut clearance = Clearance::default();
    clearance.push(0.0);
    let mut trail: std::collections::VecDeque<Vec<f64>> = std::collections::VecDeque::new();
    trail.push_back(z.clone());
    // The pieces of the recent points (piecewise residuals only).
    let mut visited: std::collections::VecDeque<u64> = std::collections::VecDeque::new();
    if let Some(piece) = piece_at(problem, &scaling, &z) {
        visited.push_back(piece);
    }

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
        let (accepted, spent) = correct(
            problem,
            &scaling,
            force,
            &settings.newton,
            Constraint::Plane {
                tangent: &current_tangent,
                predicted: &predicted,
            },
            &mut candidate,
            &mut evaluation,
        );
        total += spent;
        let next_tangent = accepted.and_then(|_| {
            oriented_tangent(
                &evaluation,
                &scaling,
                force,
                &current_tangent,
                &z,
                &candidate,
            )
        });
        let correction = candidate
            .iter()
            .zip(&predicted)
            .map(|(a, b)| (a - b) * (a - b))
            .sum::<f64>()
            .sqrt();
        // How far beyond the admissible turn this step went (> 1: too far).
        let turn = next_tangent.as_ref().map(|(t, _)| {
            let cosine: f64 = t.iter().zip(&current_tangent).map(|(a, b)| a * b).sum();
            ((1.0 - cosine) / (1.0 - min_cosine)).max(correction / (max_correction * step))
        });
        let turning_too_fast = turn.is_some_and(|t| t > 1.0) && step > 2.0 * settings.min_step;
        // The orientation is kept along a branch: a step that reverses it
        // went back along the branch or jumped onto a nearby sheet, unless
        // it crossed a branch point, which only a short step may do. On a
        // smooth residual only: the kinks of a piecewise one (DLFT) keep it
        // by construction, and refusing there stalled DLFT branches.
        let may_flip = step <= BRANCH_POINT_STEP * good_step || step <= 2.0 * settings.min_step;
        let flipped = smooth
            && next_tangent
                .as_ref()
                .is_some_and(|(_, o)| o * orientation < 0.0);
        // Near the tip of a fold, the sheet beyond runs close to and against
        // the one travelled: on a smooth branch that is no sign of a jump.
        let back = !tight
            && next_tangent
                .as_ref()
                .is_some_and(|(t, _)| retraces(&candidate, t, trail.make_contiguous(), step));
        // A step that lands on a sheet travelled long before (see `clearance`).
        let lands =
            |candidate: &[f64]| clearance.lands_on_old_sheet(&points, &scaling, &z, candidate);
        let landed = accepted.is_some()
            && next_tangent.is_some()
            && !(turning_too_fast || back || (flipped && !may_flip))
            && lands(&candidate);
        let refused = turning_too_fast || back || (flipped && !may_flip) || landed;
        let mut outcome = match (accepted, next_tangent, refused) {
            (Some((iterations, residual_norm)), Some((tangent, orientation)), false) => {
                Some(Step {
                    candidate,
                    iterations,
                    residual_norm,
                    tangent,
                    orientation,
                })
            }
            _ => None,
        };
        let mut spent_on_kink = 0;
        if outcome.is_none() {
            // Why steps fail, for `RUST_LOG=debug` when a branch stalls.
            tracing::debug!(
                "step {step:.2e} from {:.6} Hz refused: corrector {}, turn {:.2}, retrace {back}, orientation reversed {flipped}, landed on an old sheet {landed}",
                hertz(scaling.unscaled(&z).1),
                if accepted.is_some() {
                    "converged"
                } else {
                    "failed"
                },
                turn.unwrap_or(f64::NAN),
            );
            failures += 1;
            let corner = !tight
                && turning_too_fast
                && matches!((turn, last_turn), (Some(t), Some(previous)) if t >= CORNER_PERSISTENCE * previous);
            if turning_too_fast {
                last_turn = turn;
            }
            let at_kink = if piecewise {
                step <= PIECEWISE_FINE_STEP || step <= PIECEWISE_KINK_CASCADE * good_step
            } else {
                !smooth && (corner || step <= KINK_CASCADE * good_step)
            };
            if at_kink {
                let first = if piecewise {
                    step
                } else {
                    step.max(KINK_CASCADE * good_step)
                };
                let (kink, spent) = kink_step(
                    problem,
                    &scaling,
                    force,
                    &settings.newton,
                    (&z, &current_tangent, step),
                    &[first, first / 8.0, first / 64.0],
                    (trail.make_contiguous(), visited.make_contiguous(), &lands),
                    piecewise,
                    &mut evaluation,
                );
                total += spent;
                spent_on_kink = spent;
                outcome = kink;
            }
            if !tight
                && outcome.is_none()
                && (spent_on_kink > 0 || step <= LEAP_CASCADE * good_step)
            {
                // Creeping: leap over the small nonsmooth structure ahead.
                let (leap, spent) = leap(
                    problem,
                    &scaling,
                    force,
                    &settings.newton,
                    (&z, &current_tangent),
                    &[good_step, 2.0 * good_step, 4.0 * good_step],
                    (trail.make_contiguous(), &lands),
                    &mut evaluation,
                );
                total += spent;
                outcome = leap;
            }
        }
        let Some(Step {
            candidate,
            iterations,
            residual_norm,
            tangent: next_tangent,
            orientation: next_orientation,
        }) = outcome
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
        let grow = failures == 0 && iterations <= EASY_ITERATIONS;
        if failures == 0 {
            good_step = step;
        }
        last_turn = None;
        failures = 0;
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
        // Turned back past the start: the branch leaves the range the
        // user asked for (and would go on toward ω ≤ 0). Keep the point.
        let left_range = (omega - settings.start) * direction < 0.0;
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
        let revisited = revisited_point(&points, &point, &scaling, step);
        points.push(point);
        if let Some(earlier) = revisited {
            return stop_with(
                points,
                StopReason::ClosedLoop {
                    frequency_hz: hertz(omega),
                    earlier_point: earlier,
                },
                total,
            );
        }
        if let Some(met) = meeting.as_mut().and_then(|m| m(&candidate, &next_tangent)) {
            let (branch, _) = stop_with(points, StopReason::EndReached, total);
            return (branch, Some(met));
        }
        if left_range {
            return stop_with(
                points,
                StopReason::LeftRange {
                    frequency_hz: hertz(omega),
                },
                total,
            );
        }
        clearance.push(norm(
            &candidate
                .iter()
                .zip(&z)
                .map(|(a, b)| a - b)
                .collect::<Vec<_>>(),
        ));
        z = candidate;
        trail.push_back(z.clone());
        if trail.len() > TRAIL {
            trail.pop_front();
        }
        if piecewise {
            if let Some(piece) = piece_at(problem, &scaling, &z) {
                visited.push_back(piece);
                if visited.len() > TRAIL {
                    visited.pop_front();
                }
            }
        }
        current_tangent = next_tangent;
        if smooth && next_orientation * orientation < 0.0 {
            tracing::info!(
                "the branch's orientation changed at {:.4} Hz (point {}): a branch point was crossed",
                hertz(omega),
                points.len() - 1,
            );
        }
        orientation = next_orientation;
        if grow {
            step = (step * GROWTH).min(max_step);
        }
    }
}

/// The unit tangent at the corrected point `candidate` (Jacobians in
/// `evaluation`), oriented along the way travelled from `z`: past a corner
/// of up to a right angle the previous tangent may no longer tell. With it,
/// its orientation (see `oriented_null_vector`).
fn oriented_tangent(
    evaluation: &Evaluation,
    scaling: &Scaling,
    force: f64,
    previous: &[f64],
    z: &[f64],
    candidate: &[f64],
) -> Option<(Vec<f64>, f64)> {
    let (t, orientation) = oriented_null_vector(evaluation, scaling, force, previous)?;
    let along: f64 = t
        .iter()
        .zip(candidate.iter().zip(z))
        .map(|(t, (a, b))| t * (a - b))
        .sum();
    // Reversing t reverses the sign of the determinant's last row.
    Some(if along < 0.0 {
        (t.iter().map(|v| -v).collect(), -orientation)
    } else {
        (t, orientation)
    })
}

/// Whether a corrected point lands on a sheet travelled long before (see
/// `clearance`).
type Lands<'a> = &'a dyn Fn(&[f64]) -> bool;

/// Where the piece of the branch through `z` ends along `tangent`, within
/// `reach`: the last point found on it (`corner`), the first one past it
/// (`past`, on the piece `beyond`), and their distance.
struct Kink {
    corner: Vec<f64>,
    past: Vec<f64>,
    width: f64,
    beyond: u64,
}

/// The piece holding the scaled point `z`, if the problem tells pieces.
fn piece_at<P: Problem>(problem: &mut P, scaling: &Scaling, z: &[f64]) -> Option<u64> {
    let (x, omega) = scaling.unscaled(z);
    problem.piece(&x, omega).ok().flatten()
}

/// Bisects the ray `z + s · tangent`, `0 ≤ s ≤ reach`, for the first change
/// of piece.
fn locate_kink<P: Problem>(
    problem: &mut P,
    scaling: &Scaling,
    z: &[f64],
    tangent: &[f64],
    reach: f64,
) -> Option<Kink> {
    let along = |s: f64| -> Vec<f64> { z.iter().zip(tangent).map(|(a, t)| a + s * t).collect() };
    let here = piece_at(problem, scaling, z)?;
    let far = piece_at(problem, scaling, &along(reach))?;
    if far == here {
        return None;
    }
    let (mut lo, mut hi, mut beyond) = (0.0, reach, far);
    while hi - lo > KINK_RESOLUTION * reach {
        let middle = 0.5 * (lo + hi);
        let piece = piece_at(problem, scaling, &along(middle))?;
        if piece == here {
            lo = middle;
        } else {
            (hi, beyond) = (middle, piece);
        }
    }
    Some(Kink {
        corner: along(lo),
        past: along(hi),
        width: hi - lo,
        beyond,
    })
}

/// The way on past a located kink, reached along `tangent`: the null vector
/// of the Jacobian on the next piece, oriented so as to keep the branch's
/// `orientation` (see [`oriented_null_vector`]), which is the way into
/// that piece; without it, the side of the kink that lies in the next
/// piece, and failing that, the side where the residual stays small.
/// Returns the direction and whether it was told exactly.
fn way_past<P: Problem>(
    problem: &mut P,
    scaling: &Scaling,
    force: f64,
    kink: &Kink,
    (tangent, orientation): (&[f64], Option<f64>),
    evaluation: &mut Evaluation,
) -> Option<(Vec<f64>, bool)> {
    let (x, omega) = scaling.unscaled(&kink.past);
    problem.evaluate(&x, omega, true, evaluation).ok()?;
    let (beyond, beyond_orientation) = oriented_null_vector(evaluation, scaling, force, tangent)?;
    if let Some(orientation) = orientation {
        // The way that keeps the branch's orientation: exact, and blind to
        // further kinks close by, which can mislead the look at the pieces.
        let sign = orientation * beyond_orientation;
        return Some((beyond.iter().map(|v| sign * v).collect(), true));
    }
    let along = |sign: f64, length: f64| -> Vec<f64> {
        kink.corner
            .iter()
            .zip(&beyond)
            .map(|(a, t)| a + sign * length * t)
            .collect()
    };
    for scale in KINK_SIDE_SCALES {
        let length = scale * kink.width;
        let sides = [1.0, -1.0]
            .map(|sign| piece_at(problem, scaling, &along(sign, length)) == Some(kink.beyond));
        if sides[0] != sides[1] {
            let sign = if sides[0] { 1.0 } else { -1.0 };
            return Some((beyond.iter().map(|v| sign * v).collect(), true));
        }
    }
    let sign = residual_side(
        problem,
        scaling,
        &kink.corner,
        &beyond,
        KINK_TEST_DISTANCE * kink.width,
        tangent,
        evaluation,
    );
    Some((beyond.iter().map(|v| sign * v).collect(), false))
}

/// Which way along `beyond` from `origin` the branch goes on: the residual
/// at `distance` on either side (on the wrong side it grows at first
/// order); if neither side stands out, the way `tangent` was going.
fn residual_side<P: Problem>(
    problem: &mut P,
    scaling: &Scaling,
    origin: &[f64],
    beyond: &[f64],
    distance: f64,
    tangent: &[f64],
    evaluation: &mut Evaluation,
) -> f64 {
    let mut side = |sign: f64| -> f64 {
        let point: Vec<f64> = origin
            .iter()
            .zip(beyond)
            .map(|(a, t)| a + sign * distance * t)
            .collect();
        let (x, omega) = scaling.unscaled(&point);
        match problem.evaluate(&x, omega, false, evaluation) {
            Ok(()) => norm(&evaluation.residual),
            Err(_) => f64::INFINITY,
        }
    };
    let (plus, minus) = (side(1.0), side(-1.0));
    if plus < KINK_SIDE_RATIO * minus {
        1.0
    } else if minus < KINK_SIDE_RATIO * plus {
        -1.0
    } else {
        beyond
            .iter()
            .zip(tangent)
            .map(|(a, b)| a * b)
            .sum::<f64>()
            .signum()
    }
}

/// Leaves `z` past a kink of the branch that lies within `probe` of it
/// along `tangent`. With pieces known (DLFT), the kink is located by
/// bisection and the branch turns there onto the next piece (again at once
/// if that piece ends right away, as when several instants switch
/// together); otherwise it leaves from `z` along the null vector of the
/// Jacobian at `z + probe · tangent`, toward the side where the residual
/// stays small. Plane-corrected steps of each length in `steps` are tried
/// in turn, the most likely side first; a step must not turn too far,
/// stray from its prediction, go back the way we came (`trail`, the
/// recent points, and `visited`, their pieces) or land on a sheet
/// travelled long before (`lands`). When the way the pieces told lands
/// there, the other way is tried too.
#[allow(clippy::too_many_arguments)]
fn kink_step<P: Problem>(
    problem: &mut P,
    scaling: &Scaling,
    force: f64,
    settings: &NewtonSettings,
    (z, tangent, probe): (&[f64], &[f64], f64),
    steps: &[f64],
    (trail, visited, lands): (&[Vec<f64>], &[u64], Lands<'_>),
    piecewise: bool,
    evaluation: &mut Evaluation,
) -> (Option<Step>, usize) {
    let (origin, beyond, told) = if piecewise {
        let Some(mut kink) = locate_kink(problem, scaling, z, tangent, probe) else {
            // No change of piece within the step: an ordinary failure.
            return (None, 0);
        };
        // The orientation of the branch where it comes from (see
        // `oriented_null_vector`): the way on past the kinks keeps it.
        let (x, omega) = scaling.unscaled(z);
        let orientation = match problem.evaluate(&x, omega, true, evaluation) {
            Ok(()) => oriented_null_vector(evaluation, scaling, force, tangent).map(|(_, o)| o),
            Err(_) => None,
        };
        let mut incoming = tangent.to_vec();
        let mut way = None;
        for _ in 0..MAX_PIVOTS {
            let Some((direction, told)) = way_past(
                problem,
                scaling,
                force,
                &kink,
                (&incoming, orientation),
                evaluation,
            ) else {
                return (None, 0);
            };
            // Does the next piece end at once?
            let reach = KINK_NEAR * steps.iter().cloned().fold(0.0, f64::max);
            let next = locate_kink(problem, scaling, &kink.past, &direction, reach);
            way = Some((kink.past.clone(), direction.clone(), told));
            match next {
                Some(next) => {
                    kink = next;
                    incoming = direction;
                }
                None => break,
            }
        }
        match way {
            Some(way) => way,
            None => return (None, 0),
        }
    } else {
        let past: Vec<f64> = z.iter().zip(tangent).map(|(a, t)| a + probe * t).collect();
        let (x, omega) = scaling.unscaled(&past);
        if problem.evaluate(&x, omega, true, evaluation).is_err() {
            return (None, 0);
        }
        let Some(beyond) = self::tangent(evaluation, scaling, force, tangent) else {
            return (None, 0);
        };
        let sign = residual_side(
            problem,
            scaling,
            z,
            &beyond,
            KINK_TEST_DISTANCE * probe,
            tangent,
            evaluation,
        );
        let beyond: Vec<f64> = beyond.iter().map(|v| sign * v).collect();
        (z.to_vec(), beyond, false)
    };
    let forward: f64 = beyond.iter().zip(tangent).map(|(a, b)| a * b).sum();
    tracing::debug!(
        "kink at {:.6} Hz: way on told exactly {told}, cosine with the way in {forward:.3}, frequency component {:.3e}",
        hertz(scaling.unscaled(&origin).1),
        beyond[beyond.len() - 1],
    );
    let along = |t: &[f64], length: f64| -> Vec<f64> {
        origin.iter().zip(t).map(|(a, b)| a + length * b).collect()
    };
    let mut spent = 0;
    // When the pieces told the side, the other is no way on, unless the
    // told one landed on a sheet travelled long before.
    let mut landed = false;
    for sign in [1.0, -1.0] {
        if sign < 0.0 && told && !landed {
            break;
        }
        if sign * forward < -MAX_KINK_REVERSAL && !(told && sign > 0.0) {
            // Straight back the way we came: not a way on.
            continue;
        }
        let beyond: Vec<f64> = beyond.iter().map(|v| sign * v).collect();
        for &step in steps {
            let predicted = along(&beyond, step);
            let mut candidate = predicted.clone();
            let (accepted, used) = correct(
                problem,
                scaling,
                force,
                settings,
                Constraint::Plane {
                    tangent: &beyond,
                    predicted: &predicted,
                },
                &mut candidate,
                evaluation,
            );
            spent += used;
            let Some((iterations, residual_norm)) = accepted else {
                continue;
            };
            let Some((next, next_orientation)) =
                oriented_tangent(evaluation, scaling, force, &beyond, &origin, &candidate)
            else {
                continue;
            };
            let correction = norm(
                &candidate
                    .iter()
                    .zip(&predicted)
                    .map(|(a, b)| a - b)
                    .collect::<Vec<_>>(),
            );
            let cosine: f64 = next.iter().zip(&beyond).map(|(a, b)| a * b).sum();
            // Going back beside the branch is the way on when the pieces
            // told it and they are new (a cusp of the piecewise-smooth
            // curve); on pieces already travelled, it is going back.
            let back = retraces(&candidate, &next, trail, step)
                && (!told
                    || piece_at(problem, scaling, &candidate)
                        .is_some_and(|piece| visited.contains(&piece)));
            tracing::debug!(
                "kink step {step:.2e} (side {sign}) to {:.6} Hz: turn cosine {cosine:.3}, correction {:.2e}, back {back}",
                hertz(scaling.unscaled(&candidate).1),
                correction / step,
            );
            if cosine < MIN_TANGENT_COSINE || correction > MAX_CORRECTION_RATIO * step || back {
                continue;
            }
            if lands(&candidate) {
                tracing::debug!(
                    "kink step {step:.2e} (side {sign}) landed on a sheet travelled before"
                );
                landed = true;
                continue;
            }
            return (
                Some(Step {
                    candidate,
                    iterations,
                    residual_norm,
                    tangent: next,
                    orientation: next_orientation,
                }),
                spent,
            );
        }
    }
    (None, spent)
}

/// Distance from `point` to the segment `[a, b]`, and the segment's length.
pub(super) fn segment_distance(point: &[f64], a: &[f64], b: &[f64]) -> (f64, f64) {
    let ab: Vec<f64> = b.iter().zip(a).map(|(b, a)| b - a).collect();
    let length2: f64 = ab.iter().map(|v| v * v).sum();
    let along: f64 = point
        .iter()
        .zip(a)
        .zip(&ab)
        .map(|((c, a), d)| (c - a) * d)
        .sum::<f64>()
        / length2.max(f64::MIN_POSITIVE);
    let t = along.clamp(0.0, 1.0);
    let distance = point
        .iter()
        .zip(a)
        .zip(&ab)
        .map(|((c, a), d)| (c - a - t * d).powi(2))
        .sum::<f64>()
        .sqrt();
    (distance, length2.sqrt())
}

/// The cosine between the segment `[a, b]` (of length `length`) and the
/// unit vector `tangent`.
pub(super) fn segment_cosine(a: &[f64], b: &[f64], length: f64, tangent: &[f64]) -> f64 {
    b.iter()
        .zip(a)
        .zip(tangent)
        .map(|((b, a), t)| (b - a) * t)
        .sum::<f64>()
        / length.max(f64::MIN_POSITIVE)
}

/// Whether `candidate`, leaving along `tangent`, goes back the way we came:
/// it lies near a segment of the branch already travelled (`trail`, the
/// recent points, oldest first; within a fraction of the segment's length,
/// which a chord of a curved branch misses by its sagitta) and runs against
/// it. Near a fold the two sheets are close too, but the branch runs on
/// through the fold (the displacement keeps its way, only the frequency
/// turns), so the direction tells them apart.
fn retraces(candidate: &[f64], tangent: &[f64], trail: &[Vec<f64>], step: f64) -> bool {
    trail.windows(2).any(|pair| {
        let (distance, length) = segment_distance(candidate, &pair[0], &pair[1]);
        if distance >= RETRACE_SEGMENT_FRACTION * length + RETRACE_FRACTION * step {
            return false;
        }
        segment_cosine(&pair[0], &pair[1], length, tangent) < -RETRACE_COSINE
    })
}

/// A last resort when the step has shrunk far below the last easy one: a
/// plane-corrected step from `z` along `tangent` of each length in `steps`
/// (long ones), accepted if it converges, does not stray further from its
/// prediction than its length and does not go back the way we came. Small
/// nonsmooth structures (an instant grazing the casing and leaving it
/// again) are passed over rather than resolved.
#[allow(clippy::too_many_arguments)]
fn leap<P: Problem>(
    problem: &mut P,
    scaling: &Scaling,
    force: f64,
    settings: &NewtonSettings,
    (z, tangent): (&[f64], &[f64]),
    steps: &[f64],
    (trail, lands): (&[Vec<f64>], Lands<'_>),
    evaluation: &mut Evaluation,
) -> (Option<Step>, usize) {
    let mut spent = 0;
    for &step in steps {
        let predicted: Vec<f64> = z.iter().zip(tangent).map(|(a, t)| a + step * t).collect();
        let mut candidate = predicted.clone();
        let (accepted, used) = correct(
            problem,
            scaling,
            force,
            settings,
            Constraint::Plane {
                tangent,
                predicted: &predicted,
            },
            &mut candidate,
            evaluation,
        );
        spent += used;
        let Some((iterations, residual_norm)) = accepted else {
            continue;
        };
        let Some((next, orientation)) =
            oriented_tangent(evaluation, scaling, force, tangent, z, &candidate)
        else {
            continue;
        };
        let correction = norm(
            &candidate
                .iter()
                .zip(&predicted)
                .map(|(a, b)| a - b)
                .collect::<Vec<_>>(),
        );
        if correction > step || retraces(&candidate, &next, trail, step) || lands(&candidate) {
            continue;
        }
        return (
            Some(Step {
                candidate,
                iterations,
                residual_norm,
                tangent: next,
                orientation,
            }),
            spent,
        );
    }
    (None, spent)
}

/// The corrector from `candidate` (the prediction): Newton on
/// `[R / F; c(z)] = 0` with backtracking on `‖(R / F, c)‖`, which keeps
/// piecewise-smooth residuals (DLFT) from wandering to far contact states.
/// Returns `(iterations, relative residual)` on convergence, and the
/// iterations spent; `evaluation` holds the last point's Jacobians.
fn correct<P: Problem>(
    problem: &mut P,
    scaling: &Scaling,
    force: f64,
    settings: &NewtonSettings,
    constraint: Constraint<'_>,
    candidate: &mut [f64],
    evaluation: &mut Evaluation,
) -> (Option<(usize, f64)>, usize) {
    let n = candidate.len() - 1;
    let (xc, omega) = scaling.unscaled(candidate);
    if let Err(error) = problem.evaluate(&xc, omega, true, evaluation) {
        // An evaluation failure (e.g. at a singular frequency) is a failed
        // step, not the end: the caller retries with a smaller step.
        tracing::debug!("evaluation failed at {:.4} Hz: {error}", hertz(omega));
        return (None, 0);
    }
    let mut residual = norm(&evaluation.residual) / force;
    let (mut value, mut gradient) = constraint.at(candidate);
    let mut trial = candidate.to_vec();
    for iteration in 0..=settings.max_iterations {
        if !residual.is_finite() {
            return (None, iteration);
        }
        if residual <= settings.tolerance {
            return (Some((iteration, residual)), iteration);
        }
        if iteration == settings.max_iterations {
            break;
        }
        let a = augmented(evaluation, scaling, force, &gradient);
        let rhs = Mat::from_fn(n + 1, 1, |r, _| {
            if r == n {
                -value
            } else {
                -evaluation.residual[r] / force
            }
        });
        let delta = a.partial_piv_lu().solve(&rhs);
        if (0..=n).any(|r| !delta[(r, 0)].is_finite()) {
            return (None, iteration + 1);
        }
        let merit = residual.hypot(value);
        let mut factor = 1.0;
        let mut improved = false;
        for _ in 0..=MAX_BACKTRACKS {
            for (r, t) in trial.iter_mut().enumerate() {
                *t = candidate[r] + factor * delta[(r, 0)];
            }
            let (xt, omega) = scaling.unscaled(&trial);
            if problem.evaluate(&xt, omega, true, evaluation).is_ok() {
                let new_residual = norm(&evaluation.residual) / force;
                let (new_value, new_gradient) = constraint.at(&trial);
                let new_merit = new_residual.hypot(new_value);
                if new_merit.is_finite()
                    && (new_merit < (1.0 - 1e-4 * factor) * merit
                        || new_residual <= settings.tolerance)
                {
                    residual = new_residual;
                    value = new_value;
                    gradient = new_gradient;
                    improved = true;
                    break;
                }
            }
            factor *= 0.5;
        }
        if !improved {
            // No descent along the Newton direction: a shorter step will do better.
            return (None, iteration + 1);
        }
        candidate.copy_from_slice(&trial);
    }
    (None, settings.max_iterations)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn point(omega: f64, x: &[f64]) -> Point {
        Point {
            omega,
            unknowns: x.to_vec(),
            iterations: 1,
            residual_norm: 0.0,
            converged: true,
        }
    }

    #[test]
    fn permutation_parity_counts_transpositions() {
        assert!(!permutation_is_odd(&[]));
        assert!(!permutation_is_odd(&[0, 1, 2]));
        assert!(permutation_is_odd(&[1, 0, 2]));
        // A 3-cycle is two transpositions, a 4-cycle three.
        assert!(!permutation_is_odd(&[1, 2, 0]));
        assert!(permutation_is_odd(&[1, 2, 3, 0]));
        assert!(!permutation_is_odd(&[1, 0, 3, 2]));
    }

    /// An evaluation with Jacobian `[a b]` (one equation, unknowns x, ω).
    fn evaluation(a: f64, b: f64) -> Evaluation {
        Evaluation {
            residual: vec![0.0],
            jacobian: Mat::from_fn(1, 1, |_, _| a),
            derivative_omega: vec![b],
        }
    }

    #[test]
    fn orientation_is_the_sign_of_the_augmented_determinant() {
        let scaling = Scaling {
            factors: vec![1.0, 1.0],
        };
        // R = ω − c − |x|, a nonsmooth fold at x = 0: on x < 0 the
        // Jacobian is [1, 1], on x > 0 [−1, 1].
        let (left, right) = (evaluation(1.0, 1.0), evaluation(-1.0, 1.0));
        let (t, sign) = oriented_null_vector(&left, &scaling, 1.0, &[1.0, -1.0]).unwrap();
        // Along x growing: t = (1, −1)/√2, det [[1, 1], [1, −1]] = −2.
        assert!((t[0] - 0.5f64.sqrt()).abs() < 1e-14 && (t[1] + 0.5f64.sqrt()).abs() < 1e-14);
        assert!(sign < 0.0);
        // Whichever way the null vector on the right piece comes out, the
        // orientation picks x growing (the way into the piece), although
        // it is orthogonal to the way in.
        for previous in [[1.0, 1.0], [-1.0, -1.0], [0.0, 1.0], [0.0, -1.0]] {
            let (u, right_sign) = oriented_null_vector(&right, &scaling, 1.0, &previous).unwrap();
            let way: Vec<f64> = u.iter().map(|v| v * sign * right_sign).collect();
            assert!(way[0] > 0.7 && way[1] > 0.7, "{previous:?}: {way:?}");
        }
        // Orientation flips with the tangent.
        let (_, flipped) = oriented_null_vector(&left, &scaling, 1.0, &[-1.0, 1.0]).unwrap();
        assert!(flipped > 0.0);
    }

    #[test]
    fn orientation_matches_the_determinant_on_random_matrices() {
        // A small linear congruential generator: reproducible, no dependency.
        let mut state = 12345_u64;
        let mut random = move || {
            state = state
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            (state >> 11) as f64 / (1u64 << 53) as f64 - 0.5
        };
        for n in [1, 2, 5, 12] {
            for _ in 0..20 {
                let evaluation = Evaluation {
                    residual: vec![0.0; n],
                    jacobian: Mat::from_fn(n, n, |_, _| random()),
                    derivative_omega: (0..n).map(|_| random()).collect(),
                };
                let scaling = Scaling {
                    factors: (0..=n).map(|_| 0.5 + random().abs()).collect(),
                };
                let previous: Vec<f64> = (0..=n).map(|_| random()).collect();
                let (t, sign) =
                    oriented_null_vector(&evaluation, &scaling, 2.0, &previous).unwrap();
                let determinant = augmented(&evaluation, &scaling, 2.0, &t).determinant();
                assert_eq!(sign > 0.0, determinant > 0.0, "n = {n}: det {determinant}");
                let along: f64 = t.iter().zip(&previous).map(|(a, b)| a * b).sum();
                assert!(along > 0.0);
            }
        }
    }

    #[test]
    fn a_repeated_point_is_found_but_not_the_last_ones() {
        let trail: Vec<Point> = (0..6)
            .map(|i| point(100.0 + i as f64, &[1e-3 * i as f64, 2e-3]))
            .collect();
        // Unknowns in units of 1e-3, frequency in units of 10.
        let scaling = Scaling {
            factors: vec![1e3, 1e3, 0.1],
        };
        let step = 0.1;
        let revisited = |p: &Point| revisited_point(&trail, p, &scaling, step);
        // The same as point 1, up to round-off: a loop.
        let again = point(101.0 * (1.0 + 1e-12), &[1e-3 * (1.0 + 1e-11), 2e-3]);
        assert_eq!(revisited(&again), Some(1));
        // Close to the last two points is normal progress, not a loop.
        assert_eq!(revisited(&point(105.0, &[5e-3, 2e-3])), None);
        assert_eq!(revisited(&point(104.0, &[4e-3, 2e-3])), None);
        // Same frequency, another state (a branch crossing in ω only).
        assert_eq!(revisited(&point(101.0, &[1.1e-3, 2e-3])), None);
        assert_eq!(revisited_point(&trail[..1], &again, &scaling, step), None);
        // Within the relative tolerance but not much closer than a (tiny)
        // step: the other sheet of a sharp fold, not a repetition.
        let near = point(101.0 * (1.0 + 5e-8), &[1e-3 * (1.0 + 5e-8), 2e-3]);
        assert_eq!(revisited(&near), Some(1));
        assert_eq!(revisited_point(&trail, &near, &scaling, 1e-7), None);
    }
}
