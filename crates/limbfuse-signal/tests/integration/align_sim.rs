//! Alignment on simulated walking with random mountings (true mounting from
//! the simulator's `imus()`). Figures for docs/ALIGNMENT.md:
//! `cargo test -p limbfuse-signal --test integration -- align_sim:: --nocapture --test-threads 1`

use limbfuse_core::{Record, Segment};
use limbfuse_io::TrialMeta;
use limbfuse_signal::align::{
    apply_alignment, apply_rotations, estimate_alignment, rotations_from_metadata, AlignOptions,
    Alignment, AxisMethod, ZeroMethod,
};
use limbfuse_sim::{Motion, Mounting, WalkingConfig, WalkingSimulator};
use nalgebra::{Matrix3, Vector3};

fn config(seed: u64, speed: f64, duration_s: f64) -> WalkingConfig {
    WalkingConfig {
        seed,
        speed_mps: speed,
        duration_s,
        mounting: Mounting::Random,
        ..Default::default()
    }
}

/// Records and true mountings (sensor to segment).
fn sim(cfg: WalkingConfig) -> (Vec<Record>, [Matrix3<f64>; 4]) {
    let s = WalkingSimulator::new(cfg).unwrap();
    let m = [0, 1, 2, 3].map(|i| s.imus()[i].mount);
    (s.collect(), m)
}

/// Errors of one sensor's alignment against the truth.
struct Errors {
    /// Angle between estimated and true z (deg); > 90 means a wrong sign.
    axis: f64,
    /// In-plane angle of `R M^T` (deg): the aligned angle reads the true
    /// angle minus this.
    zero: f64,
    /// RMS of aligned gyro z - d(ref)/dt (deg/s), estimated and true frame.
    rate: (f64, f64),
    /// Mean reference angle (deg).
    mean_ref: f64,
}

fn errors(rec: &[Record], m: &[Matrix3<f64>; 4], a: &Alignment) -> [Option<Errors>; 4] {
    Segment::ALL.map(|s| {
        let i = s.index();
        let r = a.per_segment[i]?.rotation.into_inner();
        let z_est: Vector3<f64> = r.row(2).transpose();
        let z_true: Vector3<f64> = m[i].row(2).transpose();
        let e = r * m[i].transpose();
        let (mut se, mut st) = (0.0, 0.0);
        for k in 1..rec.len() - 1 {
            let d = (rec[k + 1].reference.segment[i].unwrap()
                - rec[k - 1].reference.segment[i].unwrap())
                / (rec[k + 1].sample.t - rec[k - 1].sample.t);
            let w = rec[k].sample.imu[i].gyr.unwrap();
            se += (z_est.dot(&w) - d).powi(2);
            st += (z_true.dot(&w) - d).powi(2);
        }
        let n = (rec.len() - 2) as f64;
        let mean_ref = rec
            .iter()
            .map(|x| x.reference.segment[i].unwrap())
            .sum::<f64>()
            / rec.len() as f64;
        Some(Errors {
            axis: z_est.dot(&z_true).clamp(-1.0, 1.0).acos().to_degrees(),
            zero: e[(1, 0)].atan2(e[(0, 0)]).to_degrees(),
            rate: ((se / n).sqrt().to_degrees(), (st / n).sqrt().to_degrees()),
            mean_ref: mean_ref.to_degrees(),
        })
    })
}

/// Runs seeds x speeds; returns per segment the max axis error, max
/// |zero - mean_ref| and max (rate est - rate true).
fn survey(opts: &AlignOptions, seeds: std::ops::Range<u64>, label: &str) -> [[f64; 3]; 4] {
    let mut worst = [[0.0f64; 3]; 4];
    let mut mean_axis = [0.0f64; 4];
    let mut min_margin = [f64::INFINITY; 4];
    let mut runs = [0.0f64; 4];
    println!("{label}: per run, per segment: axis error / zero - mean ref / rate rms est (true) (deg, deg, deg/s)");
    // `partial`: a sensor that cannot be aligned is reported, not fatal. With
    // the realistic pelvis path the trunk's walking direction (hip-link
    // correlation) is unobservable at slow speeds (pelvis acceleration
    // ~0.3 m/s^2 RMS at 0.4 m/s); it may be skipped there, never at >= 1 m/s,
    // and the legs must always be aligned.
    let opts = &AlignOptions {
        partial: true,
        ..*opts
    };
    for seed in seeds {
        for speed in [0.4, 0.7, 1.0, 1.4, 1.8] {
            let (rec, m) = sim(config(seed, speed, 30.0));
            let a = estimate_alignment(&rec, opts).unwrap();
            let e = errors(&rec, &m, &a);
            let mut line = format!(
                "  seed {seed} {speed} m/s (leg {:?}, not walking {}):",
                a.leg.map(|l| (l.leg, (l.score * 100.0).round() / 100.0)),
                a.not_walking_samples
            );
            for s in Segment::ALL {
                let Some(x) = &e[s.index()] else {
                    assert!(
                        s == Segment::Trunk && speed < 1.0,
                        "{label} seed {seed} {speed}: {} not aligned",
                        s.name()
                    );
                    line += &format!(" {} skipped", s.name());
                    continue;
                };
                assert!(
                    x.axis < 90.0,
                    "{label} seed {seed} {speed}: {} z sign wrong",
                    s.name()
                );
                let w = &mut worst[s.index()];
                w[0] = w[0].max(x.axis);
                w[1] = w[1].max((x.zero - x.mean_ref).abs());
                w[2] = w[2].max(x.rate.0 - x.rate.1);
                mean_axis[s.index()] += x.axis;
                runs[s.index()] += 1.0;
                let sm = a.per_segment[s.index()].unwrap().sign_margin;
                min_margin[s.index()] = min_margin[s.index()].min(sm);
                line += &format!(
                    " {} {:.2}/{:+.2}/{:.2}({:.2}) ratio {:.2} margin {:.2}",
                    s.name(),
                    x.axis,
                    x.zero - x.mean_ref,
                    x.rate.0,
                    x.rate.1,
                    a.per_segment[s.index()]
                        .unwrap()
                        .axis_ratio
                        .unwrap_or(f64::NAN),
                    sm
                );
            }
            println!("{line}");
        }
    }
    for s in Segment::ALL {
        let w = worst[s.index()];
        println!(
            "{label}: {:5}: axis error mean {:.2} max {:.2} deg; |zero - mean ref| max {:.2} deg; rate rms est - true max {:+.2} deg/s; sign margin min {:.2}",
            s.name(),
            mean_axis[s.index()] / runs[s.index()],
            w[0],
            w[1],
            w[2],
            min_margin[s.index()]
        );
    }
    worst
}

#[test]
fn random_mountings_axes_signs_and_zero() {
    let worst = survey(&AlignOptions::default(), 0..6, "default");
    // Bounds from the measured maxima (docs/ALIGNMENT.md) with ~1 deg margin.
    // The axis "error" is against the segment z of the simulator; with
    // out-of-plane motion the functional axis differs from it by a few
    // degrees, which the rate check shows does not hurt gyro_z.
    // Trunk bound raised from 5.5 to 8.0 deg (and its rate bound to 2.0 deg/s)
    // when the simulator's pelvis path became realistic (smaller pelvis
    // accelerations make the hip-link walking direction noisier: measured
    // max 6.79 deg, +1.52 deg/s).
    let axis_max = [8.0, 9.5, 8.0, 5.5];
    let rate_max = [2.0, 1.5, 1.5, 1.5];
    for s in Segment::ALL {
        let w = worst[s.index()];
        assert!(
            w[0] < axis_max[s.index()],
            "{}: axis error {:.2} deg",
            s.name(),
            w[0]
        );
        // Mean-inclination zero: the aligned angle is the true angle minus
        // its mean over the trial, up to accelerometer bias (20 mg ~ 1.1 deg).
        assert!(w[1] < 4.0, "{}: zero error {:.2} deg", s.name(), w[1]);
        assert!(
            w[2] < rate_max[s.index()],
            "{}: gyro z rate error exceeds the true frame's by {:.2} deg/s",
            s.name(),
            w[2]
        );
    }
}

#[test]
fn hinge_option_also_recovers_the_axes() {
    let opts = AlignOptions {
        hinge: true,
        ..Default::default()
    };
    let worst = survey(&opts, 0..2, "hinge");
    let axis_max = [8.5, 8.0, 4.0, 6.0];
    for s in Segment::ALL {
        let w = worst[s.index()];
        assert!(
            w[0] < axis_max[s.index()],
            "{}: axis error {:.2} deg",
            s.name(),
            w[0]
        );
        assert!(w[2] < 1.5, "{}: rate error {:.2} deg/s", s.name(), w[2]);
    }
    let (rec, _) = sim(config(0, 1.0, 20.0));
    let a = estimate_alignment(&rec, &opts).unwrap();
    let shank = a.per_segment[Segment::Shank.index()].unwrap();
    assert_eq!(
        shank.axis_method,
        AxisMethod::Hinge {
            knee: true,
            ankle: true
        }
    );
    assert!(shank.hinge_residual.unwrap() < 0.5);
}

#[test]
fn known_mean_angles_remove_the_zero_bias() {
    for seed in 0..3 {
        let (rec, m) = sim(config(seed, 1.0, 30.0));
        let means = [0, 1, 2, 3].map(|i| {
            rec.iter()
                .map(|x| x.reference.segment[i].unwrap())
                .sum::<f64>()
                / rec.len() as f64
        });
        let opts = AlignOptions {
            mean_angle_rad: means,
            ..Default::default()
        };
        let a = estimate_alignment(&rec, &opts).unwrap();
        for (s, e) in Segment::ALL
            .iter()
            .zip(errors(&rec, &m, &a).map(|e| e.expect("every sensor aligned")))
        {
            println!(
                "seed {seed} {}: zero error with the true mean given {:+.2} deg",
                s.name(),
                e.zero
            );
            assert!(e.zero.abs() < 4.0, "{}: {:.2}", s.name(), e.zero);
            let z = a.per_segment[s.index()].unwrap().zero_method;
            assert_eq!(
                z,
                ZeroMethod::MeanInclination {
                    target_rad: means[s.index()]
                }
            );
        }
    }
}

#[test]
fn quiet_standing_sets_the_zero() {
    for seed in 0..4 {
        // Same seed: the same mountings (set-up draws do not depend on the motion).
        let stand = WalkingConfig {
            motion: Motion::Stand,
            ..config(seed, 1.0, 3.0)
        };
        let (mut rec, m) = sim(stand);
        let (walk, m2) = sim(config(seed, 1.0, 30.0));
        assert_eq!(m, m2);
        let t0 = rec.last().unwrap().sample.t + 0.01;
        rec.extend(walk.into_iter().map(|mut r| {
            r.sample.t += t0;
            r
        }));
        let a = estimate_alignment(&rec, &AlignOptions::default()).unwrap();
        let (q0, q1) = a.quiet.unwrap();
        assert!(q0 < 0.05 && q1 > 2.9 && q1 < 3.0, "quiet {q0}..{q1}");
        for (s, e) in Segment::ALL
            .iter()
            .zip(errors(&rec, &m, &a).map(|e| e.expect("every sensor aligned")))
        {
            let sa = a.per_segment[s.index()].unwrap();
            println!(
                "seed {seed} {}: standing zero error {:+.2} deg, walking mean {:+.2} deg (true {:+.2})",
                s.name(),
                e.zero,
                sa.walking_mean_angle_rad.to_degrees(),
                e.mean_ref
            );
            assert!(matches!(sa.zero_method, ZeroMethod::QuietStanding { .. }));
            // Accelerometer turn-on bias (20 mg, 1 sigma per axis) limits this.
            assert!(e.zero.abs() < 3.0, "{}: {:.2}", s.name(), e.zero);
            assert!((sa.walking_mean_angle_rad.to_degrees() - e.mean_ref).abs() < 4.0);
        }
        // Aligned standing accelerometer reads about (0, g, 0). Its z
        // component is the standing elevation of the functional (walking)
        // axis: with the gyro-only axis (issue 14, `gyro_axis_max_tilt_rad`)
        // the simulated foot reads 0.81-1.04 m/s^2 (4.7-6.1 deg: the foot's
        // out-of-plane motion tilts where it rotates; 0.36-0.57 with the
        // horizontal axis alone), every other sensor <= 0.55.
        let r = apply_alignment(&rec[100], &a);
        for imu in r.sample.imu {
            let f = imu.acc.unwrap();
            assert!(
                f.x.abs() < 0.5 && (f.y - 9.81).abs() < 0.5 && f.z.abs() < 1.1,
                "{f:?}"
            );
        }
    }
}

#[test]
fn a_quiet_period_that_is_not_upright_is_not_used_for_that_segment() {
    let stand = WalkingConfig {
        motion: Motion::Stand,
        ..config(2, 1.0, 3.0)
    };
    let (mut rec, m) = sim(stand);
    // The thigh held 80 deg forward (as when sitting): its sensor sees
    // gravity turned about the segment z.
    let th = Segment::Thigh.index();
    let tilt = nalgebra::Rotation3::from_axis_angle(&Vector3::z_axis(), 80f64.to_radians());
    for r in &mut rec {
        let f_seg = tilt.inverse() * Vector3::new(0.0, 9.81, 0.0);
        r.sample.imu[th].acc = Some(m[th].transpose() * f_seg);
    }
    let (walk, _) = sim(config(2, 1.0, 30.0));
    let t0 = rec.last().unwrap().sample.t + 0.01;
    rec.extend(walk.into_iter().map(|mut r| {
        r.sample.t += t0;
        r
    }));
    let a = estimate_alignment(&rec, &AlignOptions::default()).unwrap();
    assert!(a.quiet.is_some());
    let z = |s: Segment| a.per_segment[s.index()].unwrap().zero_method;
    assert!(matches!(
        z(Segment::Thigh),
        ZeroMethod::MeanInclination { .. }
    ));
    assert!(matches!(
        z(Segment::Shank),
        ZeroMethod::QuietStanding { .. }
    ));
}

#[test]
fn aligned_gyro_integrates_to_the_reference() {
    let (rec, m) = sim(config(5, 1.2, 20.0));
    let a = estimate_alignment(&rec, &AlignOptions::default()).unwrap();
    let aligned: Vec<Record> = rec.iter().map(|r| apply_alignment(r, &a)).collect();
    let truly: Vec<Record> = rec
        .iter()
        .map(|r| {
            apply_rotations(
                r,
                &m.map(|x| Some(nalgebra::Rotation3::from_matrix_unchecked(x))),
            )
        })
        .collect();
    // Trapezoidal integration of gyro z over 5 s windows started from the reference.
    let drift = |recs: &[Record], i: usize| -> f64 {
        let mut worst: f64 = 0.0;
        for start in (0..recs.len() - 500).step_by(500) {
            let mut th = recs[start].reference.segment[i].unwrap();
            for k in start + 1..start + 500 {
                let dt = recs[k].sample.t - recs[k - 1].sample.t;
                th += 0.5
                    * dt
                    * (recs[k].sample.imu[i].gyr.unwrap().z
                        + recs[k - 1].sample.imu[i].gyr.unwrap().z);
                worst = worst.max((th - recs[k].reference.segment[i].unwrap()).abs());
            }
        }
        worst.to_degrees()
    };
    for s in Segment::ALL {
        let (e, t) = (drift(&aligned, s.index()), drift(&truly, s.index()));
        println!("{}: max |integrated gyro z - ref| over 5 s: estimated frame {e:.2} deg, true frame {t:.2} deg", s.name());
        assert!(e < t + 1.5, "{}: {e:.2} vs {t:.2}", s.name());
    }
}

#[test]
fn metadata_round_trip_and_device_quaternion() {
    let (rec, _) = sim(config(3, 1.0, 15.0));
    let a = estimate_alignment(&rec, &AlignOptions::default()).unwrap();
    let mut meta = TrialMeta::trial_v1();
    a.annotate(&mut meta);
    for key in [
        "align_method",
        "align_quiet",
        "thigh_align_quat",
        "thigh_align_axis",
        "trunk_align_zero",
        "foot_align_quality",
    ] {
        assert!(meta.get(key).is_some(), "{key}");
    }
    assert_eq!(meta.get("shank_align_axis"), Some("principal"));
    assert_eq!(meta.get("trunk_align_axis"), Some("gravity+hip-link"));
    let back = rotations_from_metadata(&meta).unwrap();
    for (r, b) in a.rotations().iter().zip(&back) {
        assert!((r.unwrap().matrix() - b.unwrap().matrix()).norm() < 1e-8);
    }
    // A device quaternion (sensor to world) becomes aligned to world.
    let mut r0 = rec[10];
    let q = nalgebra::UnitQuaternion::from_euler_angles(0.3, -0.2, 1.1);
    r0.sample.imu[1].quat = Some([q.w, q.i, q.j, q.k]);
    let out = apply_alignment(&r0, &a);
    let [w, x, y, z] = out.sample.imu[1].quat.unwrap();
    let qa = nalgebra::UnitQuaternion::from_quaternion(nalgebra::Quaternion::new(w, x, y, z));
    let v_raw = Vector3::new(0.2, -0.7, 0.4);
    let v_al = a.per_segment[1].unwrap().rotation * v_raw;
    assert!((qa * v_al - q * v_raw).norm() < 1e-12);
    // Readings rotate; encoders and references are untouched.
    assert_eq!(out.sample.encoder, r0.sample.encoder);
    assert_eq!(out.reference, r0.reference);
    let g = a.per_segment[1].unwrap().rotation * r0.sample.imu[1].gyr.unwrap();
    assert!((out.sample.imu[1].gyr.unwrap() - g).norm() < 1e-12);
}
