//! The open fan: a finite-element sector of a fan stage (titanium disk
//! sector and one twisted blade of constant thickness, 20-node quadratic
//! hexahedra) written as model files, so that the paper's Sec. 5 studies
//! can be run on a model anyone may ship.
//!
//! This module only *writes* files (docs/design.md §1): the solver never depends
//! on it. [`fan`] builds the mesh and its node sets, [`assemble`] the sparse
//! sector matrices, [`write_fan`] the folder (Matrix Market matrices, node
//! coordinates, node sets, a case file and a README).

mod assembly;
mod fan;
mod hexahedron;
mod lattice;
mod readme;
mod write;

#[cfg(test)]
mod tests;

pub use assembly::{assemble, AssembledMatrices, SymmetricMatrix};
pub use fan::{fan, FanGeometry, FanMesh, NodeSets, DEFAULT_REFINE, MAX_REFINE};
pub use hexahedron::{
    element_matrices, point_geometry, shape_functions, strain, ElementMatrices, Material,
    PointGeometry, GAUSS3, HEX20_DOFS, HEX20_NATURAL, HEX20_NODES,
};
pub use readme::MEASURED_FIRST_FAMILY;
pub use write::{write_fan, FanOutput, FAN_FILES};

use std::path::PathBuf;

/// A mesh of 20-node hexahedra: node coordinates (m) and elements.
#[derive(Clone, Debug, PartialEq)]
pub struct Mesh {
    /// Node coordinates (x, y, z), 0-based node numbers.
    pub nodes: Vec<[f64; 3]>,
    /// Elements, each with its 20 nodes in [`HEX20_NATURAL`] order.
    pub elements: Vec<Element>,
    /// Materials, referred to by index from the elements.
    pub materials: Vec<Material>,
}

/// One 20-node hexahedron.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Element {
    /// Its nodes (0-based), in [`HEX20_NATURAL`] order.
    pub nodes: [usize; HEX20_NODES],
    /// Index into [`Mesh::materials`].
    pub material: usize,
}

/// Why a mesh could not be built or written.
#[derive(Debug, thiserror::Error)]
pub enum MeshError {
    /// A parameter is out of its allowed range.
    #[error("{what}: {message}")]
    Invalid {
        /// The parameter (e.g. `--sectors`, `blade material`).
        what: String,
        /// The value and what is allowed.
        message: String,
    },
    /// An element is inverted or degenerate at a point.
    #[error("an element has Jacobian determinant {jacobian:e} at natural point {at:?}: inverted or degenerate")]
    BadElement {
        /// The determinant found.
        jacobian: f64,
        /// The natural coordinates of the point.
        at: [f64; 3],
    },
    /// The output folder cannot be used.
    #[error("{path}: {message}")]
    Output {
        /// The folder.
        path: PathBuf,
        /// Why, and what to do.
        message: String,
    },
    /// A file could not be written.
    #[error("cannot write {path}: {source}")]
    Io {
        /// The file.
        path: PathBuf,
        /// The system's reason.
        source: std::io::Error,
    },
}

impl MeshError {
    /// Whether the error is in what the user gave (exit code 2 at the
    /// command line) rather than a failure while working.
    pub fn is_input_error(&self) -> bool {
        matches!(self, Self::Invalid { .. } | Self::Output { .. })
    }
}
