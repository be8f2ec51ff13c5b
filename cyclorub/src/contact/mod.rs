//! Contact laws: time samples of penetration in, forces and derivatives out.
