//! The linear solve of pseudo-arc-length continuation: the bordered system
//! `[J D⁻¹ / F, ∂R/∂ω / (d_ω F); bᵀ] y = r`, the Jacobian of the residual in
//! scaled unknowns closed by one row `bᵀ` (the tangent, or the gradient of
//! the corrector's constraint). The predictor solves it for the tangent
//! and the sign of its determinant (the branch's orientation), the
//! corrector for its Newton steps. [`LinearSolver`] is the part a sparse or
//! iterative solver replaces; [`DenseLu`] factors the dense matrix. A
//! solver that keeps its factors solves again with them: the tangent at a
//! corrected point comes from the corrector's last factorization.

use super::Evaluation;
use faer::dyn_stack::{MemBuffer, MemStack};
use faer::linalg::lu::partial_pivoting::{factor, solve};
use faer::Mat;

/// The bordered matrix `[[J D⁻¹ / F, ∂R/∂ω / (d_ω F)], [bᵀ]]` of one
/// evaluation: `D` the scaling factors (per unknown, then the frequency's),
/// `F` the force scale, `b` the border row.
#[derive(Clone, Copy)]
pub struct Bordered<'a> {
    /// The residual's Jacobians at the point.
    pub evaluation: &'a Evaluation,
    /// The scaling factors `D` (per unknown, then the frequency's).
    pub factors: &'a [f64],
    /// The force scale `F`.
    pub force: f64,
    /// The last row `b` (as long as `factors`).
    pub border: &'a [f64],
}

impl Bordered<'_> {
    /// The dense matrix.
    pub fn matrix(&self) -> Mat<f64> {
        let n = self.evaluation.residual.len();
        let mut out = Mat::zeros(n + 1, n + 1);
        self.fill(&mut out);
        out
    }

    /// Writes the dense matrix into `out` (`n + 1` square), column by
    /// column.
    pub fn fill(&self, out: &mut Mat<f64>) {
        let n = self.evaluation.residual.len();
        let (evaluation, factors, force) = (self.evaluation, self.factors, self.force);
        for c in 0..=n {
            let (source, factor) = if c == n {
                (evaluation.derivative_omega.as_slice(), factors[n])
            } else {
                (evaluation.jacobian.col_as_slice(c), factors[c])
            };
            let column = out.col_as_slice_mut(c);
            // One division per column, not per entry.
            let scale = 1.0 / (factor * force);
            for (o, v) in column.iter_mut().zip(source) {
                *o = v * scale;
            }
            column[n] = self.border[c];
        }
    }
}

/// A solution of a bordered system.
pub struct Solution {
    /// `y` (not finite when the matrix is singular).
    pub y: Vec<f64>,
    /// The sign of the matrix's determinant, ±1.
    pub determinant_sign: f64,
}

/// Solves bordered systems (see the module's header).
pub trait LinearSolver {
    /// Solves `A y = rhs` for the bordered matrix `A` of `system`, with the
    /// sign of `det A`. A singular matrix may give a `y` that is not
    /// finite: callers check.
    fn solve(&mut self, system: &Bordered<'_>, rhs: &[f64]) -> Solution;
    /// Solves with the matrix of the last [`Self::solve`] again, from its
    /// kept factors (`rhs` as long as that matrix). `None` (the default)
    /// when the solver keeps none.
    fn solve_again(&mut self, rhs: &[f64]) -> Option<Solution> {
        let _ = rhs;
        None
    }
}

/// Dense LU with partial pivoting (faer): every Jacobian is factored anew,
/// in place in a matrix kept between solves (no allocation of the size of
/// the matrix once it is known).
#[derive(Clone, Debug)]
pub struct DenseLu {
    /// The bordered matrix, then its factors `L` (unit, below the
    /// diagonal) and `U`.
    factors: Mat<f64>,
    /// The row permutation and its inverse.
    forward: Vec<usize>,
    inverse: Vec<usize>,
    /// The sign of the last factored matrix's determinant (`None` before
    /// the first factorization).
    determinant_sign: Option<f64>,
}

impl Default for DenseLu {
    fn default() -> Self {
        Self {
            factors: Mat::new(),
            forward: Vec::new(),
            inverse: Vec::new(),
            determinant_sign: None,
        }
    }
}

impl DenseLu {
    /// Solves with the kept factors (`rhs` as long as them).
    fn substitute(&self, rhs: &[f64], determinant_sign: f64) -> Solution {
        let n = rhs.len();
        let par = parallelism(n);
        let permutation = faer::perm::PermRef::new_checked(&self.forward, &self.inverse, n);
        let mut y = Mat::from_fn(n, 1, |r, _| rhs[r]);
        let lu = self.factors.as_ref();
        solve::solve_in_place(
            lu,
            lu,
            permutation,
            y.as_mut(),
            par,
            MemStack::new(&mut MemBuffer::new(solve::solve_in_place_scratch::<
                usize,
                f64,
            >(n, 1, par))),
        );
        Solution {
            y: (0..n).map(|r| y[(r, 0)]).collect(),
            determinant_sign,
        }
    }
}

impl LinearSolver for DenseLu {
    fn solve(&mut self, system: &Bordered<'_>, rhs: &[f64]) -> Solution {
        let n = rhs.len();
        if self.factors.nrows() != n {
            self.factors = Mat::zeros(n, n);
            self.forward = vec![0; n];
            self.inverse = vec![0; n];
        }
        system.fill(&mut self.factors);
        let par = parallelism(n);
        factor::lu_in_place(
            self.factors.as_mut(),
            &mut self.forward,
            &mut self.inverse,
            par,
            MemStack::new(&mut MemBuffer::new(
                factor::lu_in_place_scratch::<usize, f64>(n, n, par, Default::default()),
            )),
            Default::default(),
        );
        // det = ± ∏ U_ii, the sign by the permutation's parity.
        let lu = self.factors.as_ref();
        let diagonal_sign = (0..n).fold(1.0, |sign, i| sign * lu[(i, i)].signum());
        let sign = if permutation_is_odd(&self.forward) {
            -diagonal_sign
        } else {
            diagonal_sign
        };
        self.determinant_sign = Some(sign);
        self.substitute(rhs, sign)
    }

    fn solve_again(&mut self, rhs: &[f64]) -> Option<Solution> {
        let sign = self.determinant_sign?;
        (rhs.len() == self.factors.nrows()).then(|| self.substitute(rhs, sign))
    }
}

/// Below this order a factorization runs on one thread: measured on the
/// open fan's 568 (2 cores), the global parallelism made the whole curve
/// 1.5 times slower.
const PARALLEL_ORDER: usize = 2000;

/// The parallelism of a solve of order `n`.
fn parallelism(n: usize) -> faer::Par {
    if n < PARALLEL_ORDER {
        faer::Par::Seq
    } else {
        faer::get_global_parallelism()
    }
}

/// Whether a permutation, given by its forward array, is odd (an odd
/// number of transpositions: `n − cycles`).
pub(crate) fn permutation_is_odd(forward: &[usize]) -> bool {
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

#[cfg(test)]
mod tests {
    use super::*;

    /// `solve_again` solves with the kept factors: the same solution and
    /// determinant sign as a fresh factorization of the same matrix, and
    /// nothing before the first or for a right-hand side of another size.
    #[test]
    #[allow(clippy::float_cmp)] // the same factors give the same bits, and signs are ±1
    fn solving_again_equals_a_fresh_solve_of_the_same_matrix() {
        let n = 5;
        let evaluation = Evaluation {
            residual: vec![0.0; n],
            jacobian: Mat::from_fn(n, n, |r, c| {
                if r == c {
                    3.0 + r as f64
                } else {
                    ((r * 7 + c * 3) % 5) as f64 - 2.0
                }
            }),
            derivative_omega: (0..n).map(|r| 0.5 - r as f64).collect(),
            structured: None,
        };
        let factors: Vec<f64> = (0..=n).map(|r| 1.0 + 0.1 * r as f64).collect();
        let border: Vec<f64> = (0..=n).map(|r| (r as f64 - 2.5) / 3.0).collect();
        let system = Bordered {
            evaluation: &evaluation,
            factors: &factors,
            force: 2.0,
            border: &border,
        };
        let mut solver = DenseLu::default();
        assert!(solver.solve_again(&[1.0; 6]).is_none());
        let first: Vec<f64> = (0..=n).map(|r| r as f64).collect();
        let second: Vec<f64> = (0..=n).map(|r| 1.0 / (1.0 + r as f64)).collect();
        let solved = solver.solve(&system, &first);
        let again = solver.solve_again(&second).unwrap();
        let fresh = DenseLu::default().solve(&system, &second);
        assert_eq!(again.y, fresh.y);
        assert_eq!(again.determinant_sign, solved.determinant_sign);
        assert_eq!(fresh.determinant_sign, solved.determinant_sign);
        // And it solves the matrix.
        let matrix = system.matrix();
        for (r, expected) in second.iter().enumerate() {
            let product: f64 = (0..=n).map(|c| matrix[(r, c)] * again.y[c]).sum();
            assert!((product - expected).abs() < 1e-12, "row {r}");
        }
        assert!(solver.solve_again(&[1.0; 4]).is_none());
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
}
