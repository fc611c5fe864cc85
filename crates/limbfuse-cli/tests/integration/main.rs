//! The integration tests of the `limbfuse` binary and the repository guards,
//! one module per former `tests/NAME.rs` (one test binary per package: each
//! binary linked the whole dependency graph again).

mod align_legs_cli;
mod calibration_cli;
mod cli_demo;
mod cli_errors;
mod cli_fes;
mod cli_fes_extended;
mod cli_gait;
mod cli_gait_events;
mod cli_methods;
mod cli_report;
mod cli_smooth;
mod closed_pipe;
mod crate_layers;
mod dash_output;
mod issue_14_chain_device_orientation;
mod issue_14_chain_mid_stride_start;
mod issue_15_knee_turn_in_the_window;
mod issue_15_knee_window_in_seconds;
mod issue_16_plant_as_stated;
mod issue_16_tune_fes;
mod issue_17_new_user;
mod issue_18_arrow_cli;
mod issue_18_bounded_io;
mod issue_18_diagnostics_option;
mod issue_18_fuzz_parsers;
mod issue_18_fuzz_steps;
mod issue_18_glitches;
mod issue_19_clock_origin;
mod issue_19_event_window;
mod issue_19_library_extension;
mod issue_19_mid_walk_start;
mod issue_19_report_gait_events;
mod issue_19_speed_on_a_walk_with_angles;
mod knee_backfill_cli;
mod knee_bad_input;
mod knee_cli;
mod raw_frames_warning;
mod results_commands;
mod s02_support;
mod simulate_gait_reference;
mod source_file_length;
mod streaming_estimate;
mod support;
mod tuning_cli;
