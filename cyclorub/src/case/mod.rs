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
//! prints (`cyclorub_app::template`) and the key tables of the case-file
//! reference (docs/case-file.md) all come from it.

use crate::contact::{ContactModel, DynamicLagrangian, RegularizedPenalty};
use crate::cyclic::ExcitationPattern;
use crate::hbm::{Casing, Forcing};
use crate::model::{ModelSpec, SectorModel, StaticPreload};
use serde::{Deserialize, Serialize};
use std::path::Path;

mod error;
mod friction;
pub mod keys;
mod memory;
mod mistuning;
mod tables;
pub mod text;
mod validate;

use error::{contact_error, invalid};
pub use error::{key_line, parse_key, CaseError};
pub use mistuning::{DistributionKind, MistuningSpec, DEFAULT_BLADE_DOFS};
pub use tables::{
    BasisChoice, BasisSpec, CasingSpec, ContactSpec, ContinuationSpec, ExcitationKind,
    ExcitationSpec, FigureFormat, HarmonicBalanceSpec, LawKind, OutputSpec, PerContactDof,
    PreloadSpec, RotationSpec, StabilitySpec,
};

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
    /// `[rotation]`.
    #[serde(skip_serializing_if = "RotationSpec::is_default")]
    pub rotation: RotationSpec,
    /// `[preload]`.
    #[serde(skip_serializing_if = "PreloadSpec::is_default")]
    pub preload: PreloadSpec,
    /// `[harmonic_balance]`.
    pub harmonic_balance: HarmonicBalanceSpec,
    /// `[continuation]`.
    pub continuation: ContinuationSpec,
    /// `[basis]`.
    pub basis: BasisSpec,
    /// `[output]`.
    pub output: OutputSpec,
    /// `[stability]`.
    pub stability: StabilitySpec,
    /// `[mistuning]` (absent: a tuned wheel).
    #[serde(skip_serializing_if = "MistuningSpec::is_default")]
    pub mistuning: MistuningSpec,
}

impl Case {
    /// Reads a case file and checks every value, a refused value located
    /// by its line in the file; keys the run will not use are logged as
    /// warnings ([`Case::unused_keys`]).
    pub fn from_file_checked(path: &Path) -> Result<Self, CaseError> {
        let text = std::fs::read_to_string(path).map_err(|source| CaseError::Io {
            path: path.to_path_buf(),
            source,
        })?;
        let case = Self::from_toml(&text, path)?;
        case.validate().map_err(|e| e.located(path, &text))?;
        // Keys the run will not use are said, not refused.
        let mut unused = case.unused_keys();
        unused.extend(validate::keys_not_in_use(&case, &text));
        for unused in unused {
            tracing::warn!("{}: {unused}", path.display());
        }
        Ok(case)
    }

    /// Parses TOML text (`origin` names it in messages).
    pub fn from_toml(text: &str, origin: &Path) -> Result<Self, CaseError> {
        toml::from_str(text).map_err(|error| CaseError::Parse {
            path: origin.to_path_buf(),
            key: error.span().and_then(|s| error::parse_key(text, s.start)),
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

    /// The speed (rad/s) of the centrifugal preload: `preload.speed`, else
    /// `rotation.speed`.
    pub fn preload_speed(&self) -> Result<f64, CaseError> {
        self.preload.speed.or(self.rotation.speed).ok_or_else(|| {
            invalid(
                "preload.speed",
                "absent",
                "with preload.centrifugal = true, give the speed Ω (rad/s) here or in \
                 rotation.speed",
            )
        })
    }

    /// Computes the centrifugal force on `model` (built from this case's
    /// `[model]`, its files relative to `case_dir`) when `preload.centrifugal`
    /// asks for it and it is not computed yet; returns the preload computed.
    pub fn resolve_preload(
        &mut self,
        case_dir: &Path,
        model: &SectorModel,
    ) -> Result<Option<StaticPreload>, CaseError> {
        if !self.preload.centrifugal || self.preload.centrifugal_forces.is_some() {
            return Ok(None);
        }
        let speed = self.preload_speed()?;
        let preload = self
            .model
            .centrifugal_preload(case_dir, model, speed)
            .map_err(|e| invalid("preload.centrifugal", "true", e.to_string()))?;
        self.preload.centrifugal_forces = Some(preload.forces.clone());
        Ok(Some(preload))
    }

    /// The static preload on `model`'s dofs (N per dof, the same on every
    /// sector), `None` without `[preload]`: `preload.static_forces` plus the
    /// centrifugal force, which must have been computed for this model
    /// ([`crate::forced_response::prepare`] does it).
    pub fn preload_forces(&self, model: &SectorModel) -> Result<Option<Vec<f64>>, CaseError> {
        let p = &self.preload;
        if !p.is_set() {
            return Ok(None);
        }
        let dofs = model.dofs_per_sector();
        let mut forces = vec![0.0; dofs];
        if !p.static_forces.is_empty() {
            if p.static_forces.len() != dofs {
                return Err(invalid(
                    "preload.static_forces",
                    format!("{} values", p.static_forces.len()),
                    format!("one force per dof of a sector: the model has {dofs}"),
                ));
            }
            if let Some(bad) = p.static_forces.iter().find(|v| !v.is_finite()) {
                return Err(invalid("preload.static_forces", bad, "finite numbers (N)"));
            }
            forces.copy_from_slice(&p.static_forces);
        }
        if p.centrifugal {
            let computed = p
                .centrifugal_forces
                .as_ref()
                .filter(|f| f.len() == dofs)
                .ok_or_else(|| {
                    invalid(
                        "preload.centrifugal",
                        "true",
                        "its force is computed when the model is built from the case file \
                         (forced_response::prepare); it was not computed for this model",
                    )
                })?;
            for (f, c) in forces.iter_mut().zip(computed) {
                *f += c;
            }
        }
        Ok(Some(forces))
    }

    /// The casing on `model` and the preload (as [`Self::preload_forces`]):
    /// with `casing.gap_after_preload`, each contact dof's gap measured from
    /// the blade at rest, `casing.gap` plus the static displacement toward
    /// the casing (the clearance is what is left on the preloaded blade).
    pub fn preloaded_casing(
        &self,
        model: &SectorModel,
    ) -> Result<(Casing, Option<Vec<f64>>), CaseError> {
        let mut casing = self.casing()?;
        let preload = self.preload_forces(model)?;
        if let (Some(forces), true) = (&preload, self.casing.gap_after_preload) {
            let growth = model
                .static_response(forces, "preload")
                .map_err(|e| invalid("preload", "the static load", e.to_string()))?;
            for (gap, d) in casing.gaps.iter_mut().zip(self.contact_dofs()) {
                *gap += growth.get(d).copied().unwrap_or(0.0);
            }
        }
        Ok((casing, preload))
    }

    /// The casing in library form. With a shape (`casing.order > 0`) the
    /// gap at contact dof `i` varies between `c_i − p_i` and `c_i + p_i`: an
    /// amplitude above the mean gap is a casing that cuts into the blade at
    /// rest, refused as a negative mean gap is.
    pub fn casing(&self) -> Result<Casing, CaseError> {
        let count = self.contact.dofs.len();
        let casing = Casing {
            gaps: self.casing.gap.expand("casing.gap", count)?,
            order: self.casing.order,
            amplitudes: self.casing.amplitude.expand("casing.amplitude", count)?,
        };
        if casing.order > 0 {
            let deeper = casing
                .gaps
                .iter()
                .zip(&casing.amplitudes)
                .enumerate()
                .find(|(_, (c, p))| p > c);
            if let Some((i, (c, p))) = deeper {
                let at = if count > 1 {
                    format!(" at contact dof {} (entry {})", self.contact.dofs[i], i + 1)
                } else {
                    String::new()
                };
                return Err(invalid(
                    "casing.amplitude",
                    p,
                    format!(
                        "deeper than casing.gap = {c}{at} with casing.order = {}: the casing's \
                         smallest gap c − p = {:e} m is below 0, it cuts into the blade at rest; \
                         give an amplitude ≤ the gap",
                        casing.order,
                        c - p
                    ),
                ));
            }
        }
        Ok(casing)
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
