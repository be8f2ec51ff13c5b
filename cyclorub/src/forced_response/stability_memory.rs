//! Whether the stability check fits in memory beside the run (issue 45
//! item 19): the size of its largest class, from the problem's pairs as
//! the check groups them, handed to [`crate::memory::check_stability`].

use super::Prepared;
use super::RunError;
use crate::basis::PairLattice;
use crate::case::CaseError;
use crate::cyclic::SignedPair;
use crate::hbm::layout::BlockKind;
use crate::memory::{check_stability, RunSizes, StabilitySizes};
use crate::stability::{pairs_per_class, StabilitySettings};

/// Rows of the largest dense eigenproblem the check may solve: a class's
/// `2 · dofs · pairs` (the condensed solver falls back to it), or on the
/// physical basis the wheel's `2 · dofs · N · (2H + 1)`.
pub(crate) fn largest_eigenproblem_rows(
    prepared: &Prepared,
    settings: &StabilitySettings,
) -> usize {
    let layout = prepared.problem.layout();
    let harmonics = settings.harmonics.unwrap_or(layout.harmonics());
    let dofs = prepared.model.dofs_per_sector();
    let pairs: Vec<SignedPair> = layout
        .blocks
        .iter()
        .filter_map(|b| match b.kind {
            BlockKind::Pair { nodal_diameter } => Some(SignedPair {
                nodal_diameter,
                harmonic: b.harmonic as i64,
            }),
            BlockKind::Wheel => None,
        })
        .collect();
    let pairs_per_class = match PairLattice::generated_by(layout.sectors, &pairs) {
        Ok(lattice) if !pairs.is_empty() => pairs_per_class(&lattice, harmonics),
        // The whole wheel (or pairs the check will refuse itself).
        _ => layout
            .sectors
            .saturating_mul(harmonics.saturating_mul(2).saturating_add(1)),
    };
    2usize.saturating_mul(dofs).saturating_mul(pairs_per_class)
}

/// Refuses the stability check of `prepared`'s points when it does not fit
/// beside the run (see [`crate::memory::StabilitySizes`]); `own_thread`:
/// the check runs on a thread of its own (`cyclorub run`'s writer).
pub(crate) fn check_stability_memory(
    prepared: &Prepared,
    settings: &StabilitySettings,
    own_thread: bool,
) -> Result<(), RunError> {
    let run = RunSizes::of(
        &prepared.case,
        prepared.model.dofs_per_sector(),
        prepared.problem.layout().unknowns,
    );
    let sizes = StabilitySizes {
        rows: largest_eigenproblem_rows(prepared, settings),
        threads: rayon::current_num_threads().max(1),
        own_thread,
    };
    check_stability(&sizes, run.estimate().total(), run.largest_matrix())
        .map_err(CaseError::from)?;
    Ok(())
}
