//! Re-mounting test of paper 002 section 3.6: after the thigh sensor is
//! turned by 50 deg about the thigh's long axis, the self-aligning knee
//! estimator re-identifies the axes and its 2 s sliding RMSE (about its own
//! pre-event zero) returns below 2 deg.

use limbfuse_estimators::knee_selfalign::KneeSelfAlignParams;
use limbfuse_sim::Remount;
use limbfuse_studies::knee_study::{mean_error, recovery_time, run, simulate, sliding_rmse};

#[test]
fn recovers_after_a_50_deg_thigh_remount() {
    let event = 20.0;
    let records = simulate(
        1,
        40.0,
        0.0,
        Some(Remount {
            t_s: event,
            angle_rad: 50f64.to_radians(),
        }),
    )
    .unwrap();
    let r = run(
        &records,
        KneeSelfAlignParams {
            window: 200,
            ..KneeSelfAlignParams::default()
        },
    )
    .unwrap();
    let before = mean_error(&r.errors, 5.0, event);
    let sliding = sliding_rmse(&r.errors, 2.0, before);
    // Quality before the event is good ...
    let worst_before = sliding
        .iter()
        .filter(|(t, _)| *t > 7.0 && *t < event)
        .map(|x| x.1)
        .fold(0.0, f64::max);
    assert!(
        worst_before < 2f64.to_radians(),
        "{}",
        worst_before.to_degrees()
    );
    // ... the event spoils it ...
    let peak = sliding
        .iter()
        .filter(|(t, _)| *t >= event)
        .map(|x| x.1)
        .fold(0.0, f64::max);
    assert!(peak > 4f64.to_radians(), "{}", peak.to_degrees());
    // ... and it comes back (measured: 6.43 s, peak 9.4 deg; the study in
    // docs/RESULTS.md gives 6.1-7.6 s for s_w = 200 over 10 seeds).
    let rec = recovery_time(&sliding, event, 2.0, 2f64.to_radians()).expect("recovers");
    eprintln!("recovery {rec:.2} s, peak {:.2} deg", peak.to_degrees());
    assert!(rec < 9.0, "recovery {rec} s");
}
