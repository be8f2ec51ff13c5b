//! The tables of a case file besides `[model]` (which is the model's own,
//! [`ModelSpec`](crate::model::ModelSpec)): `[excitation]`, `[casing]`,
//! `[contact]`, `[harmonic_balance]`, `[continuation]`, `[basis]` and
//! `[output]`, with the paper's defaults.

use super::error::{invalid, CaseError};
use crate::continuation::PiecewisePredictor;
use serde::{Deserialize, Serialize};
use std::fmt;
use std::path::PathBuf;

/// One value for every contact dof, or one per contact dof.
#[derive(Serialize, Clone, Debug, PartialEq)]
#[serde(untagged)]
pub enum PerContactDof {
    /// The same value on every contact dof.
    One(f64),
    /// One value per contact dof.
    Each(Vec<f64>),
}

/// Read by hand so that a wrong type says what is allowed (serde's
/// untagged enums only say "did not match any variant").
impl<'de> Deserialize<'de> for PerContactDof {
    fn deserialize<D: serde::Deserializer<'de>>(deserializer: D) -> Result<Self, D::Error> {
        struct Visitor;
        impl<'de> serde::de::Visitor<'de> for Visitor {
            type Value = PerContactDof;
            fn expecting(&self, f: &mut std::fmt::Formatter) -> std::fmt::Result {
                f.write_str("a number, or a list of numbers, one per contact dof")
            }
            fn visit_f64<E: serde::de::Error>(self, v: f64) -> Result<Self::Value, E> {
                Ok(PerContactDof::One(v))
            }
            fn visit_i64<E: serde::de::Error>(self, v: i64) -> Result<Self::Value, E> {
                Ok(PerContactDof::One(v as f64))
            }
            fn visit_u64<E: serde::de::Error>(self, v: u64) -> Result<Self::Value, E> {
                Ok(PerContactDof::One(v as f64))
            }
            fn visit_seq<A: serde::de::SeqAccess<'de>>(
                self,
                mut seq: A,
            ) -> Result<Self::Value, A::Error> {
                let mut values = Vec::new();
                while let Some(v) = seq.next_element::<f64>()? {
                    values.push(v);
                }
                Ok(PerContactDof::Each(values))
            }
        }
        deserializer.deserialize_any(Visitor)
    }
}

impl PerContactDof {
    /// The values of `count` contact dofs; `key` names it in the error.
    pub(super) fn expand(&self, key: &str, count: usize) -> Result<Vec<f64>, CaseError> {
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

impl ExcitationKind {
    /// The name used in case files (`excitation.kind`).
    pub fn name(self) -> &'static str {
        match self {
            Self::Traveling => "traveling",
            Self::Standing => "standing",
            Self::Mixed => "mixed",
            Self::PerSector => "per_sector",
            Self::None => "none",
        }
    }
}

/// The case file's name ([`ExcitationKind::name`]).
impl fmt::Display for ExcitationKind {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
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
    /// With a preload: the gap is measured on the preloaded blade (true,
    /// the paper's) or on the blade at rest (false).
    #[serde(skip_serializing_if = "is_true")]
    pub gap_after_preload: bool,
}

fn is_true(value: &bool) -> bool {
    *value
}

impl Default for CasingSpec {
    fn default() -> Self {
        Self {
            gap: PerContactDof::One(1e-3),
            order: 0,
            amplitude: PerContactDof::One(0.0),
            gap_after_preload: true,
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

    /// The paper's name of the method this law makes: "R-HBM" (Eq. 70) or
    /// "DLFT-HBM" (Sec. 3.4.3), for titles and reports.
    pub fn method(self) -> &'static str {
        match self {
            Self::Regularized => "R-HBM",
            Self::Dlft => "DLFT-HBM",
        }
    }
}

/// The case file's name ([`LawKind::name`]).
impl fmt::Display for LawKind {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
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
    /// Sliding friction coefficient μ (Eqs. 83–84); absent: frictionless,
    /// the contact dofs alone.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub friction: Option<f64>,
    /// With friction: the circumferential dof of each contact dof's node
    /// (1-based), positive in the direction of rotation.
    #[serde(skip_serializing_if = "Vec::is_empty")]
    pub circumferential_dofs: Vec<usize>,
    /// With friction: the axial dof of each contact dof's node (1-based).
    #[serde(skip_serializing_if = "Vec::is_empty")]
    pub axial_dofs: Vec<usize>,
    /// With friction: the radius ρ of each contact node, m (absent: from
    /// the model's node coordinates).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub radius: Option<PerContactDof>,
}

impl RotationSpec {
    /// Whether it holds the defaults (then a case file need not show it).
    pub fn is_default(&self) -> bool {
        *self == Self::default()
    }
}

/// `[rotation]`: the wheel's speed, which sets the sliding speed `ρ Ω` of
/// friction.
#[derive(Deserialize, Serialize, Clone, Debug, PartialEq, Default)]
#[serde(deny_unknown_fields, default)]
pub struct RotationSpec {
    /// A fixed speed Ω, rad/s.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub speed: Option<f64>,
    /// `Ω = ω` along the sweep (the excitation synchronous with the rotation).
    #[serde(skip_serializing_if = "std::ops::Not::not")]
    pub synchronous: bool,
}

/// `[preload]`: a static load on every sector alike, solved on harmonic 0.
#[derive(Deserialize, Serialize, Clone, Debug, PartialEq, Default)]
#[serde(deny_unknown_fields, default)]
pub struct PreloadSpec {
    /// The centrifugal body force `Ω² M r` of a finite-element sector.
    #[serde(skip_serializing_if = "std::ops::Not::not")]
    pub centrifugal: bool,
    /// The speed of the centrifugal force, rad/s (absent: `rotation.speed`).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub speed: Option<f64>,
    /// A static force per dof of a sector, N.
    #[serde(skip_serializing_if = "Vec::is_empty")]
    pub static_forces: Vec<f64>,
    /// The centrifugal force on the model's dofs, once computed for a
    /// built model (not read from or written to case files).
    #[serde(skip)]
    pub centrifugal_forces: Option<Vec<f64>>,
}

impl PreloadSpec {
    /// Whether it holds the defaults (then a case file need not show it).
    pub fn is_default(&self) -> bool {
        *self == Self::default()
    }

    /// Whether any preload is asked for.
    pub fn is_set(&self) -> bool {
        self.centrifugal || !self.static_forces.is_empty()
    }
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
            friction: None,
            circumferential_dofs: Vec::new(),
            axial_dofs: Vec::new(),
            radius: None,
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
    /// The prediction on DLFT-HBM's piecewise-smooth branches.
    pub dlft_predictor: PiecewisePredictor,
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
            dlft_predictor: PiecewisePredictor::Tangent,
        }
    }
}

/// Which unknowns are solved for.
#[derive(Deserialize, Serialize, Clone, Copy, Debug, PartialEq, Eq, Default)]
#[serde(rename_all = "snake_case")]
pub enum BasisChoice {
    /// The symmetry rule (docs/design.md §3): the smallest exact basis.
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

/// The case file's name ([`BasisChoice::name`]).
impl fmt::Display for BasisChoice {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

/// `[basis]`.
#[derive(Deserialize, Serialize, Clone, Debug, PartialEq, Default)]
#[serde(deny_unknown_fields, default)]
pub struct BasisSpec {
    /// `symmetry`, `paper`, `nodal_diameter`, `full` or `physical`.
    pub kind: BasisChoice,
}

/// `[stability]`: the stability check of every point (Hill's method per
/// symmetry class, see [`crate::stability`]).
#[derive(Deserialize, Serialize, Clone, Debug, PartialEq)]
#[serde(deny_unknown_fields, default)]
pub struct StabilitySpec {
    /// Whether `cyclorub run` checks every point.
    pub enabled: bool,
    /// Harmonics of Hill's truncation (absent: `harmonic_balance.harmonics`).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub harmonics: Option<usize>,
}

impl Default for StabilitySpec {
    fn default() -> Self {
        Self {
            enabled: true,
            harmonics: None,
        }
    }
}

impl StabilitySpec {
    /// The check's settings when it is enabled.
    pub fn settings(&self) -> Option<crate::stability::StabilitySettings> {
        self.enabled.then(|| crate::stability::StabilitySettings {
            harmonics: self.harmonics,
            ..Default::default()
        })
    }
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
    /// Whether `observed_harmonics.csv` is written (the same coordinates
    /// are in `results.h5`).
    pub harmonics_csv: bool,
    /// Whether `results.h5` keeps the harmonic coordinates of every
    /// contact force per point.
    pub contact_harmonics: bool,
    /// Whether `results.h5` keeps the time histories of the point of
    /// largest amplitude (`/peak`).
    pub peak_histories: bool,
    /// The formats of the figures in `plots/` (with the feature `plot`).
    pub figures: Vec<FigureFormat>,
}

/// A format of the figures.
#[derive(Deserialize, Serialize, Clone, Copy, Debug, PartialEq, Eq)]
#[serde(rename_all = "lowercase")]
pub enum FigureFormat {
    /// Scalable vector graphics (always written when any figure is).
    Svg,
    /// A PNG image at 300 dpi beside each SVG, rasterized from it.
    Png,
}

impl OutputSpec {
    /// The observed dof, 0-based: `observed_dof` counts from 1 as in case
    /// files (validation refuses 0). The one conversion its readers use.
    pub fn observed_index(&self) -> usize {
        self.observed_dof.saturating_sub(1)
    }

    /// Whether the figures are also written as PNG.
    pub fn png_figures(&self) -> bool {
        self.figures.contains(&FigureFormat::Png)
    }
}

impl Default for OutputSpec {
    fn default() -> Self {
        Self {
            directory: PathBuf::from("results"),
            observed_dof: 1,
            sectors: Vec::new(),
            harmonics_csv: false,
            contact_harmonics: false,
            peak_histories: false,
            figures: vec![FigureFormat::Svg, FigureFormat::Png],
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Each enum says itself in the word a case file holds for it (serde's),
    /// so that a message or a report quotes what the user can write back.
    #[test]
    fn the_names_are_the_case_file_words() {
        fn word(value: impl Serialize) -> String {
            serde_json::to_value(value)
                .expect("json")
                .as_str()
                .expect("a word")
                .to_string()
        }
        for law in [LawKind::Regularized, LawKind::Dlft] {
            assert_eq!(law.to_string(), word(law));
            assert_eq!(LawKind::parse(&law.to_string()).expect("parse"), law);
        }
        assert_eq!(LawKind::Regularized.method(), "R-HBM");
        assert_eq!(LawKind::Dlft.method(), "DLFT-HBM");
        for basis in [
            BasisChoice::Symmetry,
            BasisChoice::Paper,
            BasisChoice::NodalDiameter,
            BasisChoice::Full,
            BasisChoice::Physical,
        ] {
            assert_eq!(basis.to_string(), word(basis));
        }
        for kind in [
            ExcitationKind::Traveling,
            ExcitationKind::Standing,
            ExcitationKind::Mixed,
            ExcitationKind::PerSector,
            ExcitationKind::None,
        ] {
            assert_eq!(kind.to_string(), word(kind));
        }
    }
}
