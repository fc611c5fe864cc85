//! The segment filters of paper 001 on accelerometers calibrated by
//! `limbfuse calibrate` (issue 14 item 3, docs/CALIBRATION.md).
//!
//! Per seed: the simulated calibration recording of the walking
//! simulator's sensors (same seed) is calibrated; the walking trial of the
//! same sensors gets the calibration on its raw channels; then the protocol
//! of paper 001 (docs/TUNING.md): resample to 50 Hz (windowed sinc), and
//! the validation block 30-50 s from 50 starting points (fresh filter per
//! start, 10 s runs, mean of the 4 segment RMSEs averaged over the starts),
//! with the default parameters or, optionally, parameters tuned on the
//! block 10-30 s first (PSO, `limbfuse tune`); optionally with the filters'
//! run-in `startup_s` (no estimate for the first seconds of each run).

use std::error::Error;

use limbfuse_core::{Estimator, Record};
use limbfuse_estimators::segment_kf::{GlobalKf, MarkovJumpKf};
use limbfuse_eval::TimeWindow;
use limbfuse_io::{Calibration, TrialLayout, TrialMeta, TrialReader, TrialWriter};
use limbfuse_methods::segment_params::{FilterMethod, FilterParams, Preset};
use limbfuse_signal::calibration::{calibrate, CalibrationParams};
use limbfuse_signal::resample::{resample_trial, ResampleOptions};
use limbfuse_sim::{PoseRecording, PoseRecordingConfig, WalkingConfig, WalkingSimulator};
use limbfuse_workflows::protocol::{multi_start, plan_intervals, StartPlan};
use limbfuse_workflows::tune_validate::{tune_and_validate, TuneValidateConfig, Validation};
use limbfuse_workflows::tuning::TuneConfig;

use crate::baseline_study::mean_rmse_deg;

/// Which sensors the walking trial has, and what is done to them.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Sensors {
    /// Default consumer-MEMS sensors, raw.
    Raw,
    /// Default sensors, calibrated from the simulated pose recording.
    Calibrated,
    /// Calibrated, and no mounting misalignment (`--no-misalignment`).
    CalibratedNoMisalignment,
    /// No static accelerometer error at all and no misalignment (the ideal
    /// a calibration could reach; the "- static accel" row of RESULTS).
    NoStaticAccelError,
}

impl Sensors {
    /// Every variant, in table order.
    pub const ALL: [Sensors; 4] = [
        Sensors::Raw,
        Sensors::Calibrated,
        Sensors::CalibratedNoMisalignment,
        Sensors::NoStaticAccelError,
    ];

    /// Table label.
    pub fn label(self) -> &'static str {
        match self {
            Sensors::Raw => "default, uncalibrated",
            Sensors::Calibrated => "calibrated (1 deg mounting misalignment)",
            Sensors::CalibratedNoMisalignment => "calibrated, misalignment 0",
            Sensors::NoStaticAccelError => "no static accel error (bound)",
        }
    }
}

/// The walking configuration of `seed` at `speed` for `sensors` (60 s, 100 Hz).
pub fn walking_config(seed: u64, speed: f64, sensors: Sensors) -> WalkingConfig {
    let mut cfg = WalkingConfig {
        seed,
        speed_mps: speed,
        ..WalkingConfig::default()
    };
    if sensors != Sensors::Raw && sensors != Sensors::Calibrated {
        cfg.imu.misalignment_rad = 0.0;
    }
    if sensors == Sensors::NoStaticAccelError {
        cfg.imu.acc.turn_on_bias = 0.0;
        cfg.imu.acc.bias_instability = 0.0;
        cfg.imu.acc.scale_error = 0.0;
        cfg.imu.acc.cross_axis = 0.0;
    }
    cfg
}

/// Calibrates the sensors of `cfg` from their simulated pose recording
/// (14 poses, 4 s holds, 2 s turns).
pub fn calibrate_sensors(cfg: &WalkingConfig) -> Result<Calibration, Box<dyn Error>> {
    let rec: Vec<Record> = PoseRecording::new(PoseRecordingConfig {
        sensors: *cfg,
        ..PoseRecordingConfig::default()
    })?
    .collect();
    Ok(calibrate(
        &rec,
        &CalibrationParams {
            gravity: cfg.g,
            ..CalibrationParams::default()
        },
    )?)
}

/// The walking trial of `seed` at the simulator's 100 Hz, calibrated when
/// `sensors` says so.
pub fn trial(seed: u64, speed: f64, sensors: Sensors) -> Result<Vec<Record>, Box<dyn Error>> {
    let cfg = walking_config(seed, speed, sensors);
    let cal = match sensors {
        Sensors::Calibrated | Sensors::CalibratedNoMisalignment => Some(calibrate_sensors(&cfg)?),
        _ => None,
    };
    Ok(WalkingSimulator::new(cfg)?
        .map(|mut r| {
            if let Some(c) = &cal {
                c.apply(&mut r);
            }
            r
        })
        .collect())
}

/// Mean 4-segment RMSE (deg) of mjls and global with default parameters
/// over the whole 100 Hz trial (the protocol of the issue-3 tables in
/// docs/RESULTS.md).
pub fn whole_trial_rmse_deg(records: &[Record]) -> Result<[f64; 2], Box<dyn Error>> {
    let m = mean_rmse_deg(&mut MarkovJumpKf::default(), records)?;
    let g = mean_rmse_deg(&mut GlobalKf::default(), records)?;
    Ok([m[0], g[0]])
}

/// [`trial`] resampled to 50 Hz as paper 001 did.
pub fn trial_at_50_hz(
    seed: u64,
    speed: f64,
    sensors: Sensors,
) -> Result<Vec<Record>, Box<dyn Error>> {
    resample_to_50_hz(&trial(seed, speed, sensors)?)
}

/// Resamples 100 Hz walking records to 50 Hz (windowed sinc, as `limbfuse resample --rate 50`).
pub fn resample_to_50_hz(records: &[Record]) -> Result<Vec<Record>, Box<dyn Error>> {
    let mut meta = TrialMeta::trial_v1();
    meta.set("sample_rate_hz", 100.0);
    let mut buf = Vec::new();
    {
        let mut w = TrialWriter::new(&mut buf, &meta, TrialLayout::walking())?;
        for r in records {
            w.write(r)?;
        }
        w.finish()?;
    }
    let reader = TrialReader::from_reader(
        std::path::Path::new("simulated.csv"),
        Box::new(std::io::Cursor::new(buf)),
    )?;
    Ok(resample_trial(reader, &ResampleOptions::new(50.0))?.records)
}

fn window(a: f64, b: f64) -> TimeWindow {
    TimeWindow {
        start: Some(a),
        end: Some(b),
    }
}

/// The figure of a filter on the validation block and the share of its
/// segment samples that were scored.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ValidationFigure {
    /// Mean 4-segment RMSE (deg), mean over the starts.
    pub rmse_deg: f64,
    /// Segment samples scored / segment samples with a reference (a run-in
    /// of `W` s leaves out `W / 10` of each 10 s run; a filter that keeps
    /// restarting leaves out more, issue 14).
    pub coverage: f64,
}

/// Mean 4-segment RMSE (deg) of `method` on the validation block 30-50 s
/// from 50 starts; parameters: the default preset with the run-in
/// `startup_s` (0 = the papers' filters), or that tuned on 10-30 s.
pub fn validation_rmse_deg(
    records: &[Record],
    method: FilterMethod,
    tune: Option<TuneConfig>,
    startup_s: f64,
) -> Result<f64, Box<dyn Error>> {
    Ok(validation_figure(records, method, tune, startup_s)?.rmse_deg)
}

/// [`validation_rmse_deg`] with the coverage of the figure.
pub fn validation_figure(
    records: &[Record],
    method: FilterMethod,
    tune: Option<TuneConfig>,
    startup_s: f64,
) -> Result<ValidationFigure, Box<dyn Error>> {
    let mut start = FilterParams::preset(method, Preset::Default);
    start.common_mut().startup_s = startup_s;
    let plan = |w| StartPlan {
        window: w,
        starts: 50,
        length_s: None,
    };
    let result = match tune {
        None => {
            let iv = plan_intervals(records, &plan(window(30.0, 50.0)))?;
            let make = || {
                start
                    .build()
                    .map(|f| f as Box<dyn Estimator>)
                    .map_err(|e| e.to_string())
            };
            multi_start(&make, records, &iv, false)?
        }
        Some(t) => {
            let cfg = TuneValidateConfig {
                start,
                plan: plan(window(10.0, 30.0)),
                validation: Validation::Window(window(30.0, 50.0)),
                tune: t,
            };
            let report = tune_and_validate(records, &cfg, &|| {})?;
            let [_, tuned] = report
                .validation_before_after
                .ok_or("the trial has no validation block 30-50 s")?;
            tuned
        }
    };
    let coverage = result.segment_coverage().unwrap_or(0.0);
    let rmse_deg = result.mean_rmse().map(f64::to_degrees).ok_or_else(|| {
        format!(
            "no segment sample scored on the validation block 30-50 s ({} of {} runs restarted)",
            result.runs.iter().filter(|e| e.resets.is_some()).count(),
            result.runs.len()
        )
    })?;
    Ok(ValidationFigure { rmse_deg, coverage })
}
