//! Matrix sets per nodal diameter and for the full wheel, and the
//! block-circulant algebra that links them.

use faer::{c64, Mat};

/// Mass, stiffness and damping of one signed nodal diameter `s`.
///
/// Hermitian, `dofs_per_sector` square. For the sector pattern
/// `x_j = X·exp(−i s α (j−1))` the full wheel's force on sector 1 is
/// `K(s) X` (and on sector `j` it is `K(s) X·exp(−i s α (j−1))`).
#[derive(Clone, Debug)]
pub struct NodalDiameterMatrices {
    /// `M(s)`.
    pub mass: Mat<c64>,
    /// `K(s)`.
    pub stiffness: Mat<c64>,
    /// `C(s)` (zero when the model has no damping).
    pub damping: Mat<c64>,
}

/// Mass, stiffness and damping of all `N` sectors assembled in physical
/// coordinates: real symmetric, `N·dofs_per_sector` square; dof `d` of sector
/// `j` (0-based) is at index `j·dofs_per_sector + d`.
#[derive(Clone, Debug)]
pub struct FullWheelMatrices {
    /// Full-wheel mass.
    pub mass: Mat<f64>,
    /// Full-wheel stiffness.
    pub stiffness: Mat<f64>,
    /// Full-wheel damping.
    pub damping: Mat<f64>,
}

/// Folds a signed nodal diameter into `(−N/2, N/2]` (modulo `N`).
pub(crate) fn fold(nodal_diameter: i64, sectors: usize) -> i64 {
    let n = sectors as i64;
    let r = nodal_diameter.rem_euclid(n);
    if 2 * r > n {
        r - n
    } else {
        r
    }
}

/// `exp(+2πi·r/N)`, exact at multiples of a quarter turn.
pub(crate) fn unit_phase(r: i64, sectors: usize) -> c64 {
    let n = sectors as i64;
    let r = r.rem_euclid(n);
    if r == 0 {
        c64::new(1.0, 0.0)
    } else if 2 * r == n {
        c64::new(-1.0, 0.0)
    } else if 4 * r == n {
        c64::new(0.0, 1.0)
    } else if 4 * r == 3 * n {
        c64::new(0.0, -1.0)
    } else {
        // Use the smaller of r and N − r so that exp(−iθ) is the exact
        // conjugate of exp(iθ).
        if 2 * r < n {
            let angle = 2.0 * std::f64::consts::PI * r as f64 / n as f64;
            c64::new(angle.cos(), angle.sin())
        } else {
            let angle = 2.0 * std::f64::consts::PI * (n - r) as f64 / n as f64;
            c64::new(angle.cos(), -angle.sin())
        }
    }
}

/// One real sector matrix in block-circulant form: the full wheel holds
/// `within` on its diagonal blocks, `coupling` on block `(j, j+1)` and
/// `couplingᵀ` on block `(j+1, j)` (sector indices modulo `N`, blocks of
/// coinciding positions added, so `N = 1` and `N = 2` need no special case).
#[derive(Clone, Debug)]
pub(crate) struct CirculantBlocks {
    pub(crate) within: Mat<f64>,
    pub(crate) coupling: Mat<f64>,
}

impl CirculantBlocks {
    /// `A(s) = A0 + A1·exp(−iαs) + A1ᵀ·exp(iαs)`.
    pub(crate) fn at(&self, nodal_diameter: i64, sectors: usize) -> Mat<c64> {
        let n = self.within.nrows();
        let forward = unit_phase(-nodal_diameter, sectors);
        let backward = forward.conj();
        Mat::from_fn(n, n, |i, j| {
            c64::new(self.within[(i, j)], 0.0)
                + forward * self.coupling[(i, j)]
                + backward * self.coupling[(j, i)]
        })
    }

    /// The real full-wheel matrix.
    pub(crate) fn assemble(&self, sectors: usize) -> Mat<f64> {
        let n = self.within.nrows();
        let mut full = Mat::<f64>::zeros(sectors * n, sectors * n);
        for j in 0..sectors {
            let next = (j + 1) % sectors;
            for a in 0..n {
                for b in 0..n {
                    full[(j * n + a, j * n + b)] += self.within[(a, b)];
                    full[(j * n + a, next * n + b)] += self.coupling[(a, b)];
                    full[(next * n + b, j * n + a)] += self.coupling[(a, b)];
                }
            }
        }
        full
    }

    /// Whether the coupling block is zero.
    pub(crate) fn has_coupling(&self) -> bool {
        let n = self.coupling.nrows();
        (0..n).any(|i| (0..n).any(|j| self.coupling[(i, j)] != 0.0))
    }

    /// `a·self + b·other` (same sizes).
    pub(crate) fn combine(&self, a: f64, other: &Self, b: f64) -> Self {
        let n = self.within.nrows();
        Self {
            within: Mat::from_fn(n, n, |i, j| {
                a * self.within[(i, j)] + b * other.within[(i, j)]
            }),
            coupling: Mat::from_fn(n, n, |i, j| {
                a * self.coupling[(i, j)] + b * other.coupling[(i, j)]
            }),
        }
    }
}

/// Assembles a real block-circulant full-wheel matrix from its per-diameter
/// blocks `A(s)`, `s = 0..N−1` (inverse DFT over sectors): block `(j, l)` is
/// `B_{l−j}` with `B_d = (1/N) Σ_s A(s)·exp(iαsd)`.
pub(crate) fn assemble_from_nodal_diameters(per_diameter: &[Mat<c64>], sectors: usize) -> Mat<f64> {
    let n = per_diameter.first().map_or(0, |m| m.nrows());
    let blocks: Vec<Mat<f64>> = (0..sectors as i64)
        .map(|d| {
            let mut block = Mat::<f64>::zeros(n, n);
            for (s, a) in per_diameter.iter().enumerate() {
                let phase = unit_phase(s as i64 * d, sectors);
                for i in 0..n {
                    for j in 0..n {
                        block[(i, j)] += (a[(i, j)] * phase).re;
                    }
                }
            }
            let scale = 1.0 / sectors as f64;
            Mat::from_fn(n, n, |i, j| block[(i, j)] * scale)
        })
        .collect();
    let mut full = Mat::<f64>::zeros(sectors * n, sectors * n);
    for j in 0..sectors {
        for l in 0..sectors {
            let block = &blocks[(l + sectors - j) % sectors];
            for a in 0..n {
                for b in 0..n {
                    full[(j * n + a, l * n + b)] = block[(a, b)];
                }
            }
        }
    }
    // Symmetrize away round-off so the result is exactly symmetric.
    let size = sectors * n;
    Mat::from_fn(size, size, |i, j| 0.5 * (full[(i, j)] + full[(j, i)]))
}

impl CirculantBlocks {
    /// `A(s)` for a real diameter (`s = 0`: `A0 + A1 + A1ᵀ`; `s = N/2`:
    /// `A0 − A1 − A1ᵀ`), in real arithmetic.
    pub(crate) fn at_real(&self, nodal_diameter: i64, sectors: usize) -> Mat<f64> {
        let sign = if fold(nodal_diameter, sectors) == 0 {
            1.0
        } else {
            -1.0
        };
        let n = self.within.nrows();
        Mat::from_fn(n, n, |i, j| {
            self.within[(i, j)] + sign * (self.coupling[(i, j)] + self.coupling[(j, i)])
        })
    }
}

/// One sector matrix, for every nodal diameter: in block-circulant form,
/// or given per nodal diameter (a reduced model whose coordinates differ
/// from diameter to diameter, e.g. Craig–Bampton's modal coordinates).
#[derive(Clone, Debug)]
pub(crate) enum SectorOperator {
    /// Within-sector and coupling blocks.
    Circulant(CirculantBlocks),
    /// `A(s)` for `s = 0..=N/2` (Hermitian, real at `0` and `N/2`);
    /// `A(−s) = conj(A(s))`.
    PerDiameter(std::sync::Arc<Vec<Mat<c64>>>),
}

impl SectorOperator {
    /// `A(s)` of the signed nodal diameter `s`.
    pub(crate) fn at(&self, nodal_diameter: i64, sectors: usize) -> Mat<c64> {
        match self {
            Self::Circulant(blocks) => blocks.at(nodal_diameter, sectors),
            Self::PerDiameter(per) => {
                let s = fold(nodal_diameter, sectors);
                let a = &per[s.unsigned_abs() as usize];
                if s < 0 {
                    Mat::from_fn(a.nrows(), a.ncols(), |i, j| a[(i, j)].conj())
                } else {
                    a.clone()
                }
            }
        }
    }

    /// `A(s)` of a real nodal diameter (`0`, or `N/2`).
    pub(crate) fn at_real(&self, nodal_diameter: i64, sectors: usize) -> Mat<f64> {
        match self {
            Self::Circulant(blocks) => blocks.at_real(nodal_diameter, sectors),
            Self::PerDiameter(_) => {
                let a = self.at(nodal_diameter, sectors);
                Mat::from_fn(a.nrows(), a.ncols(), |i, j| a[(i, j)].re)
            }
        }
    }

    /// The real full-wheel matrix.
    pub(crate) fn assemble(&self, sectors: usize) -> Mat<f64> {
        match self {
            Self::Circulant(blocks) => blocks.assemble(sectors),
            Self::PerDiameter(_) => {
                let all: Vec<Mat<c64>> = (0..sectors as i64).map(|s| self.at(s, sectors)).collect();
                assemble_from_nodal_diameters(&all, sectors)
            }
        }
    }

    /// `a·self + b·other` (same sizes) for a wheel of `sectors` sectors.
    pub(crate) fn combine(&self, a: f64, other: &Self, b: f64, sectors: usize) -> Self {
        match (self, other) {
            (Self::Circulant(x), Self::Circulant(y)) => Self::Circulant(x.combine(a, y, b)),
            _ => Self::PerDiameter(std::sync::Arc::new(
                (0..=sectors as i64 / 2)
                    .map(|s| {
                        let (u, v) = (self.at(s, sectors), other.at(s, sectors));
                        Mat::from_fn(u.nrows(), u.ncols(), |i, j| u[(i, j)] * a + v[(i, j)] * b)
                    })
                    .collect(),
            )),
        }
    }
}
