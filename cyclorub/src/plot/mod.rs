//! SVG figures (plotters, SVG backend only: no system fonts needed).
