//! `tune_torque_error` (`limbfuse tune --method sdre|ekf`, Python `tune`):
//! the cancellation hook is asked inside a candidate's run, not only
//! between candidates (session 45: a candidate takes up to 15 s on an hour).

use std::path::Path;
use std::sync::atomic::{AtomicUsize, Ordering};

use limbfuse_methods::{MethodFlags, MethodName, MethodSpec};
use limbfuse_sim::knee_fes::KneeFesConfig;
use limbfuse_workflows::fes_torque_tuning::{tune_torque_error, TorqueTuningError};
use limbfuse_workflows::simulated_trials::knee_fes;

const EXTENDED: &str = "[states]\nactivation = true\ngyro_bias = true\nacc_bias = true\n";

static ASKED: AtomicUsize = AtomicUsize::new(0);

/// No on its first call (before the first candidate), yes after.
fn stop_after_the_first_question() -> bool {
    ASKED.fetch_add(1, Ordering::Relaxed) > 0
}

#[test]
fn a_cancelled_tuning_stops_inside_the_first_candidate() {
    let cfg = KneeFesConfig {
        duration_s: 120.0,
        ..KneeFesConfig::default()
    };
    let trial = knee_fes(&cfg, "test").unwrap();
    let records: Vec<_> = trial.records.collect();
    assert!(records.len() > 2 * 4096);
    let spec = MethodSpec::from_parts(
        MethodName::Sdre,
        Some((EXTENDED, Path::new("<test>"))),
        &MethodFlags::default(),
    )
    .unwrap();
    let MethodSpec::Sdre(file) = spec else {
        panic!("not sdre")
    };
    let tune = |on_candidate: &dyn Fn(), cancel: Option<fn() -> bool>| {
        let window = "the test window";
        let trial_settings = (&trial.meta, &trial.layout);
        tune_torque_error(
            MethodName::Sdre,
            &file,
            trial_settings,
            &records,
            window,
            on_candidate,
            cancel,
        )
    };
    let done = AtomicUsize::new(0);
    let count = || {
        done.fetch_add(1, Ordering::Relaxed);
    };
    let r = tune(&count, Some(stop_after_the_first_question));
    assert!(matches!(r, Err(TorqueTuningError::Cancelled)), "{r:?}");
    // (asked between candidates only, the first would have finished)
    assert_eq!(done.load(Ordering::Relaxed), 0);
    assert_eq!(ASKED.load(Ordering::Relaxed), 2);
    // Without a hook it tunes.
    let r = tune(&|| (), None).unwrap();
    assert_eq!(r.rmse_deg.len(), 7);
    assert!(r.rmse_deg.iter().any(|e| e.is_finite()) && r.cv_rmse_deg.is_finite());
}
