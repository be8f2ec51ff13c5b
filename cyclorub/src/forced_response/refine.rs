//! A point's orbit refined: the same case with more harmonics, the point's
//! truncated solution as the start, Newton at its frequency. What the
//! stability check needs to say how converged its exponents are (their
//! change from the orbit to the refined one): raising Hill's truncation
//! alone on a truncated orbit does not converge on a stiff contact.

use super::RunError;
use super::{prepare, Prepared};
use crate::case::BasisChoice;
use crate::continuation::{correct, NewtonSettings};
use crate::stability::{PointStability, Stability, StabilityError, StabilitySettings};
use std::path::Path;
use std::time::{Duration, Instant};

/// A refined orbit: the problem with `factor` times the harmonics (and
/// time samples) and the corrected unknowns.
pub struct RefinedPoint {
    /// The refined case, model and problem.
    pub prepared: Prepared,
    /// The point's unknowns on the refined problem.
    pub unknowns: Vec<f64>,
    /// Newton's iterations.
    pub iterations: usize,
}

/// The point `(unknowns, omega)` of `prepared`'s problem on `factor` times
/// its harmonics (`factor ≥ 2`), corrected by Newton at `omega` from the
/// truncated solution; `None` when Newton does not converge there (the
/// refined orbit is then not this one's). `case_dir` as for [`prepare`].
pub fn refined_point(
    prepared: &Prepared,
    case_dir: &Path,
    basis: BasisChoice,
    unknowns: &[f64],
    omega: f64,
    factor: usize,
) -> Result<Option<RefinedPoint>, RunError> {
    let fine = refined_problem(prepared, case_dir, basis, factor)?;
    solved_on(prepared, fine, unknowns, omega)
}

/// `prepared`'s case on `factor` times its harmonics and time samples
/// (`factor ≥ 2`), prepared but not solved.
fn refined_problem(
    prepared: &Prepared,
    case_dir: &Path,
    basis: BasisChoice,
    factor: usize,
) -> Result<Prepared, RunError> {
    let mut case = prepared.case.clone();
    let factor = factor.max(2);
    case.harmonic_balance.harmonics *= factor;
    case.harmonic_balance.time_samples *= factor;
    prepare(&case, case_dir, basis)
}

/// The point `(unknowns, omega)` of `prepared`'s problem corrected by
/// Newton on the refined problem `fine`; `None` when Newton does not
/// converge.
fn solved_on(
    prepared: &Prepared,
    fine: Prepared,
    unknowns: &[f64],
    omega: f64,
) -> Result<Option<RefinedPoint>, RunError> {
    let case = fine.case.clone();
    let Some(mut x) = prepared
        .problem
        .layout()
        .embed(unknowns, fine.problem.layout())
    else {
        return Ok(None);
    };
    let newton = NewtonSettings {
        tolerance: case.continuation.tolerance,
        max_iterations: case.continuation.max_iterations.saturating_mul(4),
        ..Default::default()
    };
    let mut problem = fine.problem;
    let (converged, iterations, _) = correct(&mut problem, &mut x, omega, &newton)?;
    Ok(converged.then(|| RefinedPoint {
        prepared: Prepared { problem, ..fine },
        unknowns: x,
        iterations,
    }))
}

/// The solutions of `prepared`'s problem at `omega` on each passage of a
/// branch through it: `points` are the branch's `(omega, unknowns)` in
/// branch order; between two points around `omega` the unknowns are
/// interpolated linearly and corrected by Newton at `omega` (a passage
/// where Newton does not converge is left out). Reading a branch at a
/// frequency between its points, exactly: linear interpolation of the
/// amplitudes alone is off by the curve's bend (a percent near a
/// resonance at the default steps).
pub fn branch_solutions_at(
    prepared: &mut Prepared,
    points: &[(f64, &[f64])],
    omega: f64,
) -> Result<Vec<Vec<f64>>, RunError> {
    let k = &prepared.case.continuation;
    let newton = NewtonSettings {
        tolerance: k.tolerance,
        max_iterations: k.max_iterations.saturating_mul(4),
        ..Default::default()
    };
    let mut found: Vec<Vec<f64>> = Vec::new();
    for pair in points.windows(2) {
        let ((w0, x0), (w1, x1)) = (pair[0], pair[1]);
        if omega < w0.min(w1) || omega > w0.max(w1) || x0.len() != x1.len() {
            continue;
        }
        let t = if (w1 - w0).abs() > 0.0 {
            (omega - w0) / (w1 - w0)
        } else {
            0.5
        };
        let mut x: Vec<f64> = x0.iter().zip(x1).map(|(a, b)| a + t * (b - a)).collect();
        let (converged, _, _) = correct(&mut prepared.problem, &mut x, omega, &newton)?;
        if !converged {
            continue;
        }
        // A point exactly at omega ends one segment and starts the next.
        let same = |y: &Vec<f64>| {
            let scale = y.iter().fold(0.0_f64, |m, v| m.max(v.abs())).max(1e-300);
            y.iter().zip(&x).all(|(a, b)| (a - b).abs() <= 1e-8 * scale)
        };
        if !found.iter().any(same) {
            found.push(x);
        }
    }
    Ok(found)
}

/// A point's stability on its refined orbit: how far the run's exponents
/// are from converged (docs/design.md §10, "sizes").
pub struct RefinedStability {
    /// Harmonics of the refined orbit's Hill truncation.
    pub harmonics: usize,
    /// Newton's iterations from the truncated solution.
    pub iterations: usize,
    /// The refined point's exponents.
    pub stability: PointStability,
}

impl RefinedStability {
    /// `|Re λ|` of the refined orbit's leading exponent (1 when it has
    /// none): the scale of the changes.
    pub fn scale(&self) -> f64 {
        self.stability
            .leading()
            .map_or(1.0, |(_, e)| e.re.abs())
            .max(f64::MIN_POSITIVE)
    }

    /// The change of the wheel's leading real part from `coarse` (the run's
    /// orbit) to the refined one, relative to the refined one: the error
    /// estimate of the sizes.
    pub fn leading_change(&self, coarse: &PointStability) -> Option<f64> {
        let (_, a) = self.stability.leading()?;
        let (_, b) = coarse.leading()?;
        Some((a.re - b.re).abs() / self.scale())
    }

    /// Per class, the change of its leading real part from `coarse` to the
    /// refined orbit, relative to the refined orbit's leading real part.
    pub fn class_changes(&self, coarse: &PointStability) -> Vec<(i64, f64)> {
        let scale = self.scale();
        self.stability
            .classes
            .iter()
            .filter_map(|fine| {
                let a = fine.leading()?;
                let b = coarse.class(fine.nodal_diameter)?.leading()?;
                Some((fine.nodal_diameter, (a.re - b.re).abs() / scale))
            })
            .collect()
    }
}

/// The point `(unknowns, omega)` re-solved on twice the harmonics
/// ([`refined_point`]) and checked with twice Hill's truncation of
/// `settings` (by classes, or on the whole wheel when `full_wheel`);
/// `None` when Newton does not converge on the refined orbit.
pub fn refined_stability(
    prepared: &Prepared,
    case_dir: &Path,
    basis: BasisChoice,
    unknowns: &[f64],
    omega: f64,
    settings: &StabilitySettings,
    full_wheel: bool,
) -> Result<Option<RefinedStability>, RefineError> {
    let point = Refinement {
        prepared,
        case_dir,
        basis,
        unknowns,
        omega,
        settings,
        full_wheel,
    };
    point.by(2)
}

/// A point to refine: where it is and how it was checked.
#[derive(Clone, Copy)]
pub struct Refinement<'a> {
    /// The run's problem.
    pub prepared: &'a Prepared,
    /// The folder the case's relative paths start from.
    pub case_dir: &'a Path,
    /// The run's basis.
    pub basis: BasisChoice,
    /// The point's unknowns on the run's orbit.
    pub unknowns: &'a [f64],
    /// Its angular frequency, rad/s.
    pub omega: f64,
    /// The run's stability settings (Hill's truncation scaled with the
    /// orbit's harmonics).
    pub settings: &'a StabilitySettings,
    /// Hill's method on the whole wheel instead of by classes.
    pub full_wheel: bool,
}

impl Refinement<'_> {
    /// The point re-solved on `factor` times the harmonics and checked with
    /// `factor` times Hill's truncation, and at least the refined orbit's
    /// harmonics (a truncation below the orbit's misses growth: two such
    /// could agree and pass for converged); `None` when Newton does not
    /// converge on that orbit.
    pub fn by(&self, factor: usize) -> Result<Option<RefinedStability>, RefineError> {
        let fine = refined_problem(self.prepared, self.case_dir, self.basis, factor)?;
        let harmonics = fine.problem.layout().harmonics();
        let settings = StabilitySettings {
            harmonics: Some(
                self.settings
                    .harmonics
                    .map_or(harmonics, |h| (factor.max(2) * h).max(harmonics)),
            ),
            ..*self.settings
        };
        let contact_dofs = fine.case.contact_dofs();
        // A refined truncation too large is refused before the orbit's
        // Newton, which takes a minute on a mistuned full wheel.
        self.check(&fine, &contact_dofs, &settings)?;
        let Some(fine) = solved_on(self.prepared, fine, self.unknowns, self.omega)? else {
            return Ok(None);
        };
        let check = self.check(&fine.prepared, &contact_dofs, &settings)?;
        let stability = check.point(&fine.unknowns, self.omega)?;
        Ok(Some(RefinedStability {
            harmonics: check.harmonics(),
            iterations: fine.iterations,
            stability,
        }))
    }

    /// The stability check of `prepared` (by classes, or on the whole
    /// wheel when [`Self::full_wheel`]).
    fn check<'p>(
        &self,
        prepared: &'p Prepared,
        contact_dofs: &[usize],
        settings: &StabilitySettings,
    ) -> Result<Stability<'p>, StabilityError> {
        let (model, problem) = (&prepared.model, &prepared.problem);
        if self.full_wheel {
            Stability::full_wheel(model, problem, contact_dofs, settings)
        } else {
            Stability::new(model, problem, contact_dofs, settings)
        }
    }

    /// The orbit and Hill's truncation doubled (2, 4, 8, … times the run's
    /// harmonics, at most `largest_factor`) until the wheel's leading real
    /// part moves by less than `tolerance` (relative) between two
    /// refinements: the exponents' sizes converged, not only their verdict
    /// (the truncated orbit linearizes a contact the harmonics smooth, so
    /// Hill's truncation alone does not converge them; docs/design.md §10).
    /// `coarse`: the point's stability on the run's orbit.
    pub fn converge(
        &self,
        coarse: &PointStability,
        tolerance: f64,
        largest_factor: usize,
    ) -> Result<Convergence, RefineError> {
        self.converge_within_time(
            coarse,
            tolerance,
            largest_factor,
            (Duration::MAX, Duration::ZERO),
        )
    }

    /// [`Refinement::converge`], starting no refinement that would end
    /// past `budget`: each is predicted to cost `REFINEMENT_GROWTH` (8) times
    /// the last (`coarse_time` for the first: what checking the point at
    /// the run's truncation took); `stopped` then says so.
    pub fn converge_within_time(
        &self,
        coarse: &PointStability,
        tolerance: f64,
        largest_factor: usize,
        (budget, coarse_time): (Duration, Duration),
    ) -> Result<Convergence, RefineError> {
        let started = Instant::now();
        let mut steps: Vec<RefinedStability> = Vec::new();
        let mut changes = Vec::new();
        let mut factor = 2;
        let mut stopped = None;
        let mut last_time = coarse_time;
        while factor <= largest_factor.max(2) {
            let spent = started.elapsed();
            if let Some(predicted) = beyond_budget(spent, last_time, budget) {
                let last = if steps.is_empty() {
                    "the point's check at the run's harmonics"
                } else {
                    "the last refinement"
                };
                stopped = Some(format!(
                    "the refinement to {factor} times the harmonics would take about \
                     {predicted:.0} s ({REFINEMENT_GROWTH} times {last}, {:.1} s), past the \
                     budget of {:.0} s ({:.1} s spent)",
                    last_time.as_secs_f64(),
                    budget.as_secs_f64(),
                    spent.as_secs_f64()
                ));
                break;
            }
            let began = Instant::now();
            let step = match self.by(factor) {
                Ok(Some(step)) => step,
                Ok(None) => break,
                Err(RefineError::Stability(error @ StabilityError::TooLarge { .. })) => {
                    stopped = Some(error.to_string());
                    break;
                }
                Err(error) => return Err(error),
            };
            last_time = began.elapsed();
            let previous = steps.last().map_or(coarse, |s| &s.stability);
            let change = step.leading_change(previous);
            steps.push(step);
            changes.push(change);
            if change.is_some_and(|c| c < tolerance) {
                break;
            }
            factor *= 2;
        }
        let estimate = changes.last().copied().flatten();
        Ok(Convergence {
            converged: estimate.is_some_and(|c| c < tolerance),
            estimate,
            changes,
            steps,
            stopped,
        })
    }
}

/// How many times the last refinement (or the point's check at the run's
/// truncation) the next one is predicted to cost: doubling the harmonics
/// doubles the width of what each contour node factors densely, so up to
/// 8 times (measured: the default branch's fastest point 2.9 and 3.3
/// times from H = 20 to 40 to 80; the mistuned default wheel's point 5.5 s
/// at H = 10, about 47 s at H = 20).
const REFINEMENT_GROWTH: f64 = 8.0;

/// The predicted cost (s) of a refinement after one that took `last`,
/// when with `spent` it would end past `budget`; `None` when it fits.
fn beyond_budget(spent: Duration, last: Duration, budget: Duration) -> Option<f64> {
    let predicted = REFINEMENT_GROWTH * last.as_secs_f64();
    (spent.as_secs_f64() + predicted > budget.as_secs_f64()).then_some(predicted)
}

/// The exponents of a point refined until their sizes settle
/// ([`Refinement::converge`]).
pub struct Convergence {
    /// The refinements, each doubling the last's harmonics.
    pub steps: Vec<RefinedStability>,
    /// Each step's change of the wheel's leading real part from the step
    /// before (the run's orbit for the first), relative to the step's.
    pub changes: Vec<Option<f64>>,
    /// The last change: the error estimate of the last step's sizes.
    pub estimate: Option<f64>,
    /// Whether it fell below the tolerance.
    pub converged: bool,
    /// Why the refinements stopped short (the next one's eigenproblem above
    /// the largest allowed, or the next one predicted past the time
    /// budget); `None` when they did
    /// not, or Newton failed.
    pub stopped: Option<String>,
}

impl Convergence {
    /// The last (finest) refinement.
    pub fn last(&self) -> Option<&RefinedStability> {
        self.steps.last()
    }
}

/// Why a refined stability check could not be made.
#[derive(Debug, thiserror::Error)]
pub enum RefineError {
    /// Building or solving the refined orbit.
    #[error("the refined orbit: {0}")]
    Orbit(#[from] RunError),
    /// Its stability check.
    #[error(transparent)]
    Stability(#[from] StabilityError),
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A refinement is started only when, predicted at 8 times the last,
    /// it ends within the budget: the mistuned default wheel's first
    /// (5.5 s at the run's truncation: about 44 s) is not, the default
    /// branch's (16 ms, then 0.13 s, 0.38 s) all are.
    #[test]
    fn a_refinement_predicted_past_the_budget_is_not_started() {
        let budget = Duration::from_secs(10);
        let s = Duration::from_secs_f64;
        let predicted = beyond_budget(Duration::ZERO, s(5.5), budget);
        assert!(predicted.is_some_and(|p| (p - 44.0).abs() < 1e-9));
        assert_eq!(beyond_budget(Duration::ZERO, s(0.016), budget), None);
        assert_eq!(beyond_budget(s(0.2), s(0.13), budget), None);
        assert_eq!(beyond_budget(s(0.6), s(0.38), budget), None);
        // Spent time counts: the same last refinement no longer fits.
        assert!(beyond_budget(s(7.5), s(0.38), budget).is_some());
        // No budget: everything fits.
        assert_eq!(beyond_budget(s(1e6), s(1e6), Duration::MAX), None);
    }
}
