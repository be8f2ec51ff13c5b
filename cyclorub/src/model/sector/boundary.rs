//! The cyclic boundary of a finite-element sector: which dofs are
//! independent, and the circulant blocks of a sector matrix.

use crate::model::input::{SectorInput, Subject};
use crate::model::matrices::CirculantBlocks;
use crate::model::ModelError;
use faer::Mat;

/// Where the independent dofs of a finite-element sector sit.
pub(super) struct BoundaryLayout {
    /// Original indices of the independent dofs (all but the right boundary).
    pub(super) kept: Vec<usize>,
    /// For each original dof: its column among the independent dofs of its
    /// own sector (`Own`) or of the next sector (`Next`, right boundary).
    place: Vec<Place>,
}

#[derive(Clone, Copy)]
enum Place {
    Own(usize),
    Next(usize),
}

impl BoundaryLayout {
    pub(super) fn new(size: usize, left: &[usize], right: &[usize]) -> Result<Self, ModelError> {
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
        for (&l, &r) in left.iter().zip(right) {
            place[r] = Place::Next(column[l]);
        }
        Ok(Self { kept, place })
    }

    /// `A0 = PᵀAP + QᵀAQ`, `A1 = PᵀAQ` where `u_sector = P q_j + Q q_{j+1}`.
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
                match (self.place[i], self.place[j]) {
                    (Place::Own(p), Place::Own(q)) | (Place::Next(p), Place::Next(q)) => {
                        within[(p, q)] += v
                    }
                    (Place::Own(p), Place::Next(q)) => coupling[(p, q)] += v,
                    (Place::Next(_), Place::Own(_)) => {}
                }
            }
        }
        CirculantBlocks { within, coupling }
    }
}
