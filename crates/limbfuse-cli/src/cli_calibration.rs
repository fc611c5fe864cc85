//! Flags of `calibrate` and `simulate calibration` (docs/CALIBRATION.md).

use std::path::PathBuf;

use clap::{Args, ValueEnum};

/// What `calibrate` estimates per accelerometer.
#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum)]
pub enum ModelArg {
    /// Bias + symmetric scale/cross-axis matrix (9 unknowns: >= 9 distinct poses).
    Full,
    /// Bias + per-axis scale (6 unknowns: >= 6 distinct poses).
    Scale,
    /// Bias only (3 unknowns: >= 3 distinct poses).
    Bias,
}

/// Options of `calibrate`.
#[derive(Debug, Args)]
pub struct CalibrateArgs {
    /// Recording of static poses (trial file, raw sensor frames; `limbfuse simulate calibration` writes one).
    pub poses: PathBuf,
    /// Output calibration file (TOML), for `import`/`estimate --calibration`, `align --imu-calibration`.
    #[arg(short, long)]
    pub output: PathBuf,
    /// Accelerometer model.
    #[arg(long, value_enum, default_value_t = ModelArg::Full)]
    pub model: ModelArg,
    /// Local gravity (m/s^2); default: the recording's `# g:` line, else 9.81.
    #[arg(long)]
    pub gravity: Option<f64>,
    /// Static test: largest accelerometer spread sqrt(sum of axis variances) over 0.5 s (m/s^2).
    #[arg(long, default_value_t = 0.05)]
    pub acc_std_max: f64,
    /// Static test: largest gyro spread over 0.5 s (rad/s).
    #[arg(long, default_value_t = 0.03)]
    pub gyro_std_max: f64,
    /// Shortest static pose (s).
    #[arg(long, default_value_t = 1.0)]
    pub min_pose: f64,
}

/// Options of `simulate calibration`.
#[derive(Debug, Args)]
pub struct CalibrationSimArgs {
    /// Output trial file (raw sensor frames, no reference).
    #[arg(short, long)]
    pub output: PathBuf,
    /// Random seed: the same four sensors as `simulate walking --seed` with this seed.
    #[arg(long, default_value_t = 1)]
    pub seed: u64,
    /// IMU sample rate (Hz); `--rate` is accepted as an alias.
    #[arg(long, alias = "rate", default_value_t = 100.0)]
    pub imu_rate: f64,
    /// Number of poses (1-14: the six faces, then the eight corners).
    #[arg(long, default_value_t = 14)]
    pub poses: usize,
    /// Time each pose is held (s).
    #[arg(long, default_value_t = 4.0)]
    pub hold: f64,
    /// Time of each turn between poses (s).
    #[arg(long, default_value_t = 2.0)]
    pub transition: f64,
    /// Distance of each sensor from the board's centre of rotation (m).
    #[arg(long, default_value_t = 0.05)]
    pub lever_arm: f64,
    /// Rock pose K (1-based) by 1.5 deg at 1 Hz instead of holding it still (a bad pose).
    #[arg(long, value_name = "K")]
    pub wobble_pose: Option<usize>,
    /// Ideal sensors (as `simulate walking --no-noise`).
    #[arg(long)]
    pub no_noise: bool,
    /// Lift the cap on the simulated length.
    #[command(flatten)]
    pub cap: RecordingCap,
}

/// `--force` of `simulate calibration`, whose length is --poses x (--hold +
/// --transition): it has no --duration, which [`crate::cli::LengthCap`]'s
/// help names (a fresh-user audit, session 28).
#[derive(Debug, Clone, Copy, Default, Args)]
pub struct RecordingCap {
    /// Allow a recording longer than 24 h of simulated time (--poses x (--hold + --transition))
    /// or 86.4 M samples: the cap keeps a typo from filling the disk.
    #[arg(long)]
    pub force: bool,
}
