//! `[mistuning]` (issue 44, docs/design.md §12): per-sector blade stiffness
//! deviations, given or generated, and the mistuned model built from them.

use super::{invalid, Case, CaseError};
use crate::model::{generate_deviations, DeviationDistribution, Mistuning, ModelKind, SectorModel};
use faer::Mat;
use serde::{Deserialize, Serialize};
use std::path::Path;

/// How generated deviations are drawn (`mistuning.distribution`).
#[derive(Deserialize, Serialize, Clone, Copy, Debug, PartialEq, Eq, Default)]
#[serde(rename_all = "snake_case")]
pub enum DistributionKind {
    /// Normal, mean 0.
    #[default]
    Normal,
    /// Uniform, mean 0, on `[−√3 σ, √3 σ]`.
    Uniform,
}

impl From<DistributionKind> for DeviationDistribution {
    fn from(kind: DistributionKind) -> Self {
        match kind {
            DistributionKind::Normal => Self::Normal,
            DistributionKind::Uniform => Self::Uniform,
        }
    }
}

/// `[mistuning]`: blade stiffness of sector `j` scaled by `1 + δ_j`.
#[derive(Deserialize, Serialize, Clone, Debug, PartialEq, Default)]
#[serde(deny_unknown_fields, default)]
pub struct MistuningSpec {
    /// `δ_1 … δ_N`, one per sector (empty: none given; `[]` written in a
    /// case file is refused, not read as a tuned wheel).
    #[serde(
        skip_serializing_if = "Vec::is_empty",
        deserialize_with = "non_empty_deviations"
    )]
    pub deviations: Vec<f64>,
    /// Standard deviation σ of generated deviations (absent: none generated).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub standard_deviation: Option<f64>,
    /// Seed of the generator (absent: 0).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub seed: Option<u64>,
    /// Distribution of generated deviations (absent: normal).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub distribution: Option<DistributionKind>,
    /// The blade's dofs, 1-based (absent: 1, 2, 3 — the academic blade).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub blade_dofs: Option<Vec<usize>>,
    /// Finite-element sectors: the node set of the blade (absent:
    /// [`DEFAULT_BLADE_NODE_SET`]).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub blade_node_set: Option<String>,
}

/// The node set a finite-element sector's blade is read from by default
/// (`cyclorub mesh fan` writes it).
pub const DEFAULT_BLADE_NODE_SET: &str = "blade";

/// The academic blade: m1 (the tip), m2, m3 (1-based); the root spring
/// m3–m4 joins the disk and is not scaled.
pub const DEFAULT_BLADE_DOFS: [usize; 3] = [1, 2, 3];

/// `mistuning.deviations` as written: refused when empty (a `[]` left in
/// a case would otherwise run a tuned wheel without a word).
fn non_empty_deviations<'de, D: serde::Deserializer<'de>>(
    deserializer: D,
) -> Result<Vec<f64>, D::Error> {
    let values = Vec::<f64>::deserialize(deserializer)?;
    if values.is_empty() {
        return Err(serde::de::Error::custom(
            "mistuning.deviations = []: give one deviation per sector (as many as \
             model.sectors), or remove the key for a tuned wheel",
        ));
    }
    Ok(values)
}

impl MistuningSpec {
    /// Whether it holds the defaults (no `[mistuning]`: a tuned wheel).
    pub fn is_default(&self) -> bool {
        *self == Self::default()
    }

    /// Whether the wheel is mistuned (deviations given or generated).
    pub fn is_set(&self) -> bool {
        !self.deviations.is_empty() || self.standard_deviation.is_some()
    }
}

impl Case {
    /// The deviations `δ_j` of `[mistuning]`: given, or generated from
    /// `standard_deviation`, `seed` and `distribution`; `None` for a tuned
    /// wheel. Each refusal names its key, the value and the rule.
    pub fn mistuning_deviations(&self) -> Result<Option<Vec<f64>>, CaseError> {
        let m = &self.mistuning;
        if !m.is_set() {
            for (key, set) in [
                ("mistuning.seed", m.seed.is_some()),
                ("mistuning.distribution", m.distribution.is_some()),
            ] {
                if set {
                    return Err(invalid(
                        key,
                        "given",
                        "only with mistuning.standard_deviation (it draws the deviations)",
                    ));
                }
            }
            return Ok(None);
        }
        if !m.deviations.is_empty() {
            // Given deviations are not drawn: a seed or a distribution
            // with them would be ignored without a word.
            let given = [
                ("mistuning.seed", m.seed.map(|s| s.to_string())),
                (
                    "mistuning.distribution",
                    m.distribution.map(|d| match d {
                        DistributionKind::Normal => "\"normal\"".to_string(),
                        DistributionKind::Uniform => "\"uniform\"".to_string(),
                    }),
                ),
            ];
            for (key, value) in given {
                if let Some(value) = value {
                    return Err(invalid(
                        key,
                        value,
                        "only with mistuning.standard_deviation (it draws the deviations); \
                         mistuning.deviations are given, so it would be ignored: remove it",
                    ));
                }
            }
        }
        let sectors = self.model.sectors;
        let (deviations, key) = match (m.deviations.is_empty(), m.standard_deviation) {
            (false, Some(_)) => {
                return Err(invalid(
                    "mistuning.standard_deviation",
                    "given",
                    "not with mistuning.deviations: give the deviations, or have them drawn, \
                     not both",
                ))
            }
            (false, None) => (m.deviations.clone(), "mistuning.deviations"),
            (true, Some(sigma)) => {
                if !(sigma.is_finite() && sigma >= 0.0) {
                    return Err(invalid(
                        "mistuning.standard_deviation",
                        sigma,
                        "must be a finite number ≥ 0",
                    ));
                }
                let drawn = generate_deviations(
                    sectors,
                    sigma,
                    m.seed.unwrap_or(0),
                    m.distribution.unwrap_or_default().into(),
                );
                (drawn, "mistuning.standard_deviation")
            }
            (true, None) => return Ok(None),
        };
        if deviations.len() != sectors {
            return Err(invalid(
                "mistuning.deviations",
                format!("{} values", deviations.len()),
                format!("needs one value each, as many as model.sectors = {sectors}"),
            ));
        }
        if let Some((j, d)) = deviations
            .iter()
            .enumerate()
            .find(|(_, d)| !(d.is_finite() && **d > -1.0))
        {
            let allowed = if key == "mistuning.deviations" {
                format!(
                    "deviation {d} of sector {} is not allowed: each must be finite and > −1 \
                     (the blade stiffness is scaled by 1 + δ, which must stay positive)",
                    j + 1
                )
            } else {
                format!(
                    "drew {d} for sector {}, at or below −1 (a blade of no or negative \
                     stiffness): give a smaller standard deviation",
                    j + 1
                )
            };
            let value = if key == "mistuning.deviations" {
                format!("{:?}", m.deviations)
            } else {
                m.standard_deviation.unwrap_or_default().to_string()
            };
            return Err(invalid(key, value, allowed));
        }
        Ok(Some(deviations))
    }

    /// The blade of `[mistuning]` (`blade_dofs`, `blade_node_set`),
    /// checked whether or not deviations are given: the key that fits the
    /// model kind, dofs numbered from 1, each once, at least two (the
    /// blade stiffness joins two of them), within the sector, and on the
    /// academic model joined by a spring. Each refusal names its key.
    pub fn check_blade(&self) -> Result<(), CaseError> {
        let m = &self.mistuning;
        let fe = self.model.kind == ModelKind::FiniteElement;
        if let Some(set) = &m.blade_node_set {
            if !fe {
                return Err(invalid(
                    "mistuning.blade_node_set",
                    format!("\"{set}\""),
                    format!(
                        "a blade node set is read with model.kind = \"finite_element\" only \
                         (this model is \"{}\"): name the blade with mistuning.blade_dofs",
                        self.model.kind.name()
                    ),
                ));
            }
        }
        let Some(dofs) = &m.blade_dofs else {
            return Ok(());
        };
        let couplings = self.model.left_boundary.is_none() && self.model.right_boundary.is_none();
        match self.model.kind {
            ModelKind::Academic | ModelKind::FiniteElement => {}
            ModelKind::Matrices if couplings => {}
            kind => return Err(no_blade(kind)),
        }
        let shown = format!("{dofs:?}");
        let refuse = |allowed: String| Err(invalid("mistuning.blade_dofs", &shown, allowed));
        if fe {
            return refuse(
                "a finite-element sector's blade is a node set: name it with \
                 mistuning.blade_node_set (default \"blade\"), not by dofs"
                    .into(),
            );
        }
        if dofs.contains(&0) {
            return refuse("dofs are numbered from 1".into());
        }
        if let Some((_, d)) = dofs
            .iter()
            .enumerate()
            .find(|(i, d)| dofs[..*i].contains(d))
        {
            return refuse(format!("dof {d} is listed twice: name each blade dof once"));
        }
        if dofs.len() < 2 {
            return refuse(
                "name at least two dofs: the blade stiffness mistuning scales joins two blade \
                 dofs (e.g. [1, 2, 3], the academic blade)"
                    .into(),
            );
        }
        let zero_based: Vec<usize> = dofs.iter().map(|d| d - 1).collect();
        match self.model.kind {
            // A model that does not build is refused by its own keys later.
            ModelKind::Academic => {
                if let Ok(sector) = self.model.lumped_sector() {
                    sector
                        .blade_stiffness(&zero_based, "mistuning.blade_dofs")
                        .map_err(|e| model_refusal(&e, &shown))?;
                }
            }
            ModelKind::Matrices => {
                let count = self.model.stiffness.as_deref().map_or(0, <[_]>::len);
                if let Some(bad) = dofs.iter().find(|&&d| d > count) {
                    return refuse(format!(
                        "dof {bad} is out of range: a sector has dofs 1..={count}"
                    ));
                }
            }
            _ => {}
        }
        Ok(())
    }

    /// `model` (built from this case's `[model]`, whose files are read
    /// from `case_dir`) mistuned when `[mistuning]` says so, else
    /// unchanged: the blade stiffness of the academic (lumped) model is the
    /// springs between two of `mistuning.blade_dofs`; of inline matrices
    /// with couplings, the sector stiffness entries between two blade dofs;
    /// of a finite-element sector, its stiffness entries between two nodes
    /// of the node set `mistuning.blade_node_set`, projected on the tuned
    /// Craig–Bampton bases (the model is then reduced again, with the
    /// blade's rows of each basis). Matrix Market sectors are refused,
    /// naming the key.
    pub fn mistuned(&self, model: SectorModel, case_dir: &Path) -> Result<SectorModel, CaseError> {
        let Some(deviations) = self.mistuning_deviations()? else {
            return Ok(model);
        };
        self.check_blade()?;
        if let Some(set) = &self.mistuning.blade_node_set {
            if self.model.kind != ModelKind::FiniteElement {
                return Err(invalid(
                    "mistuning.blade_node_set",
                    format!("\"{set}\""),
                    format!(
                        "a blade node set is read with model.kind = \"finite_element\" only \
                         (this model is \"{}\"): name the blade with mistuning.blade_dofs",
                        self.model.kind.name()
                    ),
                ));
            }
        }
        if self.model.kind == ModelKind::FiniteElement {
            if let Some(dofs) = &self.mistuning.blade_dofs {
                return Err(invalid(
                    "mistuning.blade_dofs",
                    format!("{dofs:?}"),
                    "a finite-element sector's blade is a node set: name it with \
                     mistuning.blade_node_set (default \"blade\"), not by dofs",
                ));
            }
            let set = self
                .mistuning
                .blade_node_set
                .as_deref()
                .unwrap_or(DEFAULT_BLADE_NODE_SET);
            let shown = format!("\"{set}\"");
            let (reduced, blade) = self
                .model
                .build_with_blade(case_dir, set, "mistuning.blade_node_set")
                .map_err(|e| model_refusal(&e, &shown))?;
            let mistuning = Mistuning::reduced(deviations, &blade, "mistuning.deviations")
                .map_err(|e| model_refusal(&e, "(drawn or given)"))?;
            return reduced
                .with_mistuning(mistuning)
                .map_err(|e| model_refusal(&e, "(as given)"));
        }
        let blade_dofs: Vec<usize> = self
            .mistuning
            .blade_dofs
            .clone()
            .unwrap_or_else(|| DEFAULT_BLADE_DOFS.to_vec());
        let shown = format!("{blade_dofs:?}");
        if blade_dofs.contains(&0) {
            return Err(invalid(
                "mistuning.blade_dofs",
                shown,
                "dofs are numbered from 1",
            ));
        }
        let zero_based: Vec<usize> = blade_dofs.iter().map(|d| d - 1).collect();
        let blade = match self.model.kind {
            ModelKind::Academic => self
                .model
                .lumped_sector()
                .map_err(|e| model_refusal(&e, "model"))?
                .blade_stiffness(&zero_based, "mistuning.blade_dofs")
                .map_err(|e| model_refusal(&e, &shown))?,
            // Inline matrices with couplings: the sector's own stiffness
            // entries between two blade dofs (docs/design.md §12).
            ModelKind::Matrices
                if self.model.left_boundary.is_none() && self.model.right_boundary.is_none() =>
            {
                let rows = self.model.stiffness.as_deref().unwrap_or_default();
                entries_between(rows, &zero_based, model.dofs_per_sector(), &shown)?
            }
            kind => return Err(no_blade(kind)),
        };
        let mistuning = Mistuning::new(deviations, blade, "mistuning.deviations")
            .map_err(|e| model_refusal(&e, "(drawn or given)"))?;
        model
            .with_mistuning(mistuning)
            .map_err(|e| model_refusal(&e, "(as given)"))
    }
}

/// The refusal of mistuning on a model kind with no blade to scale.
fn no_blade(kind: ModelKind) -> CaseError {
    invalid(
        "mistuning",
        format!("(with model.kind = \"{}\")", kind.name()),
        "mistuning is available on the academic (lumped) model, on inline matrices with \
         couplings (model.kind = \"matrices\") and on finite-element sectors (model.kind = \
         \"finite_element\", the blade a node set); a Matrix Market sector, or inline \
         matrices with cyclic boundary lists, has no blade to scale",
    )
}

/// The stiffness entries `rows[a][b]` with `a`, `b` both blade dofs
/// (0-based, diagonal included), zero elsewhere: a sector of `dofs` dofs.
fn entries_between(
    rows: &[Vec<f64>],
    blade: &[usize],
    dofs: usize,
    shown: &str,
) -> Result<Mat<f64>, CaseError> {
    if let Some(bad) = blade.iter().find(|&&d| d >= dofs) {
        return Err(invalid(
            "mistuning.blade_dofs",
            shown,
            format!(
                "dof {} is out of range: a sector has dofs 1..={dofs}",
                bad + 1
            ),
        ));
    }
    Ok(Mat::from_fn(dofs, dofs, |a, b| {
        if blade.contains(&a) && blade.contains(&b) {
            rows.get(a).and_then(|r| r.get(b)).copied().unwrap_or(0.0)
        } else {
            0.0
        }
    }))
}

/// A model's refusal as a case error: its key, `value`, its message.
fn model_refusal(error: &crate::model::ModelError, value: &str) -> CaseError {
    match error {
        crate::model::ModelError::Invalid { key, message } => {
            invalid(&key.to_string(), value, message.clone())
        }
        other => invalid("mistuning", value, other.to_string()),
    }
}
