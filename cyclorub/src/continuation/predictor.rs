//! The tangent predictor: the unit null vector of `[J_x, J_ω]` (in scaled
//! unknowns), oriented like the way travelled, and the prediction along it.
//! With it comes the branch's *orientation*, the sign of `det [J; tᵀ]`.

use super::geometry::{along, distance};
use super::linear::Solution;
#[cfg(test)]
use super::linear::{Bordered, LinearSolver};
use super::workspace::Workspace;
use super::{norm, Problem};

/// The predicted point `z + step · tangent`.
pub(crate) fn predict(z: &[f64], tangent: &[f64], step: f64) -> Vec<f64> {
    along(z, tangent, step)
}

/// The least cosine between the last chord and the tangent at its end for
/// the chord to serve as the secant predictor: past a kink or a fold tip
/// turned on a short chord, the chord may point well off the way on, and
/// the tangent serves instead.
const SECANT_MIN_COSINE: f64 = 0.5;

/// The unit vector from `from` to `to`, if they differ.
pub(crate) fn unit_chord(from: &[f64], to: &[f64]) -> Option<Vec<f64>> {
    let chord: Vec<f64> = to.iter().zip(from).map(|(b, a)| b - a).collect();
    let length = norm(&chord);
    (length.is_finite() && length > 0.0).then(|| chord.iter().map(|v| v / length).collect())
}

/// How much shorter or longer than the step to try the last chord may be
/// for it to serve as the secant predictor. The chord tells the branch's
/// direction at its own scale: a far shorter one (the short step that
/// located a kink) tells it over too short a length, and for a far shorter
/// step (halved after refusals) the chord from it is the corrector's
/// noise, not a direction (on the fan's partly standing wave, steps
/// refused for turning, the turn growing as they shrank, crept at the
/// smallest step); the tangent of the piece serves there, and kinks are
/// located and turned with it.
const SECANT_CHORD_RATIO: f64 = 4.0;

/// The secant predictor's direction at `z`, the last of `trail`, for a
/// step of `step`: the unit chord from the point before it, unless that
/// chord is more than 4 times shorter or longer than the step
/// ([`SECANT_CHORD_RATIO`]) or points more than 60° off `tangent`
/// ([`SECANT_MIN_COSINE`]).
pub(crate) fn secant(
    trail: &[Vec<f64>],
    z: &[f64],
    tangent: &[f64],
    step: f64,
) -> Option<Vec<f64>> {
    let before = trail.len().checked_sub(2).map(|i| &trail[i])?;
    let length = distance(before, z);
    if !(step / SECANT_CHORD_RATIO..=step * SECANT_CHORD_RATIO).contains(&length) {
        return None;
    }
    let chord = unit_chord(before, z)?;
    let cosine: f64 = chord.iter().zip(tangent).map(|(a, b)| a * b).sum();
    (cosine >= SECANT_MIN_COSINE).then_some(chord)
}

/// [`unit_null_vector`] from a factorization of `system`.
#[cfg(test)]
fn null_vector(solver: &mut dyn LinearSolver, system: &Bordered<'_>) -> Option<(Vec<f64>, f64)> {
    let n = system.evaluation.residual.len();
    unit_null_vector(solver.solve(system, &last_unit(n + 1)))
}

/// `e`, the last unit vector of length `len`.
fn last_unit(len: usize) -> Vec<f64> {
    (0..len)
        .map(|r| if r + 1 == len { 1.0 } else { 0.0 })
        .collect()
}

/// The unit tangent `t` from the solution of `[J D⁻¹ / F; pᵀ] t = e` (the
/// bordered system's Jacobian, its border `p` the previous tangent),
/// oriented like the border, and its orientation: the sign of
/// `det [J D⁻¹ / F; tᵀ]`.
///
/// The orientation is kept along a regular branch, through smooth folds
/// and through the kinks of a piecewise-smooth one alike (for a kink: the
/// null vectors of the Jacobians on either side, each scaled to cross the
/// switching surface at unit speed, are joined by those of the Jacobians
/// in between, which are all regular on a regular branch), so it tells
/// the way on past a kink without looking at the pieces around it; a
/// change of it is a branch point.
fn unit_null_vector(solution: Solution) -> Option<(Vec<f64>, f64)> {
    let t = solution.y;
    let length = norm(&t);
    if !(length.is_finite() && length > 0.0) {
        return None;
    }
    // `[J; pᵀ] t = e` gives `det [J; tᵀ] = det [J; pᵀ] · |t|` for the unit
    // `t` returned (determinant lemma, with `pᵀ t = 1`): the sign of
    // `det [J; pᵀ]`.
    Some((
        t.iter().map(|v| v / length).collect(),
        solution.determinant_sign,
    ))
}

impl<P: Problem> Workspace<'_, P> {
    /// [`unit_null_vector`] from a fresh factorization of the bordered
    /// system of the last evaluation, its border `previous`.
    pub(crate) fn null_vector(&mut self, previous: &[f64]) -> Option<(Vec<f64>, f64)> {
        let n = self.evaluation.residual.len();
        unit_null_vector(self.solve(previous, &last_unit(n + 1)))
    }

    /// The unit tangent at the corrected point `candidate`, oriented along
    /// the way travelled from `z`: past a corner of up to a right angle the
    /// previous tangent may no longer tell. With it, its orientation.
    ///
    /// After `iterations` Newton steps of the corrector, when its factors
    /// serve here ([`Workspace::factors_serve_here`]: a smooth residual,
    /// or the same piece), the corrector's last factorization is used:
    /// that of its last iterate before `candidate` (as close to it as the
    /// last Newton step, which converged: the tangent is off by about that
    /// distance times the branch's curvature, far below any turn limit),
    /// bordered by `previous` (the plane's normal). Else the Jacobians of
    /// the last evaluation are factored: those at `candidate`, or, when
    /// the factors would have served but the solver keeps none, the same
    /// last iterate's (the corrector skipped the Jacobians at
    /// `candidate`).
    pub(crate) fn oriented_tangent(
        &mut self,
        previous: &[f64],
        z: &[f64],
        candidate: &[f64],
        iterations: usize,
    ) -> Option<(Vec<f64>, f64)> {
        let again = if iterations > 0 && self.factors_serve_here() {
            self.solver.solve_again(&last_unit(candidate.len()))
        } else {
            None
        };
        let (t, orientation) = match again {
            Some(solution) => unit_null_vector(solution)?,
            None => self.null_vector(previous)?,
        };
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
}

#[cfg(test)]
mod tests {
    use super::super::linear::DenseLu;
    use super::super::Evaluation;
    use super::*;
    use faer::Mat;

    /// The last chord serves as the secant when it is within 4 times the
    /// step and within 60° of the tangent; else the tangent serves.
    #[test]
    fn the_secant_is_the_last_chord_within_its_limits() {
        let trail = vec![vec![0.0, 0.0], vec![0.3, 0.4]];
        let z = trail[1].as_slice();
        let along = [0.6, 0.8];
        assert_eq!(secant(&trail, z, &along, 0.5), Some(vec![0.6, 0.8]));
        assert_eq!(secant(&trail, z, &along, 2.0), Some(vec![0.6, 0.8]));
        assert_eq!(secant(&trail, z, &along, 0.125), Some(vec![0.6, 0.8]));
        // Far shorter or longer steps than the chord (0.5): the tangent.
        assert_eq!(secant(&trail, z, &along, 2.1), None);
        assert_eq!(secant(&trail, z, &along, 0.12), None);
        // More than 60° off the tangent: the tangent.
        assert_eq!(secant(&trail, z, &[0.0, 1.0], 0.5), Some(vec![0.6, 0.8]));
        assert_eq!(secant(&trail, z, &[1.0, 0.0], 0.5), Some(vec![0.6, 0.8]));
        assert_eq!(secant(&trail, z, &[-0.6, 0.8], 0.5), None);
        // One point: no chord.
        assert_eq!(secant(&trail[..1], &trail[0], &along, 0.5), None);
    }

    /// An evaluation with Jacobian `[a b]` (one equation, unknowns x, ω).
    fn evaluation(a: f64, b: f64) -> Evaluation {
        Evaluation {
            residual: vec![0.0],
            jacobian: Mat::from_fn(1, 1, |_, _| a),
            derivative_omega: vec![b],
            structured: None,
        }
    }

    fn oriented(
        evaluation: &Evaluation,
        factors: &[f64],
        force: f64,
        previous: &[f64],
    ) -> Option<(Vec<f64>, f64)> {
        let system = Bordered {
            evaluation,
            factors,
            force,
            border: previous,
        };
        null_vector(&mut DenseLu::default(), &system)
    }

    #[test]
    fn orientation_is_the_sign_of_the_augmented_determinant() {
        let factors = [1.0, 1.0];
        // R = ω − c − |x|, a nonsmooth fold at x = 0: on x < 0 the
        // Jacobian is [1, 1], on x > 0 [−1, 1].
        let (left, right) = (evaluation(1.0, 1.0), evaluation(-1.0, 1.0));
        let (t, sign) = oriented(&left, &factors, 1.0, &[1.0, -1.0]).unwrap();
        // Along x growing: t = (1, −1)/√2, det [[1, 1], [1, −1]] = −2.
        assert!((t[0] - 0.5f64.sqrt()).abs() < 1e-14 && (t[1] + 0.5f64.sqrt()).abs() < 1e-14);
        assert!(sign < 0.0);
        // Whichever way the null vector on the right piece comes out, the
        // orientation picks x growing (the way into the piece), although
        // it is orthogonal to the way in.
        for previous in [[1.0, 1.0], [-1.0, -1.0], [0.0, 1.0], [0.0, -1.0]] {
            let (u, right_sign) = oriented(&right, &factors, 1.0, &previous).unwrap();
            let way: Vec<f64> = u.iter().map(|v| v * sign * right_sign).collect();
            assert!(way[0] > 0.7 && way[1] > 0.7, "{previous:?}: {way:?}");
        }
        // Orientation flips with the tangent.
        let (_, flipped) = oriented(&left, &factors, 1.0, &[-1.0, 1.0]).unwrap();
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
                    structured: None,
                };
                let factors: Vec<f64> = (0..=n).map(|_| 0.5 + random().abs()).collect();
                let previous: Vec<f64> = (0..=n).map(|_| random()).collect();
                let (t, sign) = oriented(&evaluation, &factors, 2.0, &previous).unwrap();
                let determinant = Bordered {
                    evaluation: &evaluation,
                    factors: &factors,
                    force: 2.0,
                    border: &t,
                }
                .matrix()
                .determinant();
                assert_eq!(sign > 0.0, determinant > 0.0, "n = {n}: det {determinant}");
                let along: f64 = t.iter().zip(&previous).map(|(a, b)| a * b).sum();
                assert!(along > 0.0);
            }
        }
    }

    /// A smooth curved branch: `x₀² + ω² + 0.3 x₁ − 1 = 0`,
    /// `x₁ − 0.5 x₀ ω = 0`.
    struct Curve;

    impl Problem for Curve {
        type Error = std::convert::Infallible;
        fn unknowns(&self) -> usize {
            2
        }
        fn force_scale(&self) -> f64 {
            1.0
        }
        fn evaluate(
            &mut self,
            x: &[f64],
            omega: f64,
            jacobian: bool,
            out: &mut Evaluation,
        ) -> Result<(), Self::Error> {
            out.residual = vec![
                x[0] * x[0] + omega * omega + 0.3 * x[1] - 1.0,
                x[1] - 0.5 * x[0] * omega,
            ];
            if jacobian {
                out.jacobian = Mat::from_fn(2, 2, |r, c| match (r, c) {
                    (0, 0) => 2.0 * x[0],
                    (0, 1) => 0.3,
                    (1, 0) => -0.5 * omega,
                    _ => 1.0,
                });
                out.derivative_omega = vec![2.0 * omega, -0.5 * x[0]];
            }
            Ok(())
        }
        fn is_smooth(&self) -> bool {
            true
        }
    }

    /// The tangent taken from the corrector's last factorization (its last
    /// iterate's Jacobian) is within the last Newton step of the tangent
    /// factored at the corrected point, with the same orientation; it is
    /// not that tangent (the factors were reused).
    #[test]
    fn the_tangent_from_the_correctors_factors_is_the_fresh_one_to_the_last_step() {
        use super::super::corrector::{Constraint, Corrector};
        use super::super::geometry::Scaling;
        use super::super::{CorrectorSettings, NewtonSettings};
        let mut problem = Curve;
        let mut work = Workspace::new(
            &mut problem,
            Scaling::identity(2),
            Box::new(DenseLu::default()),
        );
        // A point of the branch at ω = 0.6, and its tangent.
        let omega: f64 = 0.6;
        let x0 =
            (-0.15 * omega + ((0.15 * omega).powi(2) + 4.0 * (1.0 - omega * omega)).sqrt()) / 2.0;
        let z = vec![x0, 0.5 * x0 * omega, omega];
        work.evaluate_at(&z, true).unwrap();
        let (tangent, orientation) = work.null_vector(&[0.0, 0.0, 1.0]).unwrap();
        let corrector = Corrector {
            newton: NewtonSettings::default(),
            line_search: CorrectorSettings::default(),
        };
        for step in [0.01, 0.05, 0.2] {
            let predicted: Vec<f64> = z.iter().zip(&tangent).map(|(a, t)| a + step * t).collect();
            let mut candidate = predicted.clone();
            let plane = Constraint::Plane {
                tangent: &tangent,
                predicted: &predicted,
            };
            let (converged, _) = corrector.correct(&mut work, plane, &mut candidate);
            let (iterations, _) = converged.unwrap();
            assert!(iterations > 0, "step {step}: converged at the prediction");
            let (reused, reused_orientation) = work
                .oriented_tangent(&tangent, &z, &candidate, iterations)
                .unwrap();
            work.evaluate_at(&candidate, true).unwrap();
            let (fresh, fresh_orientation) =
                work.oriented_tangent(&tangent, &z, &candidate, 0).unwrap();
            let difference = reused
                .iter()
                .zip(&fresh)
                .map(|(a, b)| (a - b).powi(2))
                .sum::<f64>()
                .sqrt();
            println!("step {step}: {iterations} iterations, tangent difference {difference:.2e}");
            // The last Newton step from a prediction `step` away is about
            // step² (quadratic convergence): so is the tangent's error.
            assert!(
                difference > 0.0 && difference < step * step,
                "step {step}: {difference:e}"
            );
            // Orientations are ±1: the same sign.
            assert!(reused_orientation * fresh_orientation > 0.0);
            assert!(fresh_orientation * orientation > 0.0);
        }
    }
}
