//! The cyclic boundary of a finite-element sector: which dofs are
//! independent, and the circulant blocks of a sector matrix.
//!
//! A right-boundary dof is a combination of the next sector's left-boundary
//! dofs: the same dof when the boundary dofs turn with the sector
//! ([`BoundaryFrame::Cylindrical`]), the rotation `R(α)` of the paired
//! node's `(x, y, z)` when they are in the sector's fixed Cartesian frame
//! ([`BoundaryFrame::Cartesian`]): `u_R = R(α) u_L(next sector)`, so for the
//! wave of nodal diameter `s`, `u_R = e^{−iαs} R(α) u_L`.

use crate::model::input::{SectorInput, Subject};
use crate::model::matrices::CirculantBlocks;
use crate::model::ModelError;
use faer::Mat;

/// The axis of the wheel's rotation, in a sector's Cartesian frame.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum Axis {
    /// `x`.
    X,
    /// `y`.
    Y,
    /// `z` (the usual choice).
    #[default]
    Z,
}

/// How a finite-element sector's cyclic boundary dofs are expressed.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum BoundaryFrame {
    /// In a frame that turns with the sector (cylindrical components, or
    /// any dofs that repeat from sector to sector): `u_R = e^{−iαs} u_L`.
    #[default]
    Cylindrical,
    /// In the sector's fixed Cartesian frame, three dofs `(x, y, z)` per
    /// boundary node in that order: `u_R = e^{−iαs} R(α) u_L`, `R(α)` the
    /// rotation by `α = 2π/N` about `axis` (the next sector is this one
    /// turned by `+α`).
    Cartesian {
        /// The rotation axis.
        axis: Axis,
    },
}

impl Axis {
    /// The rotation by `angle` (radians, right-handed) about this axis,
    /// acting on `(x, y, z)` components.
    pub fn rotation(self, angle: f64) -> [[f64; 3]; 3] {
        let (s, c) = angle.sin_cos();
        match self {
            Self::X => [[1.0, 0.0, 0.0], [0.0, c, -s], [0.0, s, c]],
            Self::Y => [[c, 0.0, s], [0.0, 1.0, 0.0], [-s, 0.0, c]],
            Self::Z => [[c, -s, 0.0], [s, c, 0.0], [0.0, 0.0, 1.0]],
        }
    }
}

/// Where the independent dofs of a finite-element sector sit.
pub(super) struct BoundaryLayout {
    /// Original indices of the independent dofs (all but the right boundary).
    pub(super) kept: Vec<usize>,
    /// For each original dof: its column among the independent dofs of its
    /// own sector (`Own`), or its combination of the next sector's
    /// independent dofs (`Next`, right boundary: columns and weights).
    place: Vec<Place>,
}

#[derive(Clone)]
enum Place {
    Own(usize),
    Next(Vec<(usize, f64)>),
}

impl BoundaryLayout {
    /// The layout of a sector of `size` dofs; `rotation` is `R(α)` for
    /// boundaries in the Cartesian frame (then both lists are node triples).
    pub(super) fn new(
        size: usize,
        left: &[usize],
        right: &[usize],
        rotation: Option<[[f64; 3]; 3]>,
    ) -> Result<Self, ModelError> {
        if left.len() != right.len() {
            return Err(ModelError::UnequalBoundaries {
                left: SectorInput::LeftBoundary.into(),
                right: SectorInput::RightBoundary.into(),
                left_dofs: left.len(),
                right_dofs: right.len(),
            });
        }
        let at = |list: SectorInput, i: usize| Subject::Input(list, format!("[{}]", i + 1));
        let mut role = vec![None::<(SectorInput, usize)>; size];
        for (list, input) in [
            (left, SectorInput::LeftBoundary),
            (right, SectorInput::RightBoundary),
        ] {
            for (i, &d) in list.iter().enumerate() {
                if d >= size {
                    return Err(ModelError::invalid(
                        at(input, i),
                        format!(
                            "dof {} is out of range: the sector matrices have dofs 1..={size}",
                            d + 1
                        ),
                    ));
                }
                if let Some((other, j)) = role[d] {
                    return Err(ModelError::RepeatedBoundaryDof {
                        at: at(input, i),
                        dof: d + 1,
                        first: at(other, j),
                    });
                }
                role[d] = Some((input, i));
            }
        }
        let is_right: Vec<bool> = {
            let mut v = vec![false; size];
            for &d in right {
                v[d] = true;
            }
            v
        };
        let kept: Vec<usize> = (0..size).filter(|&d| !is_right[d]).collect();
        let mut column = vec![usize::MAX; size];
        for (c, &d) in kept.iter().enumerate() {
            column[d] = c;
        }
        let mut place: Vec<Place> = (0..size).map(|d| Place::Own(column[d])).collect();
        match rotation {
            None => {
                for (&l, &r) in left.iter().zip(right) {
                    place[r] = Place::Next(vec![(column[l], 1.0)]);
                }
            }
            Some(rotation) => {
                if !left.len().is_multiple_of(3) {
                    return Err(ModelError::invalid(
                        SectorInput::LeftBoundary,
                        format!(
                            "{} dofs: with Cartesian boundary dofs they come in node triples (x, y, z), a multiple of 3",
                            left.len()
                        ),
                    ));
                }
                for (l, r) in left.chunks_exact(3).zip(right.chunks_exact(3)) {
                    for (d, &rd) in r.iter().enumerate() {
                        place[rd] = Place::Next(
                            (0..3)
                                .filter(|&e| rotation[d][e] != 0.0)
                                .map(|e| (column[l[e]], rotation[d][e]))
                                .collect(),
                        );
                    }
                }
            }
        }
        Ok(Self { kept, place })
    }

    /// `A0 = PᵀAP + QᵀAQ`, `A1 = PᵀAQ` where `u_sector = P q_j + Q q_{j+1}`
    /// (`Q` holds the weights of the right boundary's combinations).
    pub(super) fn blocks(&self, a: &Mat<f64>) -> CirculantBlocks {
        let n = self.kept.len();
        let mut within = Mat::<f64>::zeros(n, n);
        let mut coupling = Mat::<f64>::zeros(n, n);
        let size = a.nrows();
        for j in 0..size {
            for i in 0..size {
                let v = a[(i, j)];
                if v == 0.0 {
                    continue;
                }
                match (&self.place[i], &self.place[j]) {
                    (Place::Own(p), Place::Own(q)) => within[(*p, *q)] += v,
                    (Place::Next(ps), Place::Next(qs)) => {
                        for &(p, wp) in ps {
                            for &(q, wq) in qs {
                                within[(p, q)] += wp * v * wq;
                            }
                        }
                    }
                    (Place::Own(p), Place::Next(qs)) => {
                        for &(q, wq) in qs {
                            coupling[(*p, q)] += v * wq;
                        }
                    }
                    // The transpose of the coupling (A is symmetric).
                    (Place::Next(_), Place::Own(_)) => {}
                }
            }
        }
        CirculantBlocks { within, coupling }
    }
}
