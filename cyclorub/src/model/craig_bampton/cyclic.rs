//! A sparse finite-element sector and its per-nodal-diameter matrices
//! `K(s) = T(s)ᴴ K T(s)`, `M(s) = T(s)ᴴ M T(s)`, built sparse.
//!
//! `T(s)` maps the kept dofs of the sector (all but the clamped and the
//! right boundary ones) to all its dofs: a kept dof is itself, a clamped
//! dof is zero, a right boundary dof is its left twin of the next sector,
//! `u_R = e^{−iαs} u_L` ([`BoundaryFrame::Cylindrical`]) or
//! `u_R = e^{−iαs} R(α) u_L` ([`BoundaryFrame::Cartesian`]), the sign
//! convention of `model/mod.rs`.

use super::error::{ReductionError, SectorMatrix};
use crate::model::matrices::unit_phase;
use crate::model::BoundaryFrame;
#[cfg(doc)]
use crate::model::DEFAULT_SYMMETRY_TOLERANCE;
use faer::c64;
use faer::sparse::{SparseColMat, Triplet};

/// A finite-element sector stored sparse, with its cyclic boundary.
#[derive(Clone, Debug)]
pub struct SparseSector {
    /// Sector mass, real symmetric, both triangles stored.
    pub mass: SparseColMat<usize, f64>,
    /// Sector stiffness, real symmetric, both triangles stored.
    pub stiffness: SparseColMat<usize, f64>,
    /// Clamped dofs (0-based): held at zero.
    pub clamped: Vec<usize>,
    /// Left cyclic boundary dofs (0-based).
    pub left_boundary: Vec<usize>,
    /// Right cyclic boundary dofs (0-based), `right_boundary[i]` the twin of
    /// `left_boundary[i]` in the next sector.
    pub right_boundary: Vec<usize>,
    /// How the boundary dofs are expressed (Cartesian: node triples `x, y, z`).
    pub boundary_frame: BoundaryFrame,
    /// Number of sectors `N` of the wheel.
    pub sectors: usize,
    /// Relative tolerance on the symmetry of the matrices (times the
    /// largest entry), e.g. [`DEFAULT_SYMMETRY_TOLERANCE`].
    pub symmetry_tolerance: f64,
}

/// The kept dofs of a sector in the order of the per-diameter matrices:
/// some chosen dofs first (in their given order), then every other kept
/// dof in ascending order.
#[derive(Clone, Debug)]
pub struct CyclicDofs {
    /// The sector dof (0-based) of each row of `K(s)`.
    pub dofs: Vec<usize>,
    /// How many leading rows are the chosen dofs.
    pub first: usize,
    /// The row of each sector dof, `None` for clamped and right boundary dofs.
    row: Vec<Option<usize>>,
}

/// `M(s)` and `K(s)` of one nodal diameter, sparse complex Hermitian (both
/// triangles stored), rows in [`CyclicDofs`] order.
#[derive(Clone, Debug)]
pub struct SparseNodalDiameter {
    /// The signed nodal diameter `s`.
    pub nodal_diameter: i64,
    /// `M(s)`.
    pub mass: SparseColMat<usize, c64>,
    /// `K(s)`.
    pub stiffness: SparseColMat<usize, c64>,
}

impl CyclicDofs {
    /// The row of sector dof `dof` (0-based) in the per-diameter matrices,
    /// `None` for a clamped, right boundary or out-of-range dof.
    pub fn row_of(&self, dof: usize) -> Option<usize> {
        self.row.get(dof).copied().flatten()
    }
}

impl SparseSector {
    /// The number of dofs of the sector.
    pub fn size(&self) -> usize {
        self.stiffness.nrows()
    }

    /// Checks sizes, finiteness, symmetry and the dof lists.
    pub fn check(&self) -> Result<(), ReductionError> {
        let n = self.size();
        if self.sectors == 0 {
            return Err(ReductionError::invalid(
                "sectors",
                "0 is not allowed: a wheel has at least one sector",
            ));
        }
        if !(self.symmetry_tolerance.is_finite() && self.symmetry_tolerance >= 0.0) {
            return Err(ReductionError::invalid(
                "symmetry tolerance",
                format!(
                    "{} is not allowed: a relative tolerance is finite and ≥ 0",
                    self.symmetry_tolerance
                ),
            ));
        }
        for (matrix, a) in [
            (SectorMatrix::Stiffness, &self.stiffness),
            (SectorMatrix::Mass, &self.mass),
        ] {
            if a.nrows() != n || a.ncols() != n {
                return Err(ReductionError::Size {
                    matrix,
                    rows: a.nrows(),
                    cols: a.ncols(),
                    expected: n,
                });
            }
            check_symmetric(a, matrix, self.symmetry_tolerance)?;
        }
        let in_range = |list: &str, dofs: &[usize]| {
            for (i, &d) in dofs.iter().enumerate() {
                if d >= n {
                    return Err(ReductionError::invalid(
                        format!("{list}[{}]", i + 1),
                        format!("dof {} is out of range: the sector has dofs 1..={n}", d + 1),
                    ));
                }
            }
            Ok(())
        };
        in_range("clamped dofs", &self.clamped)?;
        in_range("left boundary dofs", &self.left_boundary)?;
        in_range("right boundary dofs", &self.right_boundary)?;
        if self.left_boundary.len() != self.right_boundary.len() {
            return Err(ReductionError::invalid(
                "left / right boundary dofs",
                format!(
                    "unequal lengths ({} left, {} right); they must pair dof by dof",
                    self.left_boundary.len(),
                    self.right_boundary.len()
                ),
            ));
        }
        if matches!(self.boundary_frame, BoundaryFrame::Cartesian { .. })
            && !self.left_boundary.len().is_multiple_of(3)
        {
            return Err(ReductionError::invalid(
                "left boundary dofs",
                format!(
                    "{} dofs: Cartesian boundary dofs come in node triples (x, y, z)",
                    self.left_boundary.len()
                ),
            ));
        }
        let mut seen = vec![false; n];
        for (list, dofs) in [
            ("left boundary dofs", &self.left_boundary),
            ("right boundary dofs", &self.right_boundary),
        ] {
            for (i, &d) in dofs.iter().enumerate() {
                if std::mem::replace(&mut seen[d], true) {
                    return Err(ReductionError::invalid(
                        format!("{list}[{}]", i + 1),
                        format!(
                            "dof {} is listed twice in the boundary lists; a dof may appear once",
                            d + 1
                        ),
                    ));
                }
            }
        }
        Ok(())
    }

    /// The kept dofs with `first` leading (0-based sector dofs, none clamped,
    /// none on the right boundary, none repeated); `what` names the list.
    pub fn cyclic_dofs(&self, first: &[usize], what: &str) -> Result<CyclicDofs, ReductionError> {
        let n = self.size();
        let mut dropped = vec![false; n];
        for &d in self.clamped.iter().chain(&self.right_boundary) {
            dropped[d] = true;
        }
        let mut row = vec![None; n];
        let mut dofs = Vec::with_capacity(n);
        for (i, &d) in first.iter().enumerate() {
            let at = || format!("{what}[{}]", i + 1);
            if d >= n {
                return Err(ReductionError::invalid(
                    at(),
                    format!("dof {} is out of range: the sector has dofs 1..={n}", d + 1),
                ));
            }
            if dropped[d] {
                return Err(ReductionError::invalid(
                    at(),
                    format!(
                        "dof {} is clamped or on the right cyclic boundary; retain its left \
                         twin instead (right boundary dofs are not independent)",
                        d + 1
                    ),
                ));
            }
            if row[d].is_some() {
                return Err(ReductionError::invalid(
                    at(),
                    format!("dof {} is listed twice", d + 1),
                ));
            }
            row[d] = Some(dofs.len());
            dofs.push(d);
        }
        for d in 0..n {
            if !dropped[d] && row[d].is_none() {
                row[d] = Some(dofs.len());
                dofs.push(d);
            }
        }
        Ok(CyclicDofs {
            dofs,
            first: first.len(),
            row,
        })
    }

    /// `T(s)` row by row: for each sector dof, the rows of the kept dofs it
    /// is made of, with their weights.
    pub(super) fn cyclic_map(
        &self,
        nodal_diameter: i64,
        dofs: &CyclicDofs,
    ) -> Vec<Vec<(usize, c64)>> {
        let n = self.size();
        let one = c64::new(1.0, 0.0);
        let mut map: Vec<Vec<(usize, c64)>> = (0..n)
            .map(|d| dofs.row[d].map(|r| vec![(r, one)]).unwrap_or_default())
            .collect();
        let phase = unit_phase(-nodal_diameter, self.sectors);
        let mut clamped = vec![false; n];
        for &d in &self.clamped {
            clamped[d] = true;
        }
        match self.boundary_frame {
            BoundaryFrame::Cylindrical => {
                for (&l, &r) in self.left_boundary.iter().zip(&self.right_boundary) {
                    if !clamped[r] {
                        map[r] = dofs.row[l].map(|c| vec![(c, phase)]).unwrap_or_default();
                    }
                }
            }
            BoundaryFrame::Cartesian { axis } => {
                let rotation = axis.rotation(2.0 * std::f64::consts::PI / self.sectors as f64);
                let pairs = self
                    .left_boundary
                    .chunks_exact(3)
                    .zip(self.right_boundary.chunks_exact(3));
                for (left, right) in pairs {
                    for (k, &r) in right.iter().enumerate() {
                        if clamped[r] {
                            continue;
                        }
                        // A clamped left dof contributes zero.
                        map[r] = (0..3)
                            .filter(|&e| rotation[k][e] != 0.0)
                            .filter_map(|e| dofs.row[left[e]].map(|c| (c, phase * rotation[k][e])))
                            .collect();
                    }
                }
            }
        }
        map
    }

    /// `M(s)`, `K(s)` of the signed nodal diameter `s`, sparse, rows in
    /// `dofs` order.
    pub fn nodal_diameter_matrices(
        &self,
        nodal_diameter: i64,
        dofs: &CyclicDofs,
    ) -> Result<SparseNodalDiameter, ReductionError> {
        let map = self.cyclic_map(nodal_diameter, dofs);
        let size = dofs.dofs.len();
        let reduce = |a: &SparseColMat<usize, f64>, what: &str| {
            let mut triplets = Vec::with_capacity(a.val().len() + a.val().len() / 4);
            let col_ptr = a.symbolic().col_ptr();
            let rows = a.symbolic().row_idx();
            let values = a.val();
            for (j, tj) in map.iter().enumerate() {
                for p in col_ptr[j]..col_ptr[j + 1] {
                    let (i, v) = (rows[p], values[p]);
                    for &(a, ta) in &map[i] {
                        for &(b, tb) in tj {
                            triplets.push(Triplet::new(a, b, ta.conj() * tb * v));
                        }
                    }
                }
            }
            SparseColMat::try_new_from_triplets(size, size, &triplets).map_err(|e| {
                ReductionError::Sparse {
                    nodal_diameter,
                    what: format!("assembling {what}(s)"),
                    message: format!("{e:?}"),
                }
            })
        };
        Ok(SparseNodalDiameter {
            nodal_diameter,
            mass: reduce(&self.mass, "M")?,
            stiffness: reduce(&self.stiffness, "K")?,
        })
    }
}

/// Finite entries and `|a_ij − a_ji| ≤ tol·max|a|`, both triangles stored.
fn check_symmetric(
    a: &SparseColMat<usize, f64>,
    matrix: SectorMatrix,
    relative: f64,
) -> Result<(), ReductionError> {
    let col_ptr = a.symbolic().col_ptr();
    let rows = a.symbolic().row_idx();
    let values = a.val();
    let mut lower = Vec::new();
    let mut upper = Vec::new();
    let mut largest = 0.0_f64;
    for j in 0..a.ncols() {
        for p in col_ptr[j]..col_ptr[j + 1] {
            let (i, v) = (rows[p], values[p]);
            if !v.is_finite() {
                return Err(ReductionError::NotFinite {
                    matrix,
                    row: i + 1,
                    col: j + 1,
                    value: v,
                });
            }
            largest = largest.max(v.abs());
            if i > j {
                lower.push((j, i, v));
            } else if i < j {
                upper.push((i, j, v));
            }
        }
    }
    // Entry (i, j) with i > j is paired with (j, i); duplicates summed.
    let merge = |mut list: Vec<(usize, usize, f64)>| {
        list.sort_by_key(|&(a, b, _)| (a, b));
        let mut out: Vec<(usize, usize, f64)> = Vec::with_capacity(list.len());
        for (a, b, v) in list {
            match out.last_mut() {
                Some(last) if (last.0, last.1) == (a, b) => last.2 += v,
                _ => out.push((a, b, v)),
            }
        }
        out
    };
    let (lower, upper) = (merge(lower), merge(upper));
    let tolerance = relative * largest;
    let (mut p, mut q) = (0, 0);
    let mismatch = |j: usize, i: usize, value: f64, transposed: f64| ReductionError::NotSymmetric {
        matrix,
        row: i + 1,
        col: j + 1,
        value,
        transposed,
        tolerance: relative,
    };
    while p < lower.len() || q < upper.len() {
        let l = lower.get(p).map(|&(a, b, _)| (a, b));
        let u = upper.get(q).map(|&(a, b, _)| (a, b));
        let (key, lv, uv) = match (l, u) {
            (Some(l), Some(u)) if l == u => {
                p += 1;
                q += 1;
                (l, lower[p - 1].2, upper[q - 1].2)
            }
            (Some(l), Some(u)) if l < u => {
                p += 1;
                (l, lower[p - 1].2, 0.0)
            }
            (Some(l), None) => {
                p += 1;
                (l, lower[p - 1].2, 0.0)
            }
            (_, Some(u)) => {
                q += 1;
                (u, 0.0, upper[q - 1].2)
            }
            (None, None) => break,
        };
        if (lv - uv).abs() > tolerance {
            return Err(mismatch(key.0, key.1, lv, uv));
        }
    }
    Ok(())
}
