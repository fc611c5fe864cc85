//! `tune_torque_error` (`limbfuse tune --method sdre|ekf`, Python `tune`):
//! a cancelled tuning stops inside the candidates' runs, not only between
//! candidates (session 45: a candidate takes up to 15 s on an hour), and
//! the candidates run in parallel with the result of one thread.

use std::cell::Cell;
use std::path::Path;
use std::sync::atomic::{AtomicUsize, Ordering};

use limbfuse_core::Record;
use limbfuse_methods::fes_params::FesParamsFile;
use limbfuse_methods::{MethodFlags, MethodName, MethodSpec};
use limbfuse_sim::knee_fes::KneeFesConfig;
use limbfuse_workflows::fes_pulse_cv::{pulse_windows, window_errors, window_errors_until};
use limbfuse_workflows::fes_torque_tuning::{tune_torque_error, TorqueTuning, TorqueTuningError};
use limbfuse_workflows::simulated_trials::{knee_fes, SimulatedTrial};

const EXTENDED: &str = "[states]\nactivation = true\ngyro_bias = true\nacc_bias = true\n";

fn now() -> bool {
    true
}

/// The pre-trial of `seconds` and the extended model.
fn pre_trial(seconds: f64) -> (SimulatedTrial<Vec<Record>>, FesParamsFile) {
    let cfg = KneeFesConfig {
        duration_s: seconds,
        ..KneeFesConfig::default()
    };
    let t = knee_fes(&cfg, "test").unwrap();
    let trial = SimulatedTrial {
        meta: t.meta,
        layout: t.layout,
        records: t.records.collect(),
    };
    let spec = MethodSpec::from_parts(
        MethodName::Sdre,
        Some((EXTENDED, Path::new("<test>"))),
        &MethodFlags::default(),
    )
    .unwrap();
    let MethodSpec::Sdre(file) = spec else {
        panic!("not sdre")
    };
    (trial, file)
}

fn tune(
    (trial, file): &(SimulatedTrial<Vec<Record>>, FesParamsFile),
    on_candidate: &(dyn Fn() + Sync),
    cancel: Option<&dyn Fn() -> bool>,
) -> Result<TorqueTuning, TorqueTuningError> {
    let trial_settings = (&trial.meta, &trial.layout);
    let (records, window) = (&trial.records[..], "the test window");
    tune_torque_error(
        MethodName::Sdre,
        file,
        trial_settings,
        records,
        window,
        on_candidate,
        cancel,
    )
}

#[test]
fn a_cancelled_tuning_stops_inside_the_first_candidate() {
    // (1800 s: the quickest candidate takes about 0.27 s here, the flag is
    // raised at the first question, 50 ms in)
    let long = pre_trial(1800.0);
    let done = AtomicUsize::new(0);
    let count = || {
        done.fetch_add(1, Ordering::Relaxed);
    };
    let r = tune(&long, &count, Some(&now));
    assert!(matches!(r, Err(TorqueTuningError::Cancelled)), "{r:?}");
    // (checked only between candidates, the two running would have finished)
    assert_eq!(done.load(Ordering::Relaxed), 0);
}

#[test]
fn the_candidates_in_parallel_give_the_result_of_one_thread() {
    let short = pre_trial(60.0);
    let parallel = tune(&short, &|| (), None).unwrap();
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(1)
        .build()
        .unwrap();
    let one = pool.install(|| tune(&short, &|| (), None)).unwrap();
    assert_eq!(parallel, one);
    assert_eq!(parallel.rmse_deg.len(), 7);
    assert!(parallel.rmse_deg.iter().any(|e| e.is_finite()) && parallel.cv_rmse_deg.is_finite());
}

/// The stop check inside a candidate's run: asked every 4096 samples, the
/// run ends at the first yes; never stopped, it is `window_errors`.
#[test]
fn a_candidate_run_stops_at_its_stop_check() {
    let (trial, file) = pre_trial(120.0);
    let starts = pulse_windows(&trial.records);
    let build = || {
        limbfuse_methods::build(&MethodSpec::Sdre(file.clone()), &trial.meta, &trial.layout)
            .unwrap()
    };
    let asked = Cell::new(0);
    let second = || {
        asked.set(asked.get() + 1);
        asked.get() >= 2
    };
    assert!(window_errors_until(build().as_mut(), &trial.records, &starts, &second).is_none());
    assert_eq!(asked.get(), 2);
    let whole = window_errors(build().as_mut(), &trial.records, &starts);
    let never = window_errors_until(build().as_mut(), &trial.records, &starts, &|| false);
    assert_eq!(never, Some(whole));
}
