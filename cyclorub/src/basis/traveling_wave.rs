//! The paper's traveling-wave hypothesis (Sec. 3.3): one signed pair per
//! harmonic, read from the zig-zag diagram (Eq. 49).

use super::{BasisError, BasisKind, SpectralBasis};
use crate::cyclic::{zigzag, HarmonicSet};

impl SpectralBasis {
    /// The traveling-wave hypothesis for the excitation `(−h, 1)` of engine
    /// order `h` (Eq. 48): harmonic `k` holds the single signed diameter
    /// `Z(k h) = −k h` folded into `(−N/2, N/2]` (Eqs. 76, 77, 85, 104, 105).
    pub fn traveling_wave(
        sectors: usize,
        harmonics: usize,
        engine_order: usize,
    ) -> Result<Self, BasisError> {
        super::check_size(sectors, harmonics)?;
        let h = (engine_order % sectors) as i64;
        let sets = HarmonicSet::up_to(harmonics)
            .iter()
            .map(|k| vec![zigzag(h, k as i64, sectors)])
            .collect();
        Self::new(BasisKind::TravelingWave, sectors, sets)
    }
}
