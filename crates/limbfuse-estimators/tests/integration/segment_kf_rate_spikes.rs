//! The paper filters' gyroscope spikes told from the encoders
//! (`segment_kf::rate_spikes`, ours; docs/ROBUST_INPUT.md, "Gyroscope spikes
//! beside the encoders"; issue 18, glitches). A single-sample spike within
//! the sensor gate's range and jump bound moved the segment's integrated
//! angle; `mjls`'s encoder rows, trusted little, hardly corrected it at the
//! spike and then refused the encoder that contradicted it until the 0.5 s
//! lockout restarted the filter (the shared independent 1.2 m/s walk with
//! sixty +-3 rad/s spikes: seven restarts, knee 0.086 -> 0.963 deg RMSE).
//! Now a thigh or shank reading is replaced by the rate the encoders imply,
//! a trunk or foot reading held (their pattern is also an encoder glitch's).

use limbfuse_core::{Estimator, Record};
use limbfuse_estimators::segment_kf::params::CommonParams;
use limbfuse_estimators::segment_kf::{GlobalKf, GlobalKfParams, MarkovJumpKf, MarkovJumpKfParams};

use crate::chain_gyro_gate::{spiked, spikes, walk};

/// `mjls` or `global` with the spike test on or off.
fn filter(mjls: bool, rate_spike_test: bool) -> Box<dyn Estimator> {
    let common = CommonParams {
        rate_spike_test,
        ..CommonParams::default()
    };
    if mjls {
        Box::new(
            MarkovJumpKf::new(MarkovJumpKfParams {
                common,
                ..Default::default()
            })
            .unwrap(),
        )
    } else {
        Box::new(
            GlobalKf::new(GlobalKfParams {
                common,
                ..Default::default()
            })
            .unwrap(),
        )
    }
}

/// Every sample's four segment and three joint angles (NaN where none),
/// the readings rejected and the restarts (`diag_resets`, last sample).
fn run(records: &[Record], mut f: Box<dyn Estimator>) -> (Vec<[f64; 7]>, [u64; 3], f64) {
    let mut resets = 0.0;
    let angles = records
        .iter()
        .map(|r| {
            let e = f.step(&r.sample).unwrap();
            let at = f
                .diagnostic_names()
                .iter()
                .position(|n| *n == "resets")
                .expect("the segment filters report their restarts");
            resets = e.diag[at].unwrap_or(f64::NAN);
            core::array::from_fn(|k| {
                if k < 4 { e.segment[k] } else { e.joint[k - 4] }.unwrap_or(f64::NAN)
            })
        })
        .collect();
    (angles, f.rejected_readings(), resets)
}

/// Largest difference (deg) of any angle between two runs from sample `from`
/// (infinite where one run has an estimate and the other none).
fn largest_difference(a: &[[f64; 7]], b: &[[f64; 7]], from: usize) -> f64 {
    a[from..]
        .iter()
        .zip(&b[from..])
        .flat_map(|(x, y)| x.iter().zip(y))
        .map(|(p, q)| match (p.is_nan(), q.is_nan()) {
            (true, true) => 0.0,
            (false, false) => (p - q).abs().to_degrees(),
            _ => f64::INFINITY, // an estimate in one run only
        })
        .fold(0.0, f64::max)
}

#[test]
fn issue_18_paper_filters_replace_a_gyro_spike_the_encoders_contradict() {
    let clean = walk();
    let noisy = spiked(&clean);
    let from = spikes(&clean)[0].0;
    for mjls in [true, false] {
        let name = if mjls { "mjls" } else { "global" };
        let (reference, rejected, resets) = run(&clean, filter(mjls, true));
        assert_eq!(
            rejected[0], 0,
            "{name}: a clean walk refuses no gyroscope reading"
        );
        assert_eq!(resets, 0.0, "{name}");
        let (off, _, resets_off) = run(&clean, filter(mjls, false));
        assert_eq!(
            largest_difference(&off, &reference, 0),
            0.0,
            "{name}: on a clean walk the test changes nothing"
        );
        assert_eq!(resets_off, 0.0);
        let (now, rejected, resets) = run(&noisy, filter(mjls, true));
        let (before, _, resets_before) = run(&noisy, filter(mjls, false));
        let now_off = largest_difference(&now, &reference, from);
        let before_off = largest_difference(&before, &reference, from);
        eprintln!(
            "{name}: largest angle difference from the clean run {before_off:.3} deg without the \
             test ({resets_before} restarts), {now_off:.3} deg with it ({resets} restarts, \
             rejected {rejected:?})"
        );
        assert_eq!(
            rejected,
            [8, 0, 0],
            "{name}: every spike refused, nothing else"
        );
        assert_eq!(resets, 0.0, "{name}");
        assert!(
            before_off > 1.0,
            "{name}: the spikes must matter without the test"
        );
        assert!(now_off < 0.15, "{name}: {now_off} deg");
    }
}

#[test]
fn a_trunk_spike_and_a_lone_knee_encoder_glitch() {
    let clean = walk();
    let at = spikes(&clean)[0].0;
    let (reference, _, _) = run(&clean, filter(true, true));
    // a trunk spike: the hip residual alone
    let mut trunk = clean.clone();
    trunk[at].sample.imu[0].gyr.as_mut().unwrap().z -= 3.0;
    let (angles, rejected, resets) = run(&trunk, filter(true, true));
    assert_eq!(rejected[0], 1);
    assert_eq!(resets, 0.0);
    let off = largest_difference(&angles, &reference, at);
    assert!(off < 0.1, "trunk spike: {off} deg");
    // a knee encoder glitch of 0.05 rad: the knee residual alone, which no
    // one segment's spike explains, so no gyroscope reading is refused
    let mut knee = clean.clone();
    *knee[at].sample.encoder[1].as_mut().unwrap() += 0.05;
    let (_, rejected, _) = run(&knee, filter(true, true));
    assert_eq!(rejected[0], 0, "{rejected:?}");
}

#[test]
fn an_end_joints_encoder_step_does_not_turn_the_end_segment() {
    // the hip (or ankle) encoder re-zeroed by 0.3 rad: for one sample its
    // rate is 30 rad/s, the trunk's (foot's) spike pattern; the segment's
    // own gyroscope is right, so it must not take the encoder's rate
    let clean = walk();
    let at = spikes(&clean)[0].0;
    for (joint, segment) in [(0, 0), (2, 3)] {
        let mut stepped = clean.clone();
        for r in &mut stepped[at..] {
            *r.sample.encoder[joint].as_mut().unwrap() += 0.3;
        }
        for mjls in [true, false] {
            let (on, _, _) = run(&stepped, filter(mjls, true));
            let (off, _, _) = run(&stepped, filter(mjls, false));
            let moved = on[at..]
                .iter()
                .zip(&off[at..])
                .map(|(a, b)| (a[segment] - b[segment]).abs().to_degrees())
                .fold(0.0, f64::max);
            eprintln!(
                "joint {joint}, mjls {mjls}: segment {segment} moved {moved:.3} deg by the test"
            );
            assert!(moved < 0.1, "joint {joint}, mjls {mjls}: {moved} deg");
        }
    }
}
