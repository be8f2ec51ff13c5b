//! What a forced-response figure draws of one sector: its curves and its
//! stability events (the figure in `forced_response`, its nonlinear
//! region's panel in `nonlinear_region`).

use super::event_symbols::EventSymbol;

/// The curves of one sector.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct SectorCurves {
    /// Legend label of the nonlinear curve (e.g. `sector 3`).
    pub label: String,
    /// Nonlinear branch `(Hz, m)`, in branch order (turning points kept).
    pub nonlinear: Vec<(f64, f64)>,
    /// Where the nonlinear branch has gaps: the indices in `nonlinear` of
    /// the points not joined to the one before (a branch followed from both
    /// ends whose sweeps did not meet).
    pub breaks: Vec<usize>,
    /// Linear response `(Hz, m)`, by increasing frequency (may be empty).
    pub linear: Vec<(f64, f64)>,
    /// Reference branch `(Hz, m)` of a comparison run (may be empty).
    pub reference: Vec<(f64, f64)>,
    /// Per point of `nonlinear`: whether it is unstable (empty: not checked).
    pub unstable: Vec<bool>,
    /// The stability events drawn on this sector's curve (each event on
    /// one curve only: one symbol per event).
    pub markers: Vec<EventSymbol>,
}
