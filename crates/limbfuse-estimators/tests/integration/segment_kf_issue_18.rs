//! Issue 18 in the segment filters: the encoder innovation gate, the
//! restart after encoder rows refused for `GATE_LOCKOUT_S`, and the restart
//! after a long time gap, each counted (`rejected_readings`, `resets`).

use crate::segment_kf_support::{Rng, StaticLimb};
use limbfuse_core::{Estimate, Estimator};
use limbfuse_estimators::segment_kf::robust::{GATE_LOCKOUT_S, LONG_GAP_S};
use limbfuse_estimators::segment_kf::{LocalDiag, LocalKf, MarkovJumpKf, MjlsDiag, SegmentDiag};

fn limb(seed: u64) -> StaticLimb {
    StaticLimb {
        theta: [0.05, 0.3, -0.2, 0.1],
        gyro_bias: [0.01, -0.02, 0.015, 0.0],
        gyro_density: 0.005,
        acc_sigma: 0.03,
        enc_sigma: 1e-3,
        dt: 0.01,
        rng: Rng::new(seed),
    }
}

fn resets_mjls(e: &Estimate) -> f64 {
    e.diag[MjlsDiag::from(SegmentDiag::Resets).index()].unwrap()
}

#[test]
fn issue_18_an_encoder_glitch_within_range_is_refused_and_counted() {
    let (mut clean, mut glitched) = (MarkovJumpKf::default(), MarkovJumpKf::default());
    let (mut a, mut b) = (limb(7), limb(7));
    let (mut ea, mut eb) = (None, None);
    for k in 0..400 {
        let s = a.sample(k);
        let mut g = b.sample(k);
        if k == 200 {
            // one knee reading 1 rad off: within +-180 deg, so the range gate passes it
            g.encoder[1] = Some(g.encoder[1].unwrap() + 1.0);
        }
        ea = Some(clean.step(&s).unwrap());
        eb = Some(glitched.step(&g).unwrap());
    }
    assert_eq!(clean.rejected_readings(), [0, 0, 0]);
    assert_eq!(glitched.rejected_readings(), [0, 0, 1]);
    let (ea, eb) = (ea.unwrap(), eb.unwrap());
    for i in 0..4 {
        let d = (ea.segment[i].unwrap() - eb.segment[i].unwrap()).abs();
        assert!(d < 1e-3, "segment {i} moved {d} rad");
    }
    assert_eq!(resets_mjls(&eb), 0.0);
}

#[test]
fn issue_18_encoders_refused_for_the_lockout_time_restart_the_filter() {
    let mut f = MarkovJumpKf::default();
    let mut l = limb(11);
    let n0 = 200;
    let mut last = None;
    let mut first_reset = None;
    for k in 0..600 {
        let mut s = l.sample(k);
        if k >= n0 {
            // the knee encoder re-zeroed by 0.6 rad: the filter's chain now
            // disagrees with it on every sample
            s.encoder[1] = Some(s.encoder[1].unwrap() + 0.6);
        }
        let e = f.step(&s).unwrap();
        if resets_mjls(&e) > 0.0 && first_reset.is_none() {
            first_reset = Some(k);
        }
        last = Some((e, s));
    }
    let k = first_reset.expect("a restart");
    let lockout = (GATE_LOCKOUT_S / 0.01).round() as usize;
    assert!(
        (n0 + lockout..=n0 + lockout + 1).contains(&k),
        "restart at sample {k}"
    );
    // after the restart the chain follows the (new) encoders
    let (e, s) = last.unwrap();
    let knee = e.segment[1].unwrap() - e.segment[2].unwrap();
    assert!((knee - s.encoder[1].unwrap()).abs() < 0.02, "{knee}");
    assert!(f.rejected_readings()[2] >= lockout as u64);
}

#[test]
fn issue_18_a_long_time_gap_restarts_from_the_data_after_it() {
    let mut f = LocalKf::default();
    let mut l = limb(3);
    let idx = LocalDiag::from(SegmentDiag::Resets).index();
    let mut est = None;
    for k in 0..300 {
        let mut s = l.sample(k);
        if k >= 150 {
            s.t += LONG_GAP_S + 0.5;
        }
        let e = f.step(&s).unwrap();
        assert_eq!(e.diag[idx], Some(if k >= 150 { 1.0 } else { 0.0 }), "{k}");
        est = Some(e);
    }
    let e = est.unwrap();
    for i in 0..4 {
        assert!(
            (e.segment[i].unwrap() - l.theta[i]).abs() < 0.02,
            "segment {i}"
        );
    }
    // a gap just under the limit does not restart
    let mut f = LocalKf::default();
    let mut l = limb(3);
    for k in 0..300 {
        let mut s = l.sample(k);
        if k >= 150 {
            s.t += LONG_GAP_S - 0.02;
        }
        assert_eq!(f.step(&s).unwrap().diag[idx], Some(0.0));
    }
}
