//! The `[model.damping]` table: modal ratios, Rayleigh factors, a matrix
//! (inline or a Matrix Market file), or none.

use super::{rows_to_mat, Keys};
use crate::model::damping::{Damping, ModalDamping};
use crate::model::matrix_market::read_matrix_market;
use crate::model::ModelError;
use serde::{Deserialize, Serialize};
use std::path::{Path, PathBuf};

/// Which damping a `[model.damping]` table describes.
#[derive(Deserialize, Serialize, Clone, Copy, Debug, PartialEq, Eq, Default)]
#[serde(rename_all = "snake_case")]
pub enum DampingKind {
    /// No damping.
    None,
    /// Modal ratios per nodal diameter (`ratio`, or `ratios` and `others`).
    #[default]
    Modal,
    /// `C = alpha·M + beta·K`.
    Rayleigh,
    /// A given matrix (`matrix` inline, optionally `coupling`, or `file`).
    Matrix,
}

/// The `[model.damping]` table.
///
/// ```toml
/// [model.damping]
/// kind = "modal"
/// ratios = [1e-3, 1e-3, 1e-3, 1e-3, 1e-3]   # modes 1..5 of every nodal diameter
/// others = 5e-3                             # the modes beyond
/// ```
#[derive(Deserialize, Serialize, Clone, Debug, PartialEq, Default)]
#[serde(deny_unknown_fields)]
pub struct DampingSpec {
    /// `"modal"` (default), `"rayleigh"`, `"matrix"` or `"none"`.
    #[serde(default)]
    pub kind: DampingKind,
    /// Modal: the ratio of every mode (default 1e-3 when neither `ratio` nor
    /// `ratios` is given).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub ratio: Option<f64>,
    /// Modal: ratios by mode index within each nodal diameter's family.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub ratios: Option<Vec<f64>>,
    /// Modal: the ratio of the modes beyond `ratios`.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub others: Option<f64>,
    /// Rayleigh: mass factor (1/s), default 0.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub alpha: Option<f64>,
    /// Rayleigh: stiffness factor (s), default 0.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub beta: Option<f64>,
    /// Matrix: the sector damping matrix inline (rows), laid out like the stiffness.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub matrix: Option<Vec<Vec<f64>>>,
    /// Matrix: coupling block to the next sector (block-circulant sectors).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub coupling: Option<Vec<Vec<f64>>>,
    /// Matrix: a Matrix Market file, relative to the case file's directory.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub file: Option<PathBuf>,
}

impl DampingSpec {
    /// The damping of a sector with `n` independent dofs; files are read
    /// from `case_dir`.
    pub(super) fn build(
        &self,
        n: usize,
        case_dir: &Path,
        keys: &Keys,
    ) -> Result<Damping, ModelError> {
        let d = self;
        let set: Vec<&str> = [
            ("ratio", d.ratio.is_some()),
            ("ratios", d.ratios.is_some()),
            ("others", d.others.is_some()),
            ("alpha", d.alpha.is_some()),
            ("beta", d.beta.is_some()),
            ("matrix", d.matrix.is_some()),
            ("coupling", d.coupling.is_some()),
            ("file", d.file.is_some()),
        ]
        .into_iter()
        .filter(|(_, s)| *s)
        .map(|(k, _)| k)
        .collect();
        let (kind, allowed): (&str, &[&str]) = match d.kind {
            DampingKind::None => ("none", &[]),
            DampingKind::Modal => ("modal", &["ratio", "ratios", "others"]),
            DampingKind::Rayleigh => ("rayleigh", &["alpha", "beta"]),
            DampingKind::Matrix => ("matrix", &["matrix", "coupling", "file"]),
        };
        for k in set {
            if !allowed.contains(&k) {
                let keys = if allowed.is_empty() {
                    "kind".to_string()
                } else {
                    format!("kind, {}", allowed.join(", "))
                };
                return Err(ModelError::invalid(
                    format!("model.damping.{k}"),
                    format!("not used with kind = \"{kind}\"; its keys are: {keys}"),
                ));
            }
        }
        match d.kind {
            DampingKind::None => Ok(Damping::None),
            DampingKind::Modal => match (d.ratio, &d.ratios) {
                (Some(_), Some(_)) => Err(ModelError::invalid(
                    "model.damping.ratio",
                    "give either ratio (all modes) or ratios (by mode index, with others), not both",
                )),
                (Some(_), None) if d.others.is_some() => Err(ModelError::invalid(
                    "model.damping.others",
                    "only used with ratios; ratio already damps every mode",
                )),
                (None, None) if d.others.is_some() => Err(ModelError::invalid(
                    "model.damping.others",
                    "only used with ratios (the ratios of the first modes); alone, give ratio",
                )),
                (ratio, None) => {
                    let ratio = ratio.unwrap_or(1e-3);
                    if !(ratio.is_finite() && ratio >= 0.0) {
                        return Err(ModelError::invalid(
                            "model.damping.ratio",
                            format!("{ratio} is not allowed: damping ratios must be finite and ≥ 0"),
                        ));
                    }
                    Ok(Damping::Modal(ModalDamping::uniform(ratio)))
                }
                (None, Some(ratios)) => {
                    if let Some((i, r)) = ratios
                        .iter()
                        .enumerate()
                        .find(|(_, r)| !(r.is_finite() && **r >= 0.0))
                    {
                        return Err(ModelError::invalid(
                            "model.damping.ratios",
                            format!(
                                "entry {} = {r} is not allowed: damping ratios must be finite \
                                 and ≥ 0",
                                i + 1
                            ),
                        ));
                    }
                    let others = match (d.others, ratios.last()) {
                        (Some(o), _) => o,
                        (None, Some(&last)) if ratios.len() >= n => last,
                        (None, _) => {
                            return Err(ModelError::invalid(
                                "model.damping.others",
                                format!(
                                    "required: model.damping.ratios lists {} ratios but each nodal diameter has {n} modes",
                                    ratios.len()
                                ),
                            ))
                        }
                    };
                    Ok(Damping::Modal(ModalDamping {
                        ratios: ratios.clone(),
                        others,
                    }))
                }
            },
            DampingKind::Rayleigh => {
                if d.alpha.is_none() && d.beta.is_none() {
                    return Err(ModelError::invalid(
                        "model.damping",
                        "kind = \"rayleigh\" needs alpha (mass factor, 1/s) and/or beta (stiffness factor, s)",
                    ));
                }
                Ok(Damping::Rayleigh {
                    alpha: d.alpha.unwrap_or(0.0),
                    beta: d.beta.unwrap_or(0.0),
                })
            }
            DampingKind::Matrix => {
                let matrix = match (&d.matrix, &d.file) {
                    (Some(rows), None) => rows_to_mat(rows, &keys.damping_matrix)?,
                    (None, Some(file)) => read_matrix_market(&case_dir.join(file), &keys.damping_matrix)?,
                    (Some(_), Some(_)) => {
                        return Err(ModelError::invalid(
                            "model.damping.file",
                            "give either matrix (inline) or file (Matrix Market), not both",
                        ))
                    }
                    (None, None) => {
                        return Err(ModelError::invalid(
                            "model.damping",
                            "kind = \"matrix\" needs matrix (inline rows) or file (Matrix Market)",
                        ))
                    }
                };
                let coupling = d
                    .coupling
                    .as_deref()
                    .map(|r| rows_to_mat(r, "model.damping.coupling"))
                    .transpose()?;
                Ok(Damping::Matrix { matrix, coupling })
            }
        }
    }
}
