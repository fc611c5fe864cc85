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
//!   from fresh starts carry each filter's start-up transient (the first
//!   second after a start mid-stride), which no sensor calibration removes
//!   (docs/RESULTS.md, "Accelerometer calibration");
//! * with the filters' run-in `startup_s` = 2 s (one stride at 0.4 m/s: no
//!   estimate for the first 2 s of each run, the filter otherwise the
//!   papers'), the paper-001 protocol meets mjls <= 1.0 and global <= 1.2
//!   deg (`issue_14_...`; it fails with `RUN_IN_S = 0`, the papers' filters).
//!
//! The study with tuning and more seeds: `examples/calibration_study.rs`.

use limbfuse_methods::segment_params::FilterMethod;
use limbfuse_studies::calibration_study::{
    resample_to_50_hz, trial, validation_rmse_deg, whole_trial_rmse_deg, Sensors,
};

const SEEDS: u64 = 3;

/// The run-in of the issue-14 check (s): one stride at 0.4 m/s (the
/// simulator's cadence there is 60 steps/min, a 2 s stride); the
/// accelerometers are reliable around stance, once per stride, so a filter
/// started mid-stride needs about one stride of updates to converge.
const RUN_IN_S: f64 = 2.0;

/// Means over the seeds of [whole mjls, whole global, 001 mjls, 001 global,
/// 001 mjls with the run-in, 001 global with the run-in].
fn means(sensors: Sensors) -> [f64; 6] {
    let mut sum = [0.0; 6];
    for seed in 1..=SEEDS {
        let full = trial(seed, 0.4, sensors).unwrap();
        let [wm, wg] = whole_trial_rmse_deg(&full).unwrap();
        let r = resample_to_50_hz(&full).unwrap();
        let m = validation_rmse_deg(&r, FilterMethod::Mjls, None, 0.0).unwrap();
        let g = validation_rmse_deg(&r, FilterMethod::Global, None, 0.0).unwrap();
        let mr = validation_rmse_deg(&r, FilterMethod::Mjls, None, RUN_IN_S).unwrap();
        let gr = validation_rmse_deg(&r, FilterMethod::Global, None, RUN_IN_S).unwrap();
        println!("{sensors:?} seed {seed}: whole mjls {wm:.3} global {wg:.3}; 001 mjls {m:.3} global {g:.3}; 001 run-in mjls {mr:.3} global {gr:.3}");
        for (s, v) in sum.iter_mut().zip([wm, wg, m, g, mr, gr]) {
            *s += v;
        }
    }
    sum.map(|s| s / SEEDS as f64)
}

#[test]
fn issue_14_calibration_meets_the_targets_at_0_4_m_s() {
    let raw = means(Sensors::Raw);
    let cal = means(Sensors::CalibratedNoMisalignment);
    let bound = means(Sensors::NoStaticAccelError);
    println!("[whole mjls, whole global, 001 mjls, 001 global, 001 run-in mjls, 001 run-in global], mean of seeds 1-{SEEDS}:");
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
    // paper-001 protocol, the filters with the run-in
    assert!(cal[4] <= 1.0, "001 run-in mjls {:.3} deg > 1.0", cal[4]);
    assert!(cal[5] <= 1.2, "001 run-in global {:.3} deg > 1.2", cal[5]);
}
