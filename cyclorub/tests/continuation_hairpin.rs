//! Continuation through a hairpin fold, independent of harmonic balance:
//! the smooth branch `ω = 2 + x + A / (1 + (x/w)²)` climbs a narrow spike
//! (width `w` = 1 % of the length scale, two sheets a few `w` apart and
//! running against each other) and comes down again. A curve parametrized
//! by `x` can be checked point by point: `x` must grow along the whole
//! branch (going back means the continuation jumped onto the sheet it came
//! along), and the top of the spike must be visited (not stepped over).
//!
//! A spike much narrower than the largest step may be stepped over (its
//! tails do not turn the tangent): the largest step is ten widths.
//!
//! The regularized contact law makes such folds: the N = 24 deformed-casing
//! case of the paper has folds whose two sheets are 1e-5 gaps apart.

use cyclorub::continuation::{
    continue_branch, ArcLengthSettings, Evaluation, NewtonSettings, Problem, StopReason,
};
use faer::Mat;

/// The spike's height (in ω) and width (in x).
const HEIGHT: f64 = 1.0;

struct Hairpin {
    width: f64,
}

#[derive(Debug, thiserror::Error)]
#[error("never")]
struct Never;

impl Hairpin {
    fn frequency(&self, x: f64) -> f64 {
        2.0 + x + HEIGHT / (1.0 + (x / self.width).powi(2))
    }
}

impl Problem for Hairpin {
    type Error = Never;
    fn unknowns(&self) -> usize {
        1
    }
    fn force_scale(&self) -> f64 {
        1.0
    }
    fn is_smooth(&self) -> bool {
        true
    }
    fn evaluate(
        &mut self,
        x: &[f64],
        omega: f64,
        jacobian: bool,
        out: &mut Evaluation,
    ) -> Result<(), Never> {
        out.residual = vec![omega - self.frequency(x[0])];
        if jacobian {
            let u = x[0] / self.width;
            let slope = 1.0 - HEIGHT * 2.0 * u / self.width / (1.0 + u * u).powi(2);
            out.jacobian = Mat::from_fn(1, 1, |_, _| -slope);
            out.derivative_omega = vec![1.0];
        }
        Ok(())
    }
}

fn settings(start: f64, end: f64, max_step: f64) -> ArcLengthSettings {
    ArcLengthSettings {
        start,
        end,
        initial_step: 0.01,
        min_step: 1e-9,
        max_step,
        length_scale: 1.0,
        newton: NewtonSettings {
            tolerance: 1e-12,
            max_iterations: 20,
        },
        max_points: 20_000,
    }
}

#[test]
fn a_narrow_fold_is_followed_around_its_tip_without_jumping_across() {
    for width in [1e-2, 1e-3, 1e-4] {
        let mut problem = Hairpin { width };
        let start_x = -1.0;
        let start = problem.frequency(start_x);
        let end = 3.5;
        let branch = continue_branch(
            &mut problem,
            vec![start_x],
            &settings(start, end, 10.0 * width),
            |_, _| {},
        );
        assert_eq!(branch.stop, StopReason::EndReached, "w = {width}");
        for pair in branch.points.windows(2) {
            assert!(
                pair[1].unknowns[0] > pair[0].unknowns[0],
                "w = {width}: went back from x = {} to {} (ω = {} to {})",
                pair[0].unknowns[0],
                pair[1].unknowns[0],
                pair[0].omega,
                pair[1].omega
            );
        }
        for p in &branch.points {
            let r = p.omega - problem.frequency(p.unknowns[0]);
            assert!(r.abs() < 1e-10, "w = {width}: residual {r}");
        }
        // The tip (the spike's part of ω reaches HEIGHT at x = 0): visited
        // to within 1 %, not stepped over.
        let highest = branch
            .points
            .iter()
            .map(|p| p.omega - 2.0 - p.unknowns[0])
            .fold(0.0, f64::max);
        assert!(highest > 0.99 * HEIGHT, "w = {width}: highest {highest}");
        eprintln!(
            "w = {width}: {} points, {} iterations",
            branch.points.len(),
            branch.total_iterations
        );
    }
}
