//! Loads expressed as signed pairs with complex coefficients.
//!
//! Convention: a field `u_j(t) = Σ_pairs 2 Re(c_(s,k) exp(i(k ω t − s α (j−1))))`
//! for `k ≥ 1`. The traveling wave `cos(ω t + α (j−1) h)` of Eq. (48) is then
//! the pair `(−h, 1)` with coefficient `1/2`.

use super::pair::SignedPair;
use serde::Serialize;
use std::f64::consts::PI;

/// Errors in the description of a load.
#[derive(Debug, thiserror::Error, PartialEq)]
pub enum LoadError {
    /// The engine order must be below the number of sectors.
    #[error("engine order {engine_order} is out of range: it must be in 0..{sectors} (below the number of sectors)")]
    EngineOrderOutOfRange {
        /// The order given.
        engine_order: usize,
        /// The number of sectors.
        sectors: usize,
    },
    /// Per-sector amplitudes and phases must have one entry per sector.
    #[error("per-sector excitation has {given} {what} but the wheel has {sectors} sectors")]
    PerSectorLength {
        /// `amplitudes` or `phases`.
        what: &'static str,
        /// Entries given.
        given: usize,
        /// Number of sectors.
        sectors: usize,
    },
    /// A weight or amplitude is not a finite number.
    #[error("{what} must be a finite number, got {value}")]
    NotFinite {
        /// Which quantity.
        what: &'static str,
        /// The value.
        value: f64,
    },
    /// A mixed excitation whose two weights are 0: no force.
    #[error("excitation.backward_weight and excitation.forward_weight are both 0: a mixed excitation needs a weight > 0")]
    NoWeight,
}

/// The spatial pattern of a first-harmonic excitation (unit amplitude).
#[derive(Clone, Debug, PartialEq, Serialize)]
#[serde(tag = "kind", rename_all = "snake_case")]
pub enum ExcitationPattern {
    /// Eq. (48): `cos(ω t + α (j−1) h)`, the pair `(−h, 1)`.
    Traveling {
        /// Engine order `h`.
        engine_order: usize,
    },
    /// Eq. (75): the sum of the backward and forward waves of order `h`.
    Standing {
        /// Engine order `h`.
        engine_order: usize,
    },
    /// Eq. (86): `w_b cos(ω t + α (j−1) h) + w_f cos(ω t − α (j−1) h)`.
    Mixed {
        /// Engine order `h`.
        engine_order: usize,
        /// Weight of the backward wave (pair `(−h, 1)`), 0.9 in Eq. (86).
        backward_weight: f64,
        /// Weight of the forward wave (pair `(h, 1)`), 0.1 in Eq. (86).
        forward_weight: f64,
    },
    /// Explicit `a_j cos(ω t + φ_j)` on each sector `j = 1..N`.
    PerSector {
        /// Amplitude per sector.
        amplitudes: Vec<f64>,
        /// Phase per sector, radians.
        phases: Vec<f64>,
    },
}

/// Coefficients below this (relative to the largest) are not counted as
/// excited pairs: they are round-off of a per-sector DFT.
const NEGLIGIBLE: f64 = 1e-12;

impl ExcitationPattern {
    /// Checks the pattern against the number of sectors.
    pub fn validate(&self, sectors: usize) -> Result<(), LoadError> {
        let check_order = |h: usize| {
            if h >= sectors.max(1) && !(sectors == 1 && h == 0) {
                Err(LoadError::EngineOrderOutOfRange {
                    engine_order: h,
                    sectors,
                })
            } else {
                Ok(())
            }
        };
        match self {
            Self::Traveling { engine_order } | Self::Standing { engine_order } => {
                check_order(*engine_order)
            }
            Self::Mixed {
                engine_order,
                backward_weight,
                forward_weight,
            } => {
                check_order(*engine_order)?;
                for (what, value) in [
                    ("backward_weight", *backward_weight),
                    ("forward_weight", *forward_weight),
                ] {
                    if !value.is_finite() {
                        return Err(LoadError::NotFinite { what, value });
                    }
                }
                if *backward_weight == 0.0 && *forward_weight == 0.0 {
                    return Err(LoadError::NoWeight);
                }
                Ok(())
            }
            Self::PerSector { amplitudes, phases } => {
                for (what, v) in [("amplitudes", amplitudes), ("phases", phases)] {
                    if v.len() != sectors {
                        return Err(LoadError::PerSectorLength {
                            what,
                            given: v.len(),
                            sectors,
                        });
                    }
                    if let Some(&value) = v.iter().find(|x| !x.is_finite()) {
                        return Err(LoadError::NotFinite { what, value });
                    }
                }
                Ok(())
            }
        }
    }

    /// The excited pairs on harmonic 1 with their complex coefficients
    /// `(re, im)` for a unit amplitude, merged when two waves fall on the
    /// same pair (`h = 0` or `h = N/2`), negligible ones dropped.
    pub fn pair_coefficients(&self, sectors: usize) -> Vec<(SignedPair, (f64, f64))> {
        let n = sectors.max(1);
        let mut coefficients: Vec<(SignedPair, (f64, f64))> = Vec::new();
        let mut add = |s: i64, re: f64, im: f64| {
            let pair = SignedPair::new(s, 1, n);
            if let Some(entry) = coefficients.iter_mut().find(|(p, _)| *p == pair) {
                entry.1 .0 += re;
                entry.1 .1 += im;
            } else {
                coefficients.push((pair, (re, im)));
            }
        };
        match self {
            Self::Traveling { engine_order } => add(-(*engine_order as i64), 0.5, 0.0),
            Self::Standing { engine_order } => {
                add(-(*engine_order as i64), 0.5, 0.0);
                add(*engine_order as i64, 0.5, 0.0);
            }
            Self::Mixed {
                engine_order,
                backward_weight,
                forward_weight,
            } => {
                add(-(*engine_order as i64), 0.5 * backward_weight, 0.0);
                add(*engine_order as i64, 0.5 * forward_weight, 0.0);
            }
            Self::PerSector { amplitudes, phases } => {
                // a_j cos(ωt + φ_j) = 2 Re((a_j/2) e^{iφ_j} e^{iωt}); project on
                // e^{−i s α (j−1)}: c_s = (1/N) Σ_j (a_j/2) e^{iφ_j} e^{i s α (j−1)}.
                let alpha = 2.0 * PI / n as f64;
                let half = n as i64 / 2;
                for s in (half + 1 - n as i64)..=half {
                    let (mut re, mut im) = (0.0, 0.0);
                    for (j, (a, phi)) in amplitudes.iter().zip(phases).enumerate() {
                        let angle = phi + s as f64 * alpha * j as f64;
                        re += 0.5 * a * angle.cos() / n as f64;
                        im += 0.5 * a * angle.sin() / n as f64;
                    }
                    add(s, re, im);
                }
            }
        }
        let largest = coefficients
            .iter()
            .map(|(_, (re, im))| re.hypot(*im))
            .fold(0.0, f64::max);
        coefficients.retain(|(_, (re, im))| re.hypot(*im) > NEGLIGIBLE * largest);
        coefficients
    }
}

/// Everything that loads the wheel, as far as the choice of basis goes:
/// the excitation pattern, the casing's diametral order and a static preload.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct LoadCase {
    /// Number of sectors `N`.
    pub sectors: usize,
    /// First-harmonic excitation, if any.
    pub excitation: Option<ExcitationPattern>,
    /// Diametral order `h_c` of a casing rotating synchronously (Eq. 74),
    /// the pair `(h_c, h_c)`; `None` or `Some(0)` for a circular casing.
    pub casing_order: Option<usize>,
}

impl LoadCase {
    /// Every load pair (excitation, casing, and the constant gap and static
    /// preload `(0, 0)`), with `k ≥ 0`.
    pub fn pairs(&self) -> Vec<SignedPair> {
        let mut pairs = vec![SignedPair::new(0, 0, self.sectors)];
        if let Some(excitation) = &self.excitation {
            pairs.extend(
                excitation
                    .pair_coefficients(self.sectors)
                    .into_iter()
                    .map(|(p, _)| p),
            );
        }
        if let Some(h_c) = self.casing_order.filter(|&h| h > 0) {
            pairs.push(SignedPair::new(h_c as i64, h_c as i64, self.sectors));
        }
        pairs.sort();
        pairs.dedup();
        pairs
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn traveling_wave_is_the_backward_pair() {
        let p = ExcitationPattern::Traveling { engine_order: 3 }.pair_coefficients(24);
        assert_eq!(p.len(), 1);
        assert_eq!(p[0].0, SignedPair::new(-3, 1, 24));
    }

    #[test]
    fn per_sector_traveling_wave_recovers_the_single_pair() {
        let n = 24;
        let h = 5.0;
        let alpha = 2.0 * PI / n as f64;
        let amplitudes = vec![1.0; n];
        let phases: Vec<f64> = (0..n).map(|j| alpha * j as f64 * h).collect();
        let p = ExcitationPattern::PerSector { amplitudes, phases }.pair_coefficients(n);
        assert_eq!(p.len(), 1);
        assert_eq!(p[0].0, SignedPair::new(-5, 1, n));
        assert!((p[0].1 .0 - 0.5).abs() < 1e-14 && p[0].1 .1.abs() < 1e-14);
    }

    #[test]
    fn standing_wave_at_half_order_merges() {
        let p = ExcitationPattern::Standing { engine_order: 12 }.pair_coefficients(24);
        assert_eq!(p.len(), 1);
        assert!((p[0].1 .0 - 1.0).abs() < 1e-15);
    }
}
