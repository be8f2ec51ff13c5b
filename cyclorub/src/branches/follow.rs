//! Off the branch point and along the bifurcated branch: a first point at
//! a given distance along the null vector (the arc-length condition on the
//! new unknowns alone keeps Newton off the symmetric branch, whose new
//! unknowns are all zero), then pseudo-arc-length continuation on the
//! enlarged problem, oriented away from the branch point, until the range
//! ends, the steps give out, or the branch returns to the symmetric one
//! at another branch point: its component along the null vector changes
//! sign (it crossed the symmetric branch), or, having grown, shrinks back
//! to a small share of its largest (it joined the symmetric branch there).

use super::locate::BranchPoint;
use super::BranchError;
use crate::continuation::{
    Continuation, Evaluation, NewtonSettings, Point, Problem, Settings, Step, StopReason,
};
use crate::hbm::HarmonicBalance;
use faer::linalg::solvers::{PartialPivLu, Solve};
use faer::Mat;
use serde::Serialize;

/// Why one side of a bifurcated branch stopped.
#[derive(Clone, Debug, PartialEq, Serialize)]
#[serde(tag = "reason", rename_all = "snake_case")]
pub enum SideStop {
    /// The continuation stopped (range, steps, cap, …).
    Continuation {
        /// Its reason.
        stop: StopReason,
    },
    /// The branch came back to the symmetric branch (another branch point
    /// of the same class): crossed it between its last point and the one
    /// before, or joined it at its last point.
    Rejoined {
        /// Frequency of its last point, Hz.
        frequency_hz: f64,
    },
    /// No first point off the branch point: Newton did not converge at any
    /// of the distances tried.
    NoFirstPoint {
        /// The smallest distance tried (scaled arc length).
        distance: f64,
    },
}

impl std::fmt::Display for SideStop {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            Self::Continuation { stop } => write!(f, "{stop}"),
            Self::Rejoined { frequency_hz } => write!(
                f,
                "rejoined the symmetric branch near {frequency_hz:.4} Hz (another branch point)"
            ),
            Self::NoFirstPoint { distance } => write!(
                f,
                "no first point off the branch point (down to {distance:.1e} of arc length)"
            ),
        }
    }
}

/// One side of a bifurcated branch: off the branch point along `+v` or `−v`.
#[derive(Clone, Debug)]
pub struct Side {
    /// `+1` along the null vector, `−1` against it.
    pub direction: f64,
    /// The points, from the branch point on (the branch point itself not
    /// included).
    pub points: Vec<Point>,
    /// Why it stopped.
    pub stop: SideStop,
}

/// Times the first distance is halved before a side is given up.
const FIRST_POINT_TRIES: usize = 6;

/// A side has left the symmetric branch once its component along the null
/// vector is this many times its first point's.
const GROWN: f64 = 10.0;

/// A side that has left the symmetric branch is back on it when that
/// component is below this share of its largest along the side (the open
/// fan's class-8 branch from 281.28 Hz, R-HBM: 6e-4 of sector spread at its
/// widest, then creeping at about 1e-5 next to where it joins the
/// symmetric branch, 286.878 Hz).
const RETURNED: f64 = 0.05;

/// The side `direction` of the branch through `point` on `problem` (the
/// enlarged problem), continued with `settings` (its `initial_step` is
/// also the first point's distance, scaled like the continuation's arc
/// length: the length scale for displacements).
pub(super) fn follow_side(
    problem: &mut HarmonicBalance,
    point: &BranchPoint,
    direction: f64,
    settings: Settings,
) -> Result<Side, BranchError> {
    let a = settings.arc_length;
    let mut distance = a.initial_step;
    let mut first = None;
    for _ in 0..FIRST_POINT_TRIES {
        if let Some(found) = first_point(
            problem,
            point,
            direction * distance * a.length_scale,
            &a.newton,
        )? {
            first = Some(found);
            break;
        }
        distance /= 2.0;
    }
    let Some((x, omega)) = first else {
        return Ok(Side {
            direction,
            points: Vec::new(),
            stop: SideStop::NoFirstPoint { distance },
        });
    };
    let weights = problem.norm_weights();
    let along = |x: &[f64]| -> f64 {
        x.iter()
            .zip(&point.null_vector)
            .zip(&weights)
            .map(|((x, v), w)| w * v * x)
            .sum::<f64>()
    };
    // The symmetry-breaking component's first and largest size: a branch
    // that comes back to the symmetric one without crossing it (it joins
    // it at another branch point and the continuation creeps along there)
    // ends where that component has grown and shrunk back.
    let first_size = along(&x).abs();
    let mut driver = Continuation::from_point(
        problem,
        x,
        omega,
        (point.unknowns.clone(), point.omega),
        settings,
    )?;
    let mut points = Vec::new();
    let mut largest = first_size;
    let stop = loop {
        match driver.step() {
            Step::Point(p) => {
                let component = along(&p.unknowns) * direction;
                largest = largest.max(component.abs());
                points.push(p.clone());
                if back_on_the_symmetric_branch(component, first_size, largest) {
                    break SideStop::Rejoined {
                        frequency_hz: p.omega / (2.0 * std::f64::consts::PI),
                    };
                }
            }
            Step::Stopped(reason) => {
                break SideStop::Continuation {
                    stop: reason.clone(),
                }
            }
        }
    };
    Ok(Side {
        direction,
        points,
        stop,
    })
}

/// Whether a side is back on the symmetric branch at a point whose
/// component along the null vector is `component` (positive on the side's
/// way out), `first` its size at the side's first point and `largest` the
/// largest since: it crossed the symmetric branch (the sign changed), or,
/// having grown [`GROWN`] times, it shrank below [`RETURNED`] of its
/// largest (it joined the symmetric branch without crossing it).
fn back_on_the_symmetric_branch(component: f64, first: f64, largest: f64) -> bool {
    component < 0.0 || (largest > GROWN * first && component.abs() < RETURNED * largest)
}

/// The solution of the enlarged problem whose weighted component along the
/// null vector is `offset` (m), from the branch point moved by it; `None`
/// when Newton does not converge.
fn first_point(
    problem: &mut HarmonicBalance,
    point: &BranchPoint,
    offset: f64,
    newton: &NewtonSettings,
) -> Result<Option<(Vec<f64>, f64)>, BranchError> {
    let weights = problem.norm_weights();
    let border: Vec<f64> = point
        .null_vector
        .iter()
        .zip(&weights)
        .map(|(v, w)| w * v)
        .collect();
    let n = point.unknowns.len();
    let mut x: Vec<f64> = point
        .unknowns
        .iter()
        .zip(&point.null_vector)
        .map(|(x, v)| x + offset * v)
        .collect();
    let mut omega = point.omega;
    let scale = problem.force_scale();
    let mut evaluation = Evaluation::default();
    for _ in 0..=newton.max_iterations {
        problem
            .evaluate(&x, omega, true, &mut evaluation)
            .map_err(|e| BranchError::Evaluation(e.to_string()))?;
        let constraint: f64 = border
            .iter()
            .zip(&x)
            .zip(&point.unknowns)
            .map(|((b, x), x0)| b * (x - x0))
            .sum::<f64>()
            - offset;
        let residual = evaluation
            .residual
            .iter()
            .map(|r| r * r)
            .sum::<f64>()
            .sqrt()
            / scale;
        if residual <= newton.tolerance && constraint.abs() <= 1e-12 * offset.abs() {
            return Ok(Some((x, omega)));
        }
        if evaluation.structured.is_some() || evaluation.jacobian.nrows() != n {
            return Err(BranchError::TooLarge { unknowns: n });
        }
        let system = Mat::from_fn(n + 1, n + 1, |r, c| match (r < n, c < n) {
            (true, true) => evaluation.jacobian[(r, c)],
            (true, false) => evaluation.derivative_omega[r],
            (false, true) => border[c],
            (false, false) => 0.0,
        });
        let rhs = Mat::from_fn(n + 1, 1, |r, _| {
            if r < n {
                -evaluation.residual[r]
            } else {
                -constraint
            }
        });
        let step = PartialPivLu::new(system.as_ref()).solve(&rhs);
        if (0..=n).any(|r| !step[(r, 0)].is_finite()) {
            return Ok(None);
        }
        x.iter_mut()
            .enumerate()
            .for_each(|(r, x)| *x += step[(r, 0)]);
        omega += step[(n, 0)];
    }
    Ok(None)
}

#[cfg(test)]
mod tests {
    use super::back_on_the_symmetric_branch;

    #[test]
    fn a_side_is_back_when_it_crosses_or_when_it_has_grown_and_shrunk_back() {
        // The open fan's class-8 side from 281.28 Hz (R-HBM), in sizes of
        // its sector spread: 3.7e-6 at the first point, 6e-4 at its widest,
        // 1.1e-5 where it creeps next to where it joins the wave, 286.878 Hz.
        let (first, widest) = (3.7e-6, 6e-4);
        assert!(back_on_the_symmetric_branch(1.1e-5, first, widest));
        // Leaving: at the first point, and growing.
        assert!(!back_on_the_symmetric_branch(first, first, first));
        assert!(!back_on_the_symmetric_branch(2e-5, first, 2e-5));
        // Still well off it, though past its widest.
        assert!(!back_on_the_symmetric_branch(1e-4, first, widest));
        // Crossed: the sign changed, whatever the sizes.
        assert!(back_on_the_symmetric_branch(-1e-9, first, first));
        // Never grown ten times its first size: shrinking does not count
        // (a side that hesitates next to its own branch point).
        assert!(!back_on_the_symmetric_branch(1e-7, 1e-5, 5e-5));
    }
}
