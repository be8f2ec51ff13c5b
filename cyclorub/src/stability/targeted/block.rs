//! One class's block of Hill's matrix solved near predicted exponents:
//! the averaged system's predictions and the strip's edges, Rayleigh–Ritz
//! on the rational Krylov space of each, Rayleigh quotient iteration, and
//! where an eigenvector is centred.

use super::super::hill::{group_offsets, Group};
use super::{CONVERGED, MOST_ITERATIONS};
use crate::stability::vectors::{dot, norm, normalize, orthonormalize};
use faer::{c64, Mat};
use solver::Solver;

pub(super) mod solver;

/// A block of Hill's method, with what its structured solves need.
pub(super) struct Block<'a> {
    pub(super) groups: &'a [Group],
    pub(super) offsets: Vec<usize>,
    /// Dofs of all groups (`A` is `2m × 2m`).
    pub(super) m: usize,
    pub(super) omega: f64,
    pub(super) step: f64,
    /// The dofs the contact couples (sorted) and the group of each.
    pub(super) contact: Vec<usize>,
    pub(super) contact_group: Vec<usize>,
    /// The contact stiffness between them, `n_c × n_c` row-major, N/m.
    pub(super) coupling: Vec<c64>,
    /// The scale of `A`'s entries: `1 + k_max²`.
    pub(super) scale: f64,
}

impl<'a> Block<'a> {
    pub(super) fn new(
        groups: &'a [Group],
        coupling: &[(usize, usize, c64)],
        omega: f64,
        step: i64,
    ) -> Option<Self> {
        let (offsets, m) = group_offsets(groups);
        let mut contact: Vec<usize> = coupling.iter().flat_map(|&(r, c, _)| [r, c]).collect();
        contact.sort_unstable();
        contact.dedup();
        if contact.last().is_some_and(|&d| d >= m) {
            return None;
        }
        let mut index = vec![usize::MAX; m];
        for (i, &d) in contact.iter().enumerate() {
            index[d] = i;
        }
        let n = contact.len();
        let mut dense = vec![c64::new(0.0, 0.0); n * n];
        for &(r, c, value) in coupling {
            dense[index[r] * n + index[c]] += value;
        }
        let contact_group = contact
            .iter()
            .map(|&d| offsets.partition_point(|&o| o <= d) - 1)
            .collect();
        Some(Self {
            groups,
            offsets,
            m,
            omega,
            step: step.max(1) as f64,
            contact,
            contact_group,
            coupling: dense,
            scale: 1.0
                + groups
                    .iter()
                    .map(|g| (g.harmonic * g.harmonic) as f64)
                    .fold(0.0, f64::max),
        })
    }

    /// The averaged system's exponents (in units of `ω`) with their
    /// eigenvectors spread over the block: the harmonic-0 groups, with the
    /// contact stiffness between them (its mean over the period).
    pub(super) fn averaged_predictions(&self) -> Option<Vec<(c64, Vec<c64>)>> {
        let rest: Vec<usize> = (0..self.groups.len())
            .filter(|&g| self.groups[g].harmonic == 0)
            .collect();
        let sizes: Vec<usize> = rest
            .iter()
            .map(|&g| self.groups[g].dynamics.dofs())
            .collect();
        let n0: usize = sizes.iter().sum();
        if n0 == 0 || rest.len() == self.groups.len() {
            return None;
        }
        // Local index of every dof of the harmonic-0 groups.
        let mut local = vec![usize::MAX; self.m];
        let mut at = 0;
        for (&g, &size) in rest.iter().zip(&sizes) {
            for r in 0..size {
                local[self.offsets[g] + r] = at + r;
            }
            at += size;
        }
        let (w1, w2) = (1.0 / self.omega, 1.0 / (self.omega * self.omega));
        let mut a = Mat::<c64>::zeros(2 * n0, 2 * n0);
        let mut at = 0;
        for (&g, &size) in rest.iter().zip(&sizes) {
            let d = self.groups[g].dynamics.as_ref();
            for r in 0..size {
                a[(at + r, n0 + at + r)] = c64::new(1.0, 0.0);
                for c in 0..size {
                    a[(n0 + at + r, at + c)] = -d.mass_inverse_stiffness()[(r, c)] * w2;
                    a[(n0 + at + r, n0 + at + c)] = -d.mass_inverse_damping()[(r, c)] * w1;
                }
            }
            at += size;
        }
        let n = self.contact.len();
        for (i, &row) in self.contact.iter().enumerate() {
            for (j, &col) in self.contact.iter().enumerate() {
                let value = self.coupling[i * n + j];
                let (lr, lc) = (local[row], local[col]);
                if value == c64::new(0.0, 0.0) || lr == usize::MAX || lc == usize::MAX {
                    continue;
                }
                let g = self.contact_group[i];
                let d = self.groups[g].dynamics.as_ref();
                let offset = local[self.offsets[g]];
                for r in 0..d.dofs() {
                    a[(n0 + offset + r, lc)] -=
                        d.mass_inverse()[(r, row - self.offsets[g])] * value * w2;
                }
            }
        }
        let eigen = a.eigen().ok()?;
        let (values, vectors) = (eigen.S(), eigen.U());
        let mut predictions = Vec::with_capacity(2 * n0);
        for i in 0..2 * n0 {
            let value = values[i];
            let mut start = vec![c64::new(0.0, 0.0); 2 * self.m];
            for (d, &l) in local.iter().enumerate() {
                if l != usize::MAX {
                    start[d] = vectors[(l, i)];
                    start[self.m + d] = vectors[(l, i)] * value;
                }
            }
            if !(value.re.is_finite() && value.im.is_finite()) {
                return None;
            }
            predictions.push((value, start));
        }
        Some(predictions)
    }

    /// The eigenpair of `A` that Rayleigh quotient iteration reaches from
    /// `(guess, start)`, checked to have converged.
    pub(super) fn rayleigh_quotient_iteration(
        &self,
        guess: c64,
        start: Vec<c64>,
    ) -> Option<(c64, Vec<c64>)> {
        let mut v = start;
        normalize(&mut v)?;
        let mut shift = guess;
        for iteration in 0..MOST_ITERATIONS {
            let solver = match Solver::at(self, shift) {
                Some(s) => s,
                // The shift is an eigenvalue to round-off: move off it.
                None => Solver::at(self, shift + c64::new(1e-13, 1e-13) * shift.norm().max(1.0))?,
            };
            let w = solver.apply(self, &v);
            let theta: c64 = v.iter().zip(&w).map(|(a, b)| a.conj() * b).sum();
            if !(theta.norm() > 0.0 && theta.re.is_finite() && theta.im.is_finite()) {
                return None;
            }
            v = w;
            normalize(&mut v)?;
            // Converged on the residual, not on the direction, which a
            // pair of (nearly) equal eigenvalues leaves undetermined.
            let av = self.hill_times(&v);
            let value: c64 = v.iter().zip(&av).map(|(a, b)| a.conj() * b).sum();
            let residual = v
                .iter()
                .zip(&av)
                .map(|(x, y)| (y - value * x).norm_sqr())
                .sum::<f64>()
                .sqrt();
            if residual <= CONVERGED * (self.scale + value.norm_sqr()) {
                return Some((value, v));
            }
            // One step at the predicted shift first, so that a poor start
            // vector does not pull the quotient towards another family.
            if iteration > 0 {
                shift = value;
            }
        }
        None
    }

    /// Guesses on the edges of the strip, `μ = ±i·step/2`, with a start
    /// vector on every dof: where a family meets a copy of its conjugate
    /// (period doubling, and its growing pair of exponents `±a + iω/2`),
    /// which the averaged system does not predict.
    pub(super) fn strip_edges(&self) -> Vec<(c64, Vec<c64>)> {
        // A fixed, irregular start (the golden ratio's multiples mod 1).
        let start: Vec<c64> = (0..2 * self.m)
            .map(|i| {
                let t = (i as f64 * 0.618_033_988_749_895).fract();
                c64::cis(2.0 * std::f64::consts::PI * t) * (0.5 + t)
            })
            .collect();
        [0.5, -0.5]
            .iter()
            .map(|&edge| (c64::new(0.0, edge * self.step), start.clone()))
            .collect()
    }

    /// Converged eigenpairs near the predictions: Rayleigh–Ritz on the
    /// rational Krylov space of `(A − g I)⁻¹` applied twice to each
    /// prediction's vector, at its own shift `g`; a Ritz pair short of
    /// convergence is refined by Rayleigh quotient iteration.
    pub(super) fn near(&self, predictions: &[(c64, Vec<c64>)]) -> Vec<(c64, Vec<c64>)> {
        const DEPTH: usize = 3;
        let mut basis: Vec<Vec<c64>> = Vec::with_capacity(DEPTH * predictions.len());
        for (guess, start) in predictions {
            // Off the guess, which is exact without contact.
            let shift = guess + c64::new(1e-9, 1e-9) * guess.norm().max(1.0);
            let Some(solver) = Solver::at(self, shift) else {
                continue;
            };
            let mut next = start.clone();
            for _ in 0..DEPTH {
                next = solver.apply(self, &next);
                if !orthonormalize(&basis, &mut next) {
                    break;
                }
                basis.push(next.clone());
            }
        }
        let n = basis.len();
        let images: Vec<Vec<c64>> = basis.iter().map(|q| self.hill_times(q)).collect();
        let projected = Mat::from_fn(n, n, |i, j| dot(&basis[i], &images[j]));
        let Ok(eigen) = projected.eigen() else {
            return Vec::new();
        };
        (0..n)
            .filter_map(|i| {
                let mut x = vec![c64::new(0.0, 0.0); 2 * self.m];
                for (j, q) in basis.iter().enumerate() {
                    let y = eigen.U()[(j, i)];
                    x.iter_mut().zip(q).for_each(|(a, b)| *a += y * b);
                }
                normalize(&mut x)?;
                let value = eigen.S()[i];
                let ax = self.hill_times(&x);
                let residual = norm(
                    &ax.iter()
                        .zip(&x)
                        .map(|(a, b)| a - value * b)
                        .collect::<Vec<_>>(),
                );
                let scale = self.scale + value.norm_sqr();
                if residual <= CONVERGED * scale {
                    Some((value, x))
                } else if residual <= 1e-2 * scale {
                    self.rayleigh_quotient_iteration(value, x)
                } else {
                    None
                }
            })
            .collect()
    }

    /// `A z` for the state `z = [q; p]`: `μq = p` and, per group,
    /// `μp = (k² − M⁻¹(ikC/ω + K/ω²)) q − (2ik + M⁻¹C/ω) p − M⁻¹(Dq)/ω²`.
    pub(super) fn hill_times(&self, z: &[c64]) -> Vec<c64> {
        let m = self.m;
        let (q, p) = z.split_at(m);
        let (w1, w2) = (1.0 / self.omega, 1.0 / (self.omega * self.omega));
        let n = self.contact.len();
        // D q on the contact dofs.
        let mut dq = vec![c64::new(0.0, 0.0); m];
        for (i, &row) in self.contact.iter().enumerate() {
            dq[row] = (0..n)
                .map(|j| self.coupling[i * n + j] * q[self.contact[j]])
                .sum();
        }
        let mut out = vec![c64::new(0.0, 0.0); 2 * m];
        out[..m].copy_from_slice(p);
        for (g, &o) in self.groups.iter().zip(&self.offsets) {
            let d = g.dynamics.as_ref();
            let k = g.harmonic as f64;
            let ik = c64::new(0.0, k);
            for r in 0..d.dofs() {
                let mut sum = q[o + r] * (k * k) - p[o + r] * (ik * 2.0);
                for c in 0..d.dofs() {
                    sum -= (d.mass_inverse_damping()[(r, c)] * ik * w1
                        + d.mass_inverse_stiffness()[(r, c)] * w2)
                        * q[o + c]
                        + d.mass_inverse_damping()[(r, c)] * w1 * p[o + c]
                        + d.mass_inverse()[(r, c)] * dq[o + c] * w2;
                }
                out[m + o + r] = sum;
            }
        }
        out
    }

    /// Signed mean harmonic of `vector`'s displacement part, in steps.
    pub(super) fn centre(&self, vector: &[c64]) -> f64 {
        let (total, moment) = self.weights(vector).fold((0.0, 0.0), |(t, m), (k, w)| {
            (t + w, m + w * k as f64 / self.step)
        });
        moment / total.max(f64::MIN_POSITIVE)
    }

    /// Share of `vector`'s displacement part on the two outermost
    /// harmonic layers (`|k| ≥ H − step`).
    pub(super) fn outer(&self, vector: &[c64]) -> f64 {
        let highest = self
            .groups
            .iter()
            .map(|g| g.harmonic.abs())
            .max()
            .unwrap_or(0);
        let from = highest - self.step as i64;
        let (total, outer) = self.weights(vector).fold((0.0, 0.0), |(t, e), (k, w)| {
            let outside = highest > 0 && k.abs() >= from.max(1);
            (t + w, e + if outside { w } else { 0.0 })
        });
        outer / total.max(f64::MIN_POSITIVE)
    }

    /// Share of `vector`'s displacement part on the highest harmonics.
    pub(super) fn edge(&self, vector: &[c64]) -> f64 {
        let highest = self
            .groups
            .iter()
            .map(|g| g.harmonic.abs())
            .max()
            .unwrap_or(0);
        let (total, edge) = self.weights(vector).fold((0.0, 0.0), |(t, e), (k, w)| {
            let on_edge = highest > 0 && k.abs() == highest;
            (t + w, e + if on_edge { w } else { 0.0 })
        });
        edge / total.max(f64::MIN_POSITIVE)
    }

    pub(super) fn weights<'v>(
        &'v self,
        vector: &'v [c64],
    ) -> impl Iterator<Item = (i64, f64)> + 'v {
        self.groups.iter().zip(&self.offsets).map(move |(g, &o)| {
            let weight = vector[o..o + g.dynamics.dofs()]
                .iter()
                .map(|z| z.norm_sqr())
                .sum();
            (g.harmonic, weight)
        })
    }
}
