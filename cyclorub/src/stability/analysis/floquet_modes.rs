//! The Floquet modes of one class at one point: the dense eigenproblem's
//! eigenvectors mapped onto the full wheel.

use super::{Stability, Wheel};
use crate::stability::hill::physical_modes;
use crate::stability::modes::{normalized, sector_mode, wheel_mode, FloquetMode};
use crate::stability::spectrum::Exponent;
use crate::stability::StabilityError;
use faer::c64;

impl Stability<'_> {
    /// The `count` exponents of largest real part of class `class` (its
    /// nodal diameter `σ`, as in [`Self::classes`]; 0 on the whole wheel)
    /// at the converged point `(x, omega)`, each with its mode on the full
    /// wheel at `t = 0` ([`FloquetMode`]), largest real part first. Always
    /// the dense eigenproblem of the class (Hill's method even where
    /// [`Self::point`] takes the weak-contact shortcut).
    pub fn modes(
        &self,
        x: &[f64],
        omega: f64,
        class: i64,
        count: usize,
    ) -> Result<Vec<FloquetMode>, StabilityError> {
        if !(omega.is_finite() && omega > 0.0) {
            return Err(StabilityError::Setting {
                key: "omega",
                value: omega.to_string(),
                allowed: "a finite angular frequency > 0",
            });
        }
        let available = || match &self.wheel {
            Wheel::Classes { classes, .. } => classes
                .iter()
                .map(|c| c.nodal_diameter.to_string())
                .collect::<Vec<_>>()
                .join(", "),
            Wheel::Physical { .. } => "0 (the whole wheel)".into(),
        };
        let no_class = || StabilityError::NoClass {
            class,
            available: available(),
        };
        let stiffness = self.contact_stiffness(x, omega)?;
        let spectrum = stiffness.spectrum(2 * self.harmonics);
        // Where each group of the eigenvector sits on the wheel.
        enum Groups {
            Pairs(Vec<(i64, i64)>),
            Harmonics(Vec<i64>, usize),
        }
        let (picked, groups) = match &self.wheel {
            Wheel::Classes { classes, dynamics } => {
                let chosen = classes
                    .iter()
                    .find(|c| c.nodal_diameter == class)
                    .ok_or_else(no_class)?;
                let table = spectrum.space_time_table();
                let b = self.class_block(chosen, dynamics, &table);
                let picked =
                    physical_modes(&b.groups, &b.coupling, &b.damping, omega, b.step, true)?;
                let pairs = chosen
                    .pairs
                    .iter()
                    .map(|p| (p.nodal_diameter, p.harmonic))
                    .collect();
                (picked, Groups::Pairs(pairs))
            }
            Wheel::Physical { dynamics } => {
                if class != 0 {
                    return Err(no_class());
                }
                let (groups, coupling, damping) = self.wheel_block(dynamics, &spectrum);
                let picked = physical_modes(&groups, &coupling, &damping, omega, 1, true)?;
                let harmonics = groups.iter().map(|g| g.harmonic).collect();
                (picked, Groups::Harmonics(harmonics, dynamics.dofs()))
            }
        };
        let sectors = self.problem.layout().sectors;
        let map = |q: &[c64], lambda: c64| match &groups {
            Groups::Pairs(pairs) => sector_mode(q, pairs, self.dofs, sectors, lambda, omega),
            Groups::Harmonics(harmonics, size) => wheel_mode(q, harmonics, *size, lambda, omega),
        };
        picked
            .into_iter()
            .take(count)
            .map(|(p, q)| {
                let (y, v) = map(&q, p.exponent);
                let (displacement, velocity) =
                    normalized(y, v).ok_or_else(|| StabilityError::Eigen {
                        message: format!(
                            "the mode of the exponent {:.6e} {:+.6e}i of class {class} vanishes at t = 0",
                            p.exponent.re, p.exponent.im
                        ),
                    })?;
                Ok(FloquetMode {
                    nodal_diameter: class,
                    exponent: Exponent::new(p.exponent),
                    omega,
                    truncation: p.edge,
                    displacement,
                    velocity,
                })
            })
            .collect()
    }
}
