//! SVG figures (plotters, SVG backend only: no system fonts needed).

pub mod modes;

pub use modes::{frequency_versus_nodal_diameter, frequency_versus_nodal_diameter_svg};

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
    /// The SVG file could not be written.
    #[error("cannot write {}: {source}", path.display())]
    Write {
        /// The file.
        path: std::path::PathBuf,
        /// The system error.
        source: std::io::Error,
    },
}
