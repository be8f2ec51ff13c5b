//! The memory a run may take, and the estimates that sizes are refused
//! with before any large allocation.
//!
//! A size a user controls (`model.sectors`, `harmonic_balance.harmonics`,
//! `harmonic_balance.time_samples`, `continuation.max_points`, the
//! periods and steps of `cyclorub simulate`) is checked either by a range
//! in the key table or by an [`Estimate`] of the bytes it makes the run
//! hold, compared with the [`Budget`]: the memory the system has available
//! (`MemAvailable` of `/proc/meminfo`) and the room left under the
//! address-space limit (`RLIMIT_AS`, from `/proc/self/limits`, less the
//! process's present size `VmSize`). A refusal ([`TooMuchMemory`]) names
//! the key, its value, the estimate in human units and the largest value
//! that fits.

use std::fmt;

mod first_point;
mod run;
mod simulate;
mod stability;

pub use first_point::IterationCost;
pub use run::{check_run, RunSizes};
pub use simulate::SimulationSizes;
pub use stability::{check_stability, StabilitySizes};

/// Rows of the largest dense matrix whose products stay in small kernels
/// (faer hands products above `16³` multiply-adds to its blocked kernels,
/// which reserve [`matrix_product_reserve`]; a factorization of a matrix
/// of a few tens of rows starts doing so).
pub const PRODUCT_ROWS: usize = 32;

/// When nothing says how much memory there is (no `/proc`): 8 GB.
pub const FALLBACK_BYTES: f64 = 8e9;

/// What bounds the memory of a run, and how much it leaves.
#[derive(Clone, Debug, PartialEq)]
pub struct Budget {
    /// Bytes a run may still allocate.
    pub bytes: f64,
    /// Where the figure comes from, as a user reads it.
    pub source: String,
}

impl Budget {
    /// The budget of this process now, for work on dense matrices of up to
    /// `largest_matrix` rows: the smaller of the memory available on the
    /// system and the room under its address-space limit, less its present
    /// size and, for matrices large enough to be multiplied by blocks
    /// ([`PRODUCT_ROWS`]), the matrix products' workspace
    /// ([`matrix_product_reserve`]); [`FALLBACK_BYTES`] when neither can be
    /// read.
    pub fn of_this_process(largest_matrix: usize) -> Self {
        Self::of_this_process_setting_aside(largest_matrix, 0.0)
    }

    /// [`Self::of_this_process`], with `more` bytes of address space set
    /// aside as well under an address-space limit (the products' workspace
    /// of threads that have not multiplied a large matrix yet, such as the
    /// stability check's; see [`check_stability`]).
    pub fn of_this_process_setting_aside(largest_matrix: usize, more: f64) -> Self {
        let read = |path: &str| std::fs::read_to_string(path).ok();
        let ram = read("/proc/meminfo").and_then(|t| mem_available(&t));
        let limit = read("/proc/self/limits").and_then(|t| address_space_limit(&t));
        let status = read("/proc/self/status");
        let size = status.as_deref().and_then(|t| status_bytes(t, "VmSize:"));
        let resident = status.as_deref().and_then(|t| status_bytes(t, "VmRSS:"));
        // The workspace is reserved once per thread and never touched: once
        // reserved it is in VmSize, not in VmRSS.
        let reserve = match limit {
            Some(_) if largest_matrix > PRODUCT_ROWS => {
                matrix_product_reserve(rayon::current_num_threads() + 1)
            }
            _ => 0.0,
        };
        let already = match (size, resident) {
            (Some(s), Some(r)) => (s - r).clamp(0.0, reserve),
            _ => 0.0,
        };
        let more = if limit.is_some() { more } else { 0.0 };
        Self::from_figures(ram, limit, size, reserve - already + more)
    }

    /// The budget from the system's available memory, the address-space
    /// limit, the process's present virtual size (bytes; `None`: unknown
    /// or unlimited) and the address space set aside for the matrix
    /// products.
    pub fn from_figures(
        ram: Option<f64>,
        limit: Option<f64>,
        size: Option<f64>,
        reserve: f64,
    ) -> Self {
        let room = limit.map(|l| (l - size.unwrap_or(0.0) - reserve).max(0.0));
        let address_space = |room: f64| {
            let aside = match reserve {
                r if r > 0.0 => format!(
                    " once {} is set aside for the matrix products' workspace \
                     (twice the L3 cache per thread; RAYON_NUM_THREADS lowers it)",
                    human(r)
                ),
                _ => String::new(),
            };
            Self {
                bytes: room,
                source: format!(
                    "{} left under the address-space limit of {} (ulimit -v){aside}",
                    human(room),
                    human(limit.unwrap_or(room))
                ),
            }
        };
        match (ram, room) {
            (Some(r), Some(a)) if a < r => address_space(a),
            (None, Some(a)) => address_space(a),
            (Some(r), _) => Self {
                bytes: r,
                source: format!("{} available on this machine (MemAvailable)", human(r)),
            },
            (None, None) => Self {
                bytes: FALLBACK_BYTES,
                source: format!(
                    "{} assumed (the available memory cannot be read)",
                    human(FALLBACK_BYTES)
                ),
            },
        }
    }

    /// Refuses `estimate` when it is above the budget, naming `key` and
    /// `value`; `fits` gives the estimate of another value of the key, to
    /// say the largest that fits (`None`: not said).
    pub fn check(
        &self,
        key: &str,
        value: u64,
        estimate: &Estimate,
        fits: Option<&dyn Fn(u64) -> f64>,
    ) -> Result<(), TooMuchMemory> {
        let total = estimate.total();
        if total <= self.bytes {
            return Ok(());
        }
        let largest = fits.map(|f| largest_fitting(f, value, self.bytes));
        Err(TooMuchMemory {
            key: key.to_string(),
            value,
            bytes: total,
            what: estimate.largest_part().to_string(),
            budget: self.clone(),
            largest,
        })
    }
}

/// The bytes a run would hold, in parts.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Estimate {
    parts: Vec<(String, f64)>,
}

impl Estimate {
    /// No bytes yet.
    pub fn new() -> Self {
        Self::default()
    }

    /// With one more part: what it is, and its bytes.
    pub fn part(mut self, what: impl Into<String>, bytes: f64) -> Self {
        self.parts.push((what.into(), bytes));
        self
    }

    /// Bytes in all.
    pub fn total(&self) -> f64 {
        self.parts.iter().map(|(_, b)| b).sum()
    }

    /// What takes the most, e.g. `the time samples (1.2 GB)`.
    pub fn largest_part(&self) -> String {
        self.parts
            .iter()
            .fold(None::<&(String, f64)>, |best, p| match best {
                Some(b) if b.1 >= p.1 => Some(b),
                _ => Some(p),
            })
            .map_or_else(String::new, |(what, bytes)| {
                format!("{what} ({})", human(*bytes))
            })
    }
}

/// A size whose estimate is above the memory the run may take.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub struct TooMuchMemory {
    /// The key (or option), e.g. `continuation.max_points`.
    pub key: String,
    /// Its value.
    pub value: u64,
    /// The estimate, bytes.
    pub bytes: f64,
    /// What takes the most.
    pub what: String,
    /// The budget it was compared with.
    pub budget: Budget,
    /// The largest value of the key that fits, the others unchanged
    /// (`Some(0)`: none).
    pub largest: Option<u64>,
}

impl TooMuchMemory {
    /// What the message says after `key = value: `: the estimate, what
    /// takes most, the budget and the largest value that fits.
    pub fn allowed(&self) -> String {
        let fits = match self.largest {
            Some(0) | None => "lower it, or the sizes it multiplies".to_string(),
            Some(n) => format!("at most {n} fits with the other sizes as they are"),
        };
        format!(
            "needs about {} of memory (most of it {}), above the {}; {fits}",
            human(self.bytes),
            self.what,
            self.budget.source
        )
    }
}

impl fmt::Display for TooMuchMemory {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{} = {}: {}", self.key, self.value, self.allowed())
    }
}

/// A check refused in words of its own (the stability check's): `key =
/// value: allowed`, like a refused case value.
#[derive(Clone, Debug, PartialEq)]
pub struct Refused {
    /// The key, e.g. `stability.enabled`.
    pub key: String,
    /// Its value.
    pub value: String,
    /// What would fit.
    pub allowed: String,
}

impl fmt::Display for Refused {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{} = {}: {}", self.key, self.value, self.allowed)
    }
}

/// Bytes in human units: `512 B`, `3.2 kB`, `1.5 MB`, `4.0 GB`, `2.1 TB`.
pub fn human(bytes: f64) -> String {
    let units = ["B", "kB", "MB", "GB", "TB", "PB", "EB"];
    let mut value = bytes.max(0.0);
    let mut unit = 0;
    while value >= 1000.0 && unit + 1 < units.len() {
        value /= 1000.0;
        unit += 1;
    }
    if unit == 0 {
        format!("{value:.0} B")
    } else if value.is_finite() {
        format!("{value:.1} {}", units[unit])
    } else {
        "more than any machine has".into()
    }
}

/// The largest value in `0..value` whose estimate fits in `bytes`
/// (estimates grow with the value): 0 when none does.
fn largest_fitting(estimate: &dyn Fn(u64) -> f64, value: u64, bytes: f64) -> u64 {
    let (mut lo, mut hi) = (0, value);
    if estimate(0) > bytes {
        return 0;
    }
    // estimate(lo) fits, estimate(hi) does not.
    while hi - lo > 1 {
        let mid = lo + (hi - lo) / 2;
        if estimate(mid) <= bytes {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    lo
}

/// The address space the matrix products of `threads` threads reserve:
/// faer's x86 kernels (`private-gemm-x86`) give each thread that multiplies
/// large matrices a buffer of twice the L3 cache (virtual, mostly never
/// touched, but counted by an address-space limit). The L3 size is read
/// from `/sys/devices/system/cpu/cpu0/cache/index3/size` (0 when absent).
pub fn matrix_product_reserve(threads: usize) -> f64 {
    let l3 = std::fs::read_to_string("/sys/devices/system/cpu/cpu0/cache/index3/size")
        .ok()
        .and_then(|t| cache_size(&t))
        .unwrap_or(0.0);
    2.0 * l3 * threads as f64
}

/// `491520K` (sysfs) → bytes.
fn cache_size(text: &str) -> Option<f64> {
    let text = text.trim();
    let (digits, scale) = match text.chars().last()? {
        'K' => (&text[..text.len() - 1], 1024.0),
        'M' => (&text[..text.len() - 1], 1024.0 * 1024.0),
        'G' => (&text[..text.len() - 1], 1024.0 * 1024.0 * 1024.0),
        _ => (text, 1.0),
    };
    Some(digits.parse::<f64>().ok()? * scale)
}

/// Bytes of a real FFT plan of `time_samples` points (twiddles and
/// scratch of rustfft, forward and inverse), measured: about 64 bytes
/// per sample when every prime factor of the size is small, and up to
/// some 450 when one is large (Rader's and Bluestein's algorithms; a
/// prime `N_t` near 10⁶ took 1.3 GB more than its neighbours).
pub fn fft_bytes(time_samples: usize) -> f64 {
    let per_sample = if largest_prime_factor(time_samples) > 1000 {
        450.0
    } else {
        64.0
    };
    per_sample * time_samples as f64
}

/// The largest prime factor of `n` (1 for `n ≤ 1`; `n` itself beyond
/// 10¹², where only its size matters).
fn largest_prime_factor(mut n: usize) -> usize {
    if n > 1_000_000_000_000 {
        return n;
    }
    let mut largest = 1;
    let mut p = 2;
    while p * p <= n {
        while n.is_multiple_of(p) {
            largest = p;
            n /= p;
        }
        p += 1;
    }
    if n > 1 {
        largest = largest.max(n);
    }
    largest
}

/// `MemAvailable` of `/proc/meminfo` text, bytes.
fn mem_available(meminfo: &str) -> Option<f64> {
    let line = meminfo.lines().find(|l| l.starts_with("MemAvailable:"))?;
    kilobytes(line)
}

/// A line of `/proc/self/status` text (`VmSize:`, `VmRSS:`), bytes.
fn status_bytes(status: &str, name: &str) -> Option<f64> {
    let line = status.lines().find(|l| l.starts_with(name))?;
    kilobytes(line)
}

/// `Name:   1234 kB` → bytes.
fn kilobytes(line: &str) -> Option<f64> {
    let mut words = line.split_whitespace().skip(1);
    let value: f64 = words.next()?.parse().ok()?;
    Some(value * 1024.0)
}

/// The soft limit of `Max address space` in `/proc/self/limits` text,
/// bytes (`None`: unlimited or absent).
fn address_space_limit(limits: &str) -> Option<f64> {
    let line = limits
        .lines()
        .find(|l| l.starts_with("Max address space"))?;
    let soft = line["Max address space".len()..]
        .split_whitespace()
        .next()?;
    soft.parse().ok()
}

/// Bytes of `count` values of 8 bytes (`f64`), as a float (no overflow).
pub fn doubles(count: f64) -> f64 {
    8.0 * count
}

/// Bytes of `count` complex values of 16 bytes.
pub fn complexes(count: f64) -> f64 {
    16.0 * count
}

#[cfg(test)]
#[allow(clippy::float_cmp)] // the figures are exact products of exact inputs
mod tests {
    use super::*;

    const LIMITS: &str =
        "Limit                     Soft Limit           Hard Limit           Units     \n\
Max cpu time              unlimited            unlimited            seconds   \n\
Max address space         2048000000           unlimited            bytes     \n";

    #[test]
    fn the_proc_files_are_read() {
        assert_eq!(
            mem_available("MemTotal:  100 kB\nMemAvailable:    2000 kB\n"),
            Some(2_048_000.0)
        );
        assert_eq!(
            status_bytes("Name: x\nVmSize:\t  10 kB\n", "VmSize:"),
            Some(10_240.0)
        );
        assert_eq!(address_space_limit(LIMITS), Some(2.048e9));
        let unlimited = LIMITS.replace("2048000000 ", "unlimited  ");
        assert_eq!(address_space_limit(&unlimited), None);
        assert_eq!(mem_available("nothing"), None);
    }

    #[test]
    fn the_budget_is_the_smaller_room() {
        let b = Budget::from_figures(Some(16e9), Some(2e9), Some(0.5e9), 0.0);
        assert_eq!(b.bytes, 1.5e9);
        assert!(
            b.source.contains("address-space limit of 2.0 GB"),
            "{}",
            b.source
        );
        let b = Budget::from_figures(Some(16e9), Some(4e9), Some(0.5e9), 1e9);
        assert_eq!(b.bytes, 2.5e9);
        assert!(
            b.source.contains("once 1.0 GB is set aside"),
            "{}",
            b.source
        );
        let b = Budget::from_figures(Some(1e9), Some(2e9), Some(0.5e9), 0.0);
        assert_eq!(b.bytes, 1e9);
        assert!(b.source.contains("MemAvailable"));
        assert_eq!(Budget::from_figures(Some(3e9), None, None, 0.0).bytes, 3e9);
        assert_eq!(
            Budget::from_figures(None, None, None, 0.0).bytes,
            FALLBACK_BYTES
        );
        assert_eq!(
            Budget::from_figures(None, Some(1e9), Some(2e9), 0.0).bytes,
            0.0
        );
        // This process: something, and finite.
        let here = Budget::of_this_process(1000);
        assert!(here.bytes.is_finite() && here.bytes >= 0.0);
    }

    #[test]
    fn fft_plans_and_caches() {
        assert_eq!(largest_prime_factor(10_000), 5);
        assert_eq!(largest_prime_factor(999_983), 999_983);
        assert_eq!(largest_prime_factor(1), 1);
        assert_eq!(fft_bytes(10_000), 640_000.0);
        assert_eq!(fft_bytes(999_983), 450.0 * 999_983.0);
        assert_eq!(cache_size("491520K\n"), Some(491_520.0 * 1024.0));
        assert_eq!(cache_size("32M"), Some(32.0 * 1024.0 * 1024.0));
        assert_eq!(cache_size("x"), None);
    }

    #[test]
    fn human_units() {
        assert_eq!(human(512.0), "512 B");
        assert_eq!(human(1.5e6), "1.5 MB");
        assert_eq!(human(4.8e11), "480.0 GB");
        assert_eq!(human(f64::INFINITY), "more than any machine has");
    }

    #[test]
    fn a_refusal_names_the_key_the_estimate_and_what_fits() {
        let budget = Budget {
            bytes: 1e9,
            source: "1.0 GB available".into(),
        };
        let per_point = |n: u64| doubles(1000.0 * n as f64);
        let estimate = Estimate::new()
            .part("the problem", 1e6)
            .part("the branch's points", per_point(10_000_000));
        let error = budget
            .check(
                "continuation.max_points",
                10_000_000,
                &estimate,
                Some(&|n| 1e6 + per_point(n)),
            )
            .unwrap_err();
        assert_eq!(error.largest, Some(124_875));
        let message = error.to_string();
        assert!(
            message.starts_with("continuation.max_points = 10000000: needs about 80.0 GB"),
            "{message}"
        );
        assert!(
            message.contains("the branch's points (80.0 GB)"),
            "{message}"
        );
        assert!(message.contains("at most 124875 fits"), "{message}");
        let small = Estimate::new().part("x", 1e8);
        assert!(budget.check("k", 1, &small, None).is_ok());
    }
}
