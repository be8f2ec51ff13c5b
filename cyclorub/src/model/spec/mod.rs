//! The `[model]` table of a case file.
//!
//! ```toml
//! [model]
//! kind = "academic"      # "academic" | "matrices" | "matrix_market" | "finite_element"
//! sectors = 24
//! ```
//! is the paper's academic model with `ξ = 1e-3` on all modes. Dofs are
//! 1-based in case files. See [`ModelSpec`] for every key.

mod blade;
mod damping;
mod finite_element;
mod full_sector;
mod keys;
mod preload;
mod sector_files;

pub use damping::{DampingKind, DampingSpec};
pub use finite_element::ReductionSpec;
pub use preload::StaticPreload;

use keys::{key, Keys};

use super::academic::{
    academic_springs, LumpedSector, Spring, SpringLink, ACADEMIC_MASSES, ACADEMIC_STIFFNESSES,
};
use super::matrix_market::read_matrix_market;
use super::sector::{Axis, BlockCirculantSector, BoundaryFrame, FiniteElementSector, SectorModel};
use super::ModelError;
use faer::Mat;
use serde::{Deserialize, Serialize};
use std::path::{Path, PathBuf};

/// Which kind of sector a `[model]` table describes.
#[derive(Deserialize, Serialize, Clone, Copy, Debug, PartialEq, Eq, Default)]
#[serde(rename_all = "snake_case")]
pub enum ModelKind {
    /// The paper's academic chain (Sec. 4.1), or any lumped chain given by
    /// `masses` and `springs`.
    #[default]
    Academic,
    /// Small matrices written inline: `mass`, `stiffness`, and either the
    /// couplings to the next sector (`mass_coupling`, `stiffness_coupling`) or
    /// cyclic boundary dof lists (`left_boundary`, `right_boundary`).
    Matrices,
    /// A finite-element sector read from Matrix Market files (`mass_file`,
    /// `stiffness_file`) with `left_boundary`, `right_boundary`.
    MatrixMarket,
    /// A sparse finite-element sector (Matrix Market files, node
    /// coordinates, node sets) reduced by Craig–Bampton per nodal diameter.
    FiniteElement,
}

impl ModelKind {
    /// The name a case file gives it (`model.kind`).
    pub fn name(self) -> &'static str {
        match self {
            ModelKind::Academic => "academic",
            ModelKind::Matrices => "matrices",
            ModelKind::MatrixMarket => "matrix_market",
            ModelKind::FiniteElement => "finite_element",
        }
    }
}

/// What a spring of a lumped sector connects.
#[derive(Deserialize, Serialize, Clone, Copy, Debug, PartialEq, Eq, Default)]
#[serde(rename_all = "snake_case")]
pub enum SpringLinkSpec {
    /// `dofs = [a, b]` of the same sector.
    #[default]
    Within,
    /// `dofs = [a, b]`: dof `a` of sector `j` to dof `b` of sector `j+1`.
    NextSector,
    /// `dofs = [a]` to the ground.
    Ground,
}

/// A spring of a lumped sector: `{ dofs = [1, 2], stiffness = 2e6 }`,
/// `{ dofs = [4], stiffness = 0.6e6, link = "ground" }`,
/// `{ dofs = [5, 4], stiffness = 50e6, link = "next_sector" }`.
#[derive(Deserialize, Serialize, Clone, Debug, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct SpringSpec {
    /// The dofs it joins (1-based): two, or one for `link = "ground"`.
    pub dofs: Vec<usize>,
    /// Stiffness (N/m).
    pub stiffness: f64,
    /// `"within"` (default), `"next_sector"` or `"ground"`.
    #[serde(default)]
    pub link: SpringLinkSpec,
}

/// The `[model]` table of a case file. Unknown keys are rejected; keys that
/// the chosen `kind` does not use are rejected with the list of its keys.
///
/// - `kind = "academic"`: `sectors`, `masses` (kg, default Table 1),
///   `springs` (default: the topology of docs/design.md §4 with Table 1's values).
/// - `kind = "matrices"`: `sectors`, `mass`, `stiffness` (lists of rows),
///   and either `mass_coupling` / `stiffness_coupling` (block to the next
///   sector) or `left_boundary` / `right_boundary` (1-based dof lists).
/// - `kind = "matrix_market"`: `sectors`, `mass_file`, `stiffness_file`
///   (relative to the case file), `left_boundary`, `right_boundary`.
/// - `kind = "finite_element"`: `sectors`, `mass_file`, `stiffness_file`,
///   `coordinates_file`, `node_sets_file`, `dofs_per_node` (3),
///   `boundary_frame`, `axis` (also the axis that turns the left face onto
///   the right one), `[model.reduction]`.
///
/// Every kind takes `damping` (default: modal, `ξ = 1e-3` on all modes) and
/// `symmetry_tolerance` (relative, default 1e-8).
#[derive(Deserialize, Serialize, Clone, Debug, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct ModelSpec {
    /// `"academic"` (default), `"matrices"` or `"matrix_market"`.
    #[serde(default)]
    pub kind: ModelKind,
    /// Number of sectors `N` (default 24).
    #[serde(default = "default_sectors")]
    pub sectors: usize,
    /// Academic: mass of each dof (kg).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub masses: Option<Vec<f64>>,
    /// Academic: the springs.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub springs: Option<Vec<SpringSpec>>,
    /// Matrices: sector mass (rows).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub mass: Option<Vec<Vec<f64>>>,
    /// Matrices: sector stiffness (rows).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub stiffness: Option<Vec<Vec<f64>>>,
    /// Matrices: mass coupling block to the next sector (rows).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub mass_coupling: Option<Vec<Vec<f64>>>,
    /// Matrices: stiffness coupling block to the next sector (rows).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub stiffness_coupling: Option<Vec<Vec<f64>>>,
    /// Matrix Market: the sector mass file.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub mass_file: Option<PathBuf>,
    /// Matrix Market: the sector stiffness file.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub stiffness_file: Option<PathBuf>,
    /// Left cyclic boundary dofs (1-based).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub left_boundary: Option<Vec<usize>>,
    /// Right cyclic boundary dofs (1-based), paired in order with the left ones.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub right_boundary: Option<Vec<usize>>,
    /// How the boundary dofs are expressed: `"cylindrical"` (default: they
    /// turn with the sector) or `"cartesian"` (node triples in the sector's
    /// fixed frame, rotated by `2π/N` about `axis` from sector to sector).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub boundary_frame: Option<FrameName>,
    /// The rotation axis for Cartesian boundary dofs (default `"z"`).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub axis: Option<AxisName>,
    /// Finite element: the node coordinates file (`node,x,y,z`).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub coordinates_file: Option<PathBuf>,
    /// Finite element: dofs per node (3: x, y, z in node order).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub dofs_per_node: Option<usize>,
    /// Finite element: the node sets file (TOML).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub node_sets_file: Option<PathBuf>,
    /// Finite element: how the contact nodes' dofs are expressed:
    /// `"cartesian"` (default: x, y, z) or `"cylindrical"` (each node's own
    /// radial, circumferential and axial directions, for 3D contact).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub contact_frame: Option<FrameName>,
    /// Finite element: the Craig–Bampton reduction (`[model.reduction]`;
    /// other kinds ignore it, like a damping they do not use).
    #[serde(default, skip_serializing_if = "ReductionSpec::is_default")]
    pub reduction: ReductionSpec,
    /// Relative tolerance on matrix symmetry (default 1e-8).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub symmetry_tolerance: Option<f64>,
    /// Damping (default: modal, `ξ = 1e-3` on all modes).
    #[serde(default)]
    pub damping: DampingSpec,
}

fn default_sectors() -> usize {
    24
}

/// `boundary_frame` in a case file.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Deserialize, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum FrameName {
    /// Boundary dofs that turn with the sector.
    Cylindrical,
    /// Boundary dofs in the sector's fixed Cartesian frame.
    Cartesian,
}

/// `axis` in a case file.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Deserialize, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum AxisName {
    /// `x`.
    X,
    /// `y`.
    Y,
    /// `z`.
    Z,
}

impl Default for ModelSpec {
    /// The paper's academic model, `N = 24`, `ξ = 1e-3` on all modes.
    fn default() -> Self {
        Self {
            kind: ModelKind::Academic,
            sectors: default_sectors(),
            masses: None,
            springs: None,
            mass: None,
            stiffness: None,
            mass_coupling: None,
            stiffness_coupling: None,
            mass_file: None,
            stiffness_file: None,
            left_boundary: None,
            right_boundary: None,
            boundary_frame: None,
            axis: None,
            coordinates_file: None,
            dofs_per_node: None,
            node_sets_file: None,
            contact_frame: None,
            reduction: ReductionSpec::default(),
            symmetry_tolerance: None,
            damping: DampingSpec::default(),
        }
    }
}

/// Converts rows to a matrix, checking they have equal lengths.
pub(crate) fn rows_to_mat(rows: &[Vec<f64>], name: &str) -> Result<Mat<f64>, ModelError> {
    let cols = rows.first().map_or(0, Vec::len);
    for (i, row) in rows.iter().enumerate() {
        if row.len() != cols {
            return Err(ModelError::invalid(
                name,
                format!(
                    "row {} has {} entries but row 1 has {cols}; a matrix is a list of rows of equal length",
                    i + 1,
                    row.len()
                ),
            ));
        }
    }
    if rows.is_empty() {
        return Err(ModelError::invalid(name, "the matrix is empty"));
    }
    Ok(Mat::from_fn(rows.len(), cols, |i, j| rows[i][j]))
}

/// 1-based dof list → 0-based.
fn zero_based(list: &[usize], name: &str) -> Result<Vec<usize>, ModelError> {
    list.iter()
        .enumerate()
        .map(|(i, &d)| {
            d.checked_sub(1).ok_or_else(|| {
                ModelError::invalid(
                    format!("{name}[{}]", i + 1),
                    "dof 0 is out of range: dofs are numbered from 1 in case files",
                )
            })
        })
        .collect()
}

impl ModelSpec {
    /// The number of sectors `N`.
    pub fn sectors(&self) -> usize {
        self.sectors
    }

    /// Reads the `[model]` table of a whole case file's text; other tables
    /// are ignored, a missing `[model]` table gives the default model. Errors
    /// show the line, the key and the allowed keys.
    pub fn from_case_toml(text: &str) -> Result<Self, toml::de::Error> {
        #[derive(Deserialize)]
        struct ModelOnly {
            #[serde(default)]
            model: ModelSpec,
        }
        toml::from_str::<ModelOnly>(text).map(|case| case.model)
    }

    /// Reads the `[model]` table of the case file at `path` (see
    /// [`ModelSpec::from_case_toml`]).
    pub fn from_case_file(path: &Path) -> Result<Self, ModelError> {
        let text = std::fs::read_to_string(path).map_err(|source| ModelError::Io {
            key: "case file".into(),
            path: path.to_path_buf(),
            source,
        })?;
        Self::from_case_toml(&text).map_err(|error| ModelError::CaseFile {
            path: path.to_path_buf(),
            message: error.to_string(),
        })
    }

    /// Checks the table and builds the sector model. Relative file paths are
    /// taken from `case_dir` (the case file's directory).
    pub fn build(&self, case_dir: &Path) -> Result<SectorModel, ModelError> {
        let model = self.sector_model(case_dir)?;
        let keys = self.keys();
        model.check_stiffness_at_rest().map_err(|e| {
            let e = e.named(|input| keys.of(input));
            match (self.kind, e) {
                (ModelKind::MatrixMarket, ModelError::Invalid { key, message }) => {
                    ModelError::Invalid {
                        key,
                        message: format!(
                            "{message} (entries listed twice in a Matrix Market file are summed)"
                        ),
                    }
                }
                (_, e) => e,
            }
        })?;
        if self.damping.kind == DampingKind::Matrix {
            model
                .check_damping_dissipates()
                .map_err(|e| e.named(|input| keys.of(input)))?;
        }
        Ok(model)
    }

    /// The sector model of the table, before the check at rest.
    fn sector_model(&self, case_dir: &Path) -> Result<SectorModel, ModelError> {
        if self.sectors == 0 {
            return Err(ModelError::invalid(
                key("sectors"),
                "0 is not allowed: the number of sectors N must be at least 1",
            ));
        }
        self.check_keys()?;
        let tol = self.symmetry_tolerance()?;
        let keys = self.keys();
        let named = |e: ModelError| e.named(|input| keys.of(input));
        match self.kind {
            ModelKind::Academic => {
                let lumped = self.lumped_sector()?;
                let n = lumped.masses.len();
                let blocks = lumped.to_block_circulant("model")?;
                let damping = self.damping.build(n, case_dir, &keys)?;
                let labels = (1..=n).map(|i| format!("m{i}")).collect();
                SectorModel::block_circulant_with_tolerance(self.sectors, blocks, damping, tol)
                    .map_err(named)?
                    .with_dof_labels(labels)
            }
            ModelKind::Matrices => {
                let mass = rows_to_mat(self.required(&self.mass, "mass")?, &keys.mass)?;
                let stiffness = rows_to_mat(
                    self.required(&self.stiffness, "stiffness")?,
                    &keys.stiffness,
                )?;
                let boundaries = self.left_boundary.is_some() || self.right_boundary.is_some();
                let couplings = self.mass_coupling.is_some() || self.stiffness_coupling.is_some();
                if boundaries && couplings {
                    let which = if self.mass_coupling.is_some() {
                        "mass_coupling"
                    } else {
                        "stiffness_coupling"
                    };
                    return Err(ModelError::invalid(
                        key(which),
                        "give either coupling blocks (block-circulant sector) or boundary dof lists \
                         (finite-element sector), not both",
                    ));
                }
                if boundaries {
                    self.finite_element(mass, stiffness, case_dir, &keys, tol)
                } else {
                    let n = stiffness.nrows();
                    let sector = BlockCirculantSector {
                        mass,
                        stiffness,
                        mass_coupling: self
                            .mass_coupling
                            .as_deref()
                            .map(|r| rows_to_mat(r, &key("mass_coupling")))
                            .transpose()?,
                        stiffness_coupling: self
                            .stiffness_coupling
                            .as_deref()
                            .map(|r| rows_to_mat(r, &key("stiffness_coupling")))
                            .transpose()?,
                    };
                    let damping = self.damping.build(n, case_dir, &keys)?;
                    SectorModel::block_circulant_with_tolerance(self.sectors, sector, damping, tol)
                        .map_err(named)
                }
            }
            ModelKind::MatrixMarket => {
                let mass_file = self.required(&self.mass_file, "mass_file")?;
                let stiffness_file = self.required(&self.stiffness_file, "stiffness_file")?;
                let mass = read_matrix_market(&case_dir.join(mass_file), &keys.mass)?;
                let stiffness =
                    read_matrix_market(&case_dir.join(stiffness_file), &keys.stiffness)?;
                self.finite_element(mass, stiffness, case_dir, &keys, tol)
            }
            ModelKind::FiniteElement => self.finite_element_sector(case_dir, &keys),
        }
    }

    fn required<'a, T>(&self, value: &'a Option<T>, name: &str) -> Result<&'a T, ModelError> {
        value.as_ref().ok_or_else(|| {
            ModelError::invalid(
                key(name),
                format!("required with kind = \"{}\"", self.kind.name()),
            )
        })
    }

    fn finite_element(
        &self,
        mass: Mat<f64>,
        stiffness: Mat<f64>,
        case_dir: &Path,
        keys: &Keys,
        tol: f64,
    ) -> Result<SectorModel, ModelError> {
        let left = zero_based(
            self.left_boundary.as_deref().unwrap_or(&[]),
            &key("left_boundary"),
        )?;
        let right = zero_based(
            self.right_boundary.as_deref().unwrap_or(&[]),
            &key("right_boundary"),
        )?;
        let n = stiffness.nrows().saturating_sub(right.len());
        let damping = self.damping.build(n, case_dir, keys)?;
        let boundary_frame = match (self.boundary_frame, self.axis) {
            (Some(FrameName::Cartesian), axis) => BoundaryFrame::Cartesian {
                axis: match axis {
                    Some(AxisName::X) => Axis::X,
                    Some(AxisName::Y) => Axis::Y,
                    Some(AxisName::Z) | None => Axis::Z,
                },
            },
            (_, Some(_)) => return Err(ModelError::invalid(
                key("axis"),
                "only with boundary_frame = \"cartesian\": cylindrical boundary dofs need no axis",
            )),
            (_, None) => BoundaryFrame::Cylindrical,
        };
        let sector = FiniteElementSector {
            mass,
            stiffness,
            left_boundary: left,
            right_boundary: right,
            boundary_frame,
        };
        SectorModel::finite_element_with_tolerance(self.sectors, sector, damping, tol)
            .map_err(|e| e.named(|input| keys.of(input)))
    }

    pub(crate) fn lumped_sector(&self) -> Result<LumpedSector, ModelError> {
        let masses = self
            .masses
            .clone()
            .unwrap_or_else(|| ACADEMIC_MASSES.to_vec());
        if masses.is_empty() {
            return Err(ModelError::invalid(
                key("masses"),
                "[] is not allowed: give the mass of each dof of a sector (kg, > 0), or leave \
                 masses out for the paper's Table 1",
            ));
        }
        let springs = match &self.springs {
            None => {
                if masses.len() != ACADEMIC_MASSES.len() {
                    return Err(ModelError::invalid(
                        key("springs"),
                        format!(
                            "required when model.masses has {} entries: the default springs join the {} masses of the paper's model",
                            masses.len(),
                            ACADEMIC_MASSES.len()
                        ),
                    ));
                }
                academic_springs(&ACADEMIC_STIFFNESSES)
            }
            Some(list) => list
                .iter()
                .enumerate()
                .map(|(i, s)| {
                    let at = format!("model.springs[{}].dofs", i + 1);
                    let dofs = zero_based(&s.dofs, &format!("model.springs[{}].dofs", i + 1))?;
                    let link = match (s.link, dofs.as_slice()) {
                        (SpringLinkSpec::Within, &[a, b]) => SpringLink::Within(a, b),
                        (SpringLinkSpec::NextSector, &[a, b]) => SpringLink::NextSector(a, b),
                        (SpringLinkSpec::Ground, &[a]) => SpringLink::Ground(a),
                        (SpringLinkSpec::Ground, _) => {
                            return Err(ModelError::invalid(
                                at,
                                format!(
                                "{} dofs given; a spring to the ground joins one dof: dofs = [a]",
                                dofs.len()
                            ),
                            ))
                        }
                        (_, _) => {
                            return Err(ModelError::invalid(
                                at,
                                format!(
                                    "{} dofs given; a spring joins two dofs: dofs = [a, b] \
                                     (or one with link = \"ground\")",
                                    dofs.len()
                                ),
                            ))
                        }
                    };
                    Ok(Spring {
                        link,
                        stiffness: s.stiffness,
                    })
                })
                .collect::<Result<Vec<_>, ModelError>>()?,
        };
        Ok(LumpedSector { masses, springs })
    }
}
