//! What `results.h5` holds, from a solved branch and its points'
//! summaries: the points, the linear response, the natural frequencies and
//! (when asked) the peak point's time histories.

use super::{RunError, Solution};
use crate::case::{BasisChoice, Case};
use crate::continuation::{Branch, Sweeps};
use crate::hbm::HarmonicBalance;
use crate::model::SectorModel;
use crate::results::data::{LinearResponse, PointHistories, PointResults, ResultsData};
use crate::results::recovery::PointSummary;
use crate::results::stability::StabilityData;
use rayon::prelude::*;
use serde::Serialize;
use std::f64::consts::PI;

impl Solution {
    /// Everything `results.h5` holds (see [`ResultsData`]).
    pub fn results_data(&self) -> Result<ResultsData, RunError> {
        let summaries = self
            .point_summaries()
            .into_iter()
            .collect::<Result<Vec<_>, _>>()?;
        results_data_from(self, summaries)
    }
}

/// The linear problem of a case on its symmetry basis: the cheapest exact
/// way to the linear response, whatever basis the branch was solved on.
/// A mistuned wheel has no symmetry basis: its linear response is the
/// full wheel's (issue 44).
fn linear_problem(case: &Case, model: &SectorModel) -> Result<HarmonicBalance, RunError> {
    let basis = if model.is_mistuned() {
        BasisChoice::Physical
    } else {
        BasisChoice::Symmetry
    };
    Ok(super::build_problem(case, model, basis)?.0)
}

/// Branch frequencies the linear curve takes at most: the continuation
/// gathers points where the response bends, which is where the linear
/// curve needs them too, but a long branch would make the linear curve
/// cost as much as the rest of the output.
const LINEAR_BRANCH_FREQUENCIES: usize = 300;

/// The frequencies (Hz) of the linear curve: the branch's (at most
/// [`LINEAR_BRANCH_FREQUENCIES`], evenly picked along it), 300 evenly
/// spaced over its range, and the natural frequencies inside it.
fn linear_frequencies(branch: &Branch, natural: &[(usize, Vec<f64>)]) -> Vec<f64> {
    let every = branch
        .points
        .len()
        .div_ceil(LINEAR_BRANCH_FREQUENCIES)
        .max(1);
    let mut list: Vec<f64> = branch
        .points
        .iter()
        .step_by(every)
        .map(|p| p.omega / (2.0 * PI))
        .collect();
    let low = list.iter().cloned().fold(f64::INFINITY, f64::min);
    let high = list.iter().cloned().fold(f64::NEG_INFINITY, f64::max);
    if high > low {
        list.extend((0..=300).map(|i| low + (high - low) * i as f64 / 300.0));
        list.extend(
            natural
                .iter()
                .flat_map(|(_, f)| f.iter().cloned())
                .filter(|f| (low..=high).contains(f)),
        );
    }
    list
}

/// [`Solution::results_data`] from the points' summaries (same order as
/// the points): per point the observed dof and the contact state on all
/// sectors and the cyclic components, the linear response, the natural
/// frequencies and, with `[output] peak_histories`, the time histories of
/// the point of largest amplitude.
pub(crate) fn results_data_from(
    solution: &Solution,
    summaries: Vec<PointSummary>,
) -> Result<ResultsData, RunError> {
    let Solution {
        case,
        model,
        problem,
        branch,
        basis,
        mode,
        ..
    } = solution;
    let dof = case.output.observed_index();
    let time_samples = case.harmonic_balance.time_samples;
    let points = branch
        .points
        .par_iter()
        .zip(summaries.into_par_iter())
        .map(|(point, summary)| {
            PointResults::from_summary(point, summary.observed, summary.contact?)
        })
        .collect::<Result<Vec<_>, _>>()?;
    let natural_frequencies = model.natural_frequencies()?;
    let linear_problem = linear_problem(case, model)?;
    let linear = LinearResponse::compute(
        &linear_problem,
        dof,
        &linear_frequencies(branch, &natural_frequencies),
        time_samples,
    )?;
    let mut data = ResultsData {
        case_json: json(case),
        basis_json: json(basis),
        mode: *mode,
        stop_json: json(&branch.stop),
        sectors: model.sectors(),
        harmonics: problem.layout().harmonics(),
        time_samples,
        observed_dof: case.output.observed_dof,
        observed_name: observed_name_of(case, model),
        contact_dofs: case.contact.dofs.clone(),
        points,
        linear,
        natural_frequencies,
        histories: None,
        gap_after: branch.sweeps.as_ref().and_then(Sweeps::gap_after),
        stability: solution
            .stability
            .computed()
            .map(StabilityData::from_branch),
        // Set by the run, which solves the tuned reference (run/mistuning.rs).
        mistuning: None,
        branches: Vec::new(),
    };
    if let Some(peak) = data.peak_point().filter(|_| case.output.peak_histories) {
        data.histories = Some(PointHistories::compute(
            problem,
            &branch.points[peak],
            peak,
            dof,
            time_samples,
        )?);
    }
    Ok(data)
}

/// The observed dof's name ([`crate::results::data::observed_name`]).
pub(crate) fn observed_name_of(case: &Case, model: &crate::model::SectorModel) -> String {
    crate::results::data::observed_name(
        model,
        case.output.observed_index(),
        case.model.kind == crate::model::ModelKind::Academic,
    )
}

/// JSON text of a record (records always serialize; say so if one did not).
pub(crate) fn json(value: &impl Serialize) -> String {
    serde_json::to_string(value).unwrap_or_else(|e| format!("{{\"error\": \"{e}\"}}"))
}
