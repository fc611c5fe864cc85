//! Issue 17 (`pyfast`): the segment filters write the gain of an update
//! straight into the one they keep (`last_gain`) instead of returning it by
//! value; a step that makes no update (predict only, every row refused by
//! the innovation gate, a restart) must still leave a zero gain, not the
//! previous step's. Checked on a simulated walk with a stretch of offset
//! encoders (gate refusals and the lockout restart) and dropped
//! accelerometers, for `mjls`, `global` and `local`.

use limbfuse_core::{Estimate, Estimator, Record};
use limbfuse_estimators::segment_kf::{GlobalKf, LocalKf, MarkovJumpKf};
use limbfuse_sim::{WalkingConfig, WalkingSimulator};

/// The walk, its encoders offset by 1.5 rad from 20 s to 24 s and the
/// accelerometers of every fifth sample dropped from 30 s to 33 s.
fn records() -> Vec<Record> {
    let sim = WalkingSimulator::new(WalkingConfig {
        seed: 17,
        ..WalkingConfig::default()
    })
    .expect("valid config");
    let mut records: Vec<Record> = sim.collect();
    for (k, r) in records.iter_mut().enumerate() {
        let t = r.sample.t;
        if (20.0..24.0).contains(&t) {
            for e in r.sample.encoder.iter_mut().flatten() {
                *e += 1.5;
            }
        }
        if (30.0..33.0).contains(&t) && k % 5 == 0 {
            for imu in r.sample.imu.iter_mut() {
                imu.acc = None;
            }
        }
    }
    records
}

/// Whether the estimate reports an updated row (`upd_*` = 1).
fn updated(names: &[&str], e: &Estimate) -> bool {
    names
        .iter()
        .zip(e.diag.iter())
        .any(|(n, v)| n.starts_with("upd_") && *v == Some(1.0))
}

fn check<E: Estimator>(name: &str, mut f: E, gain: impl Fn(&E) -> &[f64]) {
    let names: Vec<&str> = f.diagnostic_names().to_vec();
    let (mut with, mut without) = (0, 0);
    let mut est = Estimate::empty(0.0);
    for r in records() {
        f.step_into(&r.sample, &mut est).expect("valid sample");
        let k = gain(&f);
        let t = r.sample.t;
        if updated(&names, &est) {
            with += 1;
            assert!(
                k.iter().any(|v| *v != 0.0),
                "{name} t = {t}: an update, a zero gain"
            );
        } else {
            without += 1;
            assert!(
                k.iter().all(|v| *v == 0.0),
                "{name} t = {t}: no update, gain {k:?}"
            );
        }
    }
    assert!(
        with > 100 && without > 100,
        "{name}: {with} updates, {without} steps without"
    );
}

#[test]
fn issue_17_a_step_without_update_leaves_a_zero_gain() {
    check("mjls", MarkovJumpKf::default(), |f| {
        f.last_gain().as_slice()
    });
    check("global", GlobalKf::default(), |f| f.last_gain().as_slice());
    check("local", LocalKf::default(), |f| f.last_gain().as_slice());
}
