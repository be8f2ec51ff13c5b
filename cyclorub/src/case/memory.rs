//! A case's sizes for the memory estimates, and the estimates' refusals
//! as case errors: here rather than in `memory`, so that `memory` (which
//! the harmonic balance problem uses) does not depend on the case.

use super::{Case, CaseError};
use crate::memory::{Refused, RunSizes, TooMuchMemory};

impl RunSizes {
    /// The sizes of `case` on a model of `dofs_per_sector` dofs, solved
    /// for `unknowns` unknowns.
    pub fn of(case: &Case, dofs_per_sector: usize, unknowns: usize) -> Self {
        let sectors = case.model.sectors;
        Self {
            sectors,
            dofs_per_sector,
            contact_dofs: case.contact.dofs.len(),
            harmonics: case.harmonic_balance.harmonics,
            time_samples: case.harmonic_balance.time_samples,
            unknowns,
            reported_sectors: match case.output.sectors.len() {
                0 => sectors,
                n => n,
            },
            max_points: case.continuation.max_points,
            stability: case.stability.enabled,
            threads: rayon::current_num_threads().max(1),
        }
    }
}

impl From<TooMuchMemory> for CaseError {
    fn from(error: TooMuchMemory) -> Self {
        CaseError::Invalid {
            key: error.key.clone(),
            value: error.value.to_string(),
            allowed: error.allowed(),
        }
    }
}

impl From<Refused> for CaseError {
    fn from(error: Refused) -> Self {
        CaseError::Invalid {
            key: error.key,
            value: error.value,
            allowed: error.allowed,
        }
    }
}
