//! Which keys a `[model]` table sets and may set for its kind, and the
//! case-file names of the sector inputs, by which the model layer's errors
//! are renamed.

use super::super::input::SectorInput;
use super::super::validate::{DEFAULT_SYMMETRY_TOLERANCE, MAX_SYMMETRY_TOLERANCE};
use super::super::ModelError;
use super::{ModelKind, ModelSpec};
use std::path::PathBuf;

/// The case-file key of `[model]`'s `name`.
pub(super) fn key(name: &str) -> String {
    format!("model.{name}")
}

/// The case-file keys of the sector inputs: the model layer names its
/// errors by [`SectorInput`], this table renames them for the case file.
pub(super) struct Keys {
    /// The mass's key (or file).
    pub(super) mass: String,
    /// The stiffness's key (or file).
    pub(super) stiffness: String,
    /// The damping matrix's key (or file).
    pub(super) damping_matrix: String,
}

impl Keys {
    /// The key of `input` (with its file, for inputs read from one).
    pub(super) fn of(&self, input: SectorInput) -> String {
        match input {
            SectorInput::Sectors => key("sectors"),
            SectorInput::Mass => self.mass.clone(),
            SectorInput::Stiffness => self.stiffness.clone(),
            SectorInput::MassCoupling => key("mass_coupling"),
            SectorInput::StiffnessCoupling => key("stiffness_coupling"),
            SectorInput::Damping => key("damping"),
            SectorInput::DampingMatrix => self.damping_matrix.clone(),
            SectorInput::DampingCoupling => "model.damping.coupling".into(),
            SectorInput::LeftBoundary => key("left_boundary"),
            SectorInput::RightBoundary => key("right_boundary"),
        }
    }
}

impl ModelSpec {
    /// The keys set in this table (besides `kind`, `sectors`, `damping`,
    /// `symmetry_tolerance`, which every kind takes).
    pub(super) fn set_keys(&self) -> Vec<&'static str> {
        let mut keys = Vec::new();
        let mut push = |set: bool, k: &'static str| {
            if set {
                keys.push(k);
            }
        };
        push(self.masses.is_some(), "masses");
        push(self.springs.is_some(), "springs");
        push(self.mass.is_some(), "mass");
        push(self.stiffness.is_some(), "stiffness");
        push(self.mass_coupling.is_some(), "mass_coupling");
        push(self.stiffness_coupling.is_some(), "stiffness_coupling");
        push(self.mass_file.is_some(), "mass_file");
        push(self.stiffness_file.is_some(), "stiffness_file");
        push(self.left_boundary.is_some(), "left_boundary");
        push(self.right_boundary.is_some(), "right_boundary");
        push(self.boundary_frame.is_some(), "boundary_frame");
        push(self.axis.is_some(), "axis");
        push(self.coordinates_file.is_some(), "coordinates_file");
        push(self.dofs_per_node.is_some(), "dofs_per_node");
        push(self.node_sets_file.is_some(), "node_sets_file");
        push(self.contact_frame.is_some(), "contact_frame");
        keys
    }

    pub(super) fn check_keys(&self) -> Result<(), ModelError> {
        let allowed: &[&str] = match self.kind {
            ModelKind::Academic => &["masses", "springs"],
            ModelKind::Matrices => &[
                "mass",
                "stiffness",
                "mass_coupling",
                "stiffness_coupling",
                "left_boundary",
                "right_boundary",
                "boundary_frame",
                "axis",
            ],
            ModelKind::MatrixMarket => &[
                "mass_file",
                "stiffness_file",
                "left_boundary",
                "right_boundary",
                "boundary_frame",
                "axis",
            ],
            ModelKind::FiniteElement => &[
                "mass_file",
                "stiffness_file",
                "coordinates_file",
                "dofs_per_node",
                "node_sets_file",
                "contact_frame",
                "boundary_frame",
                "axis",
            ],
        };
        for k in self.set_keys() {
            if !allowed.contains(&k) {
                return Err(ModelError::invalid(
                    key(k),
                    format!(
                        "not used with kind = \"{}\"; its keys are: kind, sectors, {}, damping, symmetry_tolerance",
                        self.kind.name(),
                        allowed.join(", ")
                    ),
                ));
            }
        }
        Ok(())
    }

    /// The relative tolerance on the symmetry of the matrices.
    pub(super) fn symmetry_tolerance(&self) -> Result<f64, ModelError> {
        let tolerance = self
            .symmetry_tolerance
            .unwrap_or(DEFAULT_SYMMETRY_TOLERANCE);
        if !(tolerance.is_finite() && tolerance >= 0.0) {
            return Err(ModelError::invalid(
                key("symmetry_tolerance"),
                format!("{tolerance} is not allowed: a relative tolerance must be finite and ≥ 0"),
            ));
        }
        if tolerance > MAX_SYMMETRY_TOLERANCE {
            return Err(ModelError::invalid(
                key("symmetry_tolerance"),
                format!(
                    "{tolerance} is not allowed: at most {MAX_SYMMETRY_TOLERANCE:e} (a difference \
                     above 0.1 % of the largest entry is not rounding: the matrix is not \
                     symmetric, and its symmetric part would be another structure)"
                ),
            ));
        }
        Ok(tolerance)
    }

    /// The case-file key of each sector input, with its file when it is
    /// read from one.
    pub(super) fn keys(&self) -> Keys {
        let file = |k: &str, p: &Option<PathBuf>| match p {
            Some(p) => format!("{} (\"{}\")", key(k), p.display()),
            None => key(k),
        };
        let (mass, stiffness) = match self.kind {
            ModelKind::MatrixMarket | ModelKind::FiniteElement => (
                file("mass_file", &self.mass_file),
                file("stiffness_file", &self.stiffness_file),
            ),
            ModelKind::Academic => (key("masses"), key("springs")),
            ModelKind::Matrices => (key("mass"), key("stiffness")),
        };
        let damping_matrix = match &self.damping.file {
            Some(p) => format!("model.damping.file (\"{}\")", p.display()),
            None => "model.damping.matrix".into(),
        };
        Keys {
            mass,
            stiffness,
            damping_matrix,
        }
    }
}
