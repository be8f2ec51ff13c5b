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

use super::hill::{Group, Picked};
use crate::cyclic::SignedPair;
use faer::c64;
use rayon::prelude::*;
use std::collections::HashMap;

mod block;

use crate::stability::vectors::{dot, norm, orthonormalize};
use block::Block;

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
/// `tests/stability_targeted.rs` with `N_h = 8` and the 1e8 N/m contact, a family of
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

#[cfg(test)]
mod tests;
