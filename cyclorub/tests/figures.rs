//! The figures of a run as a designer reads them (issue 46): one symbol
//! per stability event on the forced response, every figure an SVG that
//! renders (parsed and rasterized with resvg) and a PNG beside it.

use cyclorub::case::Case;
use cyclorub::forced_response::ForcedResponse;
use cyclorub::plot::event_symbols::SYMBOL_COLOUR;
use cyclorub::plot::png::svg_to_png;
use cyclorub::run::group_markers;
use cyclorub::stability::StabilitySettings;
use plotters::style::RGBColor;
use std::collections::BTreeSet;
use std::path::Path;

/// The elements drawn in the symbols' colour: the symbols and their
/// legend entries.
fn symbol_elements(svg: &str) -> usize {
    let RGBColor(r, g, b) = SYMBOL_COLOUR;
    let colour = format!("#{r:02X}{g:02X}{b:02X}");
    let document = roxmltree::Document::parse(svg).expect("valid XML");
    document
        .descendants()
        .filter(|n| {
            n.attribute("stroke")
                .is_some_and(|s| s.eq_ignore_ascii_case(&colour))
        })
        .count()
}

/// Rasterizes an SVG file at 30 dpi and returns the share of its pixels
/// that are not white.
fn inked(path: &Path) -> f64 {
    let svg = std::fs::read_to_string(path).expect("an SVG");
    let png = svg_to_png(&svg, 30.0, &path.display().to_string())
        .unwrap_or_else(|e| panic!("{} does not render: {e}", path.display()));
    let image = resvg::tiny_skia::Pixmap::decode_png(&png).expect("a PNG");
    let dark = image.pixels().iter().filter(|p| p.red() < 200).count();
    dark as f64 / image.pixels().len() as f64
}

#[test]
fn the_default_branch_has_one_symbol_per_event_and_every_figure_renders() {
    let solution = ForcedResponse::from_case(&Case::default())
        .unwrap()
        .stability(Some(StabilitySettings::default()))
        .build()
        .unwrap()
        .run(&mut [])
        .unwrap();
    let folder = std::env::temp_dir().join(format!("cyclorub-figures-{}", std::process::id()));
    let (record, _) = cyclorub::run::write(&solution, &folder).unwrap();
    let groups = group_markers(&record.stability.markers);
    let kinds: BTreeSet<String> = groups
        .iter()
        .map(|g| format!("{:?}", g.first().marker.kind))
        .collect();
    assert!(groups.len() > 5, "{} events", groups.len());
    let plots = folder.join("plots");
    let svg = std::fs::read_to_string(plots.join("forced_response.svg")).unwrap();
    // One symbol per event, one legend entry per kind.
    assert_eq!(symbol_elements(&svg), groups.len() + kinds.len());
    // Named as the user knows the observed dof.
    assert!(
        svg.contains("Forced response of m1, the blade tip"),
        "title"
    );
    assert!(svg.contains("amplitude of m1, the blade tip (m)"), "axis");
    // The zoomed panel on the plateau.
    assert!(svg.contains("Nonlinear region"), "no zoomed panel");
    for name in [
        "forced_response",
        "cyclic_components",
        "first_harmonic_components",
        "stability_exponents",
        "frequency_vs_nodal_diameter",
    ] {
        let svg_path = plots.join(format!("{name}.svg"));
        let ink = inked(&svg_path);
        assert!(ink > 0.01 && ink < 0.6, "{name}: {ink}");
        let png = std::fs::read(plots.join(format!("{name}.png"))).expect("a PNG beside");
        let image = resvg::tiny_skia::Pixmap::decode_png(&png).expect("a PNG");
        let text = std::fs::read_to_string(&svg_path).unwrap();
        let document = roxmltree::Document::parse(&text).unwrap();
        let width: f64 = document
            .root_element()
            .attribute("width")
            .unwrap()
            .parse()
            .unwrap();
        // 300 dpi of the SVG's 96 px per inch.
        let expected = width * 300.0 / 96.0;
        assert!((f64::from(image.width()) - expected).abs() <= 1.0, "{name}");
    }
    for name in ["forced_response", "stability_exponents"] {
        compare_with_stored(&plots.join(format!("{name}.svg")), name);
    }
    let _ = std::fs::remove_dir_all(&folder);
}

/// The resolution of the stored images: enough to see a curve move.
const STORED_DPI: f64 = 24.0;

/// Compares the SVG at `path`, rasterized at [`STORED_DPI`], with the
/// stored `tests/fixtures/figures/{name}.png`: at most 2 % of the pixels
/// may differ by more than a quarter of the range in a channel (the same
/// figure on another machine differs by rounding in a few pixels; a moved
/// curve, a new symbol or a lost panel by far more). Regenerate on purpose
/// after changing a figure with `CYCLORUB_WRITE_FIGURES=1 cargo test -p
/// cyclorub --test integration figures::`.
fn compare_with_stored(path: &Path, name: &str) {
    let stored = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("tests/fixtures/figures")
        .join(format!("{name}.png"));
    let svg = std::fs::read_to_string(path).unwrap();
    let png = svg_to_png(&svg, STORED_DPI, name).unwrap();
    if std::env::var_os("CYCLORUB_WRITE_FIGURES").is_some() {
        std::fs::create_dir_all(stored.parent().unwrap()).unwrap();
        std::fs::write(&stored, &png).unwrap();
        return;
    }
    let now = resvg::tiny_skia::Pixmap::decode_png(&png).unwrap();
    let before =
        resvg::tiny_skia::Pixmap::decode_png(&std::fs::read(&stored).unwrap_or_else(|e| {
            panic!(
                "{}: {e}; write it with CYCLORUB_WRITE_FIGURES=1",
                stored.display()
            )
        }))
        .unwrap();
    assert_eq!(
        (now.width(), now.height()),
        (before.width(), before.height()),
        "{name}: the figure's size changed"
    );
    let differing = now
        .pixels()
        .iter()
        .zip(before.pixels())
        .filter(|(a, b)| {
            let channels =
                |p: &resvg::tiny_skia::PremultipliedColorU8| [p.red(), p.green(), p.blue()];
            channels(a)
                .iter()
                .zip(channels(b))
                .any(|(x, y)| x.abs_diff(y) > 64)
        })
        .count();
    let share = differing as f64 / now.pixels().len() as f64;
    assert!(
        share < 0.02,
        "{name}: {:.1} % of the pixels differ from {} (regenerate on purpose with CYCLORUB_WRITE_FIGURES=1)",
        100.0 * share,
        stored.display()
    );
}
