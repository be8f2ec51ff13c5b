//! Is a reduced run exact? Three independent checks against the full
//! wheel solved in physical coordinates:
//!
//! - **point by point**: every point of the reduced branch, carried over to
//!   the full wheel ([`physical_unknowns`]), is put through the full
//!   residual (how far from a full solution it is) and corrected by Newton
//!   on the full problem at the same frequency; the correction it needs,
//!   and the difference of the recovered observed dof on every sector, are
//!   the reduction's error;
//! - **curve by curve**: the independent full branch (its own continuation)
//!   must lie on the reduced one: the largest distance from a full point to
//!   the reduced polyline, sector by sector, in the plane of frequency over
//!   the swept range and amplitude over the largest amplitude;
//! - **spectrum**: at the full branch's resonance, the energy of every
//!   sector dof outside the pairs the reduced basis keeps.

use cyclorub::continuation::{correct, NewtonSettings, Problem};
use cyclorub::hbm::recovery::{dof_coordinates, physical_unknowns};
use cyclorub::hbm::{HarmonicBalance, HbmError};
use cyclorub::results::components::PairEnergies;
use cyclorub::results::ResultsError;
use cyclorub::run::HarmonicRecord;
use cyclorub::run::RunOutcome;
use serde::Serialize;

/// The point-by-point comparison of a reduced branch with the full wheel.
#[derive(Clone, Debug, Default, Serialize)]
pub struct PointByPoint {
    /// Reduced points compared (the converged ones).
    pub points: usize,
    /// The tolerance on `‖R‖ / f_ex` both solutions are brought to before
    /// they are compared (tighter than the continuation's, so that the
    /// comparison measures the reduction, not the continuation's tolerance).
    pub tight_tolerance: f64,
    /// Points where Newton on the reduced or the full problem did not
    /// reach the tight tolerance, nor the problem's round-off floor.
    pub not_converged: usize,
    /// The largest round-off floor of a point ([`round_off_floor`]): where
    /// it is above the tight tolerance, a residual below it counts as
    /// converged (a large model cannot do better).
    pub largest_round_off_floor: f64,
    /// Largest `‖R_full‖ / f_ex` of a (tightened) reduced point carried over.
    pub largest_full_residual: f64,
    /// Largest `‖x_full − x_reduced‖∞ / ‖x_reduced‖∞` over the contact unknowns.
    pub largest_unknowns_difference: f64,
    /// Largest difference of the observed dof's recovered coordinates on
    /// every sector, relative to their largest value.
    pub largest_displacement_difference: f64,
}

/// `max |a − b| / max |b|` (0 when both vanish).
fn relative_difference(a: &[f64], b: &[f64]) -> f64 {
    let scale = b.iter().fold(0.0_f64, |m, v| m.max(v.abs()));
    let difference = a
        .iter()
        .zip(b)
        .fold(0.0_f64, |m, (x, y)| m.max((x - y).abs()));
    if scale > 0.0 {
        difference / scale
    } else {
        difference
    }
}

/// The tolerance both solutions are brought to before the comparison:
/// three decades below the continuation's, but not below what round-off
/// allows.
pub fn tight_tolerance(tolerance: f64) -> f64 {
    (1e-3 * tolerance).max(1e-11)
}

/// How many times machine precision the round-off floor allows: the sums
/// behind `Z x − F` lose more than one ulp per term.
const ROUND_OFF_MARGIN: f64 = 100.0;

/// The residual `‖R‖ / force scale` that round-off alone leaves at `x`
/// (after an evaluation at the point's frequency, which sets `Z` and `F`):
/// machine ε times the size of the terms that cancel, `‖ |Z| |x| ‖ + ‖F‖`,
/// times [`ROUND_OFF_MARGIN`]. On the open fan (stiff contact nodes, 9072
/// unknowns) it is 1e-10 to 1e-9, above the fixed 1e-11 a small model
/// reaches.
pub fn round_off_floor(problem: &HarmonicBalance, x: &[f64]) -> f64 {
    let linear = problem.linear();
    let terms = linear.absolute_product_norm(problem.layout(), x);
    let load = linear.load.iter().map(|f| f * f).sum::<f64>().sqrt();
    ROUND_OFF_MARGIN * f64::EPSILON * (terms + load) / problem.force_scale()
}

/// Compares every converged point of `reduced` with the full problem
/// `full` (physical coordinates, the same case), for the sector dof
/// `observed_dof` (0-based): the reduced point is first brought to
/// [`tight_tolerance`] on its own problem, carried over, put through the
/// full residual, then corrected on the full problem to the same tolerance.
pub fn point_by_point(
    reduced: &mut RunOutcome,
    full: &mut HarmonicBalance,
    observed_dof: usize,
    newton: &NewtonSettings,
) -> Result<PointByPoint, HbmError> {
    let sectors: Vec<usize> = (0..full.layout().sectors).collect();
    let scale = full.force_scale();
    let tight = NewtonSettings {
        tolerance: tight_tolerance(newton.tolerance),
        max_iterations: newton.max_iterations.max(20),
        ..Default::default()
    };
    let mut out = PointByPoint {
        tight_tolerance: tight.tolerance,
        ..PointByPoint::default()
    };
    let mut evaluation = cyclorub::continuation::Evaluation::default();
    for point in reduced.branch.points.iter().filter(|p| p.converged) {
        let mut x = point.unknowns.clone();
        let (converged, _, reached) = correct(&mut reduced.problem, &mut x, point.omega, &tight)?;
        let floor = round_off_floor(&reduced.problem, &x);
        let reduced_converged = converged || reached <= floor;
        let carried = physical_unknowns(&reduced.problem, &x);
        full.evaluate(&carried, point.omega, false, &mut evaluation)?;
        let residual = evaluation
            .residual
            .iter()
            .map(|r| r * r)
            .sum::<f64>()
            .sqrt()
            / scale;
        let mut corrected = carried.clone();
        let (converged, _, reached) = correct(full, &mut corrected, point.omega, &tight)?;
        let full_floor = round_off_floor(full, &corrected);
        let full_converged = converged || reached <= full_floor;
        out.largest_round_off_floor = out.largest_round_off_floor.max(floor).max(full_floor);
        out.points += 1;
        if !(reduced_converged && full_converged) {
            out.not_converged += 1;
        }
        out.largest_full_residual = out.largest_full_residual.max(residual);
        out.largest_unknowns_difference = out
            .largest_unknowns_difference
            .max(relative_difference(&corrected, &carried));
        let from_reduced: Vec<f64> =
            dof_coordinates(&reduced.problem, &x, point.omega, observed_dof, &sectors)?.concat();
        let from_full: Vec<f64> =
            dof_coordinates(full, &corrected, point.omega, observed_dof, &sectors)?.concat();
        out.largest_displacement_difference = out
            .largest_displacement_difference
            .max(relative_difference(&from_reduced, &from_full));
    }
    Ok(out)
}

/// A branch as `(Hz, amplitude per sector)` points.
pub type Curve = Vec<(f64, Vec<f64>)>;

/// The distance from a point to a segment in the plane.
fn segment_distance(p: (f64, f64), a: (f64, f64), b: (f64, f64)) -> f64 {
    let (dx, dy) = (b.0 - a.0, b.1 - a.1);
    let length = dx * dx + dy * dy;
    let t = if length > 0.0 {
        (((p.0 - a.0) * dx + (p.1 - a.1) * dy) / length).clamp(0.0, 1.0)
    } else {
        0.0
    };
    let (x, y) = (a.0 + t * dx, a.1 + t * dy);
    ((p.0 - x).powi(2) + (p.1 - y).powi(2)).sqrt()
}

/// The largest distance from a point of `other` to the polyline of
/// `reference`, sector by sector, with frequencies divided by the range of
/// `reference` and amplitudes by its largest amplitude. Points of `other`
/// outside the frequency range of `reference` are left out (a branch that
/// stopped early is judged on what it has). `None` if either is empty.
pub fn curve_distance(reference: &Curve, other: &Curve) -> Option<f64> {
    let (low, high) = reference
        .iter()
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(l, h), (f, _)| {
            (l.min(*f), h.max(*f))
        });
    let amplitude = reference
        .iter()
        .flat_map(|(_, a)| a.iter())
        .fold(0.0_f64, |m, a| m.max(a.abs()));
    let sectors = reference.first()?.1.len();
    if reference.len() < 2
        || other.is_empty()
        || high.partial_cmp(&low) != Some(std::cmp::Ordering::Greater)
        || amplitude <= 0.0
    {
        return None;
    }
    let scaled = |f: f64, a: f64| ((f - low) / (high - low), a / amplitude);
    let mut largest = 0.0_f64;
    for (f, amplitudes) in other.iter().filter(|(f, _)| (low..=high).contains(f)) {
        for (j, a) in amplitudes.iter().enumerate().take(sectors) {
            let p = scaled(*f, *a);
            let nearest = reference
                .windows(2)
                .map(|w| segment_distance(p, scaled(w[0].0, w[0].1[j]), scaled(w[1].0, w[1].1[j])))
                .fold(f64::INFINITY, f64::min);
            largest = largest.max(nearest);
        }
    }
    Some(largest)
}

/// The curve of a run: frequency and the observed amplitude on every sector.
pub fn curve(outcome: &RunOutcome) -> Curve {
    outcome
        .data
        .points
        .iter()
        .filter(|p| p.converged)
        .map(|p| (p.frequency_hz, p.amplitude.clone()))
        .collect()
}

/// The pair energies of every sector dof at each converged point of a
/// run, with the point's frequency (Hz).
pub fn branch_energies(outcome: &RunOutcome) -> Result<Vec<(f64, PairEnergies)>, ResultsError> {
    let layout = outcome.problem.layout();
    let sectors: Vec<usize> = (0..layout.sectors).collect();
    let mut out = Vec::new();
    for point in outcome.branch.points.iter().filter(|p| p.converged) {
        let mut energies = PairEnergies::new(layout.sectors, layout.harmonics());
        for dof in 0..outcome.model.dofs_per_sector() {
            let field = dof_coordinates(
                &outcome.problem,
                &point.unknowns,
                point.omega,
                dof,
                &sectors,
            )?;
            energies.add_field(&field)?;
        }
        out.push((point.omega / (2.0 * std::f64::consts::PI), energies));
    }
    Ok(out)
}

/// Where a branch's energy leaves a basis.
#[derive(Clone, Debug, Default, Serialize)]
pub struct EnergyOutside {
    /// Fraction outside the basis at the branch's resonance (largest amplitude).
    pub at_resonance: f64,
    /// Largest fraction outside the basis along the branch.
    pub largest: f64,
    /// Frequency (Hz) of the first point whose fraction outside exceeds
    /// the tolerance it was judged with, if any.
    pub leaves_at_hz: Option<f64>,
}

/// The energy of a branch outside a basis: at `resonance` (an index into
/// the converged points) and along the branch, judged against `tolerance`.
pub fn energy_outside(
    energies: &[(f64, PairEnergies)],
    resonance: Option<usize>,
    basis: &[HarmonicRecord],
    tolerance: f64,
) -> EnergyOutside {
    let fractions: Vec<(f64, f64)> = energies
        .iter()
        .map(|(hz, e)| (*hz, fraction_outside(e, basis)))
        .collect();
    EnergyOutside {
        at_resonance: resonance
            .and_then(|i| fractions.get(i))
            .map_or(0.0, |(_, f)| *f),
        largest: fractions.iter().map(|(_, f)| *f).fold(0.0, f64::max),
        leaves_at_hz: fractions
            .iter()
            .find(|(_, f)| *f > tolerance)
            .map(|(hz, _)| *hz),
    }
}

/// The fraction of `energies` outside the pairs of a basis (as `run.json`
/// lists them, harmonic by harmonic).
pub fn fraction_outside(energies: &PairEnergies, basis: &[HarmonicRecord]) -> f64 {
    let total = energies.total();
    if total <= 0.0 {
        return 0.0;
    }
    let outside = energies.outside(|k, s| {
        basis
            .get(k)
            .is_some_and(|h| h.signed_nodal_diameters.contains(&s))
    });
    outside / total
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_curve_is_at_distance_zero_from_itself_and_a_shift_is_seen() {
        let reference: Curve = (0..50)
            .map(|i| {
                let f = 100.0 + i as f64;
                (f, vec![(-(f - 125.0).powi(2) / 100.0).exp(), 0.5])
            })
            .collect();
        // Points on the reference's segments are at distance 0.
        let midpoints: Curve = reference
            .windows(2)
            .map(|w| {
                (
                    0.5 * (w[0].0 + w[1].0),
                    vec![0.5 * (w[0].1[0] + w[1].1[0]), 0.5],
                )
            })
            .collect();
        assert!(curve_distance(&reference, &midpoints).unwrap() < 1e-15);
        // One sector shifted up by 1 % of the largest amplitude.
        let shifted: Curve = reference
            .iter()
            .map(|(f, a)| (*f, vec![a[0], a[1] + 0.01]))
            .collect();
        let d = curve_distance(&reference, &shifted).unwrap();
        assert!((d - 0.01).abs() < 1e-12, "{d}");
        assert!(curve_distance(&reference, &Vec::new()).is_none());
    }

    #[test]
    fn relative_difference_is_scaled_by_the_reference() {
        assert!((relative_difference(&[1.0, 2.0], &[1.0, 4.0]) - 0.5).abs() < 1e-15);
        assert!(relative_difference(&[0.0], &[0.0]).abs() < 1e-300);
    }
}
