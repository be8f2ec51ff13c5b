//! The residual of a case on a sector model, on the basis a rule of the
//! case gives ([`build_problem`]) or on any given basis
//! ([`problem_on_basis`]: a bifurcated branch's, docs/design.md §11).

use super::RunError;
use crate::basis::{BasisError, SpectralBasis};
use crate::case::{BasisChoice, Case, CaseError};
use crate::hbm::{Casing, Formulation, HarmonicBalance, HbmError, ProblemSpec};
use crate::model::SectorModel;

/// The residual of `case` on `model` with `basis`, and the spectral basis
/// it is built on (`None` for the physical full wheel).
pub(crate) fn build_problem(
    case: &Case,
    model: &SectorModel,
    basis: BasisChoice,
) -> Result<(HarmonicBalance, Option<SpectralBasis>), RunError> {
    let parts = SpecParts::new(case, model)?;
    let spec = parts.spec(case, model);
    let load = spec.load_case();
    let harmonics = case.harmonic_balance.harmonics;
    let spectral = match basis {
        BasisChoice::Symmetry => Some(SpectralBasis::symmetry(&load, harmonics)),
        BasisChoice::Paper => Some(SpectralBasis::paper(&load, harmonics)),
        BasisChoice::NodalDiameter => Some(SpectralBasis::nodal_diameter(&load, harmonics)),
        BasisChoice::Full => Some(SpectralBasis::full(model.sectors(), harmonics)),
        BasisChoice::Physical => None,
    }
    .transpose()
    .map_err(|error| match error {
        BasisError::TooLarge { .. } => RunError::Case(CaseError::Invalid {
            key: "harmonic_balance.harmonics".into(),
            value: harmonics.to_string(),
            allowed: format!("{error} (model.sectors = {})", model.sectors()),
        }),
        other => HbmError::Basis(other).into(),
    })?;
    let formulation = match &spectral {
        Some(b) => Formulation::Cyclic(b.clone()),
        None => Formulation::Physical,
    };
    Ok((spec.build(&formulation)?, spectral))
}

/// The residual of `case` on `model` with the given spectral basis (the
/// physical full wheel for `None`): a basis no rule of the case gives, such
/// as a bifurcated branch's (docs/design.md §11).
pub fn problem_on_basis(
    case: &Case,
    model: &SectorModel,
    basis: Option<SpectralBasis>,
) -> Result<HarmonicBalance, RunError> {
    let parts = SpecParts::new(case, model)?;
    let formulation = match basis {
        Some(b) => Formulation::Cyclic(b),
        None => Formulation::Physical,
    };
    Ok(parts.spec(case, model).build(&formulation)?)
}

/// What a [`ProblemSpec`] borrows, resolved from the case once.
struct SpecParts {
    forcing: Option<crate::hbm::Forcing>,
    casing: Casing,
    preload: Option<Vec<f64>>,
    contact_dofs: Vec<usize>,
    friction: Option<crate::contact::SlidingFriction>,
    contact: crate::contact::ContactModel,
}

impl SpecParts {
    fn new(case: &Case, model: &SectorModel) -> Result<Self, RunError> {
        let (casing, preload) = case.preloaded_casing(model)?;
        Ok(Self {
            forcing: case.forcing(),
            casing,
            preload,
            contact_dofs: case.contact_dofs(),
            friction: case.friction(model)?,
            contact: case.contact_model()?,
        })
    }

    fn spec<'a>(&'a self, case: &Case, model: &'a SectorModel) -> ProblemSpec<'a> {
        ProblemSpec {
            model,
            contact_dofs: &self.contact_dofs,
            forcing: self.forcing.as_ref(),
            casing: &self.casing,
            contact: self.contact.clone(),
            friction: self.friction.as_ref(),
            preload: self.preload.as_deref(),
            harmonics: case.harmonic_balance.harmonics,
            time_samples: case.harmonic_balance.time_samples,
        }
    }
}
