//! The integration tests of limbfuse-estimators, one module per former
//! `tests/NAME.rs` (one test binary per package: each binary linked the whole
//! dependency graph again). The allocation-counting tests are the separate
//! `tests/allocation` binary (they install a global allocator).

mod chain_encoder_gate;
mod chain_gyro_gate;
mod controller_loop_example;
mod diagnostics;
mod fes_gyro_spikes;
mod fes_no_resets;
mod fes_simulated;
mod gait_events_sim;
mod imm_bslip;
mod imm_continuous;
mod imm_continuous_support;
mod issue_14_chain_rate;
mod issue_14_run_in;
mod issue_16_shank_gap;
mod issue_17_gain_kept_in_place;
mod issue_18_fuzz;
mod issue_18_fuzz_chain_knee;
mod issue_18_gaps_in_shared_recordings;
mod issue_18_imm_restart_after_gap;
mod issue_18_missing_data;
mod issue_18_partial_imu_cells;
mod issue_19_long_trials;
mod issue_19_off_grid_branches;
mod issue_29_imm_start_mid_step;
mod knee_flexion_evidence;
mod knee_hinge;
mod knee_late_start;
mod knee_real_conditions;
mod knee_rest_gravity;
mod knee_selfalign_hinge;
mod knee_selfalign_properties;
mod knee_selfalign_real;
mod knee_selfalign_shared;
mod knee_selfalign_sim;
mod knee_sensor_delay;
mod lowback_sides;
mod segment_kf_accel_gate;
mod segment_kf_golden;
mod segment_kf_issue_18;
mod segment_kf_mid_walk_start;
mod segment_kf_papers;
mod segment_kf_rate_spikes;
mod segment_kf_robustness;
mod segment_kf_static;
mod segment_kf_support;
mod shared_data_support;
