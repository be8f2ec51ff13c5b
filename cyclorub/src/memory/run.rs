//! The memory of a forced response beyond its harmonic balance problem
//! (which [`crate::hbm::ProblemSpec::build`] estimates itself): what the
//! branch keeps per point, up to `continuation.max_points`, and the time
//! histories of one point's recovery on the reported sectors.

use super::{doubles, fft_bytes, human, Budget, Estimate, TooMuchMemory};

/// The sizes of a run that its memory depends on.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct RunSizes {
    /// `N`.
    pub sectors: usize,
    /// Dofs of a sector.
    pub dofs_per_sector: usize,
    /// Contact dofs of a sector.
    pub contact_dofs: usize,
    /// `N_h`.
    pub harmonics: usize,
    /// `N_t`.
    pub time_samples: usize,
    /// Real unknowns of the problem.
    pub unknowns: usize,
    /// Sectors reported (`output.sectors`, all when empty).
    pub reported_sectors: usize,
    /// `continuation.max_points`.
    pub max_points: usize,
    /// Whether every point's stability is kept.
    pub stability: bool,
    /// Threads that recover points at once.
    pub threads: usize,
}

impl RunSizes {
    /// Rows of the largest dense matrix of the solve: the Jacobian or a
    /// sector's matrices (the stability check's eigenproblems are bounded
    /// by its own `largest_eigenproblem`, and the CLI may skip it).
    pub fn largest_matrix(&self) -> usize {
        self.unknowns.max(self.dofs_per_sector)
    }

    /// Bytes the branch keeps per point today (all points are held until
    /// the results are written): the unknowns and the tangent's frequency,
    /// the per-sector results (observed dof's harmonics, amplitudes,
    /// contact summary per contact dof) and, with stability, the exponents
    /// of every class (`N/2 + 1` classes of `2 · dofs` exponents, with
    /// their truncation edges).
    pub fn per_point(&self) -> f64 {
        let reported = self.reported_sectors as f64;
        let point = doubles(self.unknowns as f64 + 8.0);
        let observed = reported * doubles(2.0 * (self.harmonics as f64 + 1.0) + 6.0);
        let contact = reported * self.contact_dofs as f64 * doubles(8.0);
        let stability = if self.stability {
            (self.sectors as f64 / 2.0 + 1.0) * 2.0 * self.dofs_per_sector as f64 * 32.0
        } else {
            0.0
        };
        point + observed + contact + stability
    }

    /// Bytes of the time histories the results are made of: per thread
    /// recovering a point, the penetration, force and contact flag of every
    /// contact dof on every reported sector (17 bytes a sample), working
    /// signals and an FFT plan; once, the casing's gap on every reported
    /// sector, and the full histories of the point of largest amplitude
    /// (displacement, velocity, contact signals) with their plots (some 24
    /// bytes a sample of text per line). Checked against the peak memory
    /// of runs at `N_t = 10⁶` (2.2 GB measured for the default case; this
    /// says 2.6 GB).
    pub fn histories(&self) -> f64 {
        let nt = self.time_samples as f64;
        let reported = self.reported_sectors as f64;
        let signals = reported * self.contact_dofs as f64;
        let per_thread = signals * nt * 17.0 + doubles(6.0 * nt) + fft_bytes(self.time_samples);
        let shared = signals * nt * (8.0 + 17.0) + reported * nt * (16.0 + 24.0);
        self.threads as f64 * per_thread + shared
    }

    /// The estimate: `max_points` points, and the recoveries in flight.
    pub fn estimate(&self) -> Estimate {
        Estimate::new()
            .part(
                format!(
                    "the branch's points ({} each on {} reported sectors, all held until written)",
                    human(self.per_point()),
                    self.reported_sectors
                ),
                self.max_points as f64 * self.per_point(),
            )
            .part(
                format!(
                    "the time histories on {} reported sectors (output.sectors)",
                    self.reported_sectors
                ),
                self.histories(),
            )
    }

    /// The part of [`Self::per_point`] that grows with the reported sectors.
    fn per_point_on_sectors(&self) -> f64 {
        self.per_point() - doubles(self.unknowns as f64 + 8.0)
    }

    /// Refuses the sizes when their estimate is above `budget`, naming the
    /// key that weighs most, with the largest value that fits: when the
    /// points weigh most, `model.sectors` if every sector is reported, the
    /// sectors make most of a point and the points would fit without
    /// them, else `continuation.max_points`;
    /// when the histories do, `harmonic_balance.time_samples`.
    pub fn check(&self, budget: &Budget) -> Result<(), TooMuchMemory> {
        let points = self.max_points as f64 * self.per_point();
        let estimate = self.estimate();
        let total = |sizes: Self| sizes.estimate().total();
        if points < self.histories() {
            let fits = |n: u64| {
                total(Self {
                    time_samples: n as usize,
                    ..*self
                })
            };
            budget.check(
                "harmonic_balance.time_samples",
                self.time_samples as u64,
                &estimate,
                Some(&fits),
            )
        } else if self.reported_sectors == self.sectors
            && 2.0 * self.per_point_on_sectors() > self.per_point()
            && self.max_points as f64 * (self.per_point() - self.per_point_on_sectors())
                < budget.bytes
        {
            let fits = |n: u64| {
                total(Self {
                    sectors: n as usize,
                    reported_sectors: n as usize,
                    ..*self
                })
            };
            budget.check("model.sectors", self.sectors as u64, &estimate, Some(&fits))
        } else {
            let fits = |n: u64| {
                total(Self {
                    max_points: n as usize,
                    ..*self
                })
            };
            budget.check(
                "continuation.max_points",
                self.max_points as u64,
                &estimate,
                Some(&fits),
            )
        }
    }
}

/// Refuses a run of `sizes` when what it keeps beyond the problem does
/// not fit in the memory this process may still take (see [`RunSizes`]);
/// called once the problem is built, before the branch is followed.
pub fn check_run(sizes: &RunSizes) -> Result<(), TooMuchMemory> {
    sizes.check(&Budget::of_this_process(sizes.largest_matrix()))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::case::Case;

    fn default_sizes() -> RunSizes {
        RunSizes::of(&Case::default(), 5, 22)
    }

    #[test]
    fn the_default_run_is_small() {
        let sizes = default_sizes();
        assert_eq!(sizes.reported_sectors, 24);
        // 24 sectors: a few kB per point; 5000 points, some tens of MB.
        let per_point = sizes.per_point();
        assert!((2e3..2e4).contains(&per_point), "{per_point}");
        let total = sizes.estimate().total();
        assert!(total < 1e8, "{}", human(total));
        let budget = Budget {
            bytes: 1e9,
            source: "1.0 GB".into(),
        };
        assert!(sizes.check(&budget).is_ok());
    }

    #[test]
    fn absurd_points_and_histories_name_their_key() {
        let budget = Budget {
            bytes: 2e9,
            source: "2.0 GB left".into(),
        };
        let points = RunSizes {
            max_points: 1_000_000_000_000,
            ..default_sizes()
        };
        let message = points.check(&budget).unwrap_err().to_string();
        // Every sector of 10000 reported: the sectors are blamed.
        let sectors = RunSizes {
            sectors: 10_000,
            reported_sectors: 10_000,
            ..default_sizes()
        };
        let refused = sectors.check(&budget).unwrap_err().to_string();
        assert!(
            refused.starts_with("model.sectors = 10000: needs about"),
            "{refused}"
        );
        assert!(
            message.starts_with("continuation.max_points = 1000000000000: needs about"),
            "{message}"
        );
        assert!(message.contains("at most"), "{message}");
        // 10000 sectors all reported at 10000 samples: 1.7 GB per thread
        // recovering, 6.5 GB of full histories.
        let histories = RunSizes {
            sectors: 10_000,
            reported_sectors: 10_000,
            max_points: 10,
            threads: 2,
            ..default_sizes()
        };
        assert!((9e9..1.1e10).contains(&histories.histories()));
        let message = histories.check(&budget).unwrap_err().to_string();
        assert!(
            message.starts_with("harmonic_balance.time_samples = 10000: needs about 9.9 GB"),
            "{message}"
        );
        assert!(message.contains("at most 1974 fits"), "{message}");
    }
}
