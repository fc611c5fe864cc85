//! Alignment on both legs (issue 14 item 1): simulated randomly mounted
//! sensors on the right and the left leg (the simulator's mirror-image leg,
//! same seed, same mountings), walking a path with 180 deg turns and
//! standing at both ends. Figures for docs/ALIGNMENT.md and docs/RESULTS.md:
//! `cargo test -p limbfuse-signal --test integration -- align_legs:: --nocapture`

use limbfuse_core::{Leg, Record, Segment};
use limbfuse_signal::align::{estimate_alignment, AlignOptions, Alignment};
use limbfuse_sim::{Motion, Mounting, Turns, WalkingConfig, WalkingSimulator};
use nalgebra::{Matrix3, Vector3};

fn config(seed: u64, speed: f64, leg: Leg, turn_deg: f64) -> WalkingConfig {
    WalkingConfig {
        seed,
        speed_mps: speed,
        duration_s: 30.0,
        mounting: Mounting::Random,
        leg,
        turns: Some(Turns {
            every_s: 10.0,
            duration_s: 2.5,
            angle_rad: turn_deg.to_radians(),
        }),
        ..Default::default()
    }
}

/// 3 s of quiet standing, the walk, 3 s of quiet standing (the standing
/// parts from the same sensors: same seed, so same mountings and biases).
fn trial(cfg: WalkingConfig) -> (Vec<Record>, [Matrix3<f64>; 4]) {
    let walk = WalkingSimulator::new(cfg).unwrap();
    let m = [0, 1, 2, 3].map(|i| walk.imus()[i].mount);
    let stand = |t0: f64| -> Vec<Record> {
        let s = WalkingSimulator::new(WalkingConfig {
            duration_s: 3.0,
            motion: Motion::Stand,
            turns: None,
            ..cfg
        })
        .unwrap();
        s.map(|mut r| {
            r.sample.t += t0;
            r
        })
        .collect()
    };
    let mut rec = stand(0.0);
    rec.extend(walk.map(|mut r| {
        r.sample.t += 3.0;
        r
    }));
    let end = rec.last().unwrap().sample.t + 0.01;
    rec.extend(stand(end));
    (rec, m)
}

/// Estimated z axis (raw coordinates) per segment.
fn axes(a: &Alignment) -> [Option<Vector3<f64>>; 4] {
    a.per_segment
        .map(|s| s.map(|s| s.rotation.into_inner().row(2).transpose()))
}

fn deg(a: &Vector3<f64>, b: &Vector3<f64>) -> f64 {
    a.dot(b).clamp(-1.0, 1.0).acos().to_degrees()
}

/// Per segment: max axis error vs truth (either leg) and max angle between
/// the left axis and the mirror image of the right one (deg).
fn survey(noise: bool, label: &str) -> ([f64; 4], [f64; 4]) {
    survey_spec(noise, label, limbfuse_sim::ImuSpec::default())
}

fn survey_spec(noise: bool, label: &str, spec: limbfuse_sim::ImuSpec) -> ([f64; 4], [f64; 4]) {
    let opts = AlignOptions {
        partial: true,
        ..Default::default()
    };
    let mut worst_between: [f64; 4] = [0.0; 4];
    let mut worst_truth: [f64; 4] = [0.0; 4];
    let mut sum = [[0.0f64; 3]; 4];
    let mut runs = [0.0f64; 4];
    println!("per run: segment axis error vs truth right/left, left vs mirror image of right (deg); leg detected (score)");
    for (seed, speed, turn) in [
        (0, 0.7, 180.0),
        (1, 1.2, -180.0),
        (2, 1.6, 180.0),
        (3, 1.0, -180.0),
    ] {
        let cfg = |leg| WalkingConfig {
            noise,
            imu: spec,
            ..config(seed, speed, leg, turn)
        };
        let (rec_r, m) = trial(cfg(Leg::Right));
        let (rec_l, m_l) = trial(cfg(Leg::Left));
        assert_eq!(m, m_l);
        let (a_r, a_l) = (
            estimate_alignment(&rec_r, &opts).unwrap(),
            estimate_alignment(&rec_l, &opts).unwrap(),
        );
        let mut line = format!(
            "  {label} seed {seed} {speed} m/s turns {turn:+} deg: turning {} / {} samples, quiet {:?}:",
            a_r.turning_samples, a_l.turning_samples, a_r.quiet
        );
        let (z_r, z_l) = (axes(&a_r), axes(&a_l));
        for s in Segment::ALL {
            let i = s.index();
            let (Some(zr), Some(zl)) = (z_r[i], z_l[i]) else {
                // The trunk's walking direction is unobservable at slow
                // speed (docs/ALIGNMENT.md); it must be skipped on both legs.
                assert!(
                    s == Segment::Trunk && speed < 1.0,
                    "seed {seed} {speed}: {} not aligned",
                    s.name()
                );
                assert!(z_r[i].is_none() && z_l[i].is_none());
                line += &format!(" {} skipped", s.name());
                continue;
            };
            let truth: Vector3<f64> = m[i].row(2).transpose();
            // In segment coordinates (`v_seg = M v_raw`) the left leg's
            // axis is the mirror image of the right's: `-S z_right`.
            let (seg_r, seg_l) = (m[i] * zr, m[i] * zl);
            let mirrored = -Vector3::new(seg_r.x, seg_r.y, -seg_r.z);
            let (er, el, between) = (deg(&zr, &truth), deg(&zl, &truth), deg(&seg_l, &mirrored));
            worst_between[i] = worst_between[i].max(between);
            worst_truth[i] = worst_truth[i].max(er).max(el);
            sum[i] = [sum[i][0] + er, sum[i][1] + el, sum[i][2] + between];
            runs[i] += 1.0;
            line += &format!(" {} {er:.2}/{el:.2}/{between:.2}", s.name());
        }
        let (lr, ll) = (a_r.leg.unwrap(), a_l.leg.unwrap());
        line += &format!(
            "; leg {:?} ({:+.2}) / {:?} ({:+.2})",
            lr.leg, lr.score, ll.leg, ll.score
        );
        println!("{line}");
        assert_eq!(lr.leg, Some(Leg::Right), "seed {seed}");
        assert_eq!(ll.leg, Some(Leg::Left), "seed {seed}");
        assert!(a_r.turning_samples > 400, "the turns are left out");
        assert!(a_r.quiet.is_some());
    }
    for s in Segment::ALL {
        let (i, n) = (s.index(), runs[s.index()]);
        println!(
            "{label} {:5}: axis error vs truth mean right {:.2} left {:.2}, max {:.2} deg; left vs mirrored right mean {:.2} max {:.2} deg ({n} runs)",
            s.name(),
            sum[i][0] / n,
            sum[i][1] / n,
            worst_truth[i],
            sum[i][2] / n,
            worst_between[i]
        );
    }
    (worst_truth, worst_between)
}

#[test]
fn both_legs_with_turns_and_standing_pick_the_same_axes() {
    let (truth, between) = survey(true, "sensor errors on");
    let (truth0, between0) = survey(false, "ideal sensors");
    // Issue 14: the same axes on both legs within 3 deg. The simulator's
    // consumer-MEMS errors are the same in the sensor frame on both legs,
    // not mirrored. Through the tracked vertical of the horizontal
    // projection the accelerometer bias alone moved the two legs' axes
    // apart by up to 4.3 deg (5.64 deg with every error); the gyro-only
    // axis (`gyro_axis_max_tilt_rad`, docs/ALIGNMENT.md "Both legs") leaves
    // the gyro's cross-axis errors: measured max 2.49 deg (trunk), 2.23
    // (thigh), 2.04 (shank), 1.35 (foot); ideal sensors <= 0.10 deg. Every
    // sign right (an error above 90 deg would be a flipped axis).
    for i in 0..4 {
        assert!(between0[i] < 0.2, "{i}: {}", between0[i]);
        assert!(between[i] < 3.0, "{i}: {}", between[i]);
        assert!(truth[i].max(truth0[i]) < 9.5, "{i}: {}", truth[i]);
    }
}
