//! Cyclic-symmetry algebra: the real cyclic Fourier matrix, signed
//! (nodal diameter, harmonic) pairs, the zig-zag diagram, loads as pairs and
//! the set of harmonics a balance holds.

mod fourier;
mod harmonics;
mod load;
mod pair;

pub use fourier::{real_cyclic_fourier_matrix, zigzag};
pub use harmonics::HarmonicSet;
pub use load::{ExcitationPattern, LoadCase, LoadError};
pub use pair::{fold_nodal_diameter, SignedPair};
