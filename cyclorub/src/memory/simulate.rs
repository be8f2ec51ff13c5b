//! The memory of a time integration of the full wheel (`cyclorub
//! simulate`): the wheel's matrices and factorizations, the contact
//! matrices of the Newton on the contact forces, a record per period and
//! every step of the last periods.

use super::{complexes, doubles, Budget, Estimate, TooMuchMemory};

/// The sizes of a time integration that its memory depends on.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SimulationSizes {
    /// `N`.
    pub sectors: usize,
    /// Dofs of a sector.
    pub dofs_per_sector: usize,
    /// Contact dofs of a sector.
    pub contact_dofs: usize,
    /// Periods integrated at most (a sweep: those of its duration).
    pub periods: u64,
    /// Steps per period.
    pub steps_per_period: u64,
    /// Periods whose every step is kept.
    pub history_periods: u64,
    /// Whether the periods come from a sweep (`--rate`) rather than
    /// `--periods`.
    pub sweep: bool,
}

impl SimulationSizes {
    /// The wheel alone: no period yet.
    pub fn of_wheel(sectors: usize, dofs_per_sector: usize, contact_dofs: usize) -> Self {
        Self {
            sectors,
            dofs_per_sector,
            contact_dofs,
            periods: 0,
            steps_per_period: 0,
            history_periods: 0,
            sweep: false,
        }
    }

    /// Bytes of the wheel: `M(s)`, `K(s)`, `C(s)` of the `N/2 + 1`
    /// diameters, their circulant copies and two factorizations (complex,
    /// `dofs²` each), and the wheel's contact flexibility, Jacobian and
    /// Lagrange matrices (`(N n_c)²` reals each).
    pub fn wheel(&self) -> f64 {
        let n = self.dofs_per_sector as f64;
        let diameters = self.sectors as f64 / 2.0 + 1.0;
        let contacts = self.sectors as f64 * self.contact_dofs as f64;
        complexes(diameters * 8.0 * n * n) + doubles(3.0 * contacts * contacts)
    }

    /// Bytes of a period's record: envelope, peak force and Poincaré
    /// section per sector.
    pub fn per_period(&self) -> f64 {
        doubles(4.0 * self.sectors as f64 + 12.0)
    }

    /// Bytes of the kept steps: time, the observed dof's displacement and
    /// velocity per sector, the contact dofs' displacement and force; the
    /// last periods are kept apart, then joined (twice).
    pub fn histories(&self) -> f64 {
        let kept = self.history_periods.min(self.periods.max(1)) as f64 + 1.0;
        let sectors = self.sectors as f64;
        let per_step = 1.0 + 2.0 * sectors + 2.0 * sectors * self.contact_dofs as f64;
        2.0 * kept * self.steps_per_period as f64 * doubles(per_step)
    }

    /// The estimate of the whole integration.
    pub fn estimate(&self) -> Estimate {
        Estimate::new()
            .part(
                format!("the full wheel's matrices ({} sectors)", self.sectors),
                self.wheel(),
            )
            .part(
                format!("a record per period ({} periods)", self.periods),
                self.periods as f64 * self.per_period(),
            )
            .part("the steps of the last periods", self.histories())
    }

    /// Refuses the wheel (`model.sectors`) when its matrices do not fit;
    /// call before they are built.
    pub fn check_wheel(&self) -> Result<(), TooMuchMemory> {
        let rows = self.dofs_per_sector.max(self.sectors * self.contact_dofs);
        let estimate = Estimate::new().part(
            format!("the full wheel's matrices ({} sectors)", self.sectors),
            self.wheel(),
        );
        let fits = |n: u64| {
            Self {
                sectors: n as usize,
                ..*self
            }
            .wheel()
        };
        Budget::of_this_process(rows).check(
            "model.sectors",
            self.sectors as u64,
            &estimate,
            Some(&fits),
        )
    }

    /// Refuses the periods (`--periods`, or `--rate` for a sweep) or the
    /// kept steps (`--history-periods`, `--steps-per-period`), whichever
    /// weighs most, when the whole integration does not fit.
    pub fn check_run(&self) -> Result<(), TooMuchMemory> {
        let rows = self.dofs_per_sector.max(self.sectors * self.contact_dofs);
        self.check_against(&Budget::of_this_process(rows))
    }

    fn check_against(&self, budget: &Budget) -> Result<(), TooMuchMemory> {
        let estimate = self.estimate();
        let records = self.periods as f64 * self.per_period();
        if records >= self.histories() {
            let key = if self.sweep {
                "the sweep's periods (--sweep, --rate)"
            } else {
                "--periods"
            };
            let fits = |n: u64| {
                Self {
                    periods: n,
                    ..*self
                }
                .estimate()
                .total()
            };
            let fits: &dyn Fn(u64) -> f64 = &fits;
            budget.check(key, self.periods, &estimate, (!self.sweep).then_some(fits))
        } else if self.history_periods >= self.steps_per_period {
            let fits = |n: u64| {
                Self {
                    history_periods: n,
                    ..*self
                }
                .estimate()
                .total()
            };
            budget.check(
                "--history-periods",
                self.history_periods,
                &estimate,
                Some(&fits),
            )
        } else {
            let fits = |n: u64| {
                Self {
                    steps_per_period: n,
                    ..*self
                }
                .estimate()
                .total()
            };
            budget.check(
                "--steps-per-period",
                self.steps_per_period,
                &estimate,
                Some(&fits),
            )
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn default_run() -> SimulationSizes {
        SimulationSizes {
            periods: 200,
            steps_per_period: 256,
            history_periods: 5,
            ..SimulationSizes::of_wheel(24, 5, 1)
        }
    }

    #[test]
    fn the_default_integration_is_small() {
        let total = default_run().estimate().total();
        assert!(total < 1e7, "{total}");
    }

    #[test]
    fn absurd_sizes_name_their_option() {
        let budget = Budget {
            bytes: 2e9,
            source: "2.0 GB left".into(),
        };
        let refused = |sizes: SimulationSizes| sizes.check_against(&budget).unwrap_err();
        let e = refused(SimulationSizes {
            periods: 1_000_000_000_000,
            ..default_run()
        });
        assert_eq!(e.key, "--periods");
        assert!(e.largest.is_some_and(|n| n > 1_000_000), "{e}");
        let e = refused(SimulationSizes {
            steps_per_period: 1_000_000_000_000,
            ..default_run()
        });
        assert_eq!(e.key, "--steps-per-period");
        let e = refused(SimulationSizes {
            periods: 1_000_000_000,
            history_periods: 1_000_000_000,
            ..default_run()
        });
        assert_eq!(e.key, "--history-periods");
        let e = refused(SimulationSizes {
            sweep: true,
            periods: 1_000_000_000_000,
            ..default_run()
        });
        assert!(e.key.starts_with("the sweep"), "{e}");
        // 10000 sectors: the contact matrices of the wheel, 2.4 GB.
        let wheel = SimulationSizes::of_wheel(10_000, 5, 1).wheel();
        assert!((2.4e9..2.5e9).contains(&wheel), "{wheel}");
    }
}
