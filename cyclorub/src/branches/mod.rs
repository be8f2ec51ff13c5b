//! Bifurcated branches (docs/design.md §11): where the wheel goes when the
//! symmetric branch loses stability to a class `σ` through a real
//! multiplier (a branch point). The bifurcated branch keeps the symmetry
//! that the pairs of `P` and `(σ, 0)` leave, so it is solved on that
//! enlarged basis ([`EnlargedBasis`]), exactly and at reduced cost:
//! located on the symmetric branch ([`BranchPoint`]), entered along the
//! null vector on both sides, and continued in frequency ([`Side`]). Its
//! points are periodic responses in which the sectors no longer move
//! alike: [`sector_amplitudes`] says how much they differ.

mod basis;
mod follow;
mod locate;

pub use basis::{layout_pairs, EnlargedBasis};
pub use follow::{Side, SideStop};
pub use locate::BranchPoint;

use crate::basis::{BasisError, SpectralBasis};
use crate::case::Case;
use crate::continuation::{ContinuationError, NewtonSettings, Point, Settings};
use crate::forced_response::problem_on_basis;
use crate::hbm::HarmonicBalance;
use crate::model::SectorModel;
use crate::results::bifurcated::BifurcatedSide;
use crate::results::recovery::dof_peaks;
use crate::results::ResultsError;

/// Why a branch could not be switched to.
#[derive(Debug, thiserror::Error, PartialEq)]
pub enum BranchError {
    /// The symmetric branch was solved on the physical full wheel: it has
    /// no symmetry to break.
    #[error("the symmetric branch is on the physical full wheel (basis.kind = \"physical\"): it has no symmetry class to switch from; solve it on a cyclic basis (\"symmetry\")")]
    PhysicalBasis,
    /// The class is the symmetric branch's own.
    #[error("class {class} is the symmetric branch's own (its pair ({class}, 0) is in the basis): a real crossing there is a fold or a branch point between symmetric branches, not switched yet")]
    ClassInBasis {
        /// The class `σ`.
        class: i64,
    },
    /// The class is not a nodal diameter of the wheel as classes are named.
    #[error("class {class}: a class is a nodal diameter in (−N/2, N/2], here {lowest}..={highest} (N = {sectors})", lowest = (*sectors as i64) / 2 + 1 - *sectors as i64, highest = *sectors as i64 / 2)]
    ClassOutOfRange {
        /// The class given.
        class: i64,
        /// The number of sectors `N`.
        sectors: usize,
    },
    /// The enlarged basis could not be built.
    #[error(transparent)]
    Basis(#[from] BasisError),
    /// The enlarged problem could not be built.
    #[error("building the enlarged problem: {0}")]
    Build(String),
    /// An evaluation of the residual failed.
    #[error("evaluating the residual: {0}")]
    Evaluation(String),
    /// The symmetric solution does not embed in the enlarged layout.
    #[error("the symmetric solution does not embed in the enlarged basis (a pair of the symmetric basis is missing there)")]
    Embedding,
    /// The problem's Jacobian is too large to be formed.
    #[error("the enlarged problem ({unknowns} unknowns) solves with a structured Jacobian; branch switching forms the dense one and is not available there yet")]
    TooLarge {
        /// Unknowns of the enlarged problem.
        unknowns: usize,
    },
    /// The test function keeps its sign between the two points.
    #[error("no real multiplier crosses +1 between {from_hz:.6} and {to_hz:.6} Hz (the enlarged Jacobian's least eigenvalue keeps its sign: {before:.3e} and {after:.3e} of its largest entry); no simple real crossing there: either a complex pair (Neimark–Sacker, a quasi-periodic response, no periodic branch) or σ and −σ crossing together (a two-dimensional kernel, whose branches this switch does not follow yet; the located marker's multiplier angle in run.json tells them apart)")]
    NoSignChange {
        /// First point, Hz.
        from_hz: f64,
        /// Second point, Hz.
        to_hz: f64,
        /// Test function at the first point (relative).
        before: f64,
        /// Test function at the second point (relative).
        after: f64,
    },
    /// The least eigenvalue of the new block is not real.
    #[error("at {frequency_hz:.6} Hz the enlarged Jacobian's eigenvalue nearest to 0 is not real (inverse iteration did not settle, last estimate {eigenvalue:.3e}): no simple real crossing there (a complex pair, or σ and −σ crossing together: a two-dimensional kernel this switch does not follow yet)")]
    NotReal {
        /// Frequency, Hz.
        frequency_hz: f64,
        /// The last Rayleigh quotient.
        eigenvalue: f64,
    },
    /// The bracket cannot be searched.
    #[error("at {frequency_hz:.6} Hz: {why}")]
    Bracket {
        /// Frequency, Hz.
        frequency_hz: f64,
        /// What went wrong.
        why: String,
    },
    /// The continuation refused its settings or its first point.
    #[error(transparent)]
    Continuation(#[from] ContinuationError),
}

impl BranchError {
    /// Whether the error is in what the user asked for (a basis or class
    /// with nothing to switch from), not in the computation.
    pub fn is_input_error(&self) -> bool {
        matches!(
            self,
            Self::PhysicalBasis | Self::ClassInBasis { .. } | Self::ClassOutOfRange { .. }
        )
    }
}

/// A bifurcated branch: both sides off one branch point.
pub struct BifurcatedBranch {
    /// The class `σ` of the branch point.
    pub class: i64,
    /// The enlarged basis.
    pub basis: SpectralBasis,
    /// Real unknowns of the enlarged problem.
    pub unknowns: usize,
    /// Real unknowns of the full wheel on the same contact dofs.
    pub full_unknowns: usize,
    /// The located branch point.
    pub branch_point: BranchPoint,
    /// The two sides, `+v` then `−v`.
    pub sides: Vec<Side>,
    /// The enlarged problem the sides' unknowns are laid out for.
    pub problem: HarmonicBalance,
}

impl BifurcatedBranch {
    /// Each side as a results folder keeps it: the frequencies, the
    /// verdicts `stable[side][point]` (missing ones: not checked) and
    /// every sector's amplitude of sector dof `dof` (0-based, time signals
    /// of `time_samples` instants).
    pub fn sides_data(
        &self,
        dof: usize,
        time_samples: usize,
        stable: &[Vec<Option<bool>>],
    ) -> Result<Vec<BifurcatedSide>, ResultsError> {
        self.sides
            .iter()
            .enumerate()
            .map(|(s, side)| {
                Ok(BifurcatedSide {
                    direction: side.direction,
                    frequency_hz: side
                        .points
                        .iter()
                        .map(|p| p.omega / (2.0 * std::f64::consts::PI))
                        .collect(),
                    stable: (0..side.points.len())
                        .map(|i| stable.get(s).and_then(|v| v.get(i)).copied().flatten())
                        .collect(),
                    sector_amplitudes_m: side
                        .points
                        .iter()
                        .map(|p| sector_amplitudes(&self.problem, p, dof, time_samples))
                        .collect::<Result<_, _>>()?,
                    stop: serde_json::to_value(&side.stop)
                        .map_err(|e| ResultsError::Input(e.to_string()))?,
                    stop_reason: side.stop.to_string(),
                })
            })
            .collect()
    }
}

/// Switches from the symmetric branch of `case` (on `model`, solved on
/// `symmetric`) to the branch of class `class` that starts between its
/// consecutive points `before` and `after` (`(unknowns, omega)`): locates
/// the branch point, builds the enlarged problem, and follows both sides
/// with `settings` (the case's range and steps; its `initial_step` is also
/// the first point's distance from the branch point).
pub fn switch_at(
    case: &Case,
    model: &SectorModel,
    symmetric: &mut HarmonicBalance,
    class: i64,
    before: (&[f64], f64),
    after: (&[f64], f64),
    settings: &Settings,
) -> Result<BifurcatedBranch, BranchError> {
    let enlarged = EnlargedBasis::new(symmetric.layout(), class)?;
    let mut problem = problem_on_basis(case, model, Some(enlarged.basis.clone()))
        .map_err(|e| BranchError::Build(e.to_string()))?;
    let class_unknowns = enlarged.class_unknowns(problem.layout());
    let newton: NewtonSettings = settings.arc_length.newton;
    let branch_point = locate::Locator {
        symmetric,
        enlarged: &mut problem,
        class_unknowns: &class_unknowns,
        newton,
    }
    .locate(before, after)?;
    tracing::info!(
        "class {class}: branch point at {:.6} Hz (least eigenvalue {:.1e} of the new block's largest entry, {} symmetric solves); enlarged basis {} unknowns",
        branch_point.omega / (2.0 * std::f64::consts::PI),
        branch_point.relative_eigenvalue,
        branch_point.solves,
        problem.layout().unknowns,
    );
    let mut sides = Vec::with_capacity(2);
    for direction in [1.0, -1.0] {
        sides.push(follow::follow_side(
            &mut problem,
            &branch_point,
            direction,
            *settings,
        )?);
    }
    let layout = problem.layout();
    Ok(BifurcatedBranch {
        class,
        unknowns: layout.unknowns,
        full_unknowns: layout.sectors * layout.contact_dofs * layout.coordinates(),
        basis: enlarged.basis,
        branch_point,
        sides,
        problem,
    })
}

/// The branch point of class `class` between the consecutive points
/// `before` and `after` (`(unknowns, omega)`) of the symmetric branch of
/// `case` (on `model`, solved on `symmetric`), located by the enlarged
/// Jacobian's test function alone (what [`switch_at`] does first, without
/// following the branches): the independent check of a marker's place.
pub fn locate_branch_point(
    case: &Case,
    model: &SectorModel,
    symmetric: &mut HarmonicBalance,
    class: i64,
    before: (&[f64], f64),
    after: (&[f64], f64),
) -> Result<BranchPoint, BranchError> {
    let enlarged = EnlargedBasis::new(symmetric.layout(), class)?;
    let mut problem = problem_on_basis(case, model, Some(enlarged.basis.clone()))
        .map_err(|e| BranchError::Build(e.to_string()))?;
    let class_unknowns = enlarged.class_unknowns(problem.layout());
    locate::Locator {
        symmetric,
        enlarged: &mut problem,
        class_unknowns: &class_unknowns,
        newton: NewtonSettings::default(),
    }
    .locate(before, after)
}

/// Where along the symmetric branch `points` (in branch order) a real
/// multiplier of class `class` crosses `+1`: the indices `i` with a branch
/// point between points `i` and `i + 1`, found from the enlarged problem's
/// Jacobian alone (independent of Hill's method and its markers).
pub fn real_crossings(
    case: &Case,
    model: &SectorModel,
    symmetric: &mut HarmonicBalance,
    class: i64,
    points: &[Point],
) -> Result<Vec<usize>, BranchError> {
    let enlarged = EnlargedBasis::new(symmetric.layout(), class)?;
    let mut problem = problem_on_basis(case, model, Some(enlarged.basis.clone()))
        .map_err(|e| BranchError::Build(e.to_string()))?;
    let class_unknowns = enlarged.class_unknowns(problem.layout());
    let pairs: Vec<(&[f64], f64)> = points
        .iter()
        .map(|p| (p.unknowns.as_slice(), p.omega))
        .collect();
    locate::Locator {
        symmetric,
        enlarged: &mut problem,
        class_unknowns: &class_unknowns,
        newton: NewtonSettings::default(),
    }
    .sign_changes(&pairs)
}

/// Follows the side `direction` (`+1` along the null vector, `−1`
/// against it) of the branch through `point` on `problem`: what
/// [`switch_at`] does on the enlarged problem, here on any problem where
/// `point` is written (the physical full wheel, to check the reduction).
pub fn follow_from(
    problem: &mut HarmonicBalance,
    point: &BranchPoint,
    direction: f64,
    settings: &Settings,
) -> Result<Side, BranchError> {
    follow::follow_side(problem, point, direction, *settings)
}

/// The largest displacement over the period (toward the casing) of sector
/// dof `dof` (0-based) on every sector at `point` of `problem`: how far the
/// sectors of a bifurcated branch are from moving alike.
pub fn sector_amplitudes(
    problem: &HarmonicBalance,
    point: &Point,
    dof: usize,
    time_samples: usize,
) -> Result<Vec<f64>, ResultsError> {
    let sectors: Vec<usize> = (0..problem.layout().sectors).collect();
    dof_peaks(
        problem,
        &point.unknowns,
        point.omega,
        dof,
        &sectors,
        time_samples,
    )
}
