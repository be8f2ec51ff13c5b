//! The stability of a branch as result files hold it: per point the
//! verdict and the leading exponents of every class, and the markers.

use crate::stability::{BranchStability, Marker};

/// How many exponents of largest real part are kept per point and class.
pub const LEADING: usize = 4;

/// The stability of every point of a branch (see [`crate::stability`]).
#[derive(Clone, Debug, PartialEq)]
pub struct StabilityData {
    /// Harmonics of Hill's truncation.
    pub harmonics: usize,
    /// The classes' nodal diameters `σ`, the columns of the arrays below.
    pub classes: Vec<i64>,
    /// Per point: whether no exponent grows.
    pub stable: Vec<bool>,
    /// Per point: how many exponents of the wheel grow.
    pub unstable_exponents: Vec<usize>,
    /// `[point][class][i]`: the real parts (1/s) of the class's [`LEADING`]
    /// exponents of largest real part (NaN where fewer).
    pub leading_re: Vec<Vec<Vec<f64>>>,
    /// The imaginary parts (rad/s), same layout.
    pub leading_im: Vec<Vec<Vec<f64>>>,
    /// Per point: the bound on the contact's effect when the point was off
    /// contact (the linear exponents), NaN when Hill's method ran.
    pub off_contact_bound: Vec<f64>,
    /// Where stability changes.
    pub markers: Vec<Marker>,
}

impl StabilityData {
    /// From a branch's stability.
    pub fn from_branch(branch: &BranchStability) -> Self {
        let classes: Vec<i64> = branch
            .points
            .first()
            .map(|p| p.classes.iter().map(|c| c.nodal_diameter).collect())
            .unwrap_or_default();
        let leading = |part: fn(&crate::stability::Exponent) -> f64| {
            branch
                .points
                .iter()
                .map(|p| {
                    p.classes
                        .iter()
                        .map(|c| {
                            let mut values: Vec<f64> =
                                c.exponents.iter().take(LEADING).map(part).collect();
                            values.resize(LEADING, f64::NAN);
                            values
                        })
                        .collect()
                })
                .collect()
        };
        Self {
            harmonics: branch.harmonics,
            classes,
            stable: branch.points.iter().map(|p| p.stable()).collect(),
            unstable_exponents: branch
                .points
                .iter()
                .map(|p| p.unstable_exponents())
                .collect(),
            leading_re: leading(|e| e.re),
            leading_im: leading(|e| e.im),
            off_contact_bound: branch
                .points
                .iter()
                .map(|p| p.off_contact_bound.unwrap_or(f64::NAN))
                .collect(),
            markers: branch.markers.clone(),
        }
    }

    /// The leading real part of each point in class column `class`.
    pub fn leading_of_class(&self, class: usize) -> Vec<f64> {
        self.leading_re
            .iter()
            .map(|row| {
                row.get(class)
                    .and_then(|v| v.first())
                    .copied()
                    .unwrap_or(f64::NAN)
            })
            .collect()
    }
}
