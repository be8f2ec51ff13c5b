//! A class's exponents followed from the previous point of a branch
//! (docs/design.md §10, "following"): each exponent refined from its value
//! and vector there, with no contour, while the spectrum moves little.
//!
//! Along a branch the exponents move continuously; a class's set in the
//! region changes only by an exponent crossing one of the region's edges.
//! The contour returns the region widened by [`super::near`] (half the
//! margin more on the damped side, a tenth of the strip more beyond each
//! of its edges), and that set is followed. It stays complete in the
//! region while
//! - no followed exponent near a strip edge (`|Im μ| > 0.45 g`) has moved
//!   along the imaginary axis by more than [`ALONG_THE_STRIP`] of the
//!   strip since the contour: an exponent leaving the strip by one edge
//!   enters by the other as its copy `g` away, which the widened set holds
//!   unless the exponent came from further inside;
//! - no followed exponent has moved along the real axis by more than
//!   [`TOWARD_THE_REGION`] of the gap between the region's damped side and
//!   the nearest exponent the contour saw beyond it (the spectrum's motion
//!   as the followed exponents show it, against the distance the others
//!   must cover to enter);
//! - each followed exponent converged to its own exponent (not to a
//!   neighbour's: [`closer_to_its_own`]) and stayed distinct.
//!
//! An exponent that cannot be followed alone (its first step longer than a
//! third of the way to its nearest neighbour, no convergence, or landing
//! nearer a neighbour) is followed again with every exponent within twice
//! that step, as one block ([`super::cluster`]): on the default branch's
//! plateau that is most of the classes the contour solved before (995 of
//! 1443 class solves followed instead of about 800). A cluster reaching
//! past half the strip, or within its reach of a strip edge (where it may
//! hold an exponent and its copy across the edge), is left to the contour.
//!
//! Otherwise the caller runs the contour, as it also does every
//! [`super::REFRESH`] points.

use super::cluster::followed_together;
use super::operator::ClassOperator;
use super::refine::{at_the_estimate, factor, inverse_step, with_the_same_factorization};
use super::{add, Contoured, Eigenpair, Region};
use crate::stability::vectors::normalize;
use faer::c64;
use rayon::prelude::*;
use std::collections::BTreeMap;

/// One followed exponent `μ = λ/ω`: its vector on the block's dofs, and
/// where the contour last found it.
#[derive(Clone, Debug)]
struct Followed {
    mu: c64,
    vector: Vec<c64>,
    origin: c64,
}

/// What a class's following carries from one point to the next: the
/// exponents of the widened region, how far the nearest exponent beyond
/// its damped side was when the contour last ran, and how many points ago.
#[derive(Clone, Debug, Default)]
pub struct ClassTrack {
    followed: Vec<Followed>,
    damped_gap: f64,
    age: usize,
}

impl ClassTrack {
    /// The track the contour starts.
    pub(super) fn found(contoured: Contoured) -> Self {
        Self {
            followed: contoured
                .found
                .into_iter()
                .map(|(mu, vector)| Followed {
                    mu,
                    vector,
                    origin: mu,
                })
                .collect(),
            damped_gap: contoured.damped_gap,
            age: 0,
        }
    }

    /// The exponents and their vectors.
    pub(super) fn exponents(&self) -> impl Iterator<Item = (c64, &[c64])> {
        self.followed.iter().map(|f| (f.mu, f.vector.as_slice()))
    }

    /// Points since the contour last ran.
    pub(super) fn age(&self) -> usize {
        self.age
    }

    /// How many exponents are followed.
    pub fn len(&self) -> usize {
        self.followed.len()
    }

    /// Whether none is followed.
    pub fn is_empty(&self) -> bool {
        self.followed.is_empty()
    }
}

/// What a branch's stability check carries from one point to the next:
/// the followed exponents of each class solved (by nodal diameter).
#[derive(Clone, Debug, Default)]
pub struct Following {
    classes: BTreeMap<i64, ClassTrack>,
}

impl Following {
    /// The class's track, if it has one.
    pub fn class(&self, nodal_diameter: i64) -> Option<&ClassTrack> {
        self.classes.get(&nodal_diameter)
    }

    /// Keeps a class's track.
    pub fn insert(&mut self, nodal_diameter: i64, track: ClassTrack) {
        self.classes.insert(nodal_diameter, track);
    }

    /// How many classes have a track.
    pub fn len(&self) -> usize {
        self.classes.len()
    }

    /// Whether no class has a track.
    pub fn is_empty(&self) -> bool {
        self.classes.is_empty()
    }

    /// How many classes were followed from the previous point rather than
    /// found by the contour.
    pub fn followed(&self) -> usize {
        self.classes.values().filter(|t| t.age > 0).count()
    }
}

/// The share of the strip's width an exponent near its edge may move
/// along the imaginary axis since the contour (the widening is a tenth on
/// each edge; the copies of a truncated Hill matrix are not exact).
const ALONG_THE_STRIP: f64 = 0.04;

/// Where an exponent counts as near a strip edge, in the strip's width
/// from its centre.
const NEAR_THE_EDGE: f64 = 0.45;

/// The share of the damped gap the followed exponents may move along the
/// real axis since the contour.
const TOWARD_THE_REGION: f64 = 0.25;

/// Inverse iterations at the guess's factorization.
const AT_THE_GUESS: usize = 6;

/// The step (relative to `max(1, |μ|)`) below which the iteration moves to
/// the estimate.
const CLOSE: f64 = 1e-7;

/// The class's exponents of the widened region at this point, followed
/// from `previous` (`step` the strip's width, in `ω`); `None` when the
/// following cannot vouch for them (the caller then runs the contour).
///
/// Each exponent is followed alone first; those that cannot be (a first
/// step too long for their neighbours, no convergence, landing nearer a
/// neighbour's previous value) are followed again together with every
/// previous exponent within their reach, as one block ([`cluster`]).
pub(super) fn followed(
    operator: &ClassOperator,
    previous: &ClassTrack,
    region: &Region,
    step: f64,
) -> Option<ClassTrack> {
    let _ = region;
    let before = &previous.followed;
    let mut new: Vec<Option<Eigenpair>> = vec![None; before.len()];
    let mut lost: Vec<(usize, f64)> = Vec::new();
    // Each exponent alone, in parallel (a whole wheel's class holds many).
    let alone: Vec<(f64, Result<Eigenpair, f64>)> = before
        .par_iter()
        .enumerate()
        .map(|(i, one)| {
            let nearest = before
                .iter()
                .enumerate()
                .filter(|(j, _)| *j != i)
                .map(|(_, other)| (other.mu - one.mu).norm())
                .fold(f64::INFINITY, f64::min);
            (nearest, follow(operator, one.mu, &one.vector, nearest))
        })
        .collect();
    for (i, (nearest, result)) in alone.into_iter().enumerate() {
        let one = &before[i];
        match result {
            Ok((mu, vector)) if closer_to_its_own(mu, i, before) => new[i] = Some((mu, vector)),
            Ok((mu, _)) => lost.push((i, REACH * (mu - one.mu).norm().max(nearest))),
            Err(first_step) => lost.push((i, REACH * first_step.max(nearest))),
        }
    }
    for members in clusters(before, &lost, step)? {
        let starts: Vec<(c64, &[c64])> = members
            .iter()
            .map(|&j| (before[j].mu, before[j].vector.as_slice()))
            .collect();
        let together = followed_together(operator, &starts)?;
        for (j, pair) in matched(&members, before, together) {
            new[j] = Some(pair);
        }
    }
    let mut found: Vec<Eigenpair> = Vec::with_capacity(before.len());
    let mut followed = Vec::with_capacity(before.len());
    for (one, pair) in before.iter().zip(new) {
        let (mu, vector) = pair?;
        let drift = mu - one.origin;
        let near_edge = mu.im.abs() > NEAR_THE_EDGE * step;
        if (near_edge && drift.im.abs() > ALONG_THE_STRIP * step)
            || drift.re.abs() > TOWARD_THE_REGION * previous.damped_gap
        {
            return None;
        }
        let count = found.len();
        add(&mut found, mu, vector.clone());
        if found.len() == count {
            // Two followed exponents met: the contour tells them apart.
            return None;
        }
        followed.push(Followed {
            mu,
            vector,
            origin: one.origin,
        });
    }
    Some(ClassTrack {
        followed,
        damped_gap: previous.damped_gap,
        age: previous.age + 1,
    })
}

/// How far around a lost exponent its cluster reaches, in its first step
/// (or its nearest neighbour's distance, if farther).
const REACH: f64 = 2.0;

/// A cluster reaching further than this share of the strip is left to the
/// contour.
const WIDEST: f64 = 0.5;

/// The most exponents followed as one block.
const LARGEST: usize = 16;

/// The clusters of the `lost` exponents (index, reach): every previous
/// exponent within a lost one's reach joins its cluster, and clusters that
/// share an exponent are one; `None` when one is too wide or too large.
fn clusters(before: &[Followed], lost: &[(usize, f64)], step: f64) -> Option<Vec<Vec<usize>>> {
    let mut root: Vec<usize> = (0..before.len()).collect();
    fn find(root: &mut [usize], i: usize) -> usize {
        let mut i = i;
        while root[i] != i {
            root[i] = root[root[i]];
            i = root[i];
        }
        i
    }
    let mut in_cluster = vec![false; before.len()];
    for &(i, reach) in lost {
        // Near a strip edge the cluster may hold an exponent and its copy
        // across the edge: the contour sorts those out.
        let wide = reach.is_nan() || reach > WIDEST * step;
        if wide || before[i].mu.im.abs() + reach > NEAR_THE_EDGE * step {
            return None;
        }
        for (j, other) in before.iter().enumerate() {
            if (other.mu - before[i].mu).norm() <= reach {
                in_cluster[j] = true;
                let (a, b) = (find(&mut root, i), find(&mut root, j));
                root[a] = b;
            }
        }
    }
    let mut groups: std::collections::BTreeMap<usize, Vec<usize>> = Default::default();
    for j in (0..before.len()).filter(|&j| in_cluster[j]) {
        let r = find(&mut root, j);
        groups.entry(r).or_default().push(j);
    }
    let out: Vec<Vec<usize>> = groups.into_values().collect();
    out.iter().all(|g| g.len() <= LARGEST).then_some(out)
}

/// The cluster's exponents given to its members, nearest pairs first (each
/// member keeps where the contour last found it).
fn matched(
    members: &[usize],
    before: &[Followed],
    mut together: Vec<Eigenpair>,
) -> Vec<(usize, Eigenpair)> {
    let mut left: Vec<usize> = members.to_vec();
    let mut out = Vec::with_capacity(members.len());
    while !left.is_empty() && !together.is_empty() {
        let (mut best, mut distance) = ((0, 0), f64::INFINITY);
        for (a, &j) in left.iter().enumerate() {
            for (b, (mu, _)) in together.iter().enumerate() {
                let d = (mu - before[j].mu).norm();
                if d < distance {
                    (best, distance) = ((a, b), d);
                }
            }
        }
        let j = left.swap_remove(best.0);
        out.push((j, together.swap_remove(best.1)));
    }
    out
}

/// Whether `mu`, followed from the `i`-th previous exponent, is closer to
/// it than to any other previous exponent by a factor 2 (else it may have
/// converged to a neighbour's exponent, leaving its own behind).
fn closer_to_its_own(mu: c64, i: usize, previous: &[Followed]) -> bool {
    let own = (mu - previous[i].mu).norm();
    previous
        .iter()
        .enumerate()
        .all(|(j, other)| j == i || (mu - other.mu).norm() > 2.0 * own)
}

/// One exponent refined from `(guess, start)`: inverse iteration at the
/// guess (`q ← Q(σ)⁻¹ Q'(μ) q`, the factorization at `σ` kept) with the
/// Newton step of `qᴴ Q(μ) q = 0` in `μ` until the step is small, then
/// residual inverse iteration on the same factorization to the exact pair
/// ([`with_the_same_factorization`]), or, where that does not contract,
/// Rayleigh functional iteration at the estimate itself ([`at_the_estimate`]).
/// Given up at once when the first step crosses a third of the way to the
/// `nearest` other exponent (a cluster moving faster than the points are
/// apart). The error is the first step's size (0 when there was none): how
/// far the exponent seems to have moved.
fn follow(
    operator: &ClassOperator,
    guess: c64,
    start: &[c64],
    nearest: f64,
) -> Result<Eigenpair, f64> {
    let mut q = start.to_vec();
    normalize(&mut q).ok_or(0.0)?;
    let mut mu = guess;
    let at_guess = factor(operator, guess).ok_or(0.0)?;
    let mut first = 0.0;
    let mut applied = operator.applied(&q);
    for iteration in 0..AT_THE_GUESS {
        let step = inverse_step(operator, &at_guess, &mut mu, &mut q, &mut applied).ok_or(first)?;
        if iteration == 0 {
            first = step;
            if step > nearest / 3.0 {
                return Err(first);
            }
        }
        if step <= CLOSE * mu.norm().max(1.0) {
            break;
        }
    }
    // The guess's factorization finishes it when the exponent moved little
    // (residual inverse iteration); else one at the estimate itself.
    if let Some(pair) = with_the_same_factorization(operator, &at_guess, mu, q.clone(), applied) {
        return Ok(pair);
    }
    at_the_estimate(operator, mu, q).ok_or(first)
}
