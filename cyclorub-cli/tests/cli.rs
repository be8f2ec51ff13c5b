//! The command's tests, in one binary: one link instead of one per file,
//! and the harness spreads every test over the cores. Run one file's tests
//! with `cargo test -p cyclorub-cli --test cli run_cli::`.

mod bad_input_cli;
mod branches_cli;
mod branches_records_cli;
mod branches_requests_cli;
mod common;
mod init_cli;
mod leftover_messages_cli;
mod mesh_cli;
mod mistuning_outputs_cli;
mod modes_cli;
mod numeric_keys_cli;
mod plan_cli;
mod recover_cli;
mod reproduce_cli;
mod results_cli;
mod run_cli;
mod simulate_checks_cli;
mod simulate_cli;
mod sizes_cli;
mod stability_cli;
mod stability_sizes_cli;
mod streaming_cli;
mod study_cli;
