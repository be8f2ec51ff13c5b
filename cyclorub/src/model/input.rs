//! What a model error is about: one input of a sector description, as the
//! model layer knows it, or a name the caller attached (a case-file key, a
//! file). The model layer never learns the case file's keys: the case layer
//! renames its errors with [`ModelError::named`](super::ModelError::named).

use std::fmt;

/// One input of a sector description ([`super::BlockCirculantSector`],
/// [`super::FiniteElementSector`], [`super::Damping`]).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum SectorInput {
    /// The number of sectors `N`.
    Sectors,
    /// The sector mass matrix (`M0` of a block-circulant sector).
    Mass,
    /// The sector stiffness matrix (`K0` of a block-circulant sector).
    Stiffness,
    /// The mass coupling block `M1` to the next sector.
    MassCoupling,
    /// The stiffness coupling block `K1` to the next sector.
    StiffnessCoupling,
    /// The damping description (modal ratios, Rayleigh factors).
    Damping,
    /// The given viscous damping matrix.
    DampingMatrix,
    /// The damping coupling block to the next sector.
    DampingCoupling,
    /// The left cyclic boundary dofs of a finite-element sector.
    LeftBoundary,
    /// The right cyclic boundary dofs of a finite-element sector.
    RightBoundary,
}

impl SectorInput {
    /// The name the model layer gives it when no caller renames it.
    pub fn name(self) -> &'static str {
        match self {
            Self::Sectors => "sectors",
            Self::Mass => "mass",
            Self::Stiffness => "stiffness",
            Self::MassCoupling => "mass coupling",
            Self::StiffnessCoupling => "stiffness coupling",
            Self::Damping => "damping",
            Self::DampingMatrix => "damping matrix",
            Self::DampingCoupling => "damping coupling",
            Self::LeftBoundary => "left boundary",
            Self::RightBoundary => "right boundary",
        }
    }
}

/// The subject of a model error: a sector input (with a suffix naming an
/// element of it, such as `[2]` or `.ratios[1]`) until the caller names it.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum Subject {
    /// A sector input and the element of it, e.g. `(LeftBoundary, "[2]")`.
    Input(SectorInput, String),
    /// A name given by the caller: a case-file key, a key and its file.
    Named(String),
}

impl Subject {
    /// A whole sector input.
    pub fn input(input: SectorInput) -> Self {
        Self::Input(input, String::new())
    }

    /// The same subject with the caller's names: `name` gives the name of
    /// each sector input (e.g. its case-file key).
    pub fn named(self, name: &impl Fn(SectorInput) -> String) -> Self {
        match self {
            Self::Input(input, suffix) => Self::Named(format!("{}{suffix}", name(input))),
            named => named,
        }
    }
}

impl fmt::Display for Subject {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Self::Input(input, suffix) => write!(f, "{}{suffix}", input.name()),
            Self::Named(name) => f.write_str(name),
        }
    }
}

impl From<SectorInput> for Subject {
    fn from(input: SectorInput) -> Self {
        Self::input(input)
    }
}

impl From<String> for Subject {
    fn from(name: String) -> Self {
        Self::Named(name)
    }
}

impl From<&str> for Subject {
    fn from(name: &str) -> Self {
        Self::Named(name.to_string())
    }
}

impl From<&String> for Subject {
    fn from(name: &String) -> Self {
        Self::Named(name.clone())
    }
}
