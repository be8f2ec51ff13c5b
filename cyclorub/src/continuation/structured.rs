//! Jacobians too large to form densely: a problem may give `∂R/∂x` as a
//! [`StructuredJacobian`] (its product with a vector and a factored
//! approximation, exact where the problem's symmetry holds) instead of
//! [`Evaluation::jacobian`]. Every linear solve of continuation then runs
//! GMRES, right-preconditioned by the approximation: one iteration where it
//! is exact, a few more elsewhere, and the answer is the exact Jacobian's
//! either way. [`KrylovSolver`] is the bordered solver that does it, and
//! the dense LU for evaluations that carry the dense Jacobian.

use super::linear::{Bordered, DenseLu, LinearSolver, Solution};
use super::Evaluation;
use std::sync::Arc;

/// GMRES iterations at most (no restart: the approximation is exact at
/// symmetric points, where one iteration does).
const MAX_ITERATIONS: usize = 60;
/// GMRES stops when the residual is this fraction of the right-hand side.
const TOLERANCE: f64 = 1e-12;

/// `∂R/∂x` kept in the problem's own structure.
pub trait StructuredJacobian: Send + Sync + std::fmt::Debug {
    /// `out = (∂R/∂x) v`.
    fn apply(&self, v: &[f64], out: &mut [f64]);
    /// A factored approximation `M ≈ ∂R/∂x`, or why there is none (a
    /// singular approximation).
    fn approximation(&self) -> Result<Arc<dyn Approximation>, String>;
}

/// A factored approximation `M` of a Jacobian.
pub trait Approximation: Send + Sync + std::fmt::Debug {
    /// `r ← M⁻¹ r`.
    fn solve_in_place(&self, r: &mut [f64]);
    /// The sign of `det M`, ±1.
    fn determinant_sign(&self) -> f64;
}

/// Solves `(∂R/∂x) y = rhs` for an evaluation with a structured Jacobian
/// (GMRES preconditioned by its approximation); `None` without one (or
/// when its approximation is singular).
pub fn solve_structured(evaluation: &Evaluation, rhs: &[f64]) -> Option<Vec<f64>> {
    let jacobian = evaluation.structured.as_ref()?;
    let approximation = jacobian.approximation().ok()?;
    let (y, _) = gmres(
        |v, out| jacobian.apply(v, out),
        |r| approximation.solve_in_place(r),
        rhs,
    );
    Some(y)
}

/// The bordered system of one evaluation with a structured Jacobian, kept
/// so that it can be solved again (the tangent after the corrector).
#[derive(Debug)]
struct Kept {
    jacobian: Arc<dyn StructuredJacobian>,
    approximation: Arc<dyn Approximation>,
    derivative_omega: Vec<f64>,
    factors: Vec<f64>,
    force: f64,
    border: Vec<f64>,
    /// `M̃⁻¹ c` for the last column `c = ∂R/∂ω / (d_ω F)`.
    column: Vec<f64>,
    /// `b_ω − b_xᵀ M̃⁻¹ c`, the Schur complement of the bordered `M̃`.
    schur: f64,
    determinant_sign: f64,
}

impl Kept {
    fn new(system: &Bordered<'_>, jacobian: Arc<dyn StructuredJacobian>) -> Option<Self> {
        let approximation = jacobian.approximation().ok()?;
        let evaluation = system.evaluation;
        let n = evaluation.residual.len();
        let (factors, force) = (system.factors, system.force);
        let mut column: Vec<f64> = evaluation
            .derivative_omega
            .iter()
            .map(|d| d / (factors[n] * force))
            .collect();
        scaled_solve(approximation.as_ref(), factors, force, &mut column);
        let schur = system.border[n]
            - system.border[..n]
                .iter()
                .zip(&column)
                .map(|(b, u)| b * u)
                .sum::<f64>();
        let determinant_sign = approximation.determinant_sign() * schur.signum();
        Some(Self {
            jacobian,
            approximation,
            derivative_omega: evaluation.derivative_omega.clone(),
            factors: factors.to_vec(),
            force,
            border: system.border.to_vec(),
            column,
            schur,
            determinant_sign,
        })
    }

    /// `out = A z` for the bordered matrix `A = [[J D⁻¹ / F, ∂R/∂ω / (d_ω F)], [bᵀ]]`.
    fn apply(&self, z: &[f64], out: &mut [f64]) {
        let n = z.len() - 1;
        let scaled: Vec<f64> = z[..n]
            .iter()
            .zip(&self.factors)
            .map(|(v, d)| v / d)
            .collect();
        self.jacobian.apply(&scaled, &mut out[..n]);
        let along = z[n] / self.factors[n];
        for (o, d) in out[..n].iter_mut().zip(&self.derivative_omega) {
            *o = (*o + d * along) / self.force;
        }
        out[n] = self.border.iter().zip(z).map(|(b, v)| b * v).sum();
    }

    /// `r ← P⁻¹ r` for `P`, the bordered matrix with `M` for `J`: by
    /// bordering, `u = M̃⁻¹ r_x`, `η = (r_ω − b_xᵀ u) / schur`, `y = u − η M̃⁻¹ c`.
    fn precondition(&self, r: &mut [f64]) {
        let n = r.len() - 1;
        scaled_solve(
            self.approximation.as_ref(),
            &self.factors,
            self.force,
            &mut r[..n],
        );
        let dot: f64 = self.border[..n]
            .iter()
            .zip(&r[..n])
            .map(|(b, u)| b * u)
            .sum();
        let eta = (r[n] - dot) / self.schur;
        for (y, c) in r[..n].iter_mut().zip(&self.column) {
            *y -= eta * c;
        }
        r[n] = eta;
    }

    fn solve(&self, rhs: &[f64]) -> Solution {
        let (y, converged) = gmres(|z, out| self.apply(z, out), |r| self.precondition(r), rhs);
        if !converged {
            tracing::debug!("GMRES on the structured Jacobian did not reach {TOLERANCE:e}");
        }
        Solution {
            y,
            determinant_sign: self.determinant_sign,
        }
    }
}

/// `r ← M̃⁻¹ r` for `M̃ = M D⁻¹ / F`: `D F M⁻¹ r`.
fn scaled_solve(approximation: &dyn Approximation, factors: &[f64], force: f64, r: &mut [f64]) {
    approximation.solve_in_place(r);
    for (v, d) in r.iter_mut().zip(factors) {
        *v *= d * force;
    }
}

/// The bordered solver: dense LU for evaluations with a dense Jacobian,
/// preconditioned GMRES for those with a structured one. The sign of the
/// determinant is the approximation's (exact where it is exact).
#[derive(Debug, Default)]
pub struct KrylovSolver {
    dense: DenseLu,
    kept: Option<Kept>,
}

impl LinearSolver for KrylovSolver {
    fn solve(&mut self, system: &Bordered<'_>, rhs: &[f64]) -> Solution {
        let Some(jacobian) = system.evaluation.structured.clone() else {
            self.kept = None;
            return self.dense.solve(system, rhs);
        };
        self.kept = Kept::new(system, jacobian);
        match &self.kept {
            Some(kept) => kept.solve(rhs),
            None => Solution {
                y: vec![f64::NAN; rhs.len()],
                determinant_sign: 1.0,
            },
        }
    }

    fn solve_again(&mut self, rhs: &[f64]) -> Option<Solution> {
        match &self.kept {
            Some(kept) => (rhs.len() == kept.border.len()).then(|| kept.solve(rhs)),
            None => self.dense.solve_again(rhs),
        }
    }
}

/// Right-preconditioned GMRES from zero for `A y = b` (`apply`: `A`,
/// `precondition`: `r ← P⁻¹ r`): the solution and whether it reached
/// [`TOLERANCE`].
fn gmres(
    apply: impl Fn(&[f64], &mut [f64]),
    precondition: impl Fn(&mut [f64]),
    b: &[f64],
) -> (Vec<f64>, bool) {
    let n = b.len();
    let beta = norm(b);
    if beta == 0.0 || !beta.is_finite() {
        return (
            vec![if beta == 0.0 { 0.0 } else { f64::NAN }; n],
            beta == 0.0,
        );
    }
    // Arnoldi basis V, the preconditioned directions Z = P⁻¹ V, Hessenberg
    // columns rotated to triangular form by Givens rotations.
    let mut basis: Vec<Vec<f64>> = vec![b.iter().map(|v| v / beta).collect()];
    let mut directions: Vec<Vec<f64>> = Vec::new();
    let mut hessenberg: Vec<Vec<f64>> = Vec::new();
    let mut rotations: Vec<(f64, f64)> = Vec::new();
    let mut g = vec![beta];
    let mut w = vec![0.0; n];
    let mut converged = false;
    for j in 0..MAX_ITERATIONS.min(n) {
        let mut z = basis[j].clone();
        precondition(&mut z);
        apply(&z, &mut w);
        directions.push(z);
        let mut h = vec![0.0; j + 2];
        // Modified Gram–Schmidt, twice for orthogonality to round-off.
        for _ in 0..2 {
            for (i, v) in basis.iter().enumerate() {
                let dot: f64 = w.iter().zip(v).map(|(a, b)| a * b).sum();
                h[i] += dot;
                w.iter_mut().zip(v).for_each(|(a, b)| *a -= dot * b);
            }
        }
        h[j + 1] = norm(&w);
        for (i, &(c, s)) in rotations.iter().enumerate() {
            let (a, b) = (h[i], h[i + 1]);
            h[i] = c * a + s * b;
            h[i + 1] = -s * a + c * b;
        }
        let radius = h[j].hypot(h[j + 1]);
        let (c, s) = if radius == 0.0 {
            (1.0, 0.0)
        } else {
            (h[j] / radius, h[j + 1] / radius)
        };
        h[j] = radius;
        h[j + 1] = 0.0;
        rotations.push((c, s));
        g.push(-s * g[j]);
        g[j] *= c;
        let breakdown = norm(&w) <= f64::EPSILON * beta;
        hessenberg.push(h);
        if g[j + 1].abs() <= TOLERANCE * beta || breakdown {
            converged = true;
            break;
        }
        let next = 1.0 / norm(&w);
        basis.push(w.iter().map(|v| v * next).collect());
    }
    // Back substitution of the triangular system, then y = Z t.
    let k = hessenberg.len();
    let mut t = vec![0.0; k];
    for i in (0..k).rev() {
        let sum: f64 = (i + 1..k).map(|c| hessenberg[c][i] * t[c]).sum();
        t[i] = (g[i] - sum) / hessenberg[i][i];
    }
    let mut y = vec![0.0; n];
    for (direction, coefficient) in directions.iter().zip(&t) {
        y.iter_mut()
            .zip(direction)
            .for_each(|(a, b)| *a += coefficient * b);
    }
    (y, converged)
}

fn norm(v: &[f64]) -> f64 {
    v.iter().map(|x| x * x).sum::<f64>().sqrt()
}

#[cfg(test)]
mod tests {
    use super::*;
    use faer::linalg::solvers::DenseSolveCore;
    use faer::Mat;

    /// A dense matrix as a structured Jacobian, approximated by its
    /// diagonal (or itself, exactly).
    #[derive(Debug)]
    struct Dense {
        matrix: Mat<f64>,
        exact: bool,
    }

    #[derive(Debug)]
    struct Factored {
        inverse: Mat<f64>,
        sign: f64,
    }

    impl Approximation for Factored {
        fn solve_in_place(&self, r: &mut [f64]) {
            let x: Vec<f64> = (0..r.len())
                .map(|i| (0..r.len()).map(|j| self.inverse[(i, j)] * r[j]).sum())
                .collect();
            r.copy_from_slice(&x);
        }
        fn determinant_sign(&self) -> f64 {
            self.sign
        }
    }

    impl StructuredJacobian for Dense {
        fn apply(&self, v: &[f64], out: &mut [f64]) {
            for (i, o) in out.iter_mut().enumerate() {
                *o = (0..v.len()).map(|j| self.matrix[(i, j)] * v[j]).sum();
            }
        }
        fn approximation(&self) -> Result<Arc<dyn Approximation>, String> {
            let n = self.matrix.nrows();
            let m = if self.exact {
                self.matrix.clone()
            } else {
                Mat::from_fn(n, n, |i, j| if i == j { self.matrix[(i, j)] } else { 0.0 })
            };
            let sign = m.determinant().signum();
            Ok(Arc::new(Factored {
                inverse: m.partial_piv_lu().inverse(),
                sign,
            }))
        }
    }

    fn matrix(n: usize) -> Mat<f64> {
        Mat::from_fn(n, n, |i, j| {
            let off = 0.3 * ((i * 7 + j * 3) as f64).sin() / n as f64;
            if i == j {
                2.0 + (i as f64 * 0.7).cos()
            } else {
                off
            }
        })
    }

    /// The bordered solve by preconditioned GMRES equals the dense LU's,
    /// with the same determinant sign, whether the approximation is exact
    /// or only the diagonal; solving again gives the same.
    #[test]
    fn the_krylov_solve_of_a_bordered_system_equals_the_dense_one() {
        let n = 30;
        let jacobian = matrix(n);
        let factors: Vec<f64> = (0..=n).map(|i| 1.0 + 0.1 * i as f64).collect();
        let border: Vec<f64> = (0..=n).map(|i| (i as f64 * 0.37).cos()).collect();
        let rhs: Vec<f64> = (0..=n).map(|i| (i as f64 * 1.3).sin()).collect();
        let derivative_omega: Vec<f64> = (0..n).map(|i| 0.5 * (i as f64).cos()).collect();
        let dense_evaluation = Evaluation {
            residual: vec![0.0; n],
            jacobian: jacobian.clone(),
            derivative_omega: derivative_omega.clone(),
            structured: None,
        };
        let system = |evaluation: &Evaluation, solver: &mut dyn LinearSolver| {
            let bordered = Bordered {
                evaluation,
                factors: &factors,
                force: 3.0,
                border: &border,
            };
            solver.solve(&bordered, &rhs)
        };
        let reference = system(&dense_evaluation, &mut DenseLu::default());
        for exact in [true, false] {
            let evaluation = Evaluation {
                residual: vec![0.0; n],
                jacobian: Mat::zeros(0, 0),
                derivative_omega: derivative_omega.clone(),
                structured: Some(Arc::new(Dense {
                    matrix: jacobian.clone(),
                    exact,
                })),
            };
            let mut solver = KrylovSolver::default();
            let solution = system(&evaluation, &mut solver);
            let again = solver.solve_again(&rhs).unwrap();
            let scale = reference.y.iter().fold(0.0_f64, |m, v| m.max(v.abs()));
            for (a, b) in [&solution.y, &again.y]
                .into_iter()
                .map(|y| (y, &reference.y))
            {
                let error = a
                    .iter()
                    .zip(b)
                    .fold(0.0_f64, |m, (x, y)| m.max((x - y).abs()));
                assert!(error < 1e-11 * scale, "exact {exact}: {error:e}");
            }
            if exact {
                assert!(solution.determinant_sign * reference.determinant_sign > 0.0);
            }
        }
    }

    /// GMRES solves an unbordered system to its tolerance with a rough
    /// preconditioner.
    #[test]
    fn gmres_with_a_diagonal_preconditioner_solves_the_system() {
        let n = 40;
        let structured = Dense {
            matrix: matrix(n),
            exact: false,
        };
        let b: Vec<f64> = (0..n).map(|i| 1.0 + (i as f64).sin()).collect();
        let evaluation = Evaluation {
            residual: vec![0.0; n],
            jacobian: Mat::zeros(0, 0),
            derivative_omega: vec![0.0; n],
            structured: Some(Arc::new(structured)),
        };
        let y = solve_structured(&evaluation, &b).unwrap();
        let mut out = vec![0.0; n];
        evaluation.structured.as_ref().unwrap().apply(&y, &mut out);
        let error = out
            .iter()
            .zip(&b)
            .fold(0.0_f64, |m, (x, y)| m.max((x - y).abs()));
        assert!(error < 1e-11, "residual {error:e}");
    }
}
