//! A case file's full wheel, loads and law, ready to integrate.

use super::loading::WheelLoads;
use super::wheel::WheelMatrices;
use super::SimulateError;
use crate::case::Case;
use crate::contact::{ContactLaw, ContactModel};
use crate::model::SectorModel;
use std::path::Path;
use std::sync::Arc;

/// Everything a time integration of a case needs, built once.
#[derive(Clone, Debug)]
pub struct WheelSetup {
    /// The sector model.
    pub model: SectorModel,
    /// The full wheel's matrices.
    pub wheel: Arc<WheelMatrices>,
    /// Excitation, casing and contact dofs.
    pub loads: Arc<WheelLoads>,
    /// The contact treatment of the case.
    pub contact: ContactModel,
}

impl WheelSetup {
    /// Builds the wheel of `case` (checked here; its relative paths start
    /// from `case_dir`).
    pub fn from_case(case: &Case, case_dir: &Path) -> Result<Self, SimulateError> {
        case.validate()?;
        let model = case.mistuned(case.model.build(case_dir)?, case_dir)?;
        // The time integration's operators are block-circulant (tuned).
        if model.is_mistuned() {
            return Err(crate::case::CaseError::Invalid {
                key: "mistuning".into(),
                value: "(set)".into(),
                allowed: "cyclorub simulate integrates a tuned wheel only (its operators are \
                          block-circulant); a mistuned wheel is not integrated in time yet \
                          (issue 44): leave [mistuning] out"
                    .into(),
            }
            .into());
        }
        case.check_model(&model)?;
        crate::memory::SimulationSizes::of_wheel(
            model.sectors(),
            model.dofs_per_sector(),
            // With friction each contact dof brings its node's two tangential dofs.
            case.contact.dofs.len()
                * if case.contact.friction.is_some_and(|mu| mu != 0.0) {
                    3
                } else {
                    1
                },
        )
        .check_wheel()?;
        let wheel = Arc::new(WheelMatrices::new(&model)?);
        let mut case = case.clone();
        case.resolve_preload(case_dir, &model)?;
        let (casing, preload) = case.preloaded_casing(&model)?;
        let mut loads = WheelLoads::new(
            model.sectors(),
            model.dofs_per_sector(),
            case.forcing().as_ref(),
            casing,
            &case.contact_dofs(),
        )?;
        if let Some(forces) = preload {
            loads = loads.with_preload(forces)?;
        }
        if let Some(friction) = case.friction(&model)? {
            loads = loads.with_friction(friction)?;
        }
        let loads = Arc::new(loads);
        Ok(Self {
            model,
            wheel,
            loads,
            contact: case.contact_model()?,
        })
    }

    /// The contact law.
    pub fn law(&self) -> Arc<dyn ContactLaw> {
        self.contact.law()
    }
}
