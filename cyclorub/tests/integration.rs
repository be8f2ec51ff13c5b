//! The integration tests, in one binary: one link instead of one per file,
//! and the harness spreads every test over the cores (a file with one long
//! test no longer leaves a core idle). Run one file's tests with
//! `cargo test -p cyclorub --test integration dlft_hbm::`.

mod common;
#[path = "fixtures/model/support.rs"]
mod support;

mod basis_paper_equations;
mod basis_sector_maps;
mod basis_symmetry_properties;
mod bifurcated;
mod bifurcated_time;
mod case_borderline;
mod contact_law;
mod continuation_both_ends;
mod continuation_close_sheets;
mod continuation_driver;
mod continuation_hairpin;
mod continuation_range;
mod continuation_regression;
mod continuation_secant;
mod continuation_snake;
mod continuation_zigzag;
mod cyclic_fourier;
mod deformed_casing;
mod dlft_hbm;
mod doc_citations;
mod fan_friction;
#[cfg(feature = "plot")]
mod figures;
mod forced_response;
mod friction;
mod full_wheel_structured;
mod hbm_core;
mod import_circles;
mod marker_kinds;
mod misleading_messages;
mod mistuned_modes;
mod mistuning;
mod mistuning_contact;
mod mistuning_fan;
#[cfg(all(feature = "plot", feature = "hdf5"))]
mod mistuning_results;
mod mistuning_stability;
mod mistuning_structured;
mod model_craig_bampton;
mod model_cyclic;
mod model_damping;
mod model_finite_element_case;
mod model_import;
#[cfg(feature = "plot")]
mod model_plot;
mod model_rotated_boundaries;
mod pitchfork;
mod preload;
#[cfg(all(feature = "plot", feature = "hdf5"))]
mod results;
mod results_folder_run_file;
mod simulate_accuracy;
mod simulate_contact;
mod simulate_fan;
mod simulate_floquet_growth;
mod simulate_friction;
mod simulate_lagrange;
mod simulate_linear;
mod stability;
mod stability_along;
mod stability_friction;
mod stability_shooting;
mod stability_targeted;
