//! What `run.json` records of a run: the basis, the timings, the stop,
//! the stability check and its markers, and the plausibility warnings.

use super::*;

/// A stability marker as `run.json` records it: the marker and the
/// amplitude there (the largest over the reported sectors, interpolated).
#[derive(Clone, Debug, Serialize)]
pub struct MarkerRecord {
    /// The marker.
    #[serde(flatten)]
    pub marker: Marker,
    /// Observed amplitude at the marker, m.
    pub amplitude_m: f64,
}

/// Markers of one kind and direction within 1e-4 of each other in
/// frequency ([`crate::stability::EVENT_GROUPING`]) (a whole set of nodal diameters crossing at first contact),
/// shown as one line.
#[derive(Clone, Debug)]
pub struct MarkerGroup<'a> {
    /// The markers, in branch order (at least one).
    pub records: Vec<&'a MarkerRecord>,
}

impl MarkerGroup<'_> {
    /// The first marker of the group.
    pub fn first(&self) -> &MarkerRecord {
        self.records[0]
    }

    /// The classes' nodal diameters, sorted, each once.
    pub fn nodal_diameters(&self) -> Vec<i64> {
        crate::stability::nodal_diameters(self.records.iter().map(|r| &r.marker))
    }

    /// The exponent, when the group is one marker.
    pub fn exponent(&self) -> Option<Exponent> {
        (self.records.len() == 1).then(|| self.records[0].marker.exponent)
    }
}

/// The events among `markers` (in branch order; see
/// [`Marker::is_event`](crate::stability::Marker::is_event)) grouped as
/// [`MarkerGroup`] says ([`crate::stability::group_events`]).
pub fn group_markers(markers: &[MarkerRecord]) -> Vec<MarkerGroup<'_>> {
    crate::stability::group_events(markers, |r| &r.marker)
        .into_iter()
        .map(|records| MarkerGroup { records })
        .collect()
}

/// How many of `markers` are not events: Neimark–Sacker crossings of a
/// further exponent in a class already unstable (kept in `run.json`).
pub fn further_crossings(markers: &[MarkerRecord]) -> usize {
    markers.iter().filter(|r| !r.marker.is_event()).count()
}

/// What the stability check of the run gave (`run.json`'s `stability`).
#[derive(Clone, Debug, Serialize)]
pub struct StabilityRecord {
    /// Computed, not computed (with its reason) or not asked.
    pub status: StabilityStatus,
    /// Why it was not computed.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub reason: Option<String>,
    /// Harmonics of Hill's truncation.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub harmonics: Option<usize>,
    /// Points solved by Hill's method (the others were off contact).
    pub points_by_hill: usize,
    /// Points with a growing exponent.
    pub unstable_points: usize,
    /// Where stability changes along the branch.
    pub markers: Vec<MarkerRecord>,
    /// Time of the check, s (in `cyclorub run`, on the writer's thread
    /// alongside the solve, point by point as they are accepted).
    pub time_s: f64,
}

/// Wall-clock times, seconds.
#[derive(Clone, Debug, Serialize)]
pub struct Timings {
    /// Model, basis and residual set-up.
    pub setup_s: f64,
    /// Continuation.
    pub solve_s: f64,
    /// Recovery and files.
    pub output_s: f64,
}

/// What `run.json` holds.
#[derive(Clone, Debug, Serialize)]
pub struct RunRecord {
    /// `finished` (everything asked for was done), `interrupted` (stopped
    /// from outside: the branch, or the stability check after it) or
    /// `stopped_early` (the branch stopped short, or points did not
    /// converge); while the run goes on, `run.json` says `running`.
    pub status: RunStatus,
    /// The case as resolved (defaults filled, frequency range set).
    pub case: Case,
    /// The basis.
    pub basis: BasisRecord,
    /// Arc-length continuation, or solves at given frequencies.
    pub mode: RunMode,
    /// How the first point was reached.
    pub start: StartRecord,
    /// Why the branch stopped.
    pub stop: StopReason,
    /// When the sweep from the start stopped short of the end: how the
    /// branch was followed back from the end and joined (absent otherwise).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub sweeps: Option<Sweeps>,
    /// Events along the branch (folds, branch points, kinks, the stop),
    /// numbered by point.
    pub events: Vec<Event>,
    /// Points written.
    pub points: usize,
    /// Points that did not converge (fixed-frequency mode only).
    pub failed_points: usize,
    /// Newton iterations in total.
    pub total_iterations: usize,
    /// Times.
    pub timings: Timings,
    /// The stability check.
    pub stability: StabilityRecord,
    /// The static preload, when `[preload]` sets one.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub preload: Option<PreloadRecord>,
    /// The results folder.
    pub output: PathBuf,
    /// Results no engineer would believe, in words (see
    /// [`PLAUSIBLE_GAPS`]); empty for a plausible run.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub warnings: Vec<String>,
    /// A mistuned wheel's sector peaks and amplification factor (issue 44;
    /// absent for a tuned wheel).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub mistuning: Option<mistuning::MistuningRecord>,
}

/// What the static preload did to the contact dofs.
#[derive(Clone, Debug, Serialize, PartialEq)]
pub struct PreloadRecord {
    /// The speed of the centrifugal force, rad/s (absent: no centrifugal force).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub centrifugal_speed: Option<f64>,
    /// The static displacement of each contact dof toward the casing, m
    /// (the tip growth).
    pub contact_static_displacements: Vec<f64>,
    /// Whether `casing.gap` is measured on the preloaded blade.
    pub gap_after_preload: bool,
    /// Each contact dof's gap measured from the blade at rest, m: `casing.gap`
    /// plus the growth when measured after the preload.
    pub gaps_from_rest: Vec<f64>,
}

impl PreloadRecord {
    /// The record of `case`'s preload on `model`, `None` without one.
    pub fn of(case: &Case, model: &crate::model::SectorModel) -> Result<Option<Self>, RunError> {
        let Some(forces) = case.preload_forces(model)? else {
            return Ok(None);
        };
        let response = model.static_response(&forces, "preload")?;
        let growth: Vec<f64> = case
            .contact_dofs()
            .iter()
            .map(|&d| response.get(d).copied().unwrap_or(0.0))
            .collect();
        let gaps = case.casing()?.gaps;
        let gaps_from_rest = gaps
            .iter()
            .zip(&growth)
            .map(|(g, u)| {
                if case.casing.gap_after_preload {
                    g + u
                } else {
                    *g
                }
            })
            .collect();
        Ok(Some(Self {
            centrifugal_speed: case
                .preload
                .centrifugal
                .then(|| case.preload_speed().ok())
                .flatten(),
            contact_static_displacements: growth,
            gap_after_preload: case.casing.gap_after_preload,
            gaps_from_rest,
        }))
    }
}

/// A displacement beyond this many gaps (the largest `casing.gap`) is not
/// believed: a blade that far from its casing means a load, a law or a
/// model out of proportion, and the run says so in its record.
pub const PLAUSIBLE_GAPS: f64 = 100.0;

/// The warnings of a run whose largest displacement of the observed dof
/// over every point and sector is `largest` (m).
pub(super) fn plausibility(case: &Case, largest: f64) -> Vec<String> {
    let gap = match &case.casing.gap {
        crate::case::PerContactDof::One(g) => *g,
        crate::case::PerContactDof::Each(g) => g.iter().cloned().fold(0.0, f64::max),
    };
    let mut warnings = Vec::new();
    if !largest.is_finite() || (gap > 0.0 && largest > PLAUSIBLE_GAPS * gap) {
        warnings.push(format!(
            "the observed dof moves by up to {largest:.3e} m, {:.0} times the gap (casing.gap = {gap:e} m): \
             results no engineer would believe; check the loads (excitation.amplitude, \
             excitation.static_force), the contact law (contact.stiffness, contact.regularization, \
             contact.epsilon) and the model's units",
            largest / gap
        ));
    }
    warnings
}

/// The warning of a stability check whose Hill truncation (`harmonics`,
/// `None`: not checked) is below the orbit's harmonics: its linearization
/// drops harmonics the orbit has, and a coarse truncation can call an
/// unstable branch stable (measured: six sectors at `N_h = 3` with `H = 1`,
/// no growth; the orbit refined to `H = 4`, six growing exponents).
pub(super) fn coarse_hill(case: &Case, harmonics: Option<usize>) -> Option<String> {
    let orbit = case.harmonic_balance.harmonics;
    let hill = harmonics?;
    (hill < orbit).then(|| {
        format!(
            "Hill's truncation (stability.harmonics = {hill}) is below the orbit's \
             (harmonic_balance.harmonics = {orbit}): the exponents are those of a coarser \
             linearization, and growth can be missed; leave stability.harmonics unset (the \
             orbit's) or raise it, and read `cyclorub stability RESULTS --point P`"
        )
    })
}

impl RunRecord {
    /// Whether the run did all it was asked: the branch reached the end
    /// frequency (or every frequency asked for was solved) and every point
    /// converged.
    pub fn finished(&self) -> bool {
        matches!(
            self.stop,
            StopReason::EndReached | StopReason::AllFrequenciesDone
        ) && self.failed_points == 0
    }
}
