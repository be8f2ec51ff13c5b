//! The linearized contact force of a converged point, sector by sector and
//! instant by instant, and its Fourier coefficients in time and in space.
//!
//! The normal force adds to each contact dof the stiffness its law gives
//! ([`ContactLaw::linearized_stiffness`](crate::contact::ContactLaw)).
//! Sliding friction (Eqs. 83–84) adds, at each friction node, the
//! linearization of `μ f_N t(w)`, `t = w/|w|`, `w = (v_θ + ρΩ, v_z)`: a
//! stiffness `μ k_N t` from the normal dof onto the tangential ones, and a
//! damping `μ f_N ∂t/∂w` between the tangential velocities (the perturbation
//! leaves `ω`, hence `Ω`, unchanged). Each is a [`ContactTerm`].

use super::StabilityError;
use crate::contact::sliding_direction;
use crate::hbm::aft::{derivative_coordinates, Aft};
use crate::hbm::recovery::wall_coordinates;
use crate::hbm::sector_shifts::sector_sources;
use crate::hbm::{HarmonicBalance, HarmonicSet};
use faer::c64;
use std::f64::consts::PI;

/// What a linearized contact term multiplies.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum TermKind {
    /// The column dof's displacement (N/m).
    Stiffness,
    /// The column dof's velocity (N·s/m).
    Damping,
}

/// One term of the linearized contact force: the force on contact dof
/// `row` from contact dof `column` (positions in the problem's contact dof
/// list: the normal dofs, then with friction each node's circumferential
/// and axial dofs).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct ContactTerm {
    /// The contact dof the force acts on.
    pub row: usize,
    /// The contact dof it depends on.
    pub column: usize,
    /// Through its displacement or its velocity.
    pub kind: TermKind,
}

/// The linearized contact terms `d_{j,t}(τ_n)` of every sector `j` and term
/// `t` at the instants `τ_n = 2π n / N_t` of one period.
#[derive(Clone, Debug)]
pub struct ContactStiffness {
    sectors: usize,
    terms: Vec<ContactTerm>,
    time_samples: usize,
    /// `[(i · terms + t) · N_t + n]` of the `i`-th sampled sector (those
    /// without a source), N/m or N·s/m.
    samples: Vec<f64>,
    /// Each sector's position among the sampled ones, or its source's.
    rows: Vec<usize>,
    /// For each sector, the earlier sector whose samples it repeats and
    /// the rotation (see [`sector_sources`]).
    sources: Vec<Option<(usize, usize)>>,
    /// A transform planned on the samples' instants.
    transform: Aft,
    /// The largest normal stiffness at any instant, N/m.
    peak: f64,
}

/// What sampling a point's contact stiffness needs that does not depend on
/// the point: the casing's gap at every instant on every sector, and which
/// sectors repeat an earlier one's samples ([`sector_sources`]). Built once
/// per stability check and reused at every point and trial point.
#[derive(Clone, Debug)]
pub struct SectorSampling {
    time_samples: usize,
    /// `[j · normal + c]`: the gap of normal contact dof `c` on sector `j`.
    gaps: Vec<Vec<f64>>,
    sources: Vec<Option<(usize, usize)>>,
    /// The time transform of the problem's harmonics on these instants,
    /// planned once.
    transform: Aft,
}

impl SectorSampling {
    /// The plan of `problem`'s sectors at `time_samples` instants a period;
    /// `repeat`: find the sectors that repeat an earlier one (false: every
    /// sector is sampled, the reference in tests).
    pub fn new(problem: &HarmonicBalance, time_samples: usize, repeat: bool) -> Self {
        let layout = problem.layout();
        let (n, normal) = (layout.sectors, problem.normal_dofs());
        let gaps: Vec<Vec<f64>> = (0..n)
            .flat_map(|j| (0..normal).map(move |c| (j, c)))
            .map(|(j, c)| problem.casing().gap_samples(n, j, c, time_samples))
            .collect();
        let sources = if repeat {
            sector_sources(layout, time_samples, &gaps)
        } else {
            vec![None; n]
        };
        Self {
            time_samples,
            gaps,
            sources,
            transform: Aft::for_set(layout.harmonic_set, time_samples),
        }
    }

    /// Instants per period.
    pub fn time_samples(&self) -> usize {
        self.time_samples
    }

    /// How many sectors are sampled (the others are rotations of them).
    pub fn sampled_sectors(&self) -> usize {
        self.sources.iter().filter(|s| s.is_none()).count()
    }
}

impl ContactStiffness {
    /// Samples the law at `(x, omega)` on every sector, `time_samples`
    /// instants per period (`time_samples > 2 N_h`), with the friction of
    /// `problem`, if any. A sector that repeats an earlier one's motion
    /// and gap a whole number of samples later (a traveling wave's
    /// sectors: [`sector_sources`]) gets that sector's samples rotated,
    /// not sampled again.
    pub fn sample(
        problem: &HarmonicBalance,
        x: &[f64],
        omega: f64,
        time_samples: usize,
    ) -> Result<Self, StabilityError> {
        let plan = SectorSampling::new(problem, time_samples, true);
        Self::sample_with(problem, &plan, x, omega)
    }

    /// [`Self::sample`] on a prepared `plan` (of the same `problem`).
    pub fn sample_with(
        problem: &HarmonicBalance,
        plan: &SectorSampling,
        x: &[f64],
        omega: f64,
    ) -> Result<Self, StabilityError> {
        let layout = problem.layout();
        let time_samples = plan.time_samples;
        let (n, normal) = (layout.sectors, problem.normal_dofs());
        let law = problem.law();
        let friction = problem.friction();
        let read = if law.input().reads_residual() {
            problem.law_variable(x, omega)?
        } else {
            x.to_vec()
        };
        let terms = contact_terms(normal, friction.is_some());
        let per_node = terms.len() / normal;
        let (gaps, sources) = (&plan.gaps, &plan.sources);
        // Only the sectors that repeat no earlier one are read and sampled.
        let sectors: Vec<usize> = (0..n).filter(|&j| sources[j].is_none()).collect();
        let mut solution = plan.transform.with_set(layout.harmonic_set);
        let mut reading = vec![0.0; time_samples];
        let mut force = vec![0.0; time_samples];
        let mut slope = vec![0.0; time_samples];
        let mut rates = [vec![0.0; time_samples], vec![0.0; time_samples]];
        let mut derivative = vec![0.0; layout.coordinates()];
        let mut samples = vec![0.0; sectors.len() * terms.len() * time_samples];
        let mut peak = 0.0_f64;
        for contact in 0..normal {
            let per_sector = wall_coordinates(problem, &read, contact, &sectors);
            // The node's tangential displacements, with friction.
            let tangential = friction.map(|_| {
                let theta = normal + 2 * contact;
                [
                    wall_coordinates(problem, x, theta, &sectors),
                    wall_coordinates(problem, x, theta + 1, &sectors),
                ]
            });
            for (index, (&j, coordinates)) in sectors.iter().zip(&per_sector).enumerate() {
                let gap = &gaps[j * normal + contact];
                solution.to_time(coordinates, &mut reading);
                law.apply(&reading, gap, &mut force, Some(&mut slope), None);
                let at = |t: usize, i: usize| {
                    ((index * terms.len() + contact * per_node + t) * time_samples) + i
                };
                for i in 0..time_samples {
                    let stiffness = law.linearized_stiffness(slope[i]);
                    peak = peak.max(stiffness.abs());
                    samples[at(0, i)] = stiffness;
                }
                let (Some(friction), Some(tangential)) = (friction, &tangential) else {
                    continue;
                };
                for (rate, signal) in rates.iter_mut().zip(tangential) {
                    derivative_coordinates(&signal[index], &mut derivative);
                    solution.to_time(&derivative, rate);
                }
                let mu = friction.coefficient();
                let sliding = friction.nodes()[contact].radius * friction.speed().at(omega);
                for i in 0..time_samples {
                    let w = [omega * rates[0][i] + sliding, omega * rates[1][i]];
                    let (t, dt) = sliding_direction(w[0], w[1]);
                    let stiffness = samples[at(0, i)];
                    let values = [
                        mu * stiffness * t[0],
                        mu * stiffness * t[1],
                        mu * force[i] * dt[0][0],
                        mu * force[i] * dt[0][1],
                        mu * force[i] * dt[1][0],
                        mu * force[i] * dt[1][1],
                    ];
                    for (t, value) in values.into_iter().enumerate() {
                        samples[at(1 + t, i)] = value;
                    }
                }
            }
        }
        // A repeating sector's samples are its source's, rotated (see
        // `spectrum`): only the sampled sectors are stored.
        let mut rows = vec![0; n];
        for j in 0..n {
            rows[j] = match sources[j] {
                Some((from, _)) => rows[from],
                None => sectors.partition_point(|&s| s < j),
            };
        }
        if !peak.is_finite() || samples.iter().any(|s| !s.is_finite()) {
            return Err(StabilityError::NotFinite {
                what: "the contact stiffness",
                frequency_hz: omega / (2.0 * PI),
            });
        }
        Ok(Self {
            sectors: n,
            terms,
            time_samples,
            samples,
            rows,
            transform: solution,
            sources: sources.clone(),
            peak,
        })
    }

    /// The terms, in the order of their samples.
    pub fn terms(&self) -> &[ContactTerm] {
        &self.terms
    }

    /// The largest normal contact stiffness at any instant on any sector,
    /// N/m.
    pub fn peak(&self) -> f64 {
        self.peak
    }

    /// Whether every term is zero at every instant on every sector (the
    /// casing is not touched: with friction too, the linearized contact
    /// vanishes and the wheel's exponents are the linear wheel's).
    pub fn vanishes(&self) -> bool {
        self.samples.iter().all(|&s| s == 0.0)
    }

    /// The time-Fourier coefficients up to harmonic `highest`
    /// (`N_t > 2 · highest`).
    pub fn spectrum(&self, highest: usize) -> StiffnessSpectrum {
        let mut transform = self.transform.with_set(HarmonicSet::up_to(highest));
        let mut real = vec![0.0; 2 * highest + 1];
        let signals = self.sectors * self.terms.len();
        let mut coefficients = vec![c64::new(0.0, 0.0); signals * (highest + 1)];
        let (terms, width) = (self.terms.len(), highest + 1);
        for signal in 0..signals {
            let offset = signal * width;
            let (sector, term) = (signal / terms, signal % terms);
            if let Some((from, r)) = self.sources[sector] {
                // d_j(τ) = d_from(τ + 2πr/N_t): d̂_j(m) = d̂_from(m) e^{i m 2π r/N_t}.
                let angle = 2.0 * PI * r as f64 / self.time_samples as f64;
                let at = (from * terms + term) * width;
                let turn = c64::cis(angle);
                let mut factor = c64::new(1.0, 0.0);
                for m in 0..=highest {
                    coefficients[offset + m] = coefficients[at + m] * factor;
                    factor *= turn;
                }
                continue;
            }
            let start = (self.rows[sector] * terms + term) * self.time_samples;
            transform.to_frequency(&self.samples[start..start + self.time_samples], &mut real);
            coefficients[offset] = c64::new(real[0], 0.0);
            for m in 1..=highest {
                coefficients[offset + m] = c64::new(real[2 * m - 1], real[2 * m]);
            }
        }
        StiffnessSpectrum {
            sectors: self.sectors,
            terms: self.terms.clone(),
            highest,
            coefficients,
        }
    }
}

/// The time-Fourier coefficients `d̂_{j,t}(m)`, `|m| ≤ highest`, of the
/// linearized contact terms: `d_{j,t}(τ) = Σ_m d̂_{j,t}(m) e^{imτ}`,
/// `d̂(−m) = conj d̂(m)`.
#[derive(Clone, Debug)]
pub struct StiffnessSpectrum {
    sectors: usize,
    terms: Vec<ContactTerm>,
    highest: usize,
    /// `[(j · terms + t) · (highest + 1) + m]`.
    coefficients: Vec<c64>,
}

impl StiffnessSpectrum {
    /// The terms, in the order of their coefficients.
    pub fn terms(&self) -> &[ContactTerm] {
        &self.terms
    }

    /// `d̂_{j,t}(m)` of sector `j` and term `t` for any `m` (0 beyond
    /// `highest`).
    pub fn sector_coefficient(&self, sector: usize, term: usize, harmonic: i64) -> c64 {
        let m = harmonic.unsigned_abs() as usize;
        if m > self.highest {
            return c64::new(0.0, 0.0);
        }
        let value = self.coefficients[(sector * self.terms.len() + term) * (self.highest + 1) + m];
        if harmonic < 0 {
            value.conj()
        } else {
            value
        }
    }

    /// The space-time coefficients `D̂_t(r, m) = (1/N) Σ_j e^{i r α j}
    /// d̂_{j,t}(m)` of every `r ∈ 0..N` and `|m| ≤ highest`: the coupling
    /// of the perturbation pair `(s, k)` into `(s + r, k + m)` by term `t`.
    pub fn space_time_table(&self) -> SpaceTimeTable {
        let (n, h) = (self.sectors, self.highest as i64);
        let width = (2 * h + 1) as usize;
        let alpha = 2.0 * PI / n as f64;
        let roots: Vec<c64> = (0..n).map(|p| c64::cis(p as f64 * alpha)).collect();
        let mut table = vec![c64::new(0.0, 0.0); self.terms.len() * n * width];
        for c in 0..self.terms.len() {
            for r in 0..n {
                for m in -h..=h {
                    let sum: c64 = (0..n)
                        .map(|j| self.sector_coefficient(j, c, m) * roots[(r * j) % n])
                        .sum();
                    table[(c * n + r) * width + (m + h) as usize] = sum / n as f64;
                }
            }
        }
        SpaceTimeTable {
            sectors: n,
            terms: self.terms.clone(),
            highest: h,
            table,
        }
    }
}

/// `D̂_t(r, m)`, see [`StiffnessSpectrum::space_time_table`].
#[derive(Clone, Debug)]
pub struct SpaceTimeTable {
    sectors: usize,
    terms: Vec<ContactTerm>,
    highest: i64,
    table: Vec<c64>,
}

impl SpaceTimeTable {
    /// The terms, in the order of the table.
    pub fn terms(&self) -> &[ContactTerm] {
        &self.terms
    }

    /// `D̂_t(r, m)` of term `t` for any `r` (taken modulo `N`) and
    /// `|m| ≤ 2H` (0 beyond).
    pub fn at(&self, term: usize, diameter: i64, harmonic: i64) -> c64 {
        if harmonic.abs() > self.highest {
            return c64::new(0.0, 0.0);
        }
        let n = self.sectors;
        let r = diameter.rem_euclid(n as i64) as usize;
        let width = (2 * self.highest + 1) as usize;
        self.table[(term * n + r) * width + (harmonic + self.highest) as usize]
    }
}

/// The terms of `normal` contact dofs, each with its friction node's when
/// `friction`: the normal stiffness first, then the node's six terms.
fn contact_terms(normal: usize, friction: bool) -> Vec<ContactTerm> {
    use TermKind::{Damping, Stiffness};
    let term = |row, column, kind| ContactTerm { row, column, kind };
    (0..normal)
        .flat_map(|c| {
            let mut terms = vec![term(c, c, Stiffness)];
            if friction {
                let (theta, axial) = (normal + 2 * c, normal + 2 * c + 1);
                terms.extend([
                    term(theta, c, Stiffness),
                    term(axial, c, Stiffness),
                    term(theta, theta, Damping),
                    term(theta, axial, Damping),
                    term(axial, theta, Damping),
                    term(axial, axial, Damping),
                ]);
            }
            terms
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::case::Case;
    use crate::forced_response::ForcedResponse;
    use std::path::Path;

    /// On a traveling wave (the default case, N = 24, h = 1) one sector is
    /// sampled and the others are its rotations: the spectrum is the one
    /// every sector's own samples give, to round-off (measured 4.3e-12 of
    /// the largest stiffness: the law's slope near its kink), at a contact
    /// point.
    #[test]
    fn the_repeating_sectors_spectrum_is_the_one_sampled_on_every_sector() {
        let case = Case::from_toml(
            "[stability]\nenabled = false\n[harmonic_balance]\ntime_samples = 2400\n",
            Path::new("case.toml"),
        )
        .unwrap();
        let solution = ForcedResponse::from_case(&case)
            .unwrap()
            .at_frequencies_hz(vec![120.0, 125.0, 127.0, 127.5])
            .build()
            .unwrap()
            .run(&mut [])
            .unwrap();
        let point = solution.branch.points.last().unwrap();
        let problem = &solution.problem;
        let repeated = ContactStiffness::sample_with(
            problem,
            &SectorSampling::new(problem, 2400, true),
            &point.unknowns,
            point.omega,
        )
        .unwrap();
        let every = ContactStiffness::sample_with(
            problem,
            &SectorSampling::new(problem, 2400, false),
            &point.unknowns,
            point.omega,
        )
        .unwrap();
        assert_eq!(repeated.sources.iter().filter(|s| s.is_none()).count(), 1);
        assert!(repeated.peak() > 0.0, "the point does not touch the casing");
        let scale = repeated.samples.iter().fold(0.0_f64, |m, v| m.max(v.abs()));
        // Sample `i` of a repeating sector is sample `i + r` of its source.
        let mut samples = 0.0_f64;
        for j in 0..24 {
            let (from, r) = repeated.sources[j].unwrap_or((j, 0));
            let stored = &repeated.samples[repeated.rows[from] * 2400..][..2400];
            let own = &every.samples[every.rows[j] * 2400..][..2400];
            for i in 0..2400 {
                samples = samples.max((stored[(i + r) % 2400] - own[i]).abs());
            }
        }
        assert!(samples <= 1e-10 * scale, "{samples:e} of {scale:e}");
        let (a, b) = (repeated.spectrum(20), every.spectrum(20));
        let mut worst = 0.0_f64;
        for j in 0..24 {
            for m in -20..=20 {
                worst = worst
                    .max((a.sector_coefficient(j, 0, m) - b.sector_coefficient(j, 0, m)).norm());
            }
        }
        assert!(worst <= 1e-10 * scale, "{worst:e} of {scale:e}");
    }
}
