//! Unit tests of the touchdown rules (paper-free hand computations).

use super::*;
use limbfuse_models::bslip::{BslipParams, GaitParameters, Side};

/// A gait whose touchdown height (`sin(1.2) cos(0.05)` = 0.931 m) lies
/// below the level CoM path of [`level_walk`] (0.96 m).
pub(super) fn template() -> GaitTemplate {
    let gait = GaitParameters {
        phi: 1.2,
        theta: 0.05,
        stiffness: 20_000.0,
        height: 0.96,
        lateral: 0.05,
        forward_speed: 0.6,
    };
    GaitTemplate {
        speed: 0.6,
        body: BslipParams::default(),
        gait,
        step_length: 0.5,
        step_width: 0.1,
        step_time: 0.8,
        t_touchdown: 0.295,
        t_lift_off: 0.45,
    }
}

/// Feeds a level CoM path at 0.6 m/s (no vertical motion, so no MS event
/// and no fall to the touchdown height) and returns, per sample, whether
/// the gait's leading foot has landed.
fn level_walk(rule: TouchdownRule) -> Vec<(f64, bool)> {
    let params = ImmBslipParams {
        touchdown: rule,
        ..ImmBslipParams::full_com()
    };
    let mut imm = ImmBslip::new(&[template()], params).unwrap();
    (0..40)
        .map(|k| {
            let t = k as f64 * 0.01;
            let mut s = Sample::empty(t);
            s.com.pos = [Some(0.6 * t), Some(0.96), Some(0.05)];
            s.com.vel = [Some(0.6), Some(0.0), None];
            imm.step(&s).unwrap();
            (t, imm.feet[0].landed.is_some())
        })
        .collect()
}

#[test]
fn step_clock_lands_the_foot_t_touchdown_after_the_start() {
    for (t, landed) in level_walk(TouchdownRule::StepClock) {
        assert_eq!(landed, t >= 0.295, "t = {t}");
    }
}

/// Paper-free check of the mixed rule against a hand computation: DS's
/// foot is `(w_DS stay ds + w_SS1 next swing) / (w_DS stay + w_SS1
/// next)`, SS2's `(w_SS2 stay ss2 + w_DS next ds) / (..)`.
#[test]
fn mixed_rule_blends_feet_by_the_weights_flowing_between_phases() {
    let t = template();
    let mut f = Feet::new(Side::Left);
    f.start(&t, [0.0, 0.05], 0.0, TouchdownRule::Mixed);
    assert_eq!(f.landed, Some(f.swinging));
    assert_eq!(f.ss2, Some(f.swinging));
    let (ds, ss2) = ([0.40, 0.10], [0.30, 0.12]);
    f.landed = Some(ds);
    f.ss2 = Some(ss2);
    let placement = FootPlacement {
        rule: TouchdownRule::Mixed,
        stay: 0.94,
        next: 0.05,
        mid_stance: MidStanceEvent::default(),
    };
    // Rising CoM: no MS.
    let x = State::new(0.1, 0.96, 0.05, 0.6, 0.1, 0.0);
    f.advance(&t, placement, &x, 0.2, 0.01, [0.6, 0.3, 0.1]);
    let (dx, dz) = t.gait.touchdown_offset(1.0, Side::Left);
    let swing = [0.1 + dx, 0.05 + dz];
    let (a, b) = (0.3 * 0.94, 0.6 * 0.05);
    let (c, d) = (0.1 * 0.94, 0.3 * 0.05);
    for i in 0..2 {
        let want_ds = (a * ds[i] + b * swing[i]) / (a + b);
        let want_ss2 = (c * ss2[i] + d * ds[i]) / (c + d);
        assert!((f.landed.unwrap()[i] - want_ds).abs() < 1e-15);
        assert!((f.ss2.unwrap()[i] - want_ss2).abs() < 1e-15);
    }
    assert_eq!(f.stance[1], 0.05 - Side::Left.sign() * t.gait.lateral);
    // The apex near SS2's foot is MS: SS2's foot becomes the stance foot.
    let ms = f.ss2.unwrap();
    let x = State::new(ms[0], 0.96, 0.05, 0.6, -0.01, 0.0);
    f.advance(&t, placement, &x, 0.01, 0.02, [0.0, 0.1, 0.9]);
    assert_eq!(f.side, Side::Right);
    assert_eq!(f.ms_t, 0.02);
    assert!((f.stance[0] - ms[0]).abs() < 0.05);
    assert_eq!(f.landed, Some(f.swinging));
}

#[test]
fn height_rule_waits_for_the_com_to_fall_to_the_touchdown_height() {
    assert!(template().gait.touchdown_height(1.0) < 0.96);
    assert!(level_walk(TouchdownRule::Height).iter().all(|&(_, l)| !l));
}

/// The MS event variants on one hand-placed case: the leading foot down at
/// x = 1.0, l0 = 1 m (BslipParams::default's rest length checked below).
#[test]
fn mid_stance_event_variants_fire_where_documented() {
    let t = template();
    assert!((t.body.rest_length - 1.0).abs() < 0.1);
    let fires = |mid_stance, com_x: f64, previous_vy: f64, vy: f64| {
        let mut f = Feet::new(Side::Left);
        f.start(&t, [0.0, 0.05], 0.0, TouchdownRule::Height);
        f.landed = Some([1.0, 0.1]);
        let placement = FootPlacement {
            rule: TouchdownRule::Height,
            stay: 0.94,
            next: 0.05,
            mid_stance,
        };
        let x = State::new(com_x, 0.96, 0.05, 0.6, vy, 0.0);
        f.advance(&t, placement, &x, previous_vy, 0.5, [0.0, 0.5, 0.5]);
        f.side == Side::Right
    };
    let l0 = t.body.rest_length;
    let default = MidStanceEvent::default();
    let tight = MidStanceEvent::ApexNearFoot { within: 0.05 };
    let past = MidStanceEvent::PastFootAndApex;
    // Apex 0.08 l0 behind the foot: the default guard (0.1 l0) fires, 0.05 does not.
    let behind = 1.0 - 0.08 * l0;
    assert!(fires(default, behind, 0.01, -0.01));
    assert!(!fires(tight, behind, 0.01, -0.01));
    assert!(!fires(past, behind, 0.01, -0.01));
    // Past the foot, already falling for a while (no zero crossing now):
    // only PastFootAndApex fires.
    assert!(!fires(default, 1.02, -0.01, -0.02));
    assert!(fires(past, 1.02, -0.01, -0.02));
    // Past the foot, still rising: none.
    assert!(!fires(past, 1.02, 0.02, 0.01));
    assert!(ImmBslipParams {
        mid_stance: MidStanceEvent::ApexNearFoot { within: -0.1 },
        ..ImmBslipParams::full_com()
    }
    .validate()
    .is_err());
}
