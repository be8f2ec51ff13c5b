//! The frequency versus nodal diameter figure.

use cyclorub::model::SectorModel;
use cyclorub::plot::{frequency_versus_nodal_diameter_svg, PlotError};

#[test]
fn svg_has_one_labelled_line_per_family() {
    let model = SectorModel::academic(24).expect("academic");
    let freqs = model.natural_frequencies().expect("frequencies");
    let svg = frequency_versus_nodal_diameter_svg(24, &freqs, None, "academic").expect("svg");
    assert!(svg.starts_with("<svg"));
    for r in 1..=5 {
        assert!(svg.contains(&format!("mode {r}")), "label of mode {r}");
    }
    assert!(svg.contains("nodal diameter (N = 24)") && svg.contains("frequency (Hz)"));
    let two = frequency_versus_nodal_diameter_svg(24, &freqs, Some(2), "academic").expect("svg");
    assert!(two.contains("mode 2") && !two.contains("mode 3"));
}

#[test]
fn nothing_to_draw_is_an_error() {
    assert!(matches!(
        frequency_versus_nodal_diameter_svg(24, &[], None, "empty"),
        Err(PlotError::Empty { .. })
    ));
}
