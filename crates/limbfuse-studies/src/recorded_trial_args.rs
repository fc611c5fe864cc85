//! Arguments of the study examples that read one recorded trial and score
//! windows of it, or write a variant of it (`gyro_shape_floor`,
//! `attitude_floor`, `chain_geometry_sensitivity`, `recording_variant`,
//! `final_contact_floor`), re-exported by [`crate::example_args`].

use clap::Parser;

/// `recording_variant TRIAL -o OUT [--drop-rows A:B ...] [--blank A:B ...]
/// [--blank-inputs A:B ...] [--blank-every N [--blank-first K]] [--drop-other-leg]
/// [--drop-imu SEGMENT ...] [--swap-legs]
/// [--jitter-ms MS [--jitter-seed S]] [--stick-encoder JOINT:A:B ...]
/// [--offset-encoder JOINT:T:RAD ...] [--gyro-spikes N [--spike-rad-s A] [--spike-from T]
/// [--spike-seed S]] [--time-glitches N [--glitch-seed S]]`.
#[derive(Debug, Parser)]
#[command(name = "recording_variant")]
pub struct RecordingVariantArgs {
    /// The trial file.
    pub trial: String,
    /// The variant's trial file.
    #[arg(short = 'o', long, required = true)]
    pub output: String,
    /// Rows with `START <= t < END` (s) removed: a time gap (repeatable).
    #[arg(long = "drop-rows", value_parser = time_window)]
    pub drop_rows: Vec<(f64, f64)>,
    /// Every IMU cell (both legs) emptied on rows with `START <= t < END`
    /// (s): a dropout (repeatable).
    #[arg(long, value_parser = time_window)]
    pub blank: Vec<(f64, f64)>,
    /// Every model input cell (stimulation `u_*`, motor torques) emptied on
    /// rows with `START <= t < END` (s): a gap in the stimulation log
    /// (repeatable).
    #[arg(long, value_parser = time_window)]
    pub blank_inputs: Vec<(f64, f64)>,
    /// Every IMU cell emptied on every N-th row (dropped packets).
    #[arg(long)]
    pub blank_every: Option<std::num::NonZeroUsize>,
    /// The first row (0-based) `--blank-every` empties.
    #[arg(long, default_value_t = 0)]
    pub blank_first: usize,
    /// The other leg's IMU columns removed (one-leg recording).
    #[arg(long)]
    pub drop_other_leg: bool,
    /// This leg's IMU on SEGMENT (trunk, thigh, shank or foot) removed: a
    /// recording without that sensor (repeatable; before `--gyro-spikes`).
    #[arg(long, value_name = "SEGMENT", value_parser = segment_index)]
    pub drop_imu: Vec<usize>,
    /// The two legs' IMU columns and contact references exchanged, the
    /// readings not mirrored (the sensors' columns mislabelled, or a
    /// recording whose two sensors are mounted alike).
    #[arg(long)]
    pub swap_legs: bool,
    /// Every time stamp moved by a seeded uniform amount within +-MS
    /// milliseconds, the readings left where they are (a receiver's stamp
    /// jitter; `limbfuse_signal::recording_variants::jitter_times`).
    #[arg(long, value_name = "MS")]
    pub jitter_ms: Option<f64>,
    /// Seed of `--jitter-ms`.
    #[arg(long, default_value_t = 1)]
    pub jitter_seed: u64,
    /// `JOINT:START:END`: the joint's encoder (hip, knee or ankle) repeats
    /// its reading at the first row of `START <= t < END` (s) over those
    /// rows: a stuck encoder (repeatable).
    #[arg(long, value_name = "JOINT:START:END", value_parser = joint_window)]
    pub stick_encoder: Vec<(usize, (f64, f64))>,
    /// `JOINT:START:RAD`: the joint's encoder reads RAD more from `START`
    /// (s) on: a re-zeroed or slipped encoder (repeatable).
    #[arg(long, value_name = "JOINT:START:RAD", value_parser = joint_window)]
    pub offset_encoder: Vec<(usize, (f64, f64))>,
    /// N single-sample spikes added to the z axis of this leg's thigh,
    /// shank or foot gyroscope at seeded random rows from `--spike-from`
    /// (`limbfuse_signal::recording_variants::add_gyro_spikes`).
    #[arg(long, value_name = "N")]
    pub gyro_spikes: Option<usize>,
    /// Size of each `--gyro-spikes` spike (rad/s, seeded random sign).
    #[arg(long, value_name = "RAD_S", default_value_t = 3.0)]
    pub spike_rad_s: f64,
    /// First time (s) a `--gyro-spikes` spike may fall at.
    #[arg(long, value_name = "S", default_value_t = 0.0)]
    pub spike_from: f64,
    /// Seed of `--gyro-spikes`.
    #[arg(long, default_value_t = 1)]
    pub spike_seed: u64,
    /// N time-stamp glitches at seeded random rows, in turn a row written
    /// twice, two rows written in the wrong order and one stamp 0.5 s late
    /// (`limbfuse_signal::recording_variants::add_time_glitches`): a file
    /// every reader refuses until `limbfuse repair-time` repairs it.
    #[arg(long, value_name = "N")]
    pub time_glitches: Option<usize>,
    /// Seed of `--time-glitches`.
    #[arg(long, default_value_t = 1)]
    pub glitch_seed: u64,
}

/// `JOINT:A:B` with JOINT one of hip, knee, ankle (its index) and two
/// numbers.
fn segment_index(s: &str) -> Result<usize, String> {
    ["trunk", "thigh", "shank", "foot"]
        .iter()
        .position(|n| *n == s.trim())
        .ok_or_else(|| format!("`{s}` is not trunk, thigh, shank or foot"))
}

fn joint_window(s: &str) -> Result<(usize, (f64, f64)), String> {
    let (joint, rest) = s
        .split_once(':')
        .ok_or_else(|| format!("`{s}`: expected JOINT:A:B (JOINT hip, knee or ankle)"))?;
    let j = match joint.trim() {
        "hip" => 0,
        "knee" => 1,
        "ankle" => 2,
        other => return Err(format!("`{s}`: `{other}` is not hip, knee or ankle")),
    };
    let (a, b) = rest
        .split_once(':')
        .ok_or_else(|| format!("`{s}`: expected JOINT:A:B"))?;
    Ok((j, (number_in(s, a, "")?, number_in(s, b, "")?)))
}

/// `final_contact_floor [TRIAL [OTHER_TRIAL ...]]`.
#[derive(Debug, Parser)]
#[command(name = "final_contact_floor")]
pub struct FinalContactFloorArgs {
    /// The two-foot trial with contact references (the gaitmap walk).
    #[arg(default_value = "../shared/data/gaitmap-foot-walk/trial.csv")]
    pub trial: String,
    /// Trials with foot IMUs (no reference needed) whose toe offs at lower
    /// rates are compared with those at their own rate.
    pub others: Vec<String>,
}

/// `gyro_shape_floor TRIAL --window A:B [--window C:D ...] [--max-lag N]`
/// (also the arguments of `attitude_floor`).
#[derive(Debug, Parser)]
#[command(name = "gyro_shape_floor")]
pub struct GyroShapeFloorArgs {
    /// The (aligned) trial file.
    pub trial: String,
    /// A scored window `START:END` in seconds of the trial's clock (repeatable).
    #[arg(long = "window", value_parser = time_window, required = true)]
    pub windows: Vec<(f64, f64)>,
    /// Lags of up to this many samples are tried per segment.
    #[arg(long, default_value_t = 5)]
    pub max_lag: u32,
}

/// `chain_geometry_sensitivity TRIAL --window A:B [--window C:D ...] [--max-lag N] [--search-cm R]`.
#[derive(Debug, Parser)]
#[command(name = "chain_geometry_sensitivity")]
pub struct ChainGeometrySensitivityArgs {
    /// The (aligned) trial file, with a segment-angle reference.
    pub trial: String,
    /// A scored window `START:END` in seconds of the trial's clock
    /// (repeatable); the search minimises the last one.
    #[arg(long = "window", value_parser = time_window, required = true)]
    pub windows: Vec<(f64, f64)>,
    /// Lags of up to this many samples are tried per channel (as
    /// `limbfuse evaluate --max-lag`).
    #[arg(long, default_value_t = 5)]
    pub max_lag: usize,
    /// The search's lattice spans +-this many cm around the base geometry
    /// (five points per quantity).
    #[arg(long, default_value_t = 3.0)]
    pub search_cm: f64,
}

/// The number `x` of the argument `s` (`unit` said in the message).
fn number_in(s: &str, x: &str, unit: &str) -> Result<f64, String> {
    x.trim()
        .parse::<f64>()
        .map_err(|_| format!("`{s}`: `{x}` is not a number{unit}"))
}

/// `START:END` seconds, `START < END`.
pub(crate) fn time_window(s: &str) -> Result<(f64, f64), String> {
    let (a, b) = s
        .split_once(':')
        .ok_or_else(|| format!("`{s}`: expected START:END in seconds"))?;
    let unit = " of seconds";
    let (a, b) = (number_in(s, a, unit)?, number_in(s, b, unit)?);
    if a < b {
        Ok((a, b))
    } else {
        Err(format!("`{s}`: START must be below END"))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn encoder_faults_name_the_joint_and_two_numbers() {
        let args = RecordingVariantArgs::try_parse_from([
            "recording_variant",
            "t.csv",
            "-o",
            "v.csv",
            "--stick-encoder",
            "knee:20:20.5",
            "--offset-encoder",
            "hip:3:-0.3",
        ])
        .unwrap();
        assert_eq!(args.stick_encoder, vec![(1, (20.0, 20.5))]);
        assert_eq!(args.offset_encoder, vec![(0, (3.0, -0.3))]);
        assert!(joint_window("elbow:1:2")
            .unwrap_err()
            .contains("not hip, knee or ankle"));
        assert!(joint_window("knee:1").is_err());
        assert!(joint_window("knee:a:2")
            .unwrap_err()
            .contains("not a number"));
    }
}
