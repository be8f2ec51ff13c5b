//! The settings of a stability check: Hill's truncation, the growth
//! tolerance, the largest eigenproblem solved, and how each class is
//! solved.

/// How the stability check runs.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct StabilitySettings {
    /// Harmonics `H` of Hill's truncation (`None`: the problem's `N_h`).
    pub harmonics: Option<usize>,
    /// A real part above `tolerance · ω` counts as growth: it keeps the
    /// round-off of exponents on the imaginary axis (an undamped mode) from
    /// reading as instability.
    pub tolerance: f64,
    /// The largest eigenproblem of one class: `2 · dofs · pairs` solved
    /// densely, `2 · contact dofs · pairs` for the condensed solver (whose
    /// LUs are half that); a larger one is refused, naming the remedy.
    pub largest_eigenproblem: usize,
    /// Give a point of weak contact the linear wheel's exponents with a
    /// bound, instead of Hill's method (see `stability::off_contact`).
    pub weak_contact_shortcut: bool,
    /// How each class's eigenproblem is solved.
    pub solver: HillSolver,
}

/// How the physical exponents of a class are found.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum HillSolver {
    /// Every exponent of each class in a region around the imaginary axis
    /// (`stability::condensed`): the poles of the contact resolvent by a
    /// contour integral, refined on the class's quadratic problem. The
    /// classes together hold every Floquet multiplier of modulus above
    /// `e^{−2π·margin}` once, whatever the truncation.
    #[default]
    Condensed,
    /// Each exponent followed from the averaged system by Rayleigh
    /// quotient iteration with structured solves (see
    /// `stability::targeted`), the dense eigenproblem whenever that cannot
    /// vouch for every family: the dense pick, faster.
    Targeted,
    /// Every eigenvalue of each class's dense Hill matrix in the condensed
    /// solver's region: the same exponents, the condensed solver's
    /// oracle (slow).
    DenseRegion,
    /// Every eigenvalue of the dense Hill matrix, then the pick (each
    /// family's copy centred on harmonic 0, `2 · dofs · |P₀|` a class).
    Dense,
}

impl Default for StabilitySettings {
    fn default() -> Self {
        Self {
            harmonics: None,
            tolerance: 1e-8,
            largest_eigenproblem: 2000,
            weak_contact_shortcut: true,
            solver: HillSolver::default(),
        }
    }
}
