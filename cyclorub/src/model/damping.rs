//! Damping of a sector model: none, modal ratios per nodal diameter,
//! Rayleigh, or a given matrix.

use faer::Mat;

/// How a sector model is damped.
#[derive(Clone, Debug)]
pub enum Damping {
    /// No damping: `C = 0`.
    None,
    /// Modal damping computed per nodal diameter:
    /// `C(s) = M Φ diag(2 ξ_r ω_r) Φᴴ M` with `Φ` the mass-normalized modes of
    /// `(K(s), M(s))`, `r` the mode index within the diameter's family.
    /// The full wheel's modal damping is the same (its modes are the
    /// per-diameter ones).
    Modal(ModalDamping),
    /// Rayleigh damping `C = alpha·M + beta·K`.
    Rayleigh {
        /// Mass factor (1/s).
        alpha: f64,
        /// Stiffness factor (s).
        beta: f64,
    },
    /// A given viscous damping matrix, laid out like the stiffness (the
    /// within-sector block of a block-circulant sector, or the whole matrix of
    /// a finite-element sector), with an optional coupling block to the next
    /// sector (block-circulant sectors only).
    Matrix {
        /// The sector damping matrix (real symmetric).
        matrix: Mat<f64>,
        /// Coupling to the next sector (block-circulant only).
        coupling: Option<Mat<f64>>,
    },
}

/// Modal damping ratios by mode index within each nodal diameter's family.
#[derive(Clone, Debug, PartialEq)]
pub struct ModalDamping {
    /// `ratios[r]` damps mode `r` (0-based, ascending frequency) of every
    /// nodal diameter.
    pub ratios: Vec<f64>,
    /// The ratio of the modes beyond `ratios`.
    pub others: f64,
}

impl ModalDamping {
    /// The same ratio on every mode.
    pub fn uniform(ratio: f64) -> Self {
        Self {
            ratios: Vec::new(),
            others: ratio,
        }
    }

    /// The ratio of mode `mode` (0-based) of a nodal diameter family.
    pub fn ratio(&self, mode: usize) -> f64 {
        self.ratios.get(mode).copied().unwrap_or(self.others)
    }
}

impl Default for Damping {
    /// The paper's: `ξ = 1e-3` on all modes.
    fn default() -> Self {
        Damping::Modal(ModalDamping::uniform(1e-3))
    }
}
