//! Hill's physical exponents without the dense eigenproblem: only the
//! eigenvalues near predicted ones, with solves that follow the block's
//! structure.
//!
//! A solve with `A − sI` (`A` the block's Hill matrix, see
//! `stability::hill`) reduces to the groups' dynamic stiffnesses
//! `Z_g(s) = (s + ik_g)²ω²M + (s + ik_g)ωC + K`, one small factorization per
//! group, plus the contact stiffness, which couples the groups on the
//! contact dofs alone: a Schur complement of that size (Woodbury). On the
//! default case that is 21 factorizations of 5 × 5 and one of 21 × 21,
//! against a dense eigenproblem of 210 × 210.
//!
//! The predictions are the exponents of each class's harmonic-0 groups
//! with the contact stiffness averaged over the period (the averaged
//! system, exact without contact), and the strip's edges `±iω/2` (where a
//! family meets a copy of its conjugate: period doubling, and the growing
//! pairs the averaged system cannot predict). Rayleigh–Ritz on the rational Krylov
//! space `(A − g I)⁻ʲ v_g`, `j = 1..3`, of every prediction `(g, v_g)` gives
//! the eigenpairs near them (refined by Rayleigh quotient iteration where
//! short of convergence). An eigenvector's centre `c` (its signed mean
//! harmonic) says which copy it is: the same perturbation written with
//! harmonics `k − m` and exponent `λ + imω` belongs to the class holding
//! the pairs `(s, k − m)`, where it is centred for `m` the integer with
//! `c − m ∈ (−1/2, 1/2]`. A strong contact spreads eigenvectors over
//! harmonics, so a family predicted in one class is often centred in a
//! neighbour: it is moved there and found again on that class's block, as
//! the dense pick finds it.
//!
//! What is found is a set of distinct centred eigenpairs of each class,
//! each therefore in that class's dense pick. The caller accepts it only
//! when the classes hold `2 · dofs · N` in all, the count of the wheel's
//! families, and every eigenvector found stays off the highest harmonics
//! (a truncation that bites can leave a family uncounted by the dense pick,
//! or counted twice): then each class's set is its whole dense pick. A
//! class where a pair is found twice at values apart, or whose centre is
//! within round-off of `±1/2`, is solved densely; so is a class holding a
//! centred copy, one harmonic over, of a family found centred in a
//! neighbour (the dense pick counts it twice, see `centred_twice`).
//! Otherwise the caller solves every class densely: a shortcut, not a
//! different answer.
//! (Within a double eigenvalue the eigenvectors, hence their centres, are
//! not unique, for the dense solver as for this one.)

use super::hill::{group_offsets, Group, Picked};
use crate::cyclic::SignedPair;
use faer::{c64, Mat};
use rayon::prelude::*;
use solver::Solver;
use std::collections::HashMap;

mod solver;
mod vectors;

use vectors::{dot, norm, normalize, orthonormalize};

/// Rayleigh quotient iterations allowed for one eigenpair.
const MOST_ITERATIONS: usize = 20;
/// Converged when `‖Av − μv‖` is below this times the scale of `A`.
const CONVERGED: f64 = 1e-13;

/// One class's block: its pairs (one group each, in order), their
/// dynamics, the contact stiffness between them and the harmonic step.
pub struct ClassBlock<'a> {
    /// The class's pairs.
    pub pairs: &'a [SignedPair],
    /// One group per pair.
    pub groups: Vec<Group>,
    /// The contact stiffness between the groups' dofs (see
    /// `hill::physical_exponents`).
    pub coupling: Vec<(usize, usize, c64)>,
    /// The contact's velocity terms (friction); the targeted solver takes
    /// none (a class with some is left to the dense solver).
    pub damping: Vec<(usize, usize, c64)>,
    /// The harmonic step of the pairs.
    pub step: i64,
}

/// An eigenpair of one class's block: the class, `μ = λ/ω`, the unit
/// eigenvector.
type Eigenpair = (usize, c64, Vec<c64>);

/// A pair found in a class: `μ` and the unit eigenvector.
type Found = (c64, Vec<c64>);

/// A guess for one class: the class, `μ`, a start vector.
type Prediction = (usize, c64, Vec<c64>);

/// What the first pass gives for one class: the eigenpairs centred in it
/// and the guesses moved to other classes, or the class when it failed.
type FirstPass = Result<(Vec<Eigenpair>, Vec<Prediction>), usize>;

/// The physical exponents of every class (in `classes`' order), `None`
/// for a class the shortcut cannot vouch for: the caller solves those
/// densely and checks the total (see the module's doc).
pub fn targeted_classes(classes: &[ClassBlock], omega: f64) -> Vec<Option<Vec<Picked>>> {
    let pairs: usize = classes.iter().map(|c| c.pairs.len()).sum();
    let distinct: std::collections::HashSet<&SignedPair> =
        classes.iter().flat_map(|c| c.pairs.iter()).collect();
    if classes
        .iter()
        .any(|c| c.pairs.len() != c.groups.len() || !c.damping.is_empty())
        || distinct.len() != pairs
    {
        return vec![None; classes.len()];
    }
    let Some(blocks) = classes
        .iter()
        .map(|c| Block::new(&c.groups, &c.coupling, omega, c.step))
        .collect::<Option<Vec<_>>>()
    else {
        return vec![None; classes.len()];
    };
    let mut home: HashMap<SignedPair, (usize, usize)> = HashMap::new();
    for (index, class) in classes.iter().enumerate() {
        for (group, pair) in class.pairs.iter().enumerate() {
            home.insert(*pair, (index, group));
        }
    }
    // Each class's eigenpairs near its predictions; those centred
    // elsewhere, moved to the class they are centred in, become that
    // class's predictions in a second pass.
    let first: Vec<FirstPass> = blocks
        .par_iter()
        .enumerate()
        .map(|(index, block)| {
            let mut predictions = block.averaged_predictions().ok_or(index)?;
            predictions.extend(block.strip_edges());
            let mut centred = Vec::new();
            let mut elsewhere = Vec::new();
            for (value, vector) in block.near(&predictions) {
                if on_the_edge(block.centre(&vector)) {
                    return Err(index);
                }
                let shift = (block.centre(&vector) - 0.5).ceil();
                if shift == 0.0 {
                    centred.push((index, value, vector));
                    continue;
                }
                let harmonics = shift as i64 * block.step as i64;
                elsewhere.extend(moved(
                    classes, &blocks, index, value, &vector, harmonics, &home,
                ));
            }
            Ok((centred, elsewhere))
        })
        .collect();
    let mut doubtful = vec![false; classes.len()];
    let mut found: Vec<Vec<(c64, Vec<c64>)>> = vec![Vec::new(); classes.len()];
    let mut second: Vec<Vec<(c64, Vec<c64>)>> = vec![Vec::new(); classes.len()];
    for outcome in first {
        match outcome {
            Err(index) => doubtful[index] = true,
            Ok((centred, elsewhere)) => {
                for (class, value, vector) in centred {
                    if !add(&mut found[class], value, &vector) {
                        doubtful[class] = true;
                    }
                }
                for (class, value, vector) in elsewhere {
                    second[class].push((value, vector));
                }
            }
        }
    }
    // The second pass: (pairs centred in the class, whether a centre fell
    // on the edge of the interval).
    let again: Vec<(Vec<Found>, bool)> = blocks
        .par_iter()
        .zip(&second)
        .map(|(block, predictions)| {
            if predictions.is_empty() {
                return (Vec::new(), false);
            }
            let near = block.near(predictions);
            let edge = near.iter().any(|(_, v)| on_the_edge(block.centre(v)));
            let centred = near
                .into_iter()
                .filter(|(_, vector)| {
                    let centre = block.centre(vector);
                    centre > -0.5 && centre <= 0.5
                })
                .collect();
            (centred, edge)
        })
        .collect();
    for (class, (pairs, edge)) in again.into_iter().enumerate() {
        doubtful[class] |= edge;
        for (value, vector) in pairs {
            if !add(&mut found[class], value, &vector) {
                doubtful[class] = true;
            }
        }
    }
    for class in centred_twice(classes, &blocks, &found, &home) {
        doubtful[class] = true;
    }
    found
        .into_iter()
        .zip(doubtful)
        .enumerate()
        .map(|(index, (class, doubtful))| {
            (!doubtful).then(|| {
                let block = &blocks[index];
                let mut picked: Vec<Picked> = class
                    .iter()
                    .map(|(value, vector)| Picked {
                        exponent: value * omega,
                        centre: block.centre(vector),
                        edge: block.edge(vector),
                    })
                    .collect();
                picked.sort_by(|p, q| q.exponent.re.total_cmp(&p.exponent.re));
                picked
            })
        })
        .collect()
}

/// Adds the eigenpair to a class's list unless it is there already: a
/// vector in the span of those found for the same value (a double
/// eigenvalue holds as many families as independent vectors). False when
/// the vector is nearly that of a pair found at a value just outside the
/// window (an ill-conditioned eigenvalue found twice): the class cannot be
/// vouched for. (Far apart values are never one pair: the states of `λ`
/// and `λ̄` of a light mode are nearly parallel.)
fn add(found: &mut Vec<(c64, Vec<c64>)>, value: c64, vector: &[c64]) -> bool {
    let close = 1e-8 * value.norm().max(1.0);
    let mut span: Vec<Vec<c64>> = Vec::new();
    for (v, x) in found.iter() {
        if (v - value).norm() < close {
            let mut q = x.clone();
            if orthonormalize(&span, &mut q) {
                span.push(q);
            }
        } else if (v - value).norm() < 1e4 * close && dot(x, vector).norm() > 0.99 {
            return false;
        }
    }
    let mut rest = vector.to_vec();
    let before = norm(&rest);
    for _ in 0..2 {
        for q in &span {
            let h = dot(q, &rest);
            rest.iter_mut().zip(q).for_each(|(x, y)| *x -= h * y);
        }
    }
    if norm(&rest) > 0.1 * before {
        found.push((value, vector.to_vec()));
    }
    true
}

/// Whether a centre is too close to `±1/2` for the targeted and the dense
/// solver (different eigenvectors, different round-off) to be sure to
/// place it alike.
fn on_the_edge(centre: f64) -> bool {
    (centre.abs() - 0.5).abs() < 1e-8
}

/// The classes whose truncated block holds a centred copy, one harmonic
/// over, of a pair found centred in a neighbouring class (and not found
/// there): the dense pick counts such a family twice, so the wheel's count
/// no longer vouches for the classes. Untruncated, the copies' centres are
/// exactly one harmonic apart; truncated, a family reaching the outer
/// harmonics can have two centred copies (on the 6-sector case of
/// `tests/stability.rs` with `N_h = 8` and the 1e8 N/m contact, a family of
/// class 0 at `−0.0075 − 7.47i` ω, whose copy in class −1 carries 9e-3 of
/// its weight on `|k| = H`). Those families are checked, by Rayleigh
/// quotient iteration on the copy; a copy that does not converge counts
/// as centred. A guard against the mechanism seen, not a proof: copies two
/// harmonics over, or a centred eigenvalue that is no copy of a found
/// family, are not looked for.
fn centred_twice(
    classes: &[ClassBlock],
    blocks: &[Block],
    found: &[Vec<Found>],
    home: &HashMap<SignedPair, (usize, usize)>,
) -> Vec<usize> {
    let checks: Vec<(usize, c64, &Vec<c64>)> = found
        .iter()
        .enumerate()
        .flat_map(|(index, pairs)| {
            pairs
                .iter()
                .filter(move |(_, vector)| blocks[index].outer(vector) > OUTER_SHARE)
                .map(move |(value, vector)| (index, *value, vector))
        })
        .collect();
    checks
        .par_iter()
        .flat_map_iter(|&(index, value, vector)| {
            [-1_i64, 1].into_iter().filter_map(move |direction| {
                let harmonics = direction * blocks[index].step as i64;
                let (target, guess, start) =
                    moved(classes, blocks, index, value, vector, harmonics, home)?;
                let block = &blocks[target];
                let Some((copy, v)) = block.rayleigh_quotient_iteration(guess, start) else {
                    return Some(target);
                };
                let centre = block.centre(&v);
                let close = 1e-8 * copy.norm().max(1.0);
                let known = found[target].iter().any(|(x, _)| (x - copy).norm() < close);
                (centre > -0.5 - 1e-8 && centre <= 0.5 + 1e-8 && !known).then_some(target)
            })
        })
        .collect()
}

/// A found pair with more than this share of its weight on the two
/// outermost harmonics is checked for a second centred copy.
const OUTER_SHARE: f64 = 1e-6;

/// Eigenvector `vector` of class `from` with eigenvalue `value`, written
/// with harmonics `k − harmonics` (eigenvalue `value + i·harmonics`): the
/// class that holds those pairs and the state there, pairs beyond the
/// truncation dropped.
fn moved(
    classes: &[ClassBlock],
    blocks: &[Block],
    from: usize,
    value: c64,
    vector: &[c64],
    harmonics: i64,
    home: &HashMap<SignedPair, (usize, usize)>,
) -> Option<(usize, c64, Vec<c64>)> {
    let mut target: Option<usize> = None;
    let mut entries = Vec::new();
    for (group, pair) in classes[from].pairs.iter().enumerate() {
        let to = SignedPair {
            nodal_diameter: pair.nodal_diameter,
            harmonic: pair.harmonic - harmonics,
        };
        let Some(&(index, at)) = home.get(&to) else {
            continue;
        };
        if target.is_some_and(|t| t != index) {
            return None;
        }
        target = Some(index);
        entries.push((group, at));
    }
    let target = target?;
    let (source, block) = (&blocks[from], &blocks[target]);
    let value = value + c64::new(0.0, harmonics as f64);
    let mut start = vec![c64::new(0.0, 0.0); 2 * block.m];
    for (group, at) in entries {
        let (o, p) = (source.offsets[group], block.offsets[at]);
        for r in 0..block.groups[at].dynamics.dofs() {
            start[p + r] = vector[o + r];
            start[block.m + p + r] = vector[o + r] * value;
        }
    }
    Some((target, value, start))
}

/// A block of Hill's method, with what its structured solves need.
struct Block<'a> {
    groups: &'a [Group],
    offsets: Vec<usize>,
    /// Dofs of all groups (`A` is `2m × 2m`).
    m: usize,
    omega: f64,
    step: f64,
    /// The dofs the contact couples (sorted) and the group of each.
    contact: Vec<usize>,
    contact_group: Vec<usize>,
    /// The contact stiffness between them, `n_c × n_c` row-major, N/m.
    coupling: Vec<c64>,
    /// The scale of `A`'s entries: `1 + k_max²`.
    scale: f64,
}

impl<'a> Block<'a> {
    fn new(
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
    fn averaged_predictions(&self) -> Option<Vec<(c64, Vec<c64>)>> {
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
    fn rayleigh_quotient_iteration(&self, guess: c64, start: Vec<c64>) -> Option<(c64, Vec<c64>)> {
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
    fn strip_edges(&self) -> Vec<(c64, Vec<c64>)> {
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
    fn near(&self, predictions: &[(c64, Vec<c64>)]) -> Vec<(c64, Vec<c64>)> {
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
    fn hill_times(&self, z: &[c64]) -> Vec<c64> {
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
    fn centre(&self, vector: &[c64]) -> f64 {
        let (total, moment) = self.weights(vector).fold((0.0, 0.0), |(t, m), (k, w)| {
            (t + w, m + w * k as f64 / self.step)
        });
        moment / total.max(f64::MIN_POSITIVE)
    }

    /// Share of `vector`'s displacement part on the two outermost
    /// harmonic layers (`|k| ≥ H − step`).
    fn outer(&self, vector: &[c64]) -> f64 {
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
    fn edge(&self, vector: &[c64]) -> f64 {
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

    fn weights<'v>(&'v self, vector: &'v [c64]) -> impl Iterator<Item = (i64, f64)> + 'v {
        self.groups.iter().zip(&self.offsets).map(move |(g, &o)| {
            let weight = vector[o..o + g.dynamics.dofs()]
                .iter()
                .map(|z| z.norm_sqr())
                .sum();
            (g.harmonic, weight)
        })
    }
}

#[cfg(test)]
mod tests;
