//! Regression (issue 14 item 3): mjls and global at 0.4 m/s on
//! accelerometers calibrated by `calibrate` from the simulated pose
//! recording of the same sensors (mounting misalignment 0, which no
//! calibration can observe), seeds 1-3:
//! * the calibration removes the static accelerometer error: it gets at
//!   least 80 % of the gain of sensors with no static accelerometer error
//!   at all (the rest is the rotation part of the cross-axis terms, which
//!   no static calibration observes), under both protocols below;
//! * the issue-3 protocol (whole 60 s trial, 100 Hz, default parameters)
//!   meets mjls <= 1.0 deg and global <= 1.2 deg;
//! * the paper-001 protocol (50 Hz, validation block 30-50 s from 50
//!   starts, default parameters) is printed, with its floor: its 10 s runs
//!   from fresh starts carry each filter's start-up, which no sensor
//!   calibration removes (docs/RESULTS.md, "Accelerometer calibration").
//!
//! The study with tuning and more seeds: `examples/calibration_study.rs`.

use limbfuse_methods::segment_params::FilterMethod;
use limbfuse_studies::calibration_study::{
    resample_to_50_hz, trial, validation_rmse_deg, whole_trial_rmse_deg, Sensors,
};

const SEEDS: u64 = 3;

/// Means over the seeds of [whole mjls, whole global, 001 mjls, 001 global].
fn means(sensors: Sensors) -> [f64; 4] {
    let mut sum = [0.0; 4];
    for seed in 1..=SEEDS {
        let full = trial(seed, 0.4, sensors).unwrap();
        let [wm, wg] = whole_trial_rmse_deg(&full).unwrap();
        let r = resample_to_50_hz(&full).unwrap();
        let m = validation_rmse_deg(&r, FilterMethod::Mjls, None).unwrap();
        let g = validation_rmse_deg(&r, FilterMethod::Global, None).unwrap();
        println!("{sensors:?} seed {seed}: whole mjls {wm:.3} global {wg:.3}; 001 mjls {m:.3} global {g:.3}");
        for (s, v) in sum.iter_mut().zip([wm, wg, m, g]) {
            *s += v;
        }
    }
    sum.map(|s| s / SEEDS as f64)
}

#[test]
fn calibration_removes_the_static_error_and_meets_the_targets_at_0_4_m_s() {
    let raw = means(Sensors::Raw);
    let cal = means(Sensors::CalibratedNoMisalignment);
    let bound = means(Sensors::NoStaticAccelError);
    println!("[whole mjls, whole global, 001 mjls, 001 global], mean of seeds 1-{SEEDS}:");
    println!(
        "raw {raw:.3?}\ncalibrated, misalignment 0 {cal:.3?}\nno static accel error {bound:.3?}"
    );
    for k in 0..4 {
        // Share of the gain of error-free static accelerometers that the
        // calibration gets (what it cannot get: the rotation part of the
        // cross-axis terms, which no static calibration observes).
        let share = (raw[k] - cal[k]) / (raw[k] - bound[k]);
        println!(
            "column {k}: calibration gets {:.0} % of the gain",
            share * 100.0
        );
        assert!(share >= 0.8, "{k}: {raw:?} -> {cal:?}, bound {bound:?}");
    }
    assert!(cal[0] <= 1.0, "whole-trial mjls {:.3} deg > 1.0", cal[0]);
    assert!(cal[1] <= 1.2, "whole-trial global {:.3} deg > 1.2", cal[1]);
}
