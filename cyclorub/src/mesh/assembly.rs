//! Sparse assembly of a sector's mass and stiffness: element blocks go in as
//! triplets of the lower triangle, duplicates are summed in a fixed order
//! (so the result is the same to the bit on every run), and the matrix is
//! kept in compressed columns.

use super::hexahedron::{element_matrices, Material, HEX20_DOFS, HEX20_NODES};
use super::{Mesh, MeshError};

/// A real symmetric matrix stored by its lower triangle in compressed
/// columns: column `j` holds rows `rows[starts[j]..starts[j + 1]]` (sorted,
/// all `≥ j`) with `values` alongside.
#[derive(Clone, Debug, PartialEq)]
pub struct SymmetricMatrix {
    /// Number of rows (= columns).
    pub size: usize,
    /// Start of each column in `rows` and `values`, `size + 1` entries.
    pub starts: Vec<usize>,
    /// 0-based row of each stored entry.
    pub rows: Vec<usize>,
    /// Value of each stored entry.
    pub values: Vec<f64>,
}

impl SymmetricMatrix {
    /// Number of stored entries (lower triangle with the diagonal).
    pub fn stored_entries(&self) -> usize {
        self.rows.len()
    }

    /// Stored entries `(row, column, value)`, column by column, 0-based.
    pub fn entries(&self) -> impl Iterator<Item = (usize, usize, f64)> + '_ {
        (0..self.size).flat_map(move |j| {
            (self.starts[j]..self.starts[j + 1]).map(move |p| (self.rows[p], j, self.values[p]))
        })
    }

    /// `y = A x` (both triangles).
    pub fn multiply(&self, x: &[f64]) -> Vec<f64> {
        let mut y = vec![0.0; self.size];
        for (i, j, v) in self.entries() {
            y[i] += v * x[j];
            if i != j {
                y[j] += v * x[i];
            }
        }
        y
    }

    /// `xᵀ A y`.
    pub fn bilinear(&self, x: &[f64], y: &[f64]) -> f64 {
        let ay = self.multiply(y);
        x.iter().zip(&ay).map(|(a, b)| a * b).sum()
    }

    /// Builds the matrix from lower-triangle triplets `(row, column, value)`
    /// with `row ≥ column`; duplicates are summed in the order given.
    pub fn from_lower_triplets(size: usize, mut triplets: Vec<(usize, usize, f64)>) -> Self {
        // A stable sort keeps the given order among duplicates: the sums
        // are then the same to the bit on every run.
        triplets.sort_by_key(|&(i, j, _)| (j, i));
        let mut starts = vec![0; size + 1];
        let mut rows = Vec::with_capacity(triplets.len() / 4);
        let mut values: Vec<f64> = Vec::with_capacity(triplets.len() / 4);
        let mut last: Option<(usize, usize)> = None;
        for (i, j, v) in triplets {
            if last == Some((i, j)) {
                if let Some(sum) = values.last_mut() {
                    *sum += v;
                }
            } else {
                rows.push(i);
                values.push(v);
                starts[j + 1] += 1;
                last = Some((i, j));
            }
        }
        for j in 0..size {
            starts[j + 1] += starts[j];
        }
        Self {
            size,
            starts,
            rows,
            values,
        }
    }
}

/// The assembled mass and stiffness of a mesh (3 dofs per node in node
/// order: x, y, z).
#[derive(Clone, Debug)]
pub struct AssembledMatrices {
    /// Consistent mass (kg).
    pub mass: SymmetricMatrix,
    /// Stiffness (N/m).
    pub stiffness: SymmetricMatrix,
}

/// Assembles every element of `mesh` with its material.
pub fn assemble(mesh: &Mesh) -> Result<AssembledMatrices, MeshError> {
    let size = 3 * mesh.nodes.len();
    let lower = HEX20_DOFS * (HEX20_DOFS + 1) / 2;
    let mut mass_triplets = Vec::with_capacity(mesh.elements.len() * lower);
    let mut stiffness_triplets = Vec::with_capacity(mesh.elements.len() * lower);
    for (e, element) in mesh.elements.iter().enumerate() {
        let material: &Material =
            mesh.materials
                .get(element.material)
                .ok_or_else(|| MeshError::Invalid {
                    what: format!("element {}", e + 1),
                    message: format!("material index {} does not exist", element.material),
                })?;
        let mut coords = [[0.0; 3]; HEX20_NODES];
        for (c, &node) in coords.iter_mut().zip(&element.nodes) {
            *c = *mesh.nodes.get(node).ok_or_else(|| MeshError::Invalid {
                what: format!("element {}", e + 1),
                message: format!("node {} does not exist", node + 1),
            })?;
        }
        let matrices = element_matrices(&coords, material).map_err(|error| match error {
            MeshError::BadElement { jacobian, at } => MeshError::Invalid {
                what: format!("element {}", e + 1),
                message: format!(
                    "Jacobian determinant {jacobian:e} at natural point {at:?}: inverted or degenerate"
                ),
            },
            other => other,
        })?;
        let dof = |local: usize| 3 * element.nodes[local / 3] + local % 3;
        for r in 0..HEX20_DOFS {
            for c in 0..HEX20_DOFS {
                let (gr, gc) = (dof(r), dof(c));
                // Keep the lower triangle only; an entry whose global
                // position is on the upper side comes in through its
                // transposed twin (r, c swapped), so each pair is kept once.
                if gr >= gc {
                    let k = matrices.stiffness[r * HEX20_DOFS + c];
                    let m = matrices.mass[r * HEX20_DOFS + c];
                    stiffness_triplets.push((gr, gc, k));
                    if m != 0.0 {
                        mass_triplets.push((gr, gc, m));
                    }
                }
            }
        }
    }
    Ok(AssembledMatrices {
        mass: SymmetricMatrix::from_lower_triplets(size, mass_triplets),
        stiffness: SymmetricMatrix::from_lower_triplets(size, stiffness_triplets),
    })
}
