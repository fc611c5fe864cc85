//! # limbfuse-eval
//!
//! Errors of estimates against references: streaming per-channel metrics
//! (RMSE, offset-free RMSE, maximum absolute error, mean error, Pearson
//! correlation), the pairing of a trial with an estimate file, and the text
//! and JSON forms of the result (SPEC section 4, `evaluate`).
#![deny(missing_docs)]

pub mod acc_rails;
pub mod blended_stride_speed;
pub mod channel_error;
pub mod clipped_swings;
pub mod contact_sides;
pub mod data_limits;
pub mod evaluation;
pub mod evaluation_kind;
mod evaluation_output;
pub mod fixed_thigh;
pub mod gait_evaluation;
mod gait_event_columns;
pub mod gait_events_evaluation;
pub mod gait_events_report;
pub mod gait_watch;
pub mod knee_errors;
pub mod knee_watch;
pub mod metrics;
pub mod notes;
pub mod output_watch;
pub mod rejections;
pub mod resets;
pub mod sample_interval;
pub mod scored_feet;
pub mod sensor_units;
pub mod speed_range;
pub mod stance_swing;
pub mod stats;
pub mod stride_table;
pub mod strided;
pub mod sync_lag;
pub mod trial_check;
pub mod trial_summary;

pub use acc_rails::{AccRailWatch, AccRails};
pub use channel_error::ChannelError;
pub use clipped_swings::{ClippedSwingWatch, ClippedSwings};
pub use evaluation::{
    evaluate_files, evaluate_files_scored, max_lag_bound, EvalError, EvalOptions, TimeWindow,
};
pub use evaluation_kind::{evaluation_kind, speed_from_com, EstimateContent, EvaluationKind};
pub use fixed_thigh::FixedThighWatch;
pub use gait_watch::GaitWatch;
pub use knee_watch::KneeWatch;
pub use metrics::{AngleMetrics, ChannelCoverage, Evaluation};
pub use rejections::{Rejected, RejectionWatch};
pub use resets::{scan_estimate_file, ResetWatch, Resets};
pub use sample_interval::{IntervalMismatch, SampleIntervalWatch};
pub use sensor_units::{unit_warnings, ReferenceUnitsWatch, SensorUnitsWatch, UnitSuspect};
pub use speed_range::{OutsideRange, RangeSide, SpeedRangeWatch};
pub use trial_check::{TrialCheck, TrialMismatch};
pub use trial_summary::{summarise, InputGroup, TrialSummary};
