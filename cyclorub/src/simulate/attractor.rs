//! What the wheel settled to at a fixed frequency, read from the per-period
//! maxima of the observed dof on every sector ([`PeriodRecord::maxima`]):
//! periodic at the excitation's period (the amplitude per sector), modulated
//! (an envelope that repeats over several periods: its period, and the
//! smallest and largest maxima per sector) or not settled (still growing or
//! decaying, or irregular).
//!
//! The window is the last periods integrated (at most [`WINDOW`], at most
//! half of them). A window whose maxima vary by less than
//! [`PERIODIC_SPREAD`] of their size is periodic. Otherwise the envelope's
//! period is the first lag at which the autocorrelation of the most varying
//! sector's maxima peaks above [`ENVELOPE_CORRELATION`] (refined by a
//! parabola through the three lags around it); a window whose straight-line
//! trend accounts for more than half its spread is not settled.

use super::run::{Ending, PeriodRecord};
use serde::Serialize;

/// Periods read at most.
pub const WINDOW: usize = 60;

/// Relative spread of the maxima below which the response is periodic.
pub const PERIODIC_SPREAD: f64 = 1e-4;

/// Autocorrelation an envelope's period must reach.
pub const ENVELOPE_CORRELATION: f64 = 0.5;

/// What the wheel settled to.
#[derive(Clone, Debug, PartialEq, Serialize)]
#[serde(tag = "kind", rename_all = "snake_case")]
pub enum Attractor {
    /// Periodic at the excitation's period.
    Periodic {
        /// The observed dof's largest displacement over the last period, per
        /// sector, m.
        amplitudes: Vec<f64>,
    },
    /// An envelope repeating over several periods (quasi-periodic, or a
    /// subharmonic).
    Modulated {
        /// The envelope's period, in excitation periods.
        envelope_periods: f64,
        /// The smallest per-period maximum over the window, per sector, m.
        minimum: Vec<f64>,
        /// The largest, per sector, m.
        maximum: Vec<f64>,
    },
    /// Still growing or decaying, or irregular.
    NotSettled {
        /// The smallest per-period maximum over the window, per sector, m.
        minimum: Vec<f64>,
        /// The largest, per sector, m.
        maximum: Vec<f64>,
        /// The relative change of the largest sector maximum per period
        /// (straight-line fit over the window).
        trend_per_period: f64,
    },
}

impl Attractor {
    /// The summary of a fixed-frequency integration's `periods` that ended
    /// as `ending`; `None` for a sweep or fewer than 4 periods.
    pub fn of(periods: &[PeriodRecord], ending: &Ending) -> Option<Self> {
        let last = periods.last()?;
        match ending {
            Ending::SweepDone => return None,
            Ending::Steady { .. } => {
                return Some(Self::Periodic {
                    amplitudes: last.maxima.clone(),
                })
            }
            Ending::PeriodsDone => {}
        }
        let length = WINDOW.min(periods.len() / 2);
        if length < 4 {
            return None;
        }
        let window = &periods[periods.len() - length..];
        let sectors = last.maxima.len();
        let series = |j: usize| -> Vec<f64> { window.iter().map(|p| p.maxima[j]).collect() };
        let bounds: Vec<(f64, f64)> = (0..sectors)
            .map(|j| {
                series(j)
                    .iter()
                    .fold((f64::INFINITY, f64::NEG_INFINITY), |(l, h), &v| {
                        (l.min(v), h.max(v))
                    })
            })
            .collect();
        let minimum: Vec<f64> = bounds.iter().map(|b| b.0).collect();
        let maximum: Vec<f64> = bounds.iter().map(|b| b.1).collect();
        let size = maximum.iter().fold(0.0_f64, |m, v| m.max(v.abs()));
        let spread = |j: usize| maximum[j] - minimum[j];
        let widest = (0..sectors).max_by(|&a, &b| spread(a).total_cmp(&spread(b)))?;
        if size == 0.0 || spread(widest) <= PERIODIC_SPREAD * size {
            return Some(Self::Periodic {
                amplitudes: last.maxima.clone(),
            });
        }
        // The largest sector maximum's straight-line trend.
        let largest: Vec<f64> = window
            .iter()
            .map(|p| p.maxima.iter().copied().fold(f64::NEG_INFINITY, f64::max))
            .collect();
        let slope = slope(&largest);
        let drift = slope.abs() * (length - 1) as f64;
        let envelope = envelope_period(&series(widest));
        match envelope {
            Some(envelope_periods) if drift <= 0.5 * spread(widest) => Some(Self::Modulated {
                envelope_periods,
                minimum,
                maximum,
            }),
            _ => Some(Self::NotSettled {
                minimum,
                maximum,
                trend_per_period: slope / size,
            }),
        }
    }

    /// A sentence for people (amplitudes in mm).
    pub fn describe(&self) -> String {
        let mm = |v: &[f64]| {
            let (low, high) = v
                .iter()
                .fold((f64::INFINITY, f64::NEG_INFINITY), |(l, h), &x| {
                    (l.min(x), h.max(x))
                });
            (low * 1e3, high * 1e3)
        };
        match self {
            Self::Periodic { amplitudes } => {
                let (low, high) = mm(amplitudes);
                format!(
                    "settled: periodic at the excitation's period, amplitude {low:.5} to {high:.5} mm over the sectors"
                )
            }
            Self::Modulated {
                envelope_periods,
                minimum,
                maximum,
            } => {
                let (low, _) = mm(minimum);
                let (_, high) = mm(maximum);
                format!(
                    "modulated: the envelope repeats every {envelope_periods:.2} periods, per-period maxima {low:.5} to {high:.5} mm over the sectors"
                )
            }
            Self::NotSettled {
                minimum,
                maximum,
                trend_per_period,
            } => {
                let (low, _) = mm(minimum);
                let (_, high) = mm(maximum);
                format!(
                    "not settled: per-period maxima {low:.5} to {high:.5} mm over the last periods, changing by {:.2e} of their size a period; integrate more --periods",
                    trend_per_period
                )
            }
        }
    }

    /// The largest amplitude over the sectors (the last period's when
    /// periodic, the window's largest maximum otherwise), m.
    pub fn largest(&self) -> f64 {
        let values = match self {
            Self::Periodic { amplitudes } => amplitudes,
            Self::Modulated { maximum, .. } | Self::NotSettled { maximum, .. } => maximum,
        };
        values.iter().copied().fold(f64::NEG_INFINITY, f64::max)
    }
}

/// The least-squares slope of `values` against their index.
fn slope(values: &[f64]) -> f64 {
    let n = values.len() as f64;
    let mean_x = (n - 1.0) / 2.0;
    let mean_y = values.iter().sum::<f64>() / n;
    let (mut sxy, mut sxx) = (0.0, 0.0);
    for (i, y) in values.iter().enumerate() {
        let dx = i as f64 - mean_x;
        sxy += dx * (y - mean_y);
        sxx += dx * dx;
    }
    if sxx > 0.0 {
        sxy / sxx
    } else {
        0.0
    }
}

/// The period (in samples) of `values`' envelope: the first lag ≥ 2 where
/// the autocorrelation of the detrended series has a local peak above
/// [`ENVELOPE_CORRELATION`], refined by a parabola; `None` without one.
/// A period-2 envelope (a period doubling) is lag 2.
fn envelope_period(values: &[f64]) -> Option<f64> {
    let n = values.len();
    let b = slope(values);
    let mean = values.iter().sum::<f64>() / n as f64;
    let centre = (n as f64 - 1.0) / 2.0;
    let residual: Vec<f64> = values
        .iter()
        .enumerate()
        .map(|(i, v)| v - mean - b * (i as f64 - centre))
        .collect();
    let energy: f64 = residual.iter().map(|r| r * r).sum();
    if energy == 0.0 {
        return None;
    }
    let correlation = |lag: usize| -> f64 {
        let sum: f64 = (0..n - lag).map(|i| residual[i] * residual[i + lag]).sum();
        // Unbiased: each lag's sum over its own overlap.
        sum / energy * n as f64 / (n - lag) as f64
    };
    let lags: Vec<f64> = (0..=n / 2).map(correlation).collect();
    (2..lags.len().saturating_sub(1))
        .find(|&k| {
            lags[k] >= ENVELOPE_CORRELATION && lags[k] >= lags[k - 1] && lags[k] >= lags[k + 1]
        })
        .map(|k| {
            let (a, c, d) = (lags[k - 1], lags[k], lags[k + 1]);
            let curvature = a - 2.0 * c + d;
            if curvature < 0.0 {
                k as f64 + 0.5 * (a - d) / curvature
            } else {
                k as f64
            }
        })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::simulate::EnergyTally;

    /// Periods whose maxima on 3 sectors are `f(period, sector)`.
    fn periods(count: usize, f: impl Fn(usize, usize) -> f64) -> Vec<PeriodRecord> {
        (0..count)
            .map(|p| PeriodRecord {
                period: p + 1,
                end_time: p as f64,
                frequency_hz: 1.0,
                maxima: (0..3).map(|j| f(p, j)).collect(),
                peak_force: vec![0.0; 3],
                section_displacement: vec![0.0; 3],
                section_velocity: vec![0.0; 3],
                poincare_distance: 1.0,
                energy: EnergyTally::default(),
                energy_change: 0.0,
            })
            .collect()
    }

    #[test]
    fn repeating_maxima_are_periodic() {
        let list = periods(100, |_, j| 1e-3 * (1.0 + 0.1 * j as f64));
        let found = Attractor::of(&list, &Ending::PeriodsDone).unwrap();
        assert_eq!(
            found,
            Attractor::Periodic {
                amplitudes: vec![1e-3, 1.1e-3, 1.2e-3]
            }
        );
        assert!((found.largest() - 1.2e-3).abs() < 1e-15);
    }

    #[test]
    fn an_envelope_is_found_with_its_period() {
        let period = 7.3;
        let list = periods(200, |p, j| {
            1e-3 * (1.0 + 0.05 * (2.0 * std::f64::consts::PI * p as f64 / period + j as f64).sin())
        });
        match Attractor::of(&list, &Ending::PeriodsDone).unwrap() {
            Attractor::Modulated {
                envelope_periods,
                minimum,
                maximum,
            } => {
                assert!(
                    (envelope_periods - period).abs() < 0.15,
                    "{envelope_periods}"
                );
                assert!(minimum.iter().all(|m| *m < 0.96e-3 && *m > 0.94e-3));
                assert!(maximum.iter().all(|m| *m > 1.04e-3 && *m < 1.06e-3));
            }
            other => panic!("{other:?}"),
        }
        // Alternating maxima: a period doubling, envelope of 2 periods.
        let list = periods(100, |p, _| 1e-3 * if p % 2 == 0 { 1.0 } else { 0.9 });
        match Attractor::of(&list, &Ending::PeriodsDone).unwrap() {
            Attractor::Modulated {
                envelope_periods, ..
            } => assert!((envelope_periods - 2.0).abs() < 0.02, "{envelope_periods}"),
            other => panic!("{other:?}"),
        }
    }

    #[test]
    fn a_decaying_transient_is_not_settled() {
        let list = periods(200, |p, _| 1e-3 * (1.0 + (-(p as f64) / 100.0).exp()));
        match Attractor::of(&list, &Ending::PeriodsDone).unwrap() {
            Attractor::NotSettled {
                trend_per_period, ..
            } => assert!(trend_per_period < 0.0),
            other => panic!("{other:?}"),
        }
    }

    #[test]
    fn a_steady_ending_is_periodic_and_a_sweep_has_no_summary() {
        let list = periods(10, |p, _| p as f64);
        assert!(matches!(
            Attractor::of(&list, &Ending::Steady { period: 10 }),
            Some(Attractor::Periodic { .. })
        ));
        assert!(Attractor::of(&list, &Ending::SweepDone).is_none());
        assert!(Attractor::of(&list[..3], &Ending::PeriodsDone).is_none());
    }
}
