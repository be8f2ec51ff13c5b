//! The stability events on a forced-response figure: one small hollow
//! symbol per event (a group of markers of one kind and direction at one
//! frequency, [`crate::stability::group_events`]), its shape telling the
//! kind, its classes in a short label beside it (`ND 2,5,7`).

use crate::stability::MarkerKind;
use plotters::style::{RGBColor, ShapeStyle};

/// The colour of the symbols and of their legend entries (a near black
/// that no curve uses: a test counts the symbols by it).
pub const SYMBOL_COLOUR: RGBColor = RGBColor(17, 17, 17);

/// The symbols' half size, px: small enough not to hide the curve.
pub const SYMBOL_SIZE: i32 = 5;

/// One event drawn on the curves.
#[derive(Clone, Debug, PartialEq)]
pub struct EventSymbol {
    /// Frequency of the event, Hz.
    pub frequency_hz: f64,
    /// Amplitude where it is drawn, m.
    pub amplitude_m: f64,
    /// How the multiplier crosses (the shape).
    pub kind: MarkerKind,
    /// The classes, e.g. `ND 2,5,7` (empty: no label).
    pub label: String,
}

/// The legend name of a marker kind.
pub fn kind_name(kind: MarkerKind) -> &'static str {
    match kind {
        MarkerKind::Fold => "fold",
        MarkerKind::BranchPoint => "branch point (symmetry breaking; at ND 0 of the same symmetry)",
        MarkerKind::RealCrossing => "fold or branch point",
        MarkerKind::PeriodDoubling => "period doubling",
        MarkerKind::NeimarkSacker => "Neimark-Sacker",
        MarkerKind::Jump => "jump at a change of contact",
    }
}

/// The short label of a set of nodal diameters (sorted): `ND 2,5,7`, runs
/// of three or more written `ND 0-6`; empty for none.
pub fn classes_label(diameters: &[i64]) -> String {
    if diameters.is_empty() {
        return String::new();
    }
    let mut parts: Vec<String> = Vec::new();
    let mut start = 0;
    while start < diameters.len() {
        let mut end = start;
        while end + 1 < diameters.len() && diameters[end + 1] == diameters[end] + 1 {
            end += 1;
        }
        if end >= start + 2 {
            parts.push(format!("{}-{}", diameters[start], diameters[end]));
        } else {
            parts.extend(diameters[start..=end].iter().map(i64::to_string));
        }
        start = end + 1;
    }
    format!("ND {}", parts.join(","))
}

/// The closed outline of a kind's shape, px around the centre: a square
/// (fold), a triangle pointing up (branch point), a diamond (fold or
/// branch point), a triangle pointing down (period doubling), a circle
/// (Neimark–Sacker, as a 16-sided polygon: every symbol is one path), a
/// tall narrow bar (a jump: the exponent steps across 0).
pub fn outline(kind: MarkerKind, size: i32) -> Vec<(i32, i32)> {
    let s = size;
    let points = match kind {
        MarkerKind::Fold => vec![(-s, -s), (s, -s), (s, s), (-s, s)],
        MarkerKind::BranchPoint => vec![(0, -s - 1), (s + 1, s), (-s - 1, s)],
        MarkerKind::RealCrossing => vec![(0, -s - 1), (s + 1, 0), (0, s + 1), (-s - 1, 0)],
        MarkerKind::PeriodDoubling => vec![(-s - 1, -s), (s + 1, -s), (0, s + 1)],
        MarkerKind::Jump => vec![
            (-s / 2, -s - 2),
            (s / 2, -s - 2),
            (s / 2, s + 2),
            (-s / 2, s + 2),
        ],
        MarkerKind::NeimarkSacker => (0..16)
            .map(|i| {
                let angle = std::f64::consts::PI * i as f64 / 8.0;
                let r = s as f64;
                (
                    (r * angle.cos()).round() as i32,
                    (r * angle.sin()).round() as i32,
                )
            })
            .collect(),
    };
    let mut closed = points.clone();
    closed.push(points[0]);
    closed
}

/// The outline of `kind` moved to `centre` (backend pixels), for a legend.
pub fn outline_at(kind: MarkerKind, centre: (i32, i32)) -> Vec<(i32, i32)> {
    outline(kind, SYMBOL_SIZE)
        .into_iter()
        .map(|(x, y)| (centre.0 + x, centre.1 + y))
        .collect()
}

/// The symbols' line: thin, hollow.
pub fn symbol_style() -> ShapeStyle {
    ShapeStyle::from(&SYMBOL_COLOUR).stroke_width(1)
}

/// Where the label of a symbol starts, px from its centre: above and to
/// the right, raised by `stagger` lines (so that the labels of close
/// events do not print over each other).
pub fn label_offset(stagger: i32) -> (i32, i32) {
    (SYMBOL_SIZE + 3, -SYMBOL_SIZE - 14 - 12 * stagger)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn classes_are_listed_short() {
        assert_eq!(classes_label(&[]), "");
        assert_eq!(classes_label(&[3]), "ND 3");
        assert_eq!(classes_label(&[2, 5, 7]), "ND 2,5,7");
        assert_eq!(classes_label(&[0, 1, 2, 3, 6]), "ND 0-3,6");
        assert_eq!(classes_label(&[1, 2, 5, 6, 7]), "ND 1,2,5-7");
    }

    #[test]
    fn every_kind_has_its_own_shape() {
        let kinds = [
            MarkerKind::Fold,
            MarkerKind::BranchPoint,
            MarkerKind::RealCrossing,
            MarkerKind::PeriodDoubling,
            MarkerKind::NeimarkSacker,
            MarkerKind::Jump,
        ];
        for (i, a) in kinds.iter().enumerate() {
            for b in &kinds[i + 1..] {
                assert_ne!(outline(*a, 5), outline(*b, 5), "{a:?} and {b:?}");
                assert_eq!(outline(*a, 5).first(), outline(*a, 5).last());
                assert_ne!(kind_name(*a), kind_name(*b));
            }
        }
    }
}
