//! SVG figures (plotters, SVG backend only: no system fonts needed).

pub mod branches;
pub mod components;
pub mod curves;
pub mod envelope;
pub mod event_symbols;
pub mod figures;
pub mod forced_response;
pub mod mistuning;
pub mod mistuning_study;
pub mod modes;
pub mod nonlinear_region;
pub mod png;
pub mod simulation;
pub mod stability;
mod svg_text;

pub use components::{
    branch_components, branch_components_svg, cyclic_components, cyclic_components_svg,
};
pub use envelope::envelope_svg;
pub use event_symbols::EventSymbol;
pub use figures::{write_figures, FigureOptions, Reference};
pub use forced_response::{forced_response, forced_response_svg, Captions, SectorCurves};
pub use modes::{
    frequency_versus_nodal_diameter, frequency_versus_nodal_diameter_compared,
    frequency_versus_nodal_diameter_compared_svg, frequency_versus_nodal_diameter_svg,
    ComparedFrequencies,
};

use plotters::style::RGBColor;

/// A colour per index (nodal diameter, curve), from a 20-colour palette
/// ("tab20" reordered so that neighbours differ), reused cyclically.
pub fn palette(index: usize) -> RGBColor {
    const COLOURS: [RGBColor; 20] = [
        RGBColor(31, 119, 180),
        RGBColor(255, 127, 14),
        RGBColor(44, 160, 44),
        RGBColor(214, 39, 40),
        RGBColor(148, 103, 189),
        RGBColor(140, 86, 75),
        RGBColor(227, 119, 194),
        RGBColor(127, 127, 127),
        RGBColor(188, 189, 34),
        RGBColor(23, 190, 207),
        RGBColor(0, 0, 0),
        RGBColor(174, 199, 232),
        RGBColor(255, 187, 120),
        RGBColor(152, 223, 138),
        RGBColor(255, 152, 150),
        RGBColor(197, 176, 213),
        RGBColor(196, 156, 148),
        RGBColor(247, 182, 210),
        RGBColor(219, 219, 141),
        RGBColor(158, 218, 229),
    ];
    COLOURS[index % COLOURS.len()]
}

/// Writes SVG text to `path`, without strokes of zero length
/// ([`svg_text`]).
pub(crate) fn write_svg(path: &std::path::Path, svg: &str) -> Result<(), PlotError> {
    std::fs::write(path, svg_text::without_empty_strokes(svg)).map_err(|source| PlotError::Write {
        path: path.to_path_buf(),
        source,
    })
}

/// Why a figure could not be drawn or written.
#[derive(Debug, thiserror::Error)]
pub enum PlotError {
    /// plotters failed while drawing.
    #[error("cannot draw {what}: {message}")]
    Draw {
        /// Which figure.
        what: String,
        /// plotters' message.
        message: String,
    },
    /// The figure has nothing to show.
    #[error("cannot draw {what}: {message}")]
    Empty {
        /// Which figure.
        what: String,
        /// What is missing.
        message: String,
    },
    /// A sector or point asked for does not exist.
    #[error("{0}")]
    Choice(String),
    /// The SVG file could not be written.
    #[error("cannot write {}: {source}", path.display())]
    Write {
        /// The file.
        path: std::path::PathBuf,
        /// The system error.
        source: std::io::Error,
    },
}

impl PlotError {
    /// Whether the error is in what the user asked for (a sector or point
    /// that does not exist), as opposed to a failure while drawing or
    /// writing.
    pub fn is_input_error(&self) -> bool {
        matches!(self, Self::Choice(_))
    }
}
