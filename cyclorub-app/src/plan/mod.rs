//! Library side of `cyclorub plan`: what each rule keeps for a load case,
//! in the shape of the paper's Tables 2, 4 and 5, and mean reductions over
//! ranges of sector counts (the paper's conclusion and Fig. 21); the sizes
//! are the core's ([`SpectralBasis`]), the text tables are in [`tables`].

pub mod tables;

use cyclorub::basis::{check_size, load_orders, BasisError, PaperRule, SpectralBasis};
use cyclorub::cyclic::{ExcitationPattern, LoadCase};
use cyclorub::model::{MAX_SECTORS, SECTOR_MAX_DOFS};
use serde::Serialize;

/// Errors in a planning request, naming the argument as `cyclorub plan`
/// takes it and its range.
#[derive(Debug, thiserror::Error, PartialEq)]
pub enum PlanError {
    /// `sectors` must be at least 1.
    #[error("--sectors {0}: the number of sectors must be at least 1")]
    NoSectors(usize),
    /// `harmonics` must be at least 1.
    #[error("--harmonics 0: the number of harmonics must be at least 1")]
    NoHarmonics,
    /// `contact_dofs` must be at least 1.
    #[error("--contact-dofs 0: the number of contact dofs per sector must be at least 1")]
    NoContactDofs,
    /// The engine order must be in `0..N`.
    #[error("--engine-order {engine_order} is out of range: it must be in 0..={max} (below --sectors {sectors})")]
    EngineOrderOutOfRange {
        /// The order given.
        engine_order: usize,
        /// Number of sectors.
        sectors: usize,
        /// `N − 1`.
        max: usize,
    },
    /// A sweep range must satisfy `1 ≤ A ≤ B ≤ 1000`.
    #[error(
        "--sweep-sectors {from}..{to} is not valid: it must be A..B with 1 <= A <= B <= {MAX_SWEEP_SECTORS}"
    )]
    BadSweepRange {
        /// First `N`.
        from: usize,
        /// Last `N`.
        to: usize,
    },
    /// More sectors than a model may have.
    #[error("--sectors {0} is too many: at most {MAX_SECTORS}")]
    TooManySectors(usize),
    /// More contact dofs than a sector may have.
    #[error("--contact-dofs {0} is too many: a sector has at most {SECTOR_MAX_DOFS} dofs")]
    TooManyContactDofs(usize),
    /// More harmonics than a basis may hold on this wheel.
    #[error("--harmonics {harmonics} is too many: {source}")]
    TooManyHarmonics {
        /// The harmonics given.
        harmonics: usize,
        /// The basis' limit.
        source: BasisError,
    },
    /// A basis could not be built.
    #[error(transparent)]
    Basis(#[from] BasisError),
}

impl PlanError {
    /// Whether the error is in the request (an argument out of range), as
    /// opposed to a basis that could not be built.
    pub fn is_input_error(&self) -> bool {
        !matches!(self, Self::Basis(_))
    }
}

/// The harmonics of a plan on `sectors` sectors within what a basis holds
/// (the full basis, `(N_h + 1)·N` pairs).
fn check_harmonics(sectors: usize, harmonics: usize) -> Result<(), PlanError> {
    match check_size(sectors, harmonics) {
        Err(source @ BasisError::TooLarge { .. }) => {
            Err(PlanError::TooManyHarmonics { harmonics, source })
        }
        _ => Ok(()),
    }
}

/// The largest `N` a sweep accepts.
pub const MAX_SWEEP_SECTORS: usize = 1000;

/// Which rule builds the basis.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum PlanRule {
    /// The paper's own choice ([`PaperRule::for_load`]).
    Paper,
    /// The symmetry rule (docs/design.md §3).
    Symmetry,
}

/// The kind of first-harmonic excitation of a planned load.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum ExcitationKind {
    /// Eq. (48): the backward wave `(−h, 1)`.
    Traveling,
    /// Eq. (75): both waves `(∓h, 1)` with equal weights.
    Standing,
    /// Eq. (86): 0.9 backward, 0.1 forward.
    Mixed,
}

impl ExcitationKind {
    /// The excitation pattern of order `h` (unit amplitude; Eq. 86's
    /// weights for `Mixed`).
    pub fn pattern(self, engine_order: usize) -> ExcitationPattern {
        match self {
            Self::Traveling => ExcitationPattern::Traveling { engine_order },
            Self::Standing => ExcitationPattern::Standing { engine_order },
            Self::Mixed => ExcitationPattern::Mixed {
                engine_order,
                backward_weight: 0.9,
                forward_weight: 0.1,
            },
        }
    }
}

/// The case file's kind of the same excitation.
impl From<ExcitationKind> for cyclorub::case::ExcitationKind {
    fn from(kind: ExcitationKind) -> Self {
        match kind {
            ExcitationKind::Traveling => Self::Traveling,
            ExcitationKind::Standing => Self::Standing,
            ExcitationKind::Mixed => Self::Mixed,
        }
    }
}

/// One planned load case.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
pub struct PlanCase {
    /// Number of sectors `N ≥ 1`.
    pub sectors: usize,
    /// Number of harmonics `N_h ≥ 1`.
    pub harmonics: usize,
    /// Contact dofs per sector (`n_nl`, 27 for the paper's Table 4).
    pub contact_dofs: usize,
    /// Engine order `h` of the excitation, in `0..N`.
    pub engine_order: usize,
    /// Kind of excitation.
    pub excitation: ExcitationKind,
    /// Diametral order of the casing (`None` or 0: circular).
    pub casing_order: Option<usize>,
}

impl PlanCase {
    /// Checks the ranges of every field.
    pub fn validate(&self) -> Result<(), PlanError> {
        if self.sectors == 0 {
            return Err(PlanError::NoSectors(self.sectors));
        }
        if self.harmonics == 0 {
            return Err(PlanError::NoHarmonics);
        }
        if self.contact_dofs == 0 {
            return Err(PlanError::NoContactDofs);
        }
        if self.sectors > MAX_SECTORS {
            return Err(PlanError::TooManySectors(self.sectors));
        }
        if self.contact_dofs > SECTOR_MAX_DOFS {
            return Err(PlanError::TooManyContactDofs(self.contact_dofs));
        }
        check_harmonics(self.sectors, self.harmonics)?;
        if self.engine_order >= self.sectors {
            return Err(PlanError::EngineOrderOutOfRange {
                engine_order: self.engine_order,
                sectors: self.sectors,
                max: self.sectors - 1,
            });
        }
        Ok(())
    }

    /// The load case: the excitation and the casing.
    pub fn load(&self) -> LoadCase {
        LoadCase {
            sectors: self.sectors,
            excitation: Some(self.excitation.pattern(self.engine_order)),
            casing_order: self.casing_order.filter(|&h| h > 0),
        }
    }
}

/// The signed nodal diameters kept on one harmonic.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct HarmonicSet {
    /// Harmonic `k`.
    pub k: usize,
    /// Signed nodal diameters in `(−N/2, N/2]`, ascending.
    pub signed_nodal_diameters: Vec<i64>,
}

/// One row of a table in the shape of the paper's Tables 2, 4, 5.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct PlanRow {
    /// Number of sectors `N`.
    pub sectors: usize,
    /// Engine order `h`.
    pub engine_order: usize,
    /// Kind of excitation.
    pub excitation: ExcitationKind,
    /// Casing order (`null` for a circular casing).
    pub casing_order: Option<usize>,
    /// The rule.
    pub rule: PlanRule,
    /// How the rule built the basis: `traveling_wave`, `nodal_diameter`,
    /// `nodal_diameter_parity` (paper) or `symmetry`.
    pub method: &'static str,
    /// `K` of Eq. (33) where the nodal-diameter rule is used.
    #[serde(rename = "K")]
    pub k: Option<usize>,
    /// Real unknowns: per contact dof times the contact dofs.
    pub reduced_size: usize,
    /// Real unknowns of the full model: `N n (2 N_h + 1)`.
    pub full_size: usize,
    /// Sectors the AFT-CP samples: `max_k |S_k|`.
    pub sectors_for_aft: usize,
    /// `100 (1 − reduced / full)`.
    pub reduction_percent: f64,
    /// The signed pairs per harmonic `0..=N_h`.
    pub harmonics: Vec<HarmonicSet>,
}

/// The basis a rule builds for a case, with how it was built and `K`.
pub fn plan_basis(
    case: &PlanCase,
    rule: PlanRule,
) -> Result<(SpectralBasis, &'static str, Option<usize>), PlanError> {
    case.validate()?;
    let load = case.load();
    Ok(match rule {
        PlanRule::Paper => {
            let paper_rule = PaperRule::for_load(&load)?;
            let method = match paper_rule {
                PaperRule::TravelingWave { .. } => "traveling_wave",
                PaperRule::NodalDiameter { parity: true, .. } => "nodal_diameter_parity",
                PaperRule::NodalDiameter { .. } => "nodal_diameter",
            };
            (
                SpectralBasis::paper(&load, case.harmonics)?,
                method,
                paper_rule.k(),
            )
        }
        PlanRule::Symmetry => (
            SpectralBasis::symmetry(&load, case.harmonics)?,
            "symmetry",
            None,
        ),
    })
}

/// The row of the table for one case and rule.
pub fn plan_row(case: &PlanCase, rule: PlanRule) -> Result<PlanRow, PlanError> {
    let (basis, method, k) = plan_basis(case, rule)?;
    Ok(PlanRow {
        sectors: case.sectors,
        engine_order: case.engine_order,
        excitation: case.excitation,
        casing_order: case.casing_order.filter(|&h| h > 0),
        rule,
        method,
        k,
        reduced_size: basis.real_unknowns_per_contact_dof() * case.contact_dofs,
        full_size: basis.full_size_per_contact_dof() * case.contact_dofs,
        sectors_for_aft: basis.sampled_sectors(),
        reduction_percent: basis.reduction_percent(),
        harmonics: (0..=case.harmonics)
            .map(|k| HarmonicSet {
                k,
                signed_nodal_diameters: basis.nodal_diameters(k).to_vec(),
            })
            .collect(),
    })
}

/// How a number of sectors is grouped in the paper's conclusion.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum SectorClass {
    /// Even `N` (including 2).
    Even,
    /// Odd `N` that is not prime (including 1).
    OddNonPrime,
    /// Odd prime `N`.
    Prime,
    /// Every `N` of the range.
    All,
}

impl SectorClass {
    /// The class of `N`.
    pub fn of(sectors: usize) -> Self {
        let is_prime = sectors >= 2
            && (2..)
                .take_while(|d| d * d <= sectors)
                .all(|d| !sectors.is_multiple_of(d));
        if sectors.is_multiple_of(2) {
            Self::Even
        } else if is_prime {
            Self::Prime
        } else {
            Self::OddNonPrime
        }
    }
}

/// Mean reductions (percent) for one `N` over a set of non-zero engine orders.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct MeanReductions {
    /// The paper's nodal-diameter rule with the parity rule where the paper
    /// applies it (one excited order, circular casing).
    pub with_parity: f64,
    /// The paper's nodal-diameter rule without the parity rule.
    pub without_parity: f64,
    /// The symmetry rule for the sweep's excitation kind and casing.
    pub symmetry: f64,
}

/// One `N` of a sweep.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct SweepRow {
    /// Number of sectors `N`.
    pub sectors: usize,
    /// Its class.
    pub class: SectorClass,
    /// Means over the engine orders `h = 1..=N−1` (every non-zero order
    /// modulo `N`; `h` and `N − h` count twice).
    pub over_engine_orders: MeanReductions,
    /// Means over the nodal diameters `h = 1..=⌊N/2⌋`.
    pub over_nodal_diameters: MeanReductions,
}

/// Means of the per-`N` means over the `N` of one class.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct SweepGroup {
    /// The class.
    pub class: SectorClass,
    /// How many `N` of the range it holds.
    pub count: usize,
    /// Mean over its `N` of the means over `h = 1..=N−1`.
    pub over_engine_orders: MeanReductions,
    /// Mean over its `N` of the means over `h = 1..=⌊N/2⌋`.
    pub over_nodal_diameters: MeanReductions,
}

/// A sweep over a range of sector counts.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Sweep {
    /// First `N`.
    pub from: usize,
    /// Last `N` (included).
    pub to: usize,
    /// Number of harmonics `N_h`.
    pub harmonics: usize,
    /// Excitation kind used for the symmetry rule.
    pub excitation: ExcitationKind,
    /// Casing order (`null` for a circular casing).
    pub casing_order: Option<usize>,
    /// One row per `N` that has a non-zero engine order (`N ≥ 2`).
    pub rows: Vec<SweepRow>,
    /// Even, odd non-prime, prime, and all `N`.
    pub groups: Vec<SweepGroup>,
}

fn reductions(
    sectors: usize,
    harmonics: usize,
    engine_order: usize,
    excitation: ExcitationKind,
    casing_order: Option<usize>,
) -> Result<MeanReductions, PlanError> {
    let case = PlanCase {
        sectors,
        harmonics,
        contact_dofs: 1,
        engine_order,
        excitation,
        casing_order,
    };
    let load = case.load();
    let (mut orders, parity_allowed) = load_orders(&load)?;
    orders.sort_unstable();
    let with_parity =
        SpectralBasis::nodal_diameter_rule(sectors, harmonics, &orders, parity_allowed)?;
    let without_parity = SpectralBasis::nodal_diameter_rule(sectors, harmonics, &orders, false)?;
    let symmetry = SpectralBasis::symmetry(&load, harmonics)?;
    Ok(MeanReductions {
        with_parity: with_parity.reduction_percent(),
        without_parity: without_parity.reduction_percent(),
        symmetry: symmetry.reduction_percent(),
    })
}

fn mean(values: &[MeanReductions]) -> MeanReductions {
    let n = values.len().max(1) as f64;
    MeanReductions {
        with_parity: values.iter().map(|m| m.with_parity).sum::<f64>() / n,
        without_parity: values.iter().map(|m| m.without_parity).sum::<f64>() / n,
        symmetry: values.iter().map(|m| m.symmetry).sum::<f64>() / n,
    }
}

/// Mean reductions over the non-zero engine orders for every `N` in
/// `from..=to`, grouped into even, odd non-prime and prime `N`, with and
/// without the parity rule, and for the symmetry rule.
pub fn sweep(
    from: usize,
    to: usize,
    harmonics: usize,
    excitation: ExcitationKind,
    casing_order: Option<usize>,
) -> Result<Sweep, PlanError> {
    if from == 0 || from > to || to > MAX_SWEEP_SECTORS {
        return Err(PlanError::BadSweepRange { from, to });
    }
    if harmonics == 0 {
        return Err(PlanError::NoHarmonics);
    }
    check_harmonics(to, harmonics)?;
    let casing_order = casing_order.filter(|&h| h > 0);
    let mut rows = Vec::new();
    for n in from.max(2)..=to {
        let per_order = (1..n)
            .map(|h| reductions(n, harmonics, h, excitation, casing_order))
            .collect::<Result<Vec<_>, _>>()?;
        rows.push(SweepRow {
            sectors: n,
            class: SectorClass::of(n),
            over_engine_orders: mean(&per_order),
            over_nodal_diameters: mean(&per_order[..n / 2]),
        });
    }
    let groups = [
        SectorClass::Even,
        SectorClass::OddNonPrime,
        SectorClass::Prime,
        SectorClass::All,
    ]
    .into_iter()
    .map(|class| {
        let members: Vec<&SweepRow> = rows
            .iter()
            .filter(|r| class == SectorClass::All || r.class == class)
            .collect();
        let engine: Vec<MeanReductions> = members.iter().map(|r| r.over_engine_orders).collect();
        let diameters: Vec<MeanReductions> =
            members.iter().map(|r| r.over_nodal_diameters).collect();
        SweepGroup {
            class,
            count: members.len(),
            over_engine_orders: mean(&engine),
            over_nodal_diameters: mean(&diameters),
        }
    })
    .collect();
    Ok(Sweep {
        from,
        to,
        harmonics,
        excitation,
        casing_order,
        rows,
        groups,
    })
}
