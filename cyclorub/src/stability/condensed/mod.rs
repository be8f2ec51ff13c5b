//! Hill's exponents of one class without its dense eigenproblem: the
//! condensed Hill method (docs/design.md §10).
//!
//! A class's Hill problem is the linear wheel, one dynamic stiffness per
//! pair, plus the contact, which couples the pairs on the contact dofs
//! alone ([`operator`]). Its exponents seen from the contact are the poles
//! of the contact resolvent `P Q(μ)⁻¹ Pᵀ`, found inside an ellipse by a
//! contour integral ([`contour`]) and refined on `Q` ([`refine`]); an
//! exponent the contact does not see (a mode at rest at the contact dofs)
//! is an exponent of the linear wheel, refined from it.
//!
//! What is returned is every exponent of the class in the [`Region`]: the
//! strip `Im λ ∈ (−gω/2, gω/2]` (`g` the class's harmonic step: every
//! Floquet multiplier of the wheel has one exponent there in exactly one
//! class) with `Re λ ≥ −margin·ω`. The classes together hold each
//! multiplier of modulus above `e^{−2π·margin}` once. Multipliers are what
//! stability reads; the representative differs from the dense pick's
//! (the copy whose eigenvector is centred on harmonic 0), not the
//! multiplier, and a real crossing is found at `λ = 0` in the class of its
//! periodic perturbation.

mod cluster;
mod contour;
mod follow;
mod low_rank;
mod operator;
mod refine;

pub use follow::{ClassTrack, Following};

use super::hill::{group_offsets, hill_matrix, Group, Picked};
use super::StabilityError;
use crate::stability::vectors::{dot, norm, normalize};
use contour::{drawn, Ellipse};
use faer::c64;
use operator::ClassOperator;
use refine::refine;

/// Where a class's exponents are sought, in units of `ω`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Region {
    /// Exponents with `Re λ ≥ −margin · ω` are returned (their multipliers
    /// have modulus above `e^{−2π·margin}`).
    pub margin: f64,
    /// The growth the contour is drawn for, `Re λ ≤ upper · ω` (a
    /// multiplier up to `e^{2π·upper}` per period): an exponent found
    /// beyond it sends the class to the dense eigenproblem, which has no
    /// such bound.
    pub upper: f64,
}

impl Default for Region {
    fn default() -> Self {
        Self {
            margin: 0.05,
            upper: 0.5,
        }
    }
}

impl Region {
    /// Whether `mu = λ/ω` lies in the region for harmonic step `step`
    /// (any growth: `upper` bounds the contour, not what is returned).
    pub fn holds(&self, mu: c64, step: f64) -> bool {
        let half = 0.5 * step;
        mu.re >= -self.margin && mu.im > -half && mu.im <= half
    }
}

/// Quadrature nodes on the contour.
const NODES: usize = 48;

/// Quadrature nodes on the contour where the Schur complement on the
/// contact positions is at least [`MANY_POSITIONS`] wide (its positions,
/// or the contact's rank where it is compressed): a node's dense LU of it
/// then costs more than the refinements that fewer nodes' coarser
/// estimates need (the fan's 150-point branch at its point 149, 567
/// positions not compressed: 10.7 → 7.6 s of CPU for its nine classes, the
/// same exponents; the default case's sizes at 80 harmonics, 161
/// positions: 1.72 → 1.46 s). Below it the refinements cost more than the
/// nodes saved (`n24-standing-h4`, 63 positions: its check 7.2 → 8.5 s
/// with 32 nodes).
const FEW_NODES: usize = 32;

/// See [`FEW_NODES`].
const MANY_POSITIONS: usize = 128;

/// The exponents of one class's block in `region`, largest real part
/// first: `groups` one per pair, `coupling` and `damping` the contact's
/// stiffness and velocity terms between their dofs (as
/// `hill::physical_exponents` takes them), `step` the harmonic step.
/// Falls back on the dense eigenproblem of the block (said in the log)
/// when a refinement does not confirm the contour's estimates.
pub fn region_exponents(
    groups: &[Group],
    coupling: &[(usize, usize, c64)],
    damping: &[(usize, usize, c64)],
    omega: f64,
    step: i64,
    region: &Region,
) -> Result<Vec<Picked>, StabilityError> {
    followed_exponents(groups, coupling, damping, omega, step, region, None)
        .map(|(picked, _)| picked)
}

/// [`region_exponents`], followed from the class's exponents at the
/// previous point of a branch when `previous` holds them and the following
/// vouches for the result ([`follow`]), by the contour otherwise; with
/// what the next point can follow from (`None` after a dense fallback).
pub fn followed_exponents(
    groups: &[Group],
    coupling: &[(usize, usize, c64)],
    damping: &[(usize, usize, c64)],
    omega: f64,
    step: i64,
    region: &Region,
    previous: Option<&ClassTrack>,
) -> Result<(Vec<Picked>, Option<ClassTrack>), StabilityError> {
    let step = step.max(1) as f64;
    let Some(operator) = ClassOperator::new(groups, coupling, damping, omega) else {
        let picked = dense_in_region(groups, coupling, damping, omega, step, region)?;
        return Ok((picked, None));
    };
    let tracked = previous
        .filter(|p| p.age() + 1 < REFRESH)
        .and_then(|p| follow::followed(&operator, p, region, step));
    let track = match tracked {
        Some(track) => Some(track),
        None => condensed(&operator, omega, step, region)?.map(ClassTrack::found),
    };
    match track {
        Some(track) => {
            let inside = track
                .exponents()
                .filter(|(mu, _)| region.holds(*mu, step))
                .map(|(mu, q)| (mu, q.to_vec()))
                .collect();
            Ok((picked(&operator, inside, omega, step), Some(track)))
        }
        None => {
            tracing::debug!(
                "condensed Hill could not confirm a class's exponents at {:.6} Hz: solved densely",
                omega / (2.0 * std::f64::consts::PI)
            );
            let picked = dense_in_region(groups, coupling, damping, omega, step, region)?;
            Ok((picked, None))
        }
    }
}

/// The class's exponent (`μ = λ/ω`) nearest to `guess`, refined from it
/// by Rayleigh functional iteration ([`refine`]) as the following does
/// (docs/design.md §10), from `start` (its vector at a nearby point of the
/// branch, on the block's dofs) or else from a fixed vector purified by
/// inverse iteration at the guess: one exponent followed, without the
/// contour (what locating a marker asks at each trial point). `None` when
/// the block does not condense or the refinement does not converge.
pub fn exponent_near(
    groups: &[Group],
    coupling: &[(usize, usize, c64)],
    damping: &[(usize, usize, c64)],
    omega: f64,
    guess: c64,
    start: Option<&[c64]>,
) -> Option<(c64, Vec<c64>)> {
    let operator = ClassOperator::new(groups, coupling, damping, omega)?;
    let n = operator.dofs();
    let start = match start {
        Some(s) if s.len() == n => s.to_vec(),
        _ => {
            let mut q: Vec<c64> = (0..n)
                .map(|i| c64::new(1.0 + 0.1 * ((i * 7919) % 13) as f64, 0.1 * (i % 7) as f64))
                .collect();
            let at_guess = operator.factor(guess).or_else(|| {
                operator.factor(guess + c64::new(1e-14, 1e-14) * guess.norm().max(1.0))
            })?;
            for _ in 0..PURIFYING_FROM_NOTHING {
                let (_, slope) = operator.times(guess, &q);
                q = operator.solve(&at_guess, &slope);
                normalize(&mut q)?;
            }
            q
        }
    };
    refine::refine(&operator, guess, start)
}

/// Inverse iterations at the guess that purify [`exponent_near`]'s fixed
/// start vector.
const PURIFYING_FROM_NOTHING: usize = 6;

/// The region widened by half its margin on the damped side and a tenth
/// of the strip on each edge: what the contour returns, and what a branch
/// follows, so that an exponent entering the region was followed before.
fn near(region: &Region) -> Region {
    Region {
        margin: 1.5 * region.margin,
        upper: region.upper,
    }
}

/// A class's exponents are found by the contour at least every this many
/// points of a branch, followed in between.
const REFRESH: usize = 16;

/// The strip's widening in [`near`].
const NEAR_STEP: f64 = 1.1;

/// An exponent `μ = λ/ω` with its vector on the block's dofs.
type Eigenpair = (c64, Vec<c64>);

/// The condensed method: the exponents of the widened region ([`near`]);
/// `None` when its estimates are not all confirmed.
fn condensed(
    operator: &ClassOperator,
    omega: f64,
    step: f64,
    region: &Region,
) -> Result<Option<Contoured>, StabilityError> {
    let poles = linear_poles(operator, omega)?;
    let ellipse = contour_for(&poles, step, region);
    let inside = poles
        .iter()
        .filter(|(p, _)| ellipse.level(*p) < 1.0)
        .count();
    // Room for half as many poles again as the linear wheel has inside,
    // probed by every contact position where they are few (high moments
    // with fewer probes amplify the quadrature's noise, measured on the
    // default case), by twice the room where they are many (the fan's 567:
    // the node's LU then solves for a few columns, not the inverse).
    let r = operator.positions().max(1);
    let capacity = (3 * inside).div_ceil(2) + 8;
    let probes = if r <= 2 * capacity { r } else { 2 * capacity };
    tracing::trace!(
        "contour: {r} contact positions (contact of rank {:?}), {probes} probes",
        operator.contact_rank()
    );
    let moments = capacity.div_ceil(probes).max(MOMENTS);
    // A node's cost is the Schur complement's LU: `r` wide, or the
    // contact's rank where it is compressed.
    let schur = operator.contact_rank().unwrap_or(r);
    let nodes = if schur >= MANY_POSITIONS {
        FEW_NODES
    } else {
        NODES
    };
    // The argument principle: the exponents of Q inside the ellipse are
    // det S's winding plus the linear wheel's poles inside. The contour
    // must account for them (those the contact barely sees are refined
    // from their own exponent below); fewer means one was missed: the
    // contour is drawn again with twice the nodes and one more moment
    // (exponents near it, or more than the moments resolve), and where it
    // still misses one the class is solved densely.
    let unseen = poles
        .iter()
        .filter(|(p, mode)| ellipse.level(*p) < 1.0 && operator.contact_share(mode) <= UNSEEN)
        .count();
    let Some(contour) = drawn(operator, &ellipse, nodes, moments, probes, inside, unseen) else {
        return Ok(None);
    };
    let estimates = contour.estimates;
    let mut found: Vec<(c64, Vec<c64>)> = Vec::new();
    // Only the estimates in (or next to) the region are worth refining.
    let near = near(region);
    // How far the nearest exponent left out on the damped side is from
    // the region (the contour sees the ellipse, far beyond it).
    let damped_gap = estimates
        .iter()
        .map(|(mu, _)| mu)
        .filter(|mu| ellipse.level(**mu) <= 1.0 && mu.re < -near.margin)
        .map(|mu| -region.margin - mu.re)
        .fold(ellipse.real_axis - region.margin, f64::min);
    for (guess, contact_vector) in &estimates {
        if ellipse.level(*guess) > 1.0 || !near.holds(*guess, NEAR_STEP * step) {
            continue;
        }
        // Growth beyond what the contour was drawn for: it may have missed
        // faster exponents.
        if guess.re > region.upper {
            tracing::debug!("unconfirmed: {guess} grows beyond the contour's bound");
            return Ok(None);
        }
        let Some(start) = operator
            .eigenvector_of_contact(*guess, contact_vector)
            .or_else(|| {
                operator
                    .factor(*guess + c64::new(1e-12, 1e-12))
                    .map(|f| operator.lift(&f, contact_vector))
            })
        else {
            continue;
        };
        if let Some((mu, q)) = accurate(operator, *guess, &start) {
            add(&mut found, mu, q);
            continue;
        }
        let Some((mu, q)) = refine(operator, *guess, start) else {
            // An estimate in the region that may grow must be an exponent.
            if in_play(*guess, step, region) {
                tracing::debug!("unconfirmed: {guess} did not converge");
                return Ok(None);
            }
            continue;
        };
        // A refinement that lands far from its estimate, from inside the
        // region, may have left an exponent behind.
        if in_play(*guess, step, region) && (mu - guess).norm() > CONFIRMED {
            tracing::debug!("unconfirmed: {guess} went to {mu}");
            return Ok(None);
        }
        add(&mut found, mu, q);
    }
    // The exponents the contact barely sees (the contour's rank test drops
    // their tiny residues): the linear wheel's, refined.
    for (pole, mode) in &poles {
        if !near.holds(*pole, NEAR_STEP * step) || operator.contact_share(mode) > UNSEEN {
            continue;
        }
        let close = 1e-8 * pole.norm().max(1.0);
        if found.iter().any(|(mu, _)| (mu - pole).norm() < close) {
            continue;
        }
        if let Some((mu, q)) = refine(operator, *pole, mode.clone()) {
            add(&mut found, mu, q);
        }
    }
    found.retain(|(mu, _)| near.holds(*mu, NEAR_STEP * step));
    if found.iter().any(|(mu, _)| mu.re > region.upper) {
        tracing::debug!("an exponent grows beyond the contour's bound");
        return Ok(None);
    }
    Ok(Some(Contoured { found, damped_gap }))
}

/// What the contour found: the exponents of the widened region, and how
/// far (in `ω`) the nearest exponent it saw beyond the region's damped
/// side lies from that side.
struct Contoured {
    found: Vec<Eigenpair>,
    damped_gap: f64,
}

/// The contour's estimate after one Newton step on its vector, when that
/// leaves a residual at round-off (no factorization: the contour's
/// estimates are that accurate away from its edge).
fn accurate(operator: &ClassOperator, guess: c64, start: &[c64]) -> Option<(c64, Vec<c64>)> {
    let mut q = start.to_vec();
    normalize(&mut q)?;
    let (value, slope) = operator.times(guess, &q);
    let denominator = dot(&q, &slope);
    if denominator.norm() <= 0.0 || denominator.norm().is_nan() {
        return None;
    }
    let mu = guess - dot(&q, &value) / denominator;
    let (value, scale) = operator.residual(mu, &q);
    (norm(&value) <= ACCURATE * scale).then_some((mu, q))
}

/// The residual `‖Q(μ) q‖` (relative to its terms) of an estimate taken as
/// it is.
pub(super) const ACCURATE: f64 = 1e-9;

/// A linear mode with less than this share of its norm on the contact
/// positions is refined from its own exponent: the resolvent's residue
/// there (the square of the share) is below the contour's rank threshold.
const UNSEEN: f64 = 1e-3;

/// The fewest block moments of the contour.
const MOMENTS: usize = 2;

/// How far (in `ω`) a refinement may move an estimate of the region: the
/// contour's estimates are far closer than this.
const CONFIRMED: f64 = 1e-3;

/// Whether an estimate lies in the region away from its damped side (an
/// unconfirmed estimate there could be a growing exponent left behind;
/// on the damped side it cannot change a verdict).
fn in_play(mu: c64, step: f64, region: &Region) -> bool {
    mu.re > -0.5 * region.margin && mu.im.abs() <= 0.5 * step
}

/// The ellipse around the region, its imaginary axis placed between the
/// linear exponents (where the moved ones are least likely to sit).
fn contour_for(poles: &[(c64, Vec<c64>)], step: f64, region: &Region) -> Ellipse {
    let real_axis = 1.05 * std::f64::consts::SQRT_2 * region.margin.max(region.upper);
    let near_axis: Vec<f64> = poles
        .iter()
        .filter(|(p, _)| p.re.abs() < 0.5 * real_axis)
        .map(|(p, _)| p.im.abs())
        .collect();
    let candidates = (0..=24).map(|i| step * (0.75 + 0.25 * i as f64 / 24.0));
    let imaginary_axis = candidates
        .map(|b| {
            let gap = near_axis
                .iter()
                .map(|y| (y - b).abs())
                .fold(f64::INFINITY, f64::min);
            (b, gap)
        })
        .max_by(|x, y| x.1.total_cmp(&y.1))
        .map_or(0.875 * step, |(b, _)| b);
    Ellipse {
        centre: 0.0,
        real_axis,
        imaginary_axis,
    }
}

/// Every group's linear exponents `μ = p/ω − ik` with their modes on the
/// block's dofs.
fn linear_poles(
    operator: &ClassOperator,
    omega: f64,
) -> Result<Vec<(c64, Vec<c64>)>, StabilityError> {
    let mut out = Vec::new();
    for (g, &offset) in operator.groups().iter().zip(operator.offsets()) {
        let shift = c64::new(0.0, g.harmonic as f64);
        for (p, mode) in g.dynamics.exponents()? {
            let mut full = vec![c64::new(0.0, 0.0); operator.dofs()];
            full[offset..offset + mode.len()].copy_from_slice(mode);
            out.push((p / omega - shift, full));
        }
    }
    Ok(out)
}

/// Adds an exponent unless found already: a vector in the span of those
/// found at the same value (a double exponent holds as many as it has
/// independent vectors).
fn add(found: &mut Vec<(c64, Vec<c64>)>, value: c64, vector: Vec<c64>) {
    let close = 1e-8 * value.norm().max(1.0);
    let mut span: Vec<Vec<c64>> = Vec::new();
    for (v, x) in found.iter() {
        if (v - value).norm() < close {
            let mut q = x.clone();
            for b in &span {
                let h = dot(b, &q);
                q.iter_mut().zip(b).for_each(|(z, y)| *z -= h * y);
            }
            if normalize(&mut q).is_some() {
                span.push(q);
            }
        }
    }
    let mut rest = vector.clone();
    for _ in 0..2 {
        for b in &span {
            let h = dot(b, &rest);
            rest.iter_mut().zip(b).for_each(|(z, y)| *z -= h * y);
        }
    }
    if norm(&rest) > 0.1 * norm(&vector) {
        found.push((value, vector));
    }
}

/// The found exponents (rad/s) with their centres and edge shares, largest
/// real part first.
fn picked(
    operator: &ClassOperator,
    found: Vec<(c64, Vec<c64>)>,
    omega: f64,
    step: f64,
) -> Vec<Picked> {
    let groups = operator.groups();
    let offsets = operator.offsets();
    let mut out: Vec<Picked> = found
        .into_iter()
        .map(|(mu, q)| {
            let (centre, edge) = centre_and_edge(groups, offsets, &q, step);
            Picked {
                exponent: mu * omega,
                centre,
                edge,
            }
        })
        .collect();
    out.sort_by(|p, q| q.exponent.re.total_cmp(&p.exponent.re));
    out
}

/// The signed mean harmonic (in steps) of a displacement vector over the
/// groups, and its share on the highest harmonics.
fn centre_and_edge(groups: &[Group], offsets: &[usize], q: &[c64], step: f64) -> (f64, f64) {
    let highest = groups.iter().map(|g| g.harmonic.abs()).max().unwrap_or(0);
    let (mut total, mut moment, mut edge) = (0.0, 0.0, 0.0);
    for (g, &o) in groups.iter().zip(offsets) {
        let weight: f64 = q[o..o + g.dynamics.dofs()]
            .iter()
            .map(|z| z.norm_sqr())
            .sum();
        total += weight;
        moment += weight * g.harmonic as f64 / step;
        if highest > 0 && g.harmonic.abs() == highest {
            edge += weight;
        }
    }
    let total = total.max(f64::MIN_POSITIVE);
    (moment / total, edge / total)
}

/// The linear wheel's exponents of a class in `region` (no contact): at a
/// point of weak contact, within the off-contact bound of the class's own.
pub fn linear_in_region(
    groups: &[Group],
    omega: f64,
    step: f64,
    region: &Region,
) -> Result<Vec<Picked>, StabilityError> {
    let highest = groups.iter().map(|g| g.harmonic.abs()).max().unwrap_or(0);
    let mut out = Vec::new();
    for g in groups {
        let shift = c64::new(0.0, g.harmonic as f64);
        for (p, _) in g.dynamics.exponents()? {
            let mu = p / omega - shift;
            if !region.holds(mu, step) {
                continue;
            }
            // Each mode lives on its own pair: centred there.
            let on_edge = highest > 0 && g.harmonic.abs() == highest;
            out.push(Picked {
                exponent: mu * omega,
                centre: g.harmonic as f64 / step,
                edge: if on_edge { 1.0 } else { 0.0 },
            });
        }
    }
    out.sort_by(|p, q| q.exponent.re.total_cmp(&p.exponent.re));
    Ok(out)
}

/// Every eigenvalue of the block's dense Hill matrix in `region`: the
/// fallback, and the oracle of the tests.
pub fn dense_in_region(
    groups: &[Group],
    coupling: &[(usize, usize, c64)],
    damping: &[(usize, usize, c64)],
    omega: f64,
    step: f64,
    region: &Region,
) -> Result<Vec<Picked>, StabilityError> {
    let (offsets, m) = group_offsets(groups);
    let a = hill_matrix(groups, coupling, damping, omega);
    let eigen = a.eigen().map_err(|e| StabilityError::Eigen {
        message: format!("{e:?}"),
    })?;
    let mut out = Vec::new();
    for i in 0..2 * m {
        let mu = eigen.S()[i];
        if !(mu.re.is_finite() && mu.im.is_finite()) {
            return Err(StabilityError::Eigen {
                message: "the eigenvalue solver returned values that are not finite".into(),
            });
        }
        if !region.holds(mu, step) {
            continue;
        }
        let q: Vec<c64> = (0..m).map(|r| eigen.U()[(r, i)]).collect();
        let (centre, edge) = centre_and_edge(groups, &offsets, &q, step);
        out.push(Picked {
            exponent: mu * omega,
            centre,
            edge,
        });
    }
    out.sort_by(|p, q| q.exponent.re.total_cmp(&p.exponent.re));
    Ok(out)
}

#[cfg(test)]
mod tests;
