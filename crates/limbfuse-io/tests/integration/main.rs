//! The integration tests of limbfuse-io, one module per former
//! `tests/NAME.rs` (one test binary per package: each binary linked the whole
//! dependency graph again).

mod byte_order_mark;
mod cut_last_line;
mod estimate_provenance;
mod import_gaittoolbox;
mod import_knee_rig;
mod issue_14_gaittoolbox_other_leg;
mod issue_18_arrow_files;
mod issue_18_mapped_io;
mod issue_18_partial_imu_cells;
mod issue_18_read_into;
mod issue_19_gaittoolbox_speed_ref;
mod trial_bad_input;
mod trial_roundtrip;
mod two_leg_trial;
