//! Sector models: one matrix set per signed nodal diameter, and the full wheel.
