//! Physics checks of the walking simulator. Run with `--nocapture` to see the
//! measured figures quoted in docs/SIMULATOR.md:
//! `CARGO_TARGET_DIR=/work/target-sim cargo test -p limbfuse-sim --test integration -- physics:: --nocapture`

use core::f64::consts::TAU;

use limbfuse_core::Segment;
use limbfuse_sim::{Motion, Mounting, Variability, WalkingConfig, WalkingSimulator};
use nalgebra::{Matrix3, Vector3};

fn ideal(speed: f64) -> WalkingConfig {
    WalkingConfig {
        speed_mps: speed,
        noise: false,
        out_of_plane: false,
        variability: None,
        ..Default::default()
    }
}

/// Trapezoidal integration of the simulated gyro z at 100 Hz over 60 s
/// (noise off, aligned mounting, planar motion, variability on) reproduces the
/// reference segment angles.
#[test]
fn integrated_gyro_z_reproduces_reference_angles() {
    for speed in [0.4, 1.0, 1.8] {
        let cfg = WalkingConfig {
            variability: Some(Variability::default()),
            ..ideal(speed)
        };
        let sim = WalkingSimulator::new(cfg).unwrap();
        let mut theta = [0.0; 4];
        let mut prev: Option<([f64; 4], f64)> = None;
        let mut worst: f64 = 0.0;
        for r in sim {
            let w: Vec<f64> = r.sample.imu.iter().map(|i| i.gyr.unwrap().z).collect();
            let reference: Vec<f64> = r.reference.segment.iter().map(|s| s.unwrap()).collect();
            match prev {
                None => theta.copy_from_slice(&reference),
                Some((wp, tp)) => {
                    let dt = r.sample.t - tp;
                    for i in 0..4 {
                        theta[i] += 0.5 * dt * (w[i] + wp[i]);
                        worst = worst.max((theta[i] - reference[i]).abs());
                    }
                }
            }
            prev = Some(([w[0], w[1], w[2], w[3]], r.sample.t));
        }
        println!(
            "gyro-z trapezoid @100 Hz over 60 s, {speed} m/s: max |theta_int - theta_ref| = {:.4} deg",
            worst.to_degrees()
        );
        assert!(worst.to_degrees() < 0.25, "{}", worst.to_degrees());
    }
}

/// Upright standing: every aligned accelerometer reads (0, +g, 0) and every
/// gyro reads 0; a held walking pose reads g rotated, and
/// atan2(acc_x, acc_y) gives the segment angle (SPEC section 1).
#[test]
fn static_accelerometers_read_gravity() {
    let cfg = WalkingConfig {
        motion: Motion::Stand,
        duration_s: 1.0,
        ..ideal(1.0)
    };
    for r in WalkingSimulator::new(cfg).unwrap() {
        for imu in r.sample.imu {
            assert!((imu.acc.unwrap() - Vector3::new(0.0, 9.81, 0.0)).norm() < 1e-12);
            assert!(imu.gyr.unwrap().norm() < 1e-12);
        }
        assert!(r.reference.segment.iter().all(|s| *s == Some(0.0)));
    }
    for phase in [0.3, 2.0, 4.5] {
        let cfg = WalkingConfig {
            motion: Motion::Pose { phase },
            duration_s: 0.5,
            ..ideal(1.2)
        };
        for r in WalkingSimulator::new(cfg).unwrap() {
            for (i, imu) in r.sample.imu.iter().enumerate() {
                let a = imu.acc.unwrap();
                assert!((a.norm() - 9.81).abs() < 1e-9);
                assert!(imu.gyr.unwrap().norm() < 1e-12);
                let th = a.x.atan2(a.y);
                assert!((th - r.reference.segment[i].unwrap()).abs() < 1e-12);
            }
        }
    }
}

fn skew_inv(m: &Matrix3<f64>) -> Vector3<f64> {
    Vector3::new(
        m[(2, 1)] - m[(1, 2)],
        m[(0, 2)] - m[(2, 0)],
        m[(1, 0)] - m[(0, 1)],
    ) * 0.5
}

/// The analytic specific force equals a numerical second derivative of the
/// sensor's world position plus gravity, rotated into the sensor frame; the
/// analytic angular rate equals the numerical derivative of the orientation.
/// Full 3D motion, random mountings, variability on.
#[test]
fn specific_force_matches_numerical_second_derivative_of_position() {
    let cfg = WalkingConfig {
        mounting: Mounting::Random,
        out_of_plane: true,
        variability: Some(Variability::default()),
        speed_mps: 1.6,
        seed: 11,
        ..ideal(1.6)
    };
    specific_force_and_rate_match_finite_differences(cfg, 0.137, 0.1493, 400);
}

/// The same on the mirrored left leg walking a path with turns both ways
/// (`limbfuse_sim::body_path`): the turned positions are integrated, the
/// readings analytic; the turns cover 2.5 of every 6 s of the sampled times.
#[test]
fn left_leg_with_turns_matches_finite_differences() {
    for angle in [180f64, -120.0] {
        let cfg = WalkingConfig {
            mounting: Mounting::Random,
            out_of_plane: true,
            variability: Some(Variability::default()),
            seed: 12,
            leg: limbfuse_core::Leg::Left,
            turns: Some(limbfuse_sim::Turns {
                every_s: 6.0,
                duration_s: 2.5,
                angle_rad: angle.to_radians(),
            }),
            duration_s: 12.0,
            ..ideal(1.2)
        };
        // Around the first turn (6.0-8.5 s) and the straight walking either side.
        specific_force_and_rate_match_finite_differences(cfg, 5.51, 0.0931, 40);
        let sim = WalkingSimulator::new(cfg).unwrap();
        // The leg turns in the swings of the simulated leg whose toe off
        // falls in 6.0-8.5 s; mid-swing the thigh's heading rate is 1.875
        // times the swing's share over its duration (smoothstep peak). The
        // trunk turns each share over the stride around its swing.
        let swings: Vec<_> = sim.turn_schedule().turning_swings().collect();
        let first: Vec<_> = swings.iter().filter(|s| s.0 < 8.5).collect();
        assert!(first.len() >= 2 && first[0].0 >= 6.0, "{swings:?}");
        for (a, b) in &first {
            let mid = sim.truth(0.5 * (a + b)).frames[1].w.y;
            let expect = 1.875 * angle.to_radians() / first.len() as f64 / (b - a);
            assert!((mid - expect).abs() < 0.6, "{mid} vs {expect}");
        }
        let (a, b) = first[0];
        let mid = sim.truth(0.5 * (a + b)).frames[0].w.y;
        let expect = 1.875 * angle.to_radians() / first.len() as f64 / ((b - a) / 0.4);
        assert!((mid - expect).abs() < 0.6, "{mid} vs {expect}");
        assert!(sim.truth(4.0).frames[0].w.y.abs() < 0.6);
    }
}

/// The stance foot rests through a turn (issue 19's turning strides; until
/// session 44 the whole leg turned about the hip at every instant and the
/// planted foot slid and turned with it): in single support the forefoot
/// contact point stands as still as on a straight walk, and the foot's rate
/// about the vertical is that of straight walking.
#[test]
fn the_stance_foot_rests_through_a_turn() {
    let turning = WalkingConfig {
        turns: Some(limbfuse_sim::Turns {
            every_s: 10.0,
            duration_s: 2.5,
            angle_rad: core::f64::consts::PI,
        }),
        duration_s: 20.0,
        ..ideal(0.7)
    };
    let straight = WalkingConfig {
        turns: None,
        ..turning
    };
    let (turned, plain) = (
        WalkingSimulator::new(turning).unwrap(),
        WalkingSimulator::new(straight).unwrap(),
    );
    let swings: Vec<_> = turned.turn_schedule().turning_swings().collect();
    assert!(swings.len() >= 2, "{swings:?}");
    let (mut worst_v, mut worst_w, mut worst_plain_v, mut n) = (0.0f64, 0.0f64, 0.0f64, 0);
    // single support (15-45 % of the stride) from the first turning swing to the last
    let (t0, t1) = (swings[0].0, swings[swings.len() - 1].1);
    let mut t = t0;
    while t < t1 {
        let frac = (turned.gait_phase(t) / core::f64::consts::TAU).rem_euclid(1.0);
        if (0.15..0.45).contains(&frac) {
            let k = turned.truth(t);
            worst_v = worst_v.max(k.contacts[1].v.norm());
            worst_w = worst_w.max(k.frames[3].w.y.abs());
            worst_plain_v = worst_plain_v.max(plain.truth(t).contacts[1].v.norm());
            n += 1;
        }
        t += 0.005;
    }
    assert!(n > 50, "{n}");
    eprintln!(
        "single support in the turn ({n} times): forefoot contact speed <= {worst_v:.2e} m/s \
         (straight walk {worst_plain_v:.2e}), foot rate about the vertical <= {worst_w:.2e} rad/s"
    );
    // The hip's rotation about the vertical (leg minus trunk heading) and
    // the trunk's peak heading rate, across speeds.
    for speed in [0.7, 1.0, 1.4, 1.8] {
        let sim = WalkingSimulator::new(WalkingConfig {
            speed_mps: speed,
            ..turning
        })
        .unwrap();
        let s = sim.turn_schedule();
        let (mut hip, mut rate) = (0.0f64, 0.0f64);
        for i in 0..2000 {
            let t = i as f64 * 0.01;
            hip = hip.max((s.heading(t).v - s.trunk_heading(t).v).abs());
            rate = rate.max(s.trunk_heading(t).d1.abs());
        }
        eprintln!(
            "{speed} m/s, 180 deg turn: hip rotation up to {:.1} deg, trunk heading rate up to {:.0} deg/s",
            hip.to_degrees(),
            rate.to_degrees()
        );
        assert!(hip.to_degrees() < 30.0 && rate.to_degrees() < 250.0);
    }
    assert!(
        worst_v <= worst_plain_v + 1e-9,
        "{worst_v} vs straight {worst_plain_v}"
    );
    assert!(
        worst_v < 0.02 && worst_w < 0.05,
        "{worst_v} m/s, {worst_w} rad/s"
    );
}

fn specific_force_and_rate_match_finite_differences(
    cfg: WalkingConfig,
    t0: f64,
    step: f64,
    count: usize,
) {
    let sim = WalkingSimulator::new(cfg).unwrap();
    let g = Vector3::new(0.0, 9.81, 0.0);
    let (mut worst_f, mut worst_w, mut peak_dyn): (f64, f64, f64) = (0.0, 0.0, 0.0);
    for k in 0..count {
        let t = t0 + k as f64 * step;
        let truth = sim.truth(t);
        for s in Segment::ALL {
            let i = s.index();
            let d2 = |h: f64| {
                (sim.sensor_position(s, t + h) - 2.0 * sim.sensor_position(s, t)
                    + sim.sensor_position(s, t - h))
                    / (h * h)
            };
            let h = 4e-4;
            let a_num = (16.0 * d2(h / 2.0) - d2(h)) / 15.0;
            let r = truth.frames[i].r * sim.imus()[i].mount;
            let f_num = r.transpose() * (a_num + g);
            worst_f = worst_f.max((f_num - truth.specific_force[i]).norm());
            peak_dyn = peak_dyn.max(truth.imu_point[i].a.norm());
            let hr = 1e-5;
            let rp = sim.truth(t + hr).frames[i].r;
            let rm = sim.truth(t - hr).frames[i].r;
            let w_num = skew_inv(&((rp - rm) / (2.0 * hr) * truth.frames[i].r.transpose()));
            let w_num_sensor = r.transpose() * w_num;
            worst_w = worst_w.max((w_num_sensor - truth.gyro[i]).norm());
        }
    }
    println!(
        "specific force vs d2/dt2(position) + g: max error {:.2e} m/s^2 (peak dynamic acceleration {:.1} m/s^2); angular rate vs dR/dt: {:.2e} rad/s",
        worst_f, peak_dyn, worst_w
    );
    assert!(worst_f < 2e-3, "{worst_f}");
    assert!(worst_w < 1e-6, "{worst_w}");
    assert!(peak_dyn > 5.0, "dynamic accelerations must be present");
}

/// Joint ranges over one stride at 1.0 m/s, in clinical signs, against
/// published normal-gait ranges (Perry & Burnfield 2010; Winter 2009;
/// Kadaba et al. 1990): hip sagittal range about 40 deg, knee peak swing
/// flexion 55-70 deg, knee loading-response flexion 10-25 deg, ankle range
/// 20-35 deg with peak plantarflexion 10-25 deg after toe-off and peak
/// dorsiflexion 5-15 deg in terminal stance.
#[test]
fn joint_ranges_fall_inside_published_normal_ranges() {
    for speed in [0.4, 1.0, 1.8] {
        let sim = WalkingSimulator::new(ideal(speed)).unwrap();
        let period = 1.0 / sim.stride_frequency();
        let (mut hip, mut knee_sw, mut knee_st, mut pf, mut df) =
            ((f64::MAX, f64::MIN), f64::MIN, f64::MIN, f64::MIN, f64::MIN);
        for i in 0..1000 {
            let t = period * i as f64 / 1000.0;
            let j = sim.truth(t).joint_angle.map(f64::to_degrees);
            let (hip_flex, knee_flex, dorsi) = (-j[0], j[1], -j[2]);
            hip = (hip.0.min(hip_flex), hip.1.max(hip_flex));
            if i < 400 {
                knee_st = knee_st.max(knee_flex);
            } else {
                knee_sw = knee_sw.max(knee_flex);
            }
            pf = pf.max(-dorsi);
            df = df.max(dorsi);
        }
        println!(
            "{speed} m/s: hip flexion {:.1}..{:.1} (range {:.1}) deg, knee peak stance {:.1} / swing {:.1} deg, ankle peak dorsi {:.1} / plantar {:.1} (range {:.1}) deg",
            hip.0, hip.1, hip.1 - hip.0, knee_st, knee_sw, df, pf, df + pf
        );
        if speed == 1.0 {
            assert!((35.0..=45.0).contains(&(hip.1 - hip.0)));
            assert!((55.0..=70.0).contains(&knee_sw));
            assert!((10.0..=25.0).contains(&knee_st));
            assert!((10.0..=25.0).contains(&pf));
            assert!((5.0..=15.0).contains(&df));
            assert!((20.0..=35.0).contains(&(df + pf)));
        }
    }
}

/// Mid-stance (12-28 % of the stride, inside Perry's 10-30 %) speed of the
/// foot IMU and of the foot contact points, every speed, with variability
/// and out-of-plane motion on.
#[test]
fn mid_stance_foot_is_nearly_still() {
    let mut worst_all: f64 = 0.0;
    for k in 0..8 {
        let speed = (0.4 + 0.2 * k as f64).min(1.8);
        let cfg = WalkingConfig {
            out_of_plane: true,
            variability: Some(Variability::default()),
            duration_s: 30.0,
            ..ideal(speed)
        };
        let sim = WalkingSimulator::new(cfg).unwrap();
        let (mut worst, mut at20): (f64, f64) = (0.0, 0.0);
        for i in 0..3000 {
            let tr = sim.truth(i as f64 * 0.01);
            let pct = (tr.phase / TAU).rem_euclid(1.0) * 100.0;
            if (12.0..=28.0).contains(&pct) {
                let v = tr.imu_point[3].v.norm();
                worst = worst.max(v);
                if (pct - 20.0).abs() < 1.0 {
                    at20 = at20.max(v);
                }
            }
        }
        println!(
            "{speed:.1} m/s: mid-stance foot IMU speed max {:.4} m/s (at 20 % of stride: {:.4} m/s)",
            worst, at20
        );
        worst_all = worst_all.max(worst);
    }
    assert!(worst_all < 0.05, "{worst_all}");
}

/// Achieved speed (hip displacement / time) against the requested one.
#[test]
fn achieved_speed_matches_requested_speed() {
    for k in 0..15 {
        let speed = (0.4 + 0.1 * k as f64).min(1.8);
        let sim = WalkingSimulator::new(ideal(speed)).unwrap();
        let period = 1.0 / sim.stride_frequency();
        let v = (sim.truth(5.0 * period).hip.p.x - sim.truth(0.0).hip.p.x) / (5.0 * period);
        let cfg = WalkingConfig {
            variability: Some(Variability::default()),
            ..ideal(speed)
        };
        let sim_v = WalkingSimulator::new(cfg).unwrap();
        let vv = (sim_v.truth(60.0).hip.p.x - sim_v.truth(0.0).hip.p.x) / 60.0;
        println!(
            "requested {speed:.1} m/s: achieved {v:.6} m/s (variability off), {vv:.4} m/s over 60 s (on); cadence {:.1} steps/min, stride {:.3} m, hip gain {:.3}",
            120.0 * sim.stride_frequency(),
            sim.model().hip.stride_length,
            sim.model().hip_gain
        );
        assert!((v - speed).abs() < 1e-6 * speed);
        assert!((vv - speed).abs() < 0.03 * speed);
    }
}

/// Stride-time coefficient of variation with the default variability.
#[test]
fn stride_time_variability_is_physiological() {
    let cfg = WalkingConfig {
        variability: Some(Variability::default()),
        ..ideal(1.0)
    };
    let sim = WalkingSimulator::new(cfg).unwrap();
    let mut crossings = Vec::new();
    let mut prev = sim.truth(0.0).phase;
    for i in 1..60_000 {
        let t = i as f64 * 0.01;
        let p = sim.truth(t).phase;
        if (p / TAU).floor() > (prev / TAU).floor() {
            let target = (p / TAU).floor() * TAU;
            crossings.push(t - 0.01 * (p - target) / (p - prev));
        }
        prev = p;
    }
    let d: Vec<f64> = crossings.windows(2).map(|w| w[1] - w[0]).collect();
    let mean = d.iter().sum::<f64>() / d.len() as f64;
    let sd = (d.iter().map(|x| (x - mean) * (x - mean)).sum::<f64>() / d.len() as f64).sqrt();
    println!(
        "stride time over 600 s: mean {mean:.4} s, CV {:.2} %",
        100.0 * sd / mean
    );
    assert!((0.01..=0.035).contains(&(sd / mean)));
}

/// RMS and peak of |dynamic acceleration| of the four IMU points and the hip
/// path figures over one stride (variability off).
struct StrideFigures {
    rms: [f64; 4],
    peak: [f64; 4],
    hip_speed: (f64, f64),
    hip_height: (f64, f64),
    hip_lateral: (f64, f64),
}

fn stride_figures(cfg: WalkingConfig) -> StrideFigures {
    let sim = WalkingSimulator::new(cfg).unwrap();
    let period = 1.0 / sim.stride_frequency();
    let n = 2000;
    let mut f = StrideFigures {
        rms: [0.0; 4],
        peak: [0.0; 4],
        hip_speed: (f64::MAX, f64::MIN),
        hip_height: (f64::MAX, f64::MIN),
        hip_lateral: (f64::MAX, f64::MIN),
    };
    let mm = |r: &mut (f64, f64), x: f64| *r = (r.0.min(x), r.1.max(x));
    for i in 0..n {
        let tr = sim.truth(period * i as f64 / n as f64);
        for s in 0..4 {
            let a = tr.imu_point[s].a.norm();
            f.peak[s] = f.peak[s].max(a);
            f.rms[s] += a * a / n as f64;
        }
        mm(&mut f.hip_speed, tr.hip.v.x);
        mm(&mut f.hip_height, tr.hip.p.y);
        mm(&mut f.hip_lateral, tr.hip.p.z);
    }
    f.rms = f.rms.map(f64::sqrt);
    f
}

/// Reports the dynamic accelerations (what makes accelerometers unreliable)
/// and the hip path at 0.4, 1.0 and 1.6 m/s, planar and with out-of-plane
/// motion; checks that they are there.
#[test]
fn dynamic_accelerations_come_from_the_motion() {
    let r = |x: [f64; 4]| x.map(|v| (v * 100.0).round() / 100.0);
    for speed in [0.4, 1.0, 1.6] {
        for oop in [false, true] {
            let f = stride_figures(WalkingConfig {
                out_of_plane: oop,
                ..ideal(speed)
            });
            println!(
                "{speed} m/s, out-of-plane {oop}: |dynamic acceleration| rms trunk/thigh/shank/foot {:?} m/s^2, peak {:?} m/s^2; hip forward speed {:.3}..{:.3} m/s, height {:.1} cm p-p, lateral {:.1} cm p-p",
                r(f.rms),
                r(f.peak),
                f.hip_speed.0,
                f.hip_speed.1,
                100.0 * (f.hip_height.1 - f.hip_height.0),
                100.0 * (f.hip_lateral.1 - f.hip_lateral.0),
            );
            assert!(f.peak[3] > 10.0 && f.peak[0] > 0.3);
        }
    }
}

/// The pelvis moves like a real one. Published ranges:
/// * lower-back (pelvis) accelerometers in level walking at preferred speed
///   show RMS accelerations of about 1.0-2.2 m/s^2 per axis (H. B. Menz,
///   S. R. Lord, R. C. Fitzpatrick, Gait Posture 18:35-46, 2003; W. Zijlstra,
///   A. L. Hof, Gait Posture 18:1-10, 2003), so the norm of the 3D dynamic
///   acceleration is a few m/s^2;
/// * the forward speed of the pelvis varies by roughly +-10-15 % within a
///   step (inverted-pendulum exchange: G. A. Cavagna, H. Thys, A. Zamboni,
///   J. Physiol. 262:639-657, 1976);
/// * the centre of mass moves 2.5-5 cm up and down and a few centimetres
///   sideways (M. S. Orendurff et al., J. Rehabil. Res. Dev. 41:829-834, 2004).
///
/// Bounds (1.0 and 1.2 m/s, out-of-plane motion on, variability off): trunk
/// dynamic acceleration RMS 0.8-3.5 m/s^2, hip forward speed within +-20 %
/// of the mean, vertical excursion 2-5 cm, lateral excursion 1-8 cm.
#[test]
fn pelvis_motion_is_realistic() {
    for speed in [1.0, 1.2] {
        let f = stride_figures(WalkingConfig {
            out_of_plane: true,
            ..ideal(speed)
        });
        let fluct = (f.hip_speed.1 - speed).max(speed - f.hip_speed.0) / speed;
        let dy = f.hip_height.1 - f.hip_height.0;
        let dz = f.hip_lateral.1 - f.hip_lateral.0;
        println!(
            "{speed} m/s: trunk dynamic acceleration rms {:.2} m/s^2, hip forward speed +-{:.1} %, vertical {:.1} cm, lateral {:.1} cm",
            f.rms[0],
            100.0 * fluct,
            100.0 * dy,
            100.0 * dz
        );
        assert!((0.8..3.5).contains(&f.rms[0]), "{}", f.rms[0]);
        assert!(fluct < 0.20, "{fluct}");
        assert!((0.02..0.05).contains(&dy), "{dy}");
        assert!((0.01..0.08).contains(&dz), "{dz}");
    }
}

/// Foot slip: how far a contact point moves along the floor while it is on
/// it (within 5 mm of the floor): the heel over 0-30 % of the stride, the
/// metatarsal head over 8-65 %. Inside single support the stance leg is held
/// by inverse kinematics; the slip comes from the double-support blends into
/// the normative curves (`docs/SIMULATOR.md`). Bound: 8 cm at any speed.
#[test]
fn foot_slip_is_limited_to_double_support() {
    let mut worst: f64 = 0.0;
    for k in 0..8 {
        let speed = (0.4 + 0.2 * k as f64).min(1.8);
        let sim = WalkingSimulator::new(WalkingConfig {
            out_of_plane: true,
            ..ideal(speed)
        })
        .unwrap();
        let period = 1.0 / sim.stride_frequency();
        let n = 2000;
        let (mut heel, mut mtp) = ((f64::MAX, f64::MIN), (f64::MAX, f64::MIN));
        let (mut heel_ss, mut mtp_ss) = ((f64::MAX, f64::MIN), (f64::MAX, f64::MIN));
        let mm = |r: &mut (f64, f64), x: f64| *r = (r.0.min(x), r.1.max(x));
        for i in 0..n {
            let s = i as f64 / n as f64;
            let tr = sim.truth(period * s);
            let (h, m) = (tr.contacts[0].p, tr.contacts[1].p);
            if s < 0.30 && h.y < 0.005 {
                mm(&mut heel, h.x);
                if s >= 0.10 {
                    mm(&mut heel_ss, h.x);
                }
            }
            if (0.08..0.65).contains(&s) && m.y < 0.005 {
                mm(&mut mtp, m.x);
                if s <= 0.50 {
                    mm(&mut mtp_ss, m.x);
                }
            }
        }
        let w = |r: (f64, f64)| if r.1 >= r.0 { r.1 - r.0 } else { 0.0 };
        let slip = w(heel).max(w(mtp));
        let m = sim.model();
        println!(
            "{speed:.1} m/s: slip heel {:.1} cm, metatarsal head {:.1} cm; in single support {:.2} / {:.2} cm; hip height {:.3} m (offset {:+.1} mm), heel strike offset {:+.1} mm, single-support deviation from the normative angles {:.1} deg",
            100.0 * w(heel),
            100.0 * w(mtp),
            100.0 * w(heel_ss),
            100.0 * w(mtp_ss),
            m.placement.hip_height,
            1e3 * m.placement_offset.0,
            1e3 * m.placement_offset.1,
            m.stance.deviation_deg
        );
        assert!(w(heel_ss).max(w(mtp_ss)) < 0.005);
        worst = worst.max(slip);
    }
    assert!(worst < 0.08, "{worst}");
}

/// The left leg's sensors read the mirror image of the right leg's: in the
/// segment frame accelerometer `S f` (polar) and gyroscope `-S w` (axial),
/// `S = diag(1, 1, -1)` (derivation in `limbfuse_sim::body_path`).
#[test]
fn left_leg_reads_the_mirror_image_of_the_right() {
    let cfg = |leg| WalkingConfig {
        mounting: Mounting::Random,
        out_of_plane: true,
        seed: 5,
        leg,
        ..ideal(1.0)
    };
    let right = WalkingSimulator::new(cfg(limbfuse_core::Leg::Right)).unwrap();
    let left = WalkingSimulator::new(cfg(limbfuse_core::Leg::Left)).unwrap();
    let s = Matrix3::from_diagonal(&Vector3::new(1.0, 1.0, -1.0));
    let mut worst: f64 = 0.0;
    for k in 0..50 {
        let t = 0.05 + 0.21 * k as f64;
        let (r, l) = (right.truth(t), left.truth(t));
        for i in 0..4 {
            let m = right.imus()[i].mount;
            assert_eq!(m, left.imus()[i].mount);
            let mirror = m.transpose() * s * m;
            worst = worst.max((l.specific_force[i] - mirror * r.specific_force[i]).norm());
            worst = worst.max((l.gyro[i] + mirror * r.gyro[i]).norm());
            assert!(r.gyro[i].norm() > 0.0);
        }
        assert_eq!(l.segment_angle, r.segment_angle);
    }
    assert!(worst < 1e-9, "{worst}");
}
