//! How long one Newton iteration will take, said up front beside the
//! memory estimate (issue 45 item 9): a case of thousands of harmonics
//! computes its first point for minutes, and the user should know before
//! waiting.
//!
//! An iteration's cost is the contact Jacobian's assembly (its
//! multiply-adds, [`crate::hbm::HarmonicBalance::jacobian_assembly_products`]:
//! `n³` on a cyclic basis with one sampled sector, `n` real unknowns), the
//! Jacobian's LU (`2n³/3` flops) and the contact signals through their
//! time samples (FFTs and the law, per signal and sample). The rates are
//! measured (release, 2 cores, November 2026): `sectors = 6`, `N_h = 800`,
//! `N_t = 3201` (1601 unknowns), 0.65 s an iteration; `N_h = 2000`,
//! `N_t = 4001` (4001 unknowns), 10 s; the default case mistuned on the
//! physical full wheel (504 unknowns, 24 signals of 10000 samples), 14 ms.
//! The estimate is an order of magnitude, not a promise.

use std::time::Duration;

/// Seconds per multiply-add of the contact Jacobian's assembly (blocked
/// products, about 10 G a second).
const PRODUCT_SECONDS: f64 = 1.0e-10;

/// Seconds per flop of a dense LU (about 10 Gflop/s).
const FACTORIZATION_SECONDS: f64 = 1.0e-10;

/// Seconds per time sample of one contact signal (its FFTs and the law).
const SAMPLE_SECONDS: f64 = 2.0e-8;

/// Below this an iteration is not worth a word.
pub const WORTH_SAYING: Duration = Duration::from_secs(3);

/// What one Newton iteration of a point costs.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct IterationCost {
    /// Real unknowns `n`.
    pub unknowns: usize,
    /// Multiply-adds of the contact Jacobian's assembly.
    pub assembly_products: f64,
    /// Contact signals times their time samples `N_t`.
    pub signal_samples: f64,
    /// Time samples `N_t`.
    pub time_samples: usize,
    /// Newton iterations a point may take (`continuation.max_iterations`).
    pub max_iterations: usize,
}

impl IterationCost {
    /// The estimated time of one iteration: the contact Jacobian's
    /// assembly, its LU and the signals' samples.
    pub fn per_iteration(&self) -> Duration {
        let n = self.unknowns as f64;
        let seconds = PRODUCT_SECONDS * self.assembly_products
            + FACTORIZATION_SECONDS * 2.0 / 3.0 * n.powi(3)
            + SAMPLE_SECONDS * self.signal_samples;
        Duration::try_from_secs_f64(seconds).unwrap_or(Duration::MAX)
    }

    /// The sentence to say when an iteration takes longer than
    /// [`WORTH_SAYING`] (`None` below it).
    pub fn notice(&self) -> Option<String> {
        let one = self.per_iteration();
        (one >= WORTH_SAYING).then(|| {
            format!(
                "the first point will take about {} per Newton iteration, up to {} \
                 (continuation.max_iterations = {}): the Jacobian of {} unknowns \
                 (harmonic_balance.harmonics) is assembled and factorized at each one, \
                 its contact part through {} time samples (harmonic_balance.time_samples)",
                words(one),
                words(one.saturating_mul(self.max_iterations.max(1) as u32)),
                self.max_iterations,
                self.unknowns,
                self.time_samples,
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

    /// One sampled sector's band read by every unknown: `n · n²`.
    fn cyclic(unknowns: usize, time_samples: usize) -> IterationCost {
        let n = unknowns as f64;
        IterationCost {
            unknowns,
            assembly_products: n * n * n,
            signal_samples: time_samples as f64,
            time_samples,
            max_iterations: 15,
        }
    }

    /// The measured cases of the module's note, within a factor 3.
    #[test]
    fn the_estimate_is_the_measured_order_of_magnitude() {
        // sectors = 6, N_h = 800, N_t = 3201: 0.65 s measured.
        let one = cyclic(1601, 3201).per_iteration().as_secs_f64();
        assert!((0.65 / 3.0..0.65 * 3.0).contains(&one), "{one} s");
        // N_h = 2000, N_t = 4001: 10 s measured.
        let one = cyclic(4001, 4001).per_iteration().as_secs_f64();
        assert!((10.0 / 3.0..30.0).contains(&one), "{one} s");
        // The default case mistuned on the full wheel: 24 bands of 21
        // coordinates, 24 signals of 10000 samples, 14 ms measured.
        let mistuned = IterationCost {
            unknowns: 504,
            assembly_products: 24.0 * 21.0 * 21.0,
            signal_samples: 24.0 * 10_000.0,
            time_samples: 10_000,
            max_iterations: 15,
        };
        let one = mistuned.per_iteration().as_secs_f64();
        assert!((0.014 / 3.0..0.014 * 3.0).contains(&one), "{one} s");
        assert_eq!(mistuned.notice(), None);
        // The default case (21 unknowns, 10000 samples): nothing to say.
        assert_eq!(cyclic(21, 10_000).notice(), None);
    }

    #[test]
    fn a_slow_first_point_is_announced_with_its_sizes_and_keys() {
        let notice = cyclic(6001, 6001).notice().expect("slow");
        assert!(
            notice.starts_with("the first point will take about 36 s per Newton iteration"),
            "{notice}"
        );
        for words in [
            "up to 9 min",
            "continuation.max_iterations = 15",
            "the Jacobian of 6001 unknowns",
            "harmonic_balance.harmonics",
            "6001 time samples (harmonic_balance.time_samples)",
        ] {
            assert!(notice.contains(words), "{words}: {notice}");
        }
        assert_eq!(words(Duration::from_secs(40)), "40 s");
        assert_eq!(words(Duration::from_secs(12 * 60)), "12 min");
        assert_eq!(words(Duration::from_secs(7 * 3600)), "7.0 h");
        assert_eq!(words(Duration::from_secs(3 * 86_400)), "3.0 days");
    }
}
