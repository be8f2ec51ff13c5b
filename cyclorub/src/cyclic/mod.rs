//! Cyclic-symmetry algebra: the real cyclic Fourier matrix, signed
//! (nodal diameter, harmonic) pairs, the zig-zag diagram and loads as pairs.

mod fourier;
mod load;
mod pair;

pub use fourier::{real_cyclic_fourier_matrix, zigzag};
pub use load::{ExcitationPattern, LoadCase, LoadError};
pub use pair::{fold_nodal_diameter, SignedPair};
