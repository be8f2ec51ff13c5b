//! What every stability check holds besides its wheel: the contact dofs
//! (with friction, each node's tangential ones), Hill's truncation, the
//! time sampling and the solver, checked against the model and the
//! problem before any work; and the size a class may have.

use super::settings::{HillSolver, StabilitySettings};
use super::StabilityError;
use crate::hbm::{HarmonicBalance, HarmonicSet};
use crate::model::SectorModel;

/// The contact dofs of `problem` on the sector: `normal` (the case's
/// contact dofs), then with friction each node's circumferential and axial
/// dofs, as the problem's layout orders them. A wall in series
/// (`contact.wall_stiffness`) with friction is refused: its tangential
/// springs are not in Hill's matrices.
pub(super) fn with_friction_nodes(
    problem: &HarmonicBalance,
    normal: &[usize],
) -> Result<Vec<usize>, StabilityError> {
    let Some(friction) = problem.friction() else {
        return Ok(normal.to_vec());
    };
    if problem.linear().wall_stiffness().is_some() {
        return Err(StabilityError::Friction);
    }
    Ok(normal
        .iter()
        .copied()
        .chain(
            friction
                .nodes()
                .iter()
                .flat_map(|n| [n.circumferential, n.axial]),
        )
        .collect())
}

/// The largest Hill truncation taken (a larger one would overflow the
/// sizes before the eigenproblem limit could refuse it).
const MOST_HARMONICS: usize = 100_000;

/// What every check holds besides its wheel.
pub(super) struct Common {
    pub(super) contact_dofs: Vec<usize>,
    pub(super) dofs: usize,
    pub(super) harmonics: usize,
    pub(super) time_samples: usize,
    pub(super) tolerance: f64,
    pub(super) solver: HillSolver,
}

impl Common {
    pub(super) fn new(
        model: &SectorModel,
        problem: &HarmonicBalance,
        contact_dofs: &[usize],
        settings: &StabilitySettings,
    ) -> Result<Self, StabilityError> {
        let layout = problem.layout();
        if contact_dofs.len() != layout.contact_dofs
            || contact_dofs.iter().any(|&d| d >= model.dofs_per_sector())
            || model.sectors() != layout.sectors
        {
            return Err(StabilityError::Mismatch {
                message: format!(
                    "{} contact dofs on a {}-sector model of {} dofs per sector, for a problem of {} contact dofs on {} sectors",
                    contact_dofs.len(),
                    model.sectors(),
                    model.dofs_per_sector(),
                    layout.contact_dofs,
                    layout.sectors
                ),
            });
        }
        let harmonics = settings.harmonics.unwrap_or(layout.harmonics());
        if harmonics > MOST_HARMONICS {
            return Err(StabilityError::Setting {
                key: "stability.harmonics",
                value: harmonics.to_string(),
                allowed: "an integer from 1 to 100000 (Hill's truncation)",
            });
        }
        if harmonics == 0 {
            return Err(StabilityError::Setting {
                key: "stability.harmonics",
                value: "0".into(),
                allowed: "an integer ≥ 1 (Hill's truncation)",
            });
        }
        if !(settings.tolerance.is_finite() && settings.tolerance >= 0.0) {
            return Err(StabilityError::Setting {
                key: "stability.tolerance",
                value: settings.tolerance.to_string(),
                allowed: "a finite number ≥ 0",
            });
        }
        Ok(Self {
            contact_dofs: contact_dofs.to_vec(),
            dofs: model.dofs_per_sector(),
            harmonics,
            // The stiffness's coefficients up to 2H must not alias.
            time_samples: problem
                .time_samples()
                .max(HarmonicSet::up_to(harmonics).coupling_time_samples()),
            tolerance: settings.tolerance,
            solver: Self::solver(problem, settings.solver),
        })
    }

    /// The solver asked for, except with friction: the targeted solver holds
    /// the normal stiffness alone, so friction is solved densely (said once).
    fn solver(problem: &HarmonicBalance, asked: HillSolver) -> HillSolver {
        if problem.friction().is_none() || asked != HillSolver::Targeted {
            return asked;
        }
        tracing::warn!(
            "stability.solver = \"targeted\" holds the normal stiffness alone: \
             with contact.friction every class is solved densely"
        );
        HillSolver::Dense
    }

    /// Refuses a class of `pairs` groups of `sectors` sectors' dofs above
    /// the largest eigenproblem: the dense one, `2 · dofs · pairs`, or for
    /// the condensed solver `2 · contact dofs · pairs` (its LUs are of
    /// `contact dofs · pairs`).
    pub(super) fn refuse_above(
        &self,
        pairs: usize,
        sectors: usize,
        settings: &StabilitySettings,
    ) -> Result<(), StabilityError> {
        let per_pair = match self.solver {
            HillSolver::Condensed => self.contact_dofs.len(),
            _ => self.dofs,
        };
        let size = 2usize
            .saturating_mul(per_pair)
            .saturating_mul(sectors)
            .saturating_mul(pairs);
        if size > settings.largest_eigenproblem {
            return Err(StabilityError::TooLarge {
                size,
                limit: settings.largest_eigenproblem,
                harmonics: self.harmonics,
            });
        }
        Ok(())
    }
}
