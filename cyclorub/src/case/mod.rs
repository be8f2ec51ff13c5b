//! The case file (TOML): every input of a run, with the paper's defaults
//! (academic model, `N = 24`, traveling wave `h = 1` of 4 N, R-HBM with
//! `κ = 1e8 N/m`, `γ = 2.5 N`, gap `1e-3 m`, `N_h = 10`, `N_t = 10000`).
//!
//! Unknown keys are refused with their line and the allowed keys
//! (`deny_unknown_fields`); values are then checked by [`Case::validate`],
//! whose messages name the key, the value and what is allowed. Dof numbers
//! are 1-based in case files.
//!
//! Every key is described once, in the key table of [`keys`]: the checks of
//! [`Case::validate`], the comments of the template that `cyclorub init`
//! prints (`cyclorub_app::template`) and README's key tables all come from
//! it.

use crate::contact::{ContactModel, DynamicLagrangian, RegularizedPenalty};
use crate::cyclic::ExcitationPattern;
use crate::hbm::{Casing, Forcing};
use crate::model::ModelSpec;
use serde::{Deserialize, Serialize};
use std::path::{Path, PathBuf};

pub mod keys;
pub mod text;
mod validate;

/// Errors reading or checking a case file.
#[derive(Debug, thiserror::Error)]
pub enum CaseError {
    /// The file cannot be read.
    #[error("cannot read the case file {path}: {source}")]
    Io {
        /// The file.
        path: PathBuf,
        /// Why.
        source: std::io::Error,
    },
    /// The TOML is malformed or holds an unknown key.
    #[error("{path}: {message}")]
    Parse {
        /// The file.
        path: PathBuf,
        /// The parser's message (line, key, allowed keys).
        message: String,
    },
    /// A value is not allowed.
    #[error("{key} = {value}: {allowed}")]
    Invalid {
        /// The key, e.g. `casing.gap`.
        key: String,
        /// The value given.
        value: String,
        /// What is allowed.
        allowed: String,
    },
}

fn invalid(key: &str, value: impl std::fmt::Display, allowed: impl Into<String>) -> CaseError {
    CaseError::Invalid {
        key: key.into(),
        value: value.to_string(),
        allowed: allowed.into(),
    }
}

/// A contact parameter refused by its law, named by its key.
fn contact_error(error: crate::contact::ContactError) -> CaseError {
    let crate::contact::ContactError::InvalidParameter {
        key,
        value,
        allowed,
    } = error;
    invalid(&format!("contact.{key}"), value, allowed)
}

/// One value for every contact dof, or one per contact dof.
#[derive(Deserialize, Serialize, Clone, Debug, PartialEq)]
#[serde(untagged)]
pub enum PerContactDof {
    /// The same value on every contact dof.
    One(f64),
    /// One value per contact dof.
    Each(Vec<f64>),
}

impl PerContactDof {
    fn expand(&self, key: &str, count: usize) -> Result<Vec<f64>, CaseError> {
        match self {
            Self::One(v) => Ok(vec![*v; count]),
            Self::Each(v) if v.len() == count => Ok(v.clone()),
            Self::Each(v) => Err(invalid(
                key,
                format!("{v:?}"),
                format!("give one value, or one per contact dof ({count})"),
            )),
        }
    }
}

/// The kind of excitation.
#[derive(Deserialize, Serialize, Clone, Copy, Debug, PartialEq, Eq, Default)]
#[serde(rename_all = "snake_case")]
pub enum ExcitationKind {
    /// Eq. (48), backward in blade numbering.
    #[default]
    Traveling,
    /// Eq. (75).
    Standing,
    /// Eq. (86): weighted backward and forward waves.
    Mixed,
    /// Explicit amplitude and phase per sector.
    PerSector,
    /// No excitation (a casing-driven case).
    None,
}

/// `[excitation]`: first-harmonic force on sector dofs.
#[derive(Deserialize, Serialize, Clone, Debug, PartialEq)]
#[serde(deny_unknown_fields, default)]
pub struct ExcitationSpec {
    /// `traveling`, `standing`, `mixed`, `per_sector` or `none`.
    pub kind: ExcitationKind,
    /// Engine order `h` (0 ≤ h < N).
    pub engine_order: usize,
    /// Amplitude `f_ex`, N.
    pub amplitude: f64,
    /// Sector dofs (1-based) where the force acts.
    pub dofs: Vec<usize>,
    /// `mixed`: weight of the backward wave (Eq. 86: 0.9).
    pub backward_weight: f64,
    /// `mixed`: weight of the forward wave (Eq. 86: 0.1).
    pub forward_weight: f64,
    /// `per_sector`: amplitude factor per sector (multiplies `amplitude`).
    pub amplitudes: Vec<f64>,
    /// `per_sector`: phase per sector, radians.
    pub phases: Vec<f64>,
    /// Static force on the same dofs of every sector (harmonic 0), N.
    pub static_force: f64,
}

impl Default for ExcitationSpec {
    fn default() -> Self {
        Self {
            kind: ExcitationKind::Traveling,
            engine_order: 1,
            amplitude: 4.0,
            dofs: vec![1],
            backward_weight: 0.9,
            forward_weight: 0.1,
            amplitudes: Vec::new(),
            phases: Vec::new(),
            static_force: 0.0,
        }
    }
}

/// `[casing]`: the gap seen by each contact dof, Eq. (74).
#[derive(Deserialize, Serialize, Clone, Debug, PartialEq)]
#[serde(deny_unknown_fields, default)]
pub struct CasingSpec {
    /// Mean gap `c`, m (one value or one per contact dof).
    pub gap: PerContactDof,
    /// Diametral order `h_c` (0: circular).
    pub order: usize,
    /// Amplitude `p` of the diametral shape, m (one or per contact dof).
    pub amplitude: PerContactDof,
}

impl Default for CasingSpec {
    fn default() -> Self {
        Self {
            gap: PerContactDof::One(1e-3),
            order: 0,
            amplitude: PerContactDof::One(0.0),
        }
    }
}

/// The contact law.
#[derive(Deserialize, Serialize, Clone, Copy, Debug, PartialEq, Eq, Default)]
#[serde(rename_all = "snake_case")]
pub enum LawKind {
    /// R-HBM, Eq. (70).
    #[default]
    Regularized,
    /// DLFT-HBM (dynamic Lagrangian).
    Dlft,
}

impl LawKind {
    /// The name used in case files and on the command line.
    pub fn name(self) -> &'static str {
        match self {
            Self::Regularized => "regularized",
            Self::Dlft => "dlft",
        }
    }

    /// Parses a name (for the command line); the error lists the allowed names.
    pub fn parse(name: &str) -> Result<Self, CaseError> {
        [Self::Regularized, Self::Dlft]
            .into_iter()
            .find(|law| law.name() == name)
            .ok_or_else(|| invalid("contact.law", name, "allowed: regularized, dlft"))
    }
}

/// `[contact]`: contact dofs and law.
#[derive(Deserialize, Serialize, Clone, Debug, PartialEq)]
#[serde(deny_unknown_fields, default)]
pub struct ContactSpec {
    /// `regularized` or `dlft`.
    pub law: LawKind,
    /// Contact dofs of a sector (1-based), displacement toward the casing.
    pub dofs: Vec<usize>,
    /// `regularized`: contact stiffness κ, N/m.
    pub stiffness: f64,
    /// `regularized`: regularization γ, N (0: plain penalty).
    pub regularization: f64,
    /// `dlft`: Lagrangian weight ε, N/m.
    pub epsilon: f64,
    /// `dlft`: stiffness of the wall between tip and casing, N/m (absent: rigid).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub wall_stiffness: Option<f64>,
}

impl Default for ContactSpec {
    fn default() -> Self {
        Self {
            law: LawKind::Regularized,
            dofs: vec![1],
            stiffness: 1e8,
            regularization: 2.5,
            epsilon: 1e9,
            // Absent: a rigid casing. The paper's academic runs put a wall
            // of 1e8 N/m (the examples do).
            wall_stiffness: None,
        }
    }
}

/// `[harmonic_balance]`.
#[derive(Deserialize, Serialize, Clone, Debug, PartialEq)]
#[serde(deny_unknown_fields, default)]
pub struct HarmonicBalanceSpec {
    /// `N_h ≥ 1`.
    pub harmonics: usize,
    /// `N_t ≥ 2 N_h + 1`; a multiple of `N` makes reduced and full agree to round-off.
    pub time_samples: usize,
}

impl Default for HarmonicBalanceSpec {
    fn default() -> Self {
        Self {
            harmonics: 10,
            time_samples: 10000,
        }
    }
}

/// `[continuation]`: frequencies in Hz; steps in scaled arc length (a
/// displacement of one gap and the whole frequency range each count 1).
#[derive(Deserialize, Serialize, Clone, Debug, PartialEq)]
#[serde(deny_unknown_fields, default)]
pub struct ContinuationSpec {
    /// Start frequency, Hz (absent: 0.95 × the first natural frequency of
    /// the excited nodal diameter).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub start_hz: Option<f64>,
    /// End frequency, Hz (absent: 1.10 × that frequency). Below the start to sweep down.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub end_hz: Option<f64>,
    /// First step.
    pub initial_step: f64,
    /// Smallest step before the run stops.
    pub min_step: f64,
    /// Largest step.
    pub max_step: f64,
    /// Newton tolerance on `‖R‖ / f_ex`.
    pub tolerance: f64,
    /// Newton iterations per step.
    pub max_iterations: usize,
    /// Cap on points.
    pub max_points: usize,
}

impl Default for ContinuationSpec {
    fn default() -> Self {
        Self {
            start_hz: None,
            end_hz: None,
            initial_step: 0.01,
            min_step: 1e-7,
            max_step: 0.1,
            tolerance: 1e-8,
            max_iterations: 15,
            max_points: 5000,
        }
    }
}

/// Which unknowns are solved for.
#[derive(Deserialize, Serialize, Clone, Copy, Debug, PartialEq, Eq, Default)]
#[serde(rename_all = "snake_case")]
pub enum BasisChoice {
    /// The symmetry rule (DESIGN.md §3): the smallest exact basis.
    #[default]
    Symmetry,
    /// The paper's own choice (Sec. 4.3).
    Paper,
    /// The paper's nodal-diameter rule, even for traveling loads.
    NodalDiameter,
    /// Every pair, in cyclic coordinates.
    Full,
    /// The full wheel assembled sector by sector (the reference).
    Physical,
}

impl BasisChoice {
    /// The name used in case files and on the command line.
    pub fn name(self) -> &'static str {
        match self {
            Self::Symmetry => "symmetry",
            Self::Paper => "paper",
            Self::NodalDiameter => "nodal_diameter",
            Self::Full => "full",
            Self::Physical => "physical",
        }
    }

    /// Parses a name (for the command line); the error lists the allowed names.
    pub fn parse(name: &str) -> Result<Self, CaseError> {
        [
            Self::Symmetry,
            Self::Paper,
            Self::NodalDiameter,
            Self::Full,
            Self::Physical,
        ]
        .into_iter()
        .find(|b| b.name() == name)
        .ok_or_else(|| {
            invalid(
                "basis.kind",
                name,
                "allowed: symmetry, paper, nodal_diameter, full, physical",
            )
        })
    }
}

/// `[basis]`.
#[derive(Deserialize, Serialize, Clone, Debug, PartialEq, Default)]
#[serde(deny_unknown_fields, default)]
pub struct BasisSpec {
    /// `symmetry`, `paper`, `nodal_diameter`, `full` or `physical`.
    pub kind: BasisChoice,
}

/// `[output]`.
#[derive(Deserialize, Serialize, Clone, Debug, PartialEq)]
#[serde(deny_unknown_fields, default)]
pub struct OutputSpec {
    /// Results folder (relative to the working directory).
    pub directory: PathBuf,
    /// The dof (1-based) whose amplitude `branch.csv` reports.
    pub observed_dof: usize,
    /// Sectors (1-based) reported in `branch.csv` (empty: all).
    pub sectors: Vec<usize>,
}

impl Default for OutputSpec {
    fn default() -> Self {
        Self {
            directory: PathBuf::from("results"),
            observed_dof: 1,
            sectors: Vec::new(),
        }
    }
}

/// A whole case file.
#[derive(Deserialize, Serialize, Clone, Debug, PartialEq, Default)]
#[serde(deny_unknown_fields, default)]
pub struct Case {
    /// `[model]`.
    pub model: ModelSpec,
    /// `[excitation]`.
    pub excitation: ExcitationSpec,
    /// `[casing]`.
    pub casing: CasingSpec,
    /// `[contact]`.
    pub contact: ContactSpec,
    /// `[harmonic_balance]`.
    pub harmonic_balance: HarmonicBalanceSpec,
    /// `[continuation]`.
    pub continuation: ContinuationSpec,
    /// `[basis]`.
    pub basis: BasisSpec,
    /// `[output]`.
    pub output: OutputSpec,
}

/// The line (1-based) of `key` (`table.leaf`, e.g. `casing.gap` or
/// `model.damping.ratio`) in TOML `text`: the first `leaf = …` line under the
/// `[table]` header. `None` when the key is not written (a default).
pub fn key_line(text: &str, key: &str) -> Option<usize> {
    let (table, leaf) = key.rsplit_once('.').unwrap_or(("", key));
    let mut current = String::new();
    for (index, line) in text.lines().enumerate() {
        let line = line.trim();
        if let Some(header) = line.strip_prefix('[') {
            current = header
                .trim_end_matches(']')
                .trim()
                .trim_end_matches(']')
                .to_string();
            continue;
        }
        if current == table {
            if let Some(rest) = line.strip_prefix(leaf) {
                if rest.trim_start().starts_with('=') {
                    return Some(index + 1);
                }
            }
        }
    }
    None
}

impl CaseError {
    /// A refused value with where it is written: `path:line` appended to
    /// what is allowed (unchanged when the key is not in `text`).
    pub fn located(self, path: &Path, text: &str) -> Self {
        match self {
            CaseError::Invalid {
                key,
                value,
                allowed,
            } => {
                let allowed = match key_line(text, &key) {
                    Some(line) => format!("{allowed} (at {}:{line})", path.display()),
                    None => allowed,
                };
                CaseError::Invalid {
                    key,
                    value,
                    allowed,
                }
            }
            other => other,
        }
    }
}

impl Case {
    /// Reads a case file and checks every value, a refused value located
    /// by its line in the file.
    pub fn from_file_checked(path: &Path) -> Result<Self, CaseError> {
        let text = std::fs::read_to_string(path).map_err(|source| CaseError::Io {
            path: path.to_path_buf(),
            source,
        })?;
        let case = Self::from_toml(&text, path)?;
        case.validate().map_err(|e| e.located(path, &text))?;
        Ok(case)
    }

    /// Parses TOML text (`origin` names it in messages).
    pub fn from_toml(text: &str, origin: &Path) -> Result<Self, CaseError> {
        toml::from_str(text).map_err(|error| CaseError::Parse {
            path: origin.to_path_buf(),
            message: error.to_string(),
        })
    }

    /// Reads a case file.
    pub fn from_file(path: &Path) -> Result<Self, CaseError> {
        let text = std::fs::read_to_string(path).map_err(|source| CaseError::Io {
            path: path.to_path_buf(),
            source,
        })?;
        Self::from_toml(&text, path)
    }

    /// The excitation in library form (0-based dofs), if any.
    pub fn forcing(&self) -> Option<Forcing> {
        let e = &self.excitation;
        let h = e.engine_order;
        let pattern = match e.kind {
            ExcitationKind::None => return None,
            ExcitationKind::Traveling => ExcitationPattern::Traveling { engine_order: h },
            ExcitationKind::Standing => ExcitationPattern::Standing { engine_order: h },
            ExcitationKind::Mixed => ExcitationPattern::Mixed {
                engine_order: h,
                backward_weight: e.backward_weight,
                forward_weight: e.forward_weight,
            },
            ExcitationKind::PerSector => ExcitationPattern::PerSector {
                amplitudes: e.amplitudes.clone(),
                phases: e.phases.clone(),
            },
        };
        Some(Forcing {
            pattern,
            amplitude: e.amplitude,
            dofs: e.dofs.iter().map(|d| d - 1).collect(),
            static_force: e.static_force,
        })
    }

    /// The casing in library form.
    pub fn casing(&self) -> Result<Casing, CaseError> {
        let count = self.contact.dofs.len();
        Ok(Casing {
            gaps: self.casing.gap.expand("casing.gap", count)?,
            order: self.casing.order,
            amplitudes: self.casing.amplitude.expand("casing.amplitude", count)?,
        })
    }

    /// Contact dofs, 0-based.
    pub fn contact_dofs(&self) -> Vec<usize> {
        self.contact.dofs.iter().map(|d| d - 1).collect()
    }

    /// The contact treatment.
    pub fn contact_model(&self) -> Result<ContactModel, CaseError> {
        match self.contact.law {
            LawKind::Regularized => {
                RegularizedPenalty::new(self.contact.stiffness, self.contact.regularization)
                    .map(ContactModel::Regularized)
                    .map_err(contact_error)
            }
            LawKind::Dlft => {
                DynamicLagrangian::new(self.contact.epsilon, self.contact.wall_stiffness)
                    .map(ContactModel::Lagrangian)
                    .map_err(contact_error)
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Parses and validates a case file's text.
    pub(super) fn parse(text: &str) -> Result<Case, CaseError> {
        let case = Case::from_toml(text, Path::new("case.toml"))?;
        case.validate()?;
        Ok(case)
    }

    #[test]
    fn an_empty_file_is_the_paper_default() {
        let case = parse("").unwrap();
        assert_eq!(case, Case::default());
        assert_eq!(case.model.sectors(), 24);
        assert_eq!(case.harmonic_balance.time_samples, 10000);
    }

    #[test]
    fn the_case_round_trips_through_toml() {
        let case = Case::default();
        let text = toml::to_string(&case).unwrap();
        assert_eq!(parse(&text).unwrap(), case);
    }

    #[test]
    fn the_case_file_selects_the_contact_law_and_the_wall() {
        use crate::contact::ContactModel;
        let rigid = parse("[contact]\nlaw = \"dlft\"\nepsilon = 1e7\n").unwrap();
        match rigid.contact_model().unwrap() {
            ContactModel::Lagrangian(l) => {
                assert!((l.epsilon() - 1e7).abs() < 1e-6);
                assert_eq!(l.wall_stiffness(), None, "absent: a rigid casing");
            }
            other => panic!("{other:?}"),
        }
        let wall = parse("[contact]\nlaw = \"dlft\"\nwall_stiffness = 1e8\n").unwrap();
        match wall.contact_model().unwrap() {
            ContactModel::Lagrangian(l) => {
                assert!(l.wall_stiffness().is_some_and(|k| (k - 1e8).abs() < 1e-6))
            }
            other => panic!("{other:?}"),
        }
        assert!(matches!(
            Case::default().contact_model().unwrap(),
            ContactModel::Regularized(_)
        ));
        let message = parse("[contact]\nlaw = \"dlft\"\nepsilon = -1.0\n")
            .unwrap_err()
            .to_string();
        assert!(message.contains("contact.epsilon = -1"), "{message}");
    }

    #[test]
    fn a_refused_value_is_located_by_its_line() {
        let text = "# a case\n[model]\nsectors = 8\n\n[casing]\norder = 0\ngap = -1.0\n[model.damping]\nratio = 1e-3\n";
        assert_eq!(key_line(text, "casing.gap"), Some(7));
        assert_eq!(key_line(text, "model.sectors"), Some(3));
        assert_eq!(key_line(text, "model.damping.ratio"), Some(9));
        assert_eq!(key_line(text, "casing.amplitude"), None);
        assert_eq!(key_line(text, "contact.gap"), None);
        let error = Case::from_toml(text, Path::new("case.toml"))
            .unwrap()
            .validate()
            .unwrap_err()
            .located(Path::new("case.toml"), text);
        let message = error.to_string();
        assert!(message.starts_with("casing.gap = -1"), "{message}");
        assert!(message.ends_with("(at case.toml:7)"), "{message}");
    }
}
