//! A sector model given by its matrices per nodal diameter: a reduced
//! model whose coordinates differ from diameter to diameter (Craig–Bampton's
//! modal coordinates), so that it has no block-circulant form.

use super::modal::{check_modal, check_rayleigh, DampingModel, ModalCache};
use super::{check_sector_dofs, check_sectors, SectorModel};
use crate::model::damping::Damping;
use crate::model::input::{SectorInput, Subject};
use crate::model::matrices::SectorOperator;
use crate::model::validate::DEFAULT_SYMMETRY_TOLERANCE;
use crate::model::ModelError;
use faer::{c64, Mat, Side};
use std::sync::Arc;

impl SectorModel {
    /// A sector given by its Hermitian `M(s)`, `K(s)` for the nodal
    /// diameters `s = 0..=N/2` (`mass[s]`, `stiffness[s]`, all of one size,
    /// real at `0` and `N/2`; `M(−s) = conj(M(s))`), `sectors` sectors, with
    /// `damping` (modal ratios by mode index within each diameter, or
    /// Rayleigh; a damping matrix has no per-diameter form and is refused).
    /// The dofs are labelled `dof 1`, `dof 2`… ([`SectorModel::with_dof_labels`]
    /// renames them).
    pub fn per_nodal_diameter(
        sectors: usize,
        mass: Vec<Mat<c64>>,
        stiffness: Vec<Mat<c64>>,
        damping: Damping,
    ) -> Result<Self, ModelError> {
        check_sectors(sectors)?;
        let diameters = sectors / 2 + 1;
        let size = stiffness.first().map_or(0, |k| k.nrows());
        if size == 0 {
            return Err(ModelError::invalid(
                SectorInput::Stiffness,
                "a sector needs at least one dof",
            ));
        }
        check_sector_dofs(size, SectorInput::Stiffness)?;
        let check_list = |input: SectorInput, list: Vec<Mat<c64>>| {
            if list.len() != diameters {
                return Err(ModelError::invalid(
                    input,
                    format!(
                        "{} matrices given; one per nodal diameter 0..={} is needed",
                        list.len(),
                        sectors / 2
                    ),
                ));
            }
            list.into_iter()
                .enumerate()
                .map(|(s, a)| hermitian(a, input, s, size, sectors))
                .collect::<Result<Vec<_>, _>>()
        };
        let stiffness = check_list(SectorInput::Stiffness, stiffness)?;
        let mass = check_list(SectorInput::Mass, mass)?;
        for (s, m) in mass.iter().enumerate() {
            if m.llt(Side::Lower).is_err() {
                return Err(ModelError::MassNotPositiveDefinite {
                    what: Subject::input(SectorInput::Mass),
                    nodal_diameter: Some(s as i64),
                });
            }
        }
        let mass = SectorOperator::PerDiameter(Arc::new(mass));
        let stiffness = SectorOperator::PerDiameter(Arc::new(stiffness));
        let damping = match damping {
            Damping::None => DampingModel::None,
            Damping::Modal(modal) => {
                check_modal(&modal)?;
                DampingModel::Modal(modal, ModalCache::new(sectors))
            }
            Damping::Rayleigh { alpha, beta } => {
                check_rayleigh(alpha, beta)?;
                DampingModel::Viscous(mass.combine(alpha, &stiffness, beta, sectors))
            }
            Damping::Matrix { .. } => {
                return Err(ModelError::invalid(
                    SectorInput::DampingMatrix,
                    "a model given per nodal diameter takes modal or Rayleigh damping, not a damping matrix",
                ))
            }
        };
        Ok(Self {
            sectors,
            labels: (1..=size).map(|d| format!("dof {d}")).collect(),
            radii: Vec::new(),
            nodes: Vec::new(),
            mass,
            stiffness,
            damping,
            mistuning: None,
        })
    }
}

/// `a` square of `size`, finite, Hermitian within the default tolerance
/// (relative to its largest entry), and real at the real diameters; returns
/// its Hermitian part (exactly real there).
fn hermitian(
    a: Mat<c64>,
    input: SectorInput,
    s: usize,
    size: usize,
    sectors: usize,
) -> Result<Mat<c64>, ModelError> {
    let what = Subject::Input(input, format!(" of nodal diameter {s}"));
    if a.nrows() != size || a.ncols() != size {
        return Err(ModelError::invalid(
            what,
            format!(
                "size {}×{}; every diameter's matrices are {size}×{size}",
                a.nrows(),
                a.ncols()
            ),
        ));
    }
    let mut largest = 0.0_f64;
    for j in 0..size {
        for i in 0..size {
            let v = a[(i, j)];
            if !(v.re.is_finite() && v.im.is_finite()) {
                return Err(ModelError::invalid(
                    what,
                    format!(
                        "entry ({}, {}) is {v}; only finite numbers are allowed",
                        i + 1,
                        j + 1
                    ),
                ));
            }
            largest = largest.max(v.norm());
        }
    }
    let tolerance = DEFAULT_SYMMETRY_TOLERANCE * largest;
    let real = s == 0 || 2 * s == sectors;
    for j in 0..size {
        for i in 0..size {
            let difference = (a[(i, j)] - a[(j, i)].conj()).norm();
            if difference > tolerance || (real && a[(i, j)].im.abs() > tolerance) {
                return Err(ModelError::invalid(
                    what,
                    format!(
                        "entry ({}, {}) = {} and ({}, {}) = {}: the matrix must be Hermitian{} \
                         (allowed difference: {DEFAULT_SYMMETRY_TOLERANCE:e} times the largest entry)",
                        i + 1,
                        j + 1,
                        a[(i, j)],
                        j + 1,
                        i + 1,
                        a[(j, i)],
                        if real { ", and real at this diameter" } else { "" }
                    ),
                ));
            }
        }
    }
    Ok(Mat::from_fn(size, size, |i, j| {
        let h = (a[(i, j)] + a[(j, i)].conj()) * 0.5;
        if real {
            c64::new(h.re, 0.0)
        } else {
            h
        }
    }))
}
