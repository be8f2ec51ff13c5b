//! A branch point located on the symmetric branch: where the enlarged
//! problem's Jacobian, restricted to the unknowns of the classes `±σ` (the
//! pairs of the cosets `(±σ, 0) + P`), is singular. At a symmetric point
//! that Jacobian is block diagonal by class (the problem commutes with the
//! symmetries `P` leaves), so this block is Hill's matrix of the classes
//! `±σ` at `λ = 0`, exactly: it is singular where an exponent of the class
//! is 0, a real multiplier at `+1`. The enlarged basis also holds the
//! classes `2σ`, `3σ`, …; their blocks are left out, since their own
//! eigenvalues could be the least of the new pairs and hide (or fake) a
//! crossing of class `σ` (`tests/bifurcated.rs`: class 1's hid class 3's
//! at 211.597 Hz on 8 sectors). Its eigenvalue of least modulus, real and
//! changing sign through a real crossing, is the test function; a
//! Neimark–Sacker crossing (a complex pair) leaves the block regular and is
//! told apart. In a class that is not its own conjugate, a real crossing
//! is σ and −σ together: a double real eigenvalue of the real block
//! changes sign (located; one vector of the two-dimensional kernel is
//! followed).

use super::BranchError;
use crate::continuation::{correct, Evaluation, NewtonSettings, Problem};
use crate::hbm::HarmonicBalance;
use faer::linalg::solvers::{PartialPivLu, Solve};
use faer::Mat;

/// A located branch point.
#[derive(Clone, Debug)]
pub struct BranchPoint {
    /// Angular frequency, rad/s.
    pub omega: f64,
    /// The symmetric solution there, on the symmetric problem's layout.
    pub symmetric_unknowns: Vec<f64>,
    /// The same on the enlarged layout (zero on the new unknowns).
    pub unknowns: Vec<f64>,
    /// The null vector of the new block, on the enlarged layout (zero on
    /// the symmetric unknowns), of unit weighted norm.
    pub null_vector: Vec<f64>,
    /// The new block's least eigenvalue there, relative to its largest
    /// entry: how singular the located point is.
    pub relative_eigenvalue: f64,
    /// Points of the symmetric branch solved to locate it.
    pub solves: usize,
}

/// The test function at one symmetric point.
struct Test {
    eigenvalue: f64,
    vector: Vec<f64>,
    scale: f64,
}

/// Evaluates the test function along the symmetric branch.
pub(super) struct Locator<'a> {
    pub symmetric: &'a mut HarmonicBalance,
    pub enlarged: &'a mut HarmonicBalance,
    /// The unknowns of the classes `±σ` in the enlarged layout
    /// ([`super::EnlargedBasis::class_unknowns`]): the test function's
    /// block.
    pub class_unknowns: &'a [usize],
    pub newton: NewtonSettings,
}

/// Inverse iterations before the least eigenvalue is declared not real.
const MAX_INVERSE_ITERATIONS: usize = 200;

impl Locator<'_> {
    /// The symmetric point embedded in the enlarged layout.
    pub fn embed(&self, x: &[f64]) -> Result<Vec<f64>, BranchError> {
        self.symmetric
            .layout()
            .embed(x, self.enlarged.layout())
            .ok_or(BranchError::Embedding)
    }

    /// The new block's eigenvalue of least modulus at `(x, omega)` by
    /// inverse iteration from `start`; an error when it does not converge
    /// to a real one (a complex pair nearest to 0).
    fn test(&mut self, x: &[f64], omega: f64, start: Option<&[f64]>) -> Result<Test, BranchError> {
        let y = self.embed(x)?;
        let mut evaluation = Evaluation::default();
        self.enlarged
            .evaluate(&y, omega, true, &mut evaluation)
            .map_err(|e| BranchError::Evaluation(e.to_string()))?;
        if evaluation.structured.is_some() || evaluation.jacobian.nrows() != y.len() {
            return Err(BranchError::TooLarge { unknowns: y.len() });
        }
        let new = self.class_unknowns;
        let m = new.len();
        let block = Mat::from_fn(m, m, |r, c| evaluation.jacobian[(new[r], new[c])]);
        drop(evaluation);
        let scale = (0..m)
            .flat_map(|c| block.col(c).try_as_col_major().unwrap().as_slice().iter())
            .fold(0.0_f64, |s, a| s.max(a.abs()))
            .max(f64::MIN_POSITIVE);
        let lu = PartialPivLu::new(block.as_ref());
        let mut v: Vec<f64> = match start {
            Some(s) if s.len() == m => s.to_vec(),
            _ => (0..m)
                .map(|i| 1.0 + 0.1 * ((i * 7919) % 13) as f64)
                .collect(),
        };
        normalize(&mut v);
        let mut eigenvalue = f64::NAN;
        for _ in 0..MAX_INVERSE_ITERATIONS {
            let rhs = Mat::from_fn(m, 1, |r, _| v[r]);
            let w = lu.solve(&rhs);
            let mut next: Vec<f64> = (0..m).map(|r| w[(r, 0)]).collect();
            if next.iter().any(|a| !a.is_finite()) {
                // Exactly singular: v is the null vector.
                return Ok(Test {
                    eigenvalue: 0.0,
                    vector: v,
                    scale,
                });
            }
            normalize(&mut next);
            let applied = apply(&block, &next);
            let rayleigh: f64 = applied.iter().zip(&next).map(|(a, b)| a * b).sum();
            let residual = applied
                .iter()
                .zip(&next)
                .map(|(a, b)| (a - rayleigh * b).powi(2))
                .sum::<f64>()
                .sqrt();
            v = next;
            eigenvalue = rayleigh;
            if residual <= 1e-9 * scale.max(rayleigh.abs()) {
                return Ok(Test {
                    eigenvalue,
                    vector: v,
                    scale,
                });
            }
        }
        Err(BranchError::NotReal {
            frequency_hz: omega / (2.0 * std::f64::consts::PI),
            eigenvalue,
        })
    }

    /// The indices `i` of `points` (the symmetric branch, in order) where
    /// the test function changes sign between points `i` and `i + 1`: a
    /// real multiplier of the new classes crosses `+1` there. Points where
    /// the least eigenvalue is not real are skipped (no real crossing is
    /// near them).
    pub fn sign_changes(&mut self, points: &[(&[f64], f64)]) -> Result<Vec<usize>, BranchError> {
        let mut values: Vec<Option<f64>> = Vec::with_capacity(points.len());
        let mut start: Option<Vec<f64>> = None;
        for &(x, omega) in points {
            match self.test(x, omega, start.as_deref()) {
                Ok(test) => {
                    values.push(Some(test.eigenvalue));
                    start = Some(test.vector);
                }
                Err(BranchError::NotReal { .. }) => values.push(None),
                Err(other) => return Err(other),
            }
        }
        Ok(values
            .windows(2)
            .enumerate()
            .filter_map(|(i, w)| match (w[0], w[1]) {
                (Some(a), Some(b))
                    if a.signum() != b.signum() && (points[i].1 - points[i + 1].1).abs() > 0.0 =>
                {
                    Some(i)
                }
                _ => None,
            })
            .collect())
    }

    /// The branch point between the symmetric points `a` and `b`
    /// (`(unknowns, omega)`, consecutive on the branch, at different
    /// frequencies), located by the Illinois variant of regula falsi on
    /// the test function, the symmetric problem solved by Newton at each
    /// trial frequency from the linear interpolation of the two.
    pub fn locate(
        &mut self,
        a: (&[f64], f64),
        b: (&[f64], f64),
    ) -> Result<BranchPoint, BranchError> {
        let hz = |w: f64| w / (2.0 * std::f64::consts::PI);
        if (a.1 - b.1).abs() <= 0.0 {
            return Err(BranchError::Bracket {
                frequency_hz: hz(a.1),
                why: "the two points are at the same frequency".into(),
            });
        }
        let (xa, xb) = (a.0.to_vec(), b.0.to_vec());
        let (wa, wb) = (a.1, b.1);
        let ta = self.test(&xa, wa, None)?;
        let tb = self.test(&xb, wb, Some(&ta.vector))?;
        if ta.eigenvalue.signum() == tb.eigenvalue.signum() {
            return Err(BranchError::NoSignChange {
                from_hz: hz(wa),
                to_hz: hz(wb),
                before: ta.eigenvalue / ta.scale,
                after: tb.eigenvalue / tb.scale,
            });
        }
        // Brackets in the interpolation parameter t ∈ [0, 1].
        let (mut lo, mut hi) = ((0.0, ta.eigenvalue), (1.0, tb.eigenvalue));
        let mut best = (0.0, xa.clone(), ta);
        let mut solves = 0;
        let mut side = 0_i8;
        for _ in 0..80 {
            let t = (lo.0 * hi.1 - hi.0 * lo.1) / (hi.1 - lo.1);
            let omega = wa + t * (wb - wa);
            let mut x: Vec<f64> = xa.iter().zip(&xb).map(|(p, q)| p + t * (q - p)).collect();
            let (converged, _, residual) =
                correct(&mut *self.symmetric, &mut x, omega, &self.newton)
                    .map_err(|e| BranchError::Evaluation(e.to_string()))?;
            solves += 1;
            if !converged {
                return Err(BranchError::Bracket {
                    frequency_hz: hz(omega),
                    why: format!("Newton on the symmetric branch did not converge there (relative residual {residual:.2e})"),
                });
            }
            let test = self.test(&x, omega, Some(&best.2.vector))?;
            let value = test.eigenvalue;
            let done = value.abs() <= 1e-13 * test.scale
                || (hi.0 - lo.0) * (wb - wa).abs() <= 1e-13 * omega;
            best = (t, x, test);
            if done {
                break;
            }
            if value.signum() == lo.1.signum() {
                lo = (t, value);
                if side == -1 {
                    hi.1 /= 2.0;
                }
                side = -1;
            } else {
                hi = (t, value);
                if side == 1 {
                    lo.1 /= 2.0;
                }
                side = 1;
            }
        }
        let (t, x, test) = best;
        let omega = wa + t * (wb - wa);
        let unknowns = self.embed(&x)?;
        let weights = self.enlarged.norm_weights();
        let mut null_vector = vec![0.0; unknowns.len()];
        for (i, &u) in self.class_unknowns.iter().enumerate() {
            null_vector[u] = test.vector[i];
        }
        let norm = null_vector
            .iter()
            .zip(&weights)
            .map(|(v, w)| w * v * v)
            .sum::<f64>()
            .sqrt();
        if norm.is_nan() || norm <= 0.0 {
            return Err(BranchError::Embedding);
        }
        null_vector.iter_mut().for_each(|v| *v /= norm);
        Ok(BranchPoint {
            omega,
            symmetric_unknowns: x,
            unknowns,
            null_vector,
            relative_eigenvalue: test.eigenvalue / test.scale,
            solves,
        })
    }
}

/// `block · v`, column by column: each entry sums its products in the
/// column order a row-by-row dot product takes (from `−0.0`, as `f64`'s
/// `Sum`), so the result is the same to the bit, read contiguously from a
/// column-major block (the row-by-row read strides by its whole height).
fn apply(block: &Mat<f64>, v: &[f64]) -> Vec<f64> {
    let mut out = vec![-0.0; block.nrows()];
    for (c, &x) in v.iter().enumerate() {
        let column = block.col(c).try_as_col_major().unwrap().as_slice();
        for (o, a) in out.iter_mut().zip(column) {
            *o += a * x;
        }
    }
    out
}

fn normalize(v: &mut [f64]) {
    let n = v.iter().map(|a| a * a).sum::<f64>().sqrt();
    if n > 0.0 {
        v.iter_mut().for_each(|a| *a /= n);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_block_product_is_the_row_by_row_dot_product_to_the_bit() {
        // Entries of many magnitudes and signs, so that another order of
        // the sums (a blocked or fused product) rounds differently.
        let m = 37;
        let block = Mat::from_fn(m, m, |r, c| {
            let k = (r * 131 + c * 71 + 7) % 97;
            (k as f64 - 48.0) * 10f64.powi((k % 13) as i32 - 6)
        });
        let v: Vec<f64> = (0..m).map(|i| ((i * 29) % 17) as f64 / 7.0 - 1.1).collect();
        let naive: Vec<f64> = (0..m)
            .map(|r| (0..m).map(|c| block[(r, c)] * v[c]).sum())
            .collect();
        let fast = apply(&block, &v);
        for (a, b) in naive.iter().zip(&fast) {
            assert_eq!(a.to_bits(), b.to_bits(), "{a:e} vs {b:e}");
        }
    }
}
