//! How long one Newton iteration will take, said up front beside the
//! memory estimate (issue 45 item 9): a case of thousands of harmonics
//! computes its first point for minutes, and the user should know before
//! waiting.
//!
//! An iteration's cost is dominated by the contact Jacobian's assembly, a
//! dense product through the time samples, `O(n² N_t)` for `n` real
//! unknowns and `N_t` samples (90 % of a first point in the profile of
//! issue 45), then the Jacobian's LU, `2n³/3` flops. The rates are
//! measured (release, 2 cores, November 2026): `sectors = 6`, `N_h = 800`,
//! `N_t = 3201` (1601 unknowns) took 25 s for its one iteration, which
//! gives 3.0 ns per unit of `n² N_t`; `N_h = 400` (801 unknowns), 3.9 s
//! for two points; the issue's `N_h = 2000`, `N_t = 4001`, 140–600 s. The
//! estimate is an order of magnitude, not a promise.

use std::time::Duration;

/// Seconds per unit of `n² N_t` of the contact Jacobian's assembly.
const ASSEMBLY_SECONDS: f64 = 3.0e-9;

/// Seconds per flop of a dense LU (about 10 Gflop/s).
const FACTORIZATION_SECONDS: f64 = 1.0e-10;

/// Below this an iteration is not worth a word.
pub const WORTH_SAYING: Duration = Duration::from_secs(3);

/// What one Newton iteration of a point costs.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct IterationCost {
    /// Real unknowns `n`.
    pub unknowns: usize,
    /// Time samples `N_t`.
    pub time_samples: usize,
    /// Newton iterations a point may take (`continuation.max_iterations`).
    pub max_iterations: usize,
}

impl IterationCost {
    /// The estimated time of one iteration: the contact Jacobian's
    /// assembly and the Jacobian's LU.
    pub fn per_iteration(&self) -> Duration {
        let n = self.unknowns as f64;
        let seconds = ASSEMBLY_SECONDS * n * n * self.time_samples as f64
            + FACTORIZATION_SECONDS * 2.0 / 3.0 * n.powi(3);
        Duration::try_from_secs_f64(seconds).unwrap_or(Duration::MAX)
    }

    /// The sentence to say when an iteration takes longer than
    /// [`WORTH_SAYING`] (`None` below it).
    pub fn notice(&self) -> Option<String> {
        let one = self.per_iteration();
        (one >= WORTH_SAYING).then(|| {
            format!(
                "the first point will take about {} per Newton iteration, up to {} \
                 (continuation.max_iterations = {}): the contact Jacobian through {} time \
                 samples on {} unknowns (harmonic_balance.harmonics, \
                 harmonic_balance.time_samples) is assembled at each one",
                words(one),
                words(one.saturating_mul(self.max_iterations.max(1) as u32)),
                self.max_iterations,
                self.time_samples,
                self.unknowns
            )
        })
    }
}

/// `40 s`, `12 min`, `3.5 h`, `2.0 days`.
pub fn words(duration: Duration) -> String {
    let seconds = duration.as_secs_f64();
    if seconds < 90.0 {
        format!("{seconds:.0} s")
    } else if seconds < 90.0 * 60.0 {
        format!("{:.0} min", seconds / 60.0)
    } else if seconds < 48.0 * 3600.0 {
        format!("{:.1} h", seconds / 3600.0)
    } else {
        format!("{:.1} days", seconds / 86_400.0)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn cost(unknowns: usize, time_samples: usize) -> IterationCost {
        IterationCost {
            unknowns,
            time_samples,
            max_iterations: 15,
        }
    }

    /// The measured cases of the module's note, within a factor 3.
    #[test]
    fn the_estimate_is_the_measured_order_of_magnitude() {
        // sectors = 6, N_h = 800, N_t = 3201: 25 s measured.
        let one = cost(1601, 3201).per_iteration().as_secs_f64();
        assert!((25.0 / 3.0..75.0).contains(&one), "{one} s");
        // The case, N_h = 2000, N_t = 4001: 140-600 s measured.
        let one = cost(4001, 4001).per_iteration().as_secs_f64();
        assert!((140.0 / 3.0..1800.0).contains(&one), "{one} s");
        // The default case (22 unknowns, 10000 samples): nothing to say.
        assert_eq!(cost(22, 10_000).notice(), None);
    }

    #[test]
    fn a_slow_first_point_is_announced_with_its_sizes_and_keys() {
        let notice = cost(4001, 4001).notice().expect("slow");
        assert!(
            notice.starts_with("the first point will take about 3 min per Newton iteration"),
            "{notice}"
        );
        for words in [
            "up to 49 min",
            "continuation.max_iterations = 15",
            "4001 time samples on 4001 unknowns",
            "harmonic_balance.harmonics",
        ] {
            assert!(notice.contains(words), "{words}: {notice}");
        }
        assert_eq!(words(Duration::from_secs(40)), "40 s");
        assert_eq!(words(Duration::from_secs(12 * 60)), "12 min");
        assert_eq!(words(Duration::from_secs(7 * 3600)), "7.0 h");
        assert_eq!(words(Duration::from_secs(3 * 86_400)), "3.0 days");
    }
}
