//! A case prepared for solving (docs/design.md §1's flow: case file →
//! model → basis → residual): the model built (mistuned where the case
//! says so), the frequency range resolved, the residual on its basis and
//! the basis record; and the length continuation scales displacements by.

use super::basis_record::{BasisRecord, HarmonicRecord};
use super::error::RunError;
use super::problem::build_problem;
use crate::case::{BasisChoice, Case, CaseError};
use crate::hbm::{Casing, HarmonicBalance};
use crate::model::SectorModel;
use std::path::{Path, PathBuf};

/// A prepared problem: everything built, nothing solved.
pub struct Prepared {
    /// The case, resolved (basis set, frequency range filled in).
    pub case: Case,
    /// The model.
    pub model: SectorModel,
    /// The residual.
    pub problem: HarmonicBalance,
    /// The basis record.
    pub basis: BasisRecord,
    /// Where the case's relative paths start (model files).
    pub case_dir: PathBuf,
}

/// The first natural frequency (Hz) of the nodal diameter the loads
/// excite (the casing's order when nothing else excites the wheel).
pub fn excited_frequency(case: &Case, model: &SectorModel) -> Result<f64, RunError> {
    let order = match case.excitation.kind {
        crate::case::ExcitationKind::None => case.casing.order as i64,
        _ => case.excitation.engine_order as i64,
    };
    let diameter =
        crate::cyclic::fold_nodal_diameter(order, model.sectors()).unsigned_abs() as usize;
    let frequencies = model.natural_frequencies()?;
    frequencies
        .iter()
        .find(|(d, _)| *d == diameter)
        .and_then(|(_, f)| f.first().copied())
        .ok_or(RunError::NoNaturalFrequency { diameter })
}

/// Builds the model, basis and residual of `case` (its relative paths taken
/// from `case_dir`) on `basis`, and resolves the frequency range.
pub fn prepare(case: &Case, case_dir: &Path, basis: BasisChoice) -> Result<Prepared, RunError> {
    case.validate()?;
    let mut case = case.clone();
    case.basis.kind = basis;
    // A mistuned wheel (issue 44) keeps the tuned sector's matrices per
    // nodal diameter and adds each sector's blade deviation to the full wheel.
    let model = case.mistuned(case.model.build(case_dir)?, case_dir)?;
    case.check_model(&model)?;
    if let Some(preload) = case.resolve_preload(case_dir, &model)? {
        log_preload(&case, &preload.displacements);
    }
    if case.continuation.start_hz.is_none() || case.continuation.end_hz.is_none() {
        let f = excited_frequency(&case, &model)?;
        case.continuation.start_hz.get_or_insert(0.95 * f);
        case.continuation.end_hz.get_or_insert(1.10 * f);
    }
    let (problem, spectral) = build_problem(&case, &model, basis)?;
    let sizes =
        crate::memory::RunSizes::of(&case, model.dofs_per_sector(), problem.layout().unknowns);
    crate::memory::check_run(&sizes).map_err(CaseError::from)?;
    // Every condensed dof: the contact dofs and, with friction, their
    // tangential dofs.
    let contact_dofs = problem.layout().contact_dofs;
    let harmonics = problem.layout().harmonic_set;
    let full_unknowns = model.sectors() * contact_dofs * harmonics.coordinates();
    let unknowns = problem.layout().unknowns;
    let record = BasisRecord {
        kind: basis.name().into(),
        unknowns,
        sampled_sectors: problem.layout().sampled_sectors,
        full_unknowns,
        reduction_percent: 100.0 * (1.0 - unknowns as f64 / full_unknowns as f64),
        harmonics: spectral
            .map(|b| {
                harmonics
                    .iter()
                    .map(|k| HarmonicRecord {
                        k,
                        signed_nodal_diameters: b.nodal_diameters(k).to_vec(),
                    })
                    .collect()
            })
            .unwrap_or_default(),
    };
    Ok(Prepared {
        case,
        model,
        problem,
        basis: record,
        case_dir: case_dir.to_path_buf(),
    })
}

/// Logs the static displacement of the contact dofs under the centrifugal
/// preload (the tip growth toward the casing).
fn log_preload(case: &Case, displacements: &[f64]) {
    let growth: Vec<String> = case
        .contact_dofs()
        .iter()
        .filter_map(|&d| displacements.get(d).map(|u| format!("{u:.3e}")))
        .collect();
    tracing::info!(
        "centrifugal preload at {} rad/s: static displacement of the contact dofs toward \
         the casing [{}] m; the gap is measured {}",
        case.preload_speed().unwrap_or(f64::NAN),
        growth.join(", "),
        if case.casing.gap_after_preload {
            "after it (casing.gap_after_preload = true)"
        } else {
            "at rest: the growth closes it (casing.gap_after_preload = false)"
        }
    );
}

/// The case's frequency range, Hz (filled in by [`prepare`]).
pub(super) fn frequency_range(case: &Case) -> Result<(f64, f64), RunError> {
    let k = &case.continuation;
    match (k.start_hz, k.end_hz) {
        (Some(start), Some(end)) => Ok((start, end)),
        _ => Err(CaseError::Invalid {
            key: "continuation.start_hz".into(),
            value: "absent".into(),
            allowed: "a frequency range (the prepared case always has one)".into(),
        }
        .into()),
    }
}

/// The length (m) by which continuation scales displacements, so that one
/// unit of arc length is worth one gap: the smallest positive mean gap;
/// when every gap is 0 (blades touching the casing at rest), the largest
/// amplitude of the casing's shape; when that is 0 too, the largest
/// coordinate of the linear response at the start frequency `linear`.
pub fn length_scale(casing: &Casing, linear: &[f64]) -> Result<f64, RunError> {
    let positive_min = |values: &[f64]| {
        values
            .iter()
            .copied()
            .filter(|v| *v > 0.0)
            .fold(None, |m: Option<f64>, v| Some(m.map_or(v, |m| m.min(v))))
    };
    let largest = |values: &[f64]| values.iter().fold(0.0_f64, |m, v| m.max(v.abs()));
    let scale = positive_min(&casing.gaps)
        .or_else(|| (largest(&casing.amplitudes) > 0.0).then(|| largest(&casing.amplitudes)))
        .or_else(|| (largest(linear) > 0.0).then(|| largest(linear)));
    match scale {
        Some(length) if length.is_finite() => Ok(length),
        _ => Err(RunError::NothingMoves),
    }
}
