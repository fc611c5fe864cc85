//! Issue 15 item 3: `knee-selfalign` and `knee-gyro-axis` under the
//! conditions of real recordings, each against a known truth: free 3D hinge
//! motion with consumer-MEMS sensor errors, 40 and 250 Hz, accelerometer
//! scale errors of +25 % / -20 % on one and on both sensors, a 60 s still
//! period, and sensors aligned with their segments.
//!
//! Figures: `cargo test --release -p limbfuse-estimators --test integration
//! -- knee_real_conditions:: --nocapture --test-threads 1`.

use crate::knee_hinge::{records, rot, Hinge, HingeMotion, SensorErrors, Still};
use limbfuse_core::{Estimator, Joint, Record, Segment};
use limbfuse_estimators::knee_gyro_axis::{KneeGyroAxis, KneeGyroAxisParams};
use limbfuse_estimators::knee_selfalign::{KneeSelfAlign, KneeSelfAlignParams};
use limbfuse_sim::{KneeScenario, KneeSimulator, Mounting, WalkingConfig, WalkingSimulator};
use nalgebra::Vector3;

/// RMSE and offset-free RMSE (deg) of the knee from sample `from` on.
#[derive(Debug, Clone, Copy)]
struct Score {
    rmse: f64,
    offset_free: f64,
    n: usize,
}

fn wrap(x: f64) -> f64 {
    let t = std::f64::consts::TAU;
    x - t * ((x + std::f64::consts::PI) / t).floor()
}

fn errors(out: &[Option<f64>], recs: &[Record], from: usize, to: usize) -> Vec<f64> {
    out.iter()
        .zip(recs)
        .take(to)
        .skip(from)
        .filter_map(|(e, r)| Some(wrap(e.as_ref()? - r.reference.joint[Joint::Knee.index()]?)))
        .collect()
}

fn score(errs: &[f64]) -> Score {
    let n = errs.len().max(1) as f64;
    let mean = errs.iter().sum::<f64>() / n;
    let ms = errs.iter().map(|e| e * e).sum::<f64>() / n;
    Score {
        rmse: ms.sqrt().to_degrees(),
        offset_free: (ms - mean * mean).max(0.0).sqrt().to_degrees(),
        n: errs.len(),
    }
}

fn knee_out(est: &mut dyn Estimator, recs: &[Record]) -> Vec<Option<f64>> {
    recs.iter()
        .map(|r| est.step(&r.sample).unwrap().joint[Joint::Knee.index()])
        .collect()
}

/// Both methods with window `window` on `recs`, scored from `from` (default:
/// the first window) to the end.
fn both(recs: &[Record], window: usize, from: Option<usize>) -> [Score; 2] {
    let axes = KneeSelfAlignParams {
        window,
        ..KneeSelfAlignParams::default()
    };
    let from = from.unwrap_or(window);
    let mut ksa = KneeSelfAlign::new(axes).unwrap();
    let mut kga = KneeGyroAxis::new(KneeGyroAxisParams {
        axes,
        ..KneeGyroAxisParams::default()
    })
    .unwrap();
    [
        score(&errors(&knee_out(&mut ksa, recs), recs, from, recs.len())),
        score(&errors(&knee_out(&mut kga, recs), recs, from, recs.len())),
    ]
}

/// Range of `diag_rms_e_o` (RMS eq-3 residual, m/s^2) over the identified
/// windows of `knee-selfalign`.
fn rms_e_o_range(recs: &[Record], window: usize) -> (f64, f64) {
    use limbfuse_estimators::knee_selfalign::KneeDiag;
    let i = KneeDiag::NAMES
        .iter()
        .position(|n| *n == "rms_e_o")
        .unwrap();
    let mut est = KneeSelfAlign::new(KneeSelfAlignParams {
        window,
        ..KneeSelfAlignParams::default()
    })
    .unwrap();
    let mut range = (f64::INFINITY, 0.0f64);
    for (k, r) in recs.iter().enumerate() {
        let e = est.step(&r.sample).unwrap();
        if (k + 1) % window == 0 {
            if let Some(v) = e.diag[i] {
                range = (range.0.min(v), range.1.max(v));
            }
        }
    }
    range
}

fn print(label: &str, s: [Score; 2]) {
    println!(
        "| {label} | {:.3} ({:.3}) | {:.3} ({:.3}) | {} |",
        s[0].rmse, s[0].offset_free, s[1].rmse, s[1].offset_free, s[0].n
    );
}

fn free_hinge(still: Option<Still>) -> Hinge {
    Hinge {
        mount: [
            rot(Vector3::new(0.3, -1.0, 0.6), 2.1),
            rot(Vector3::new(-0.8, 0.2, 0.5), -1.4),
        ],
        point: [
            Vector3::new(0.0, 0.21, 0.08),
            Vector3::new(0.0, -0.19, 0.06),
        ],
        motion: HingeMotion::Free3d,
        still,
    }
}

fn noisy(seed: u64) -> Option<SensorErrors> {
    Some(SensorErrors {
        seed,
        acc_scale: [1.0, 1.0],
        bias: [1.0, 1.0],
    })
}

/// Issue 15 item 3, cause 6: on free 3D hinge motion (ideal sensors) the
/// first window's accelerometer angle is not trusted (eq 2 has not
/// converged from the dominant-axis start), so its flexion side came from
/// the gyro angle's skewness, which picked the extension side; the second
/// window, trusted, committed the pair and kept that side by continuity: the
/// knee read -kappa (88 deg RMSE). Now a trusted window re-reads the side
/// while the pair is not committed.
#[test]
fn issue_15_free_3d_hinge_flexes_to_positive_angles() {
    let recs = records(&free_hinge(None), 100.0, 60.0, None);
    let s = both(&recs, 500, Some(2000));
    print("free 3D hinge, ideal sensors, from 20 s", s);
    for (m, s) in s.iter().enumerate() {
        assert!(s.rmse < 0.5, "method {m}: {s:?}");
    }
}

/// Issue 15 item 3, condition 5: a 60 s still period must hold the last
/// geometry. The window in which the hinge stops (1 s of slowing motion, 4 s
/// still) passed the axis-information test and re-identified the positions
/// from that second alone: the zero of the accelerometer angle moved by
/// 90 deg and both methods followed it for the whole still period (74.6 /
/// 54.0 deg RMSE). Now a window with fewer than half its samples moving
/// keeps the previous geometry.
#[test]
fn issue_15_a_still_period_holds_the_geometry() {
    let mut hinge = free_hinge(Some(Still {
        start_s: 20.0,
        still_s: 60.0,
    }));
    hinge.motion = HingeMotion::WalkLike;
    let recs = records(&hinge, 100.0, 102.0, noisy(1));
    let mut ksa = KneeSelfAlign::new(KneeSelfAlignParams::default()).unwrap();
    let mut held = None;
    let mut out = Vec::with_capacity(recs.len());
    for (k, r) in recs.iter().enumerate() {
        out.push(ksa.step(&r.sample).unwrap().joint[Joint::Knee.index()]);
        if k == 1999 {
            held = ksa.geometry().copied();
        }
        if k == 7999 {
            assert_eq!(
                ksa.geometry().copied(),
                held,
                "geometry re-identified while still"
            );
        }
    }
    let mut kga = KneeGyroAxis::new(KneeGyroAxisParams::default()).unwrap();
    let outs = [out, knee_out(&mut kga, &recs)];
    for (m, out) in outs.iter().enumerate() {
        // the still samples: from 21 s (rest reached) to 81 s (start again)
        let still = errors(out, &recs, 2100, 8100);
        let s = score(&still);
        let drift = (still[still.len() - 1] - still[0]).to_degrees();
        let after = score(&errors(out, &recs, 8600, recs.len()));
        println!(
            "still period, method {m}: RMSE {:.3} deg (offset-free {:.3}), drift {drift:.3} deg; after it {:.3} ({:.3})",
            s.rmse, s.offset_free, after.rmse, after.offset_free
        );
        // Held: the angle's shape through the still period (offset-free)
        // and its drift. The level is the zero of the accelerometer angle,
        // set by the accelerometer biases (4.3 deg on this seed since the
        // relative scale of eq 3, 1.2 before; docs/RESULTS.md).
        assert!(
            s.rmse < 5.0 && s.offset_free < 1.5 && drift.abs() < 5.0,
            "method {m}: {s:?} drift {drift}"
        );
    }
}

fn only_noise(bias: [f64; 2]) -> Option<SensorErrors> {
    Some(SensorErrors {
        seed: 1,
        acc_scale: [1.0, 1.0],
        bias,
    })
}

/// Free 3D hinge motion with sensor errors, 100 / 40 / 250 Hz, scored after
/// the first window and from 20 s. White noise alone leaves the angle within
/// 1 deg from 20 s; the turn-on biases (docs/KNEE_SELFALIGN.md "Conditions
/// of real recordings": the accelerometer biases move the eq-3 positions, and
/// with them the zero, from window to window) are printed, not asserted.
#[test]
fn free_3d_hinge_with_sensor_errors() {
    let hinge = free_hinge(None);
    let cases = [
        ("MEMS seed 1", noisy(1)),
        ("MEMS seed 2", noisy(2)),
        ("noise only", only_noise([0.0, 0.0])),
        ("noise + gyro bias", only_noise([1.0, 0.0])),
        ("noise + acc bias", only_noise([0.0, 1.0])),
    ];
    for (label, errs) in cases {
        let recs = records(&hinge, 100.0, 60.0, errs);
        let first = both(&recs, 500, None);
        let late = both(&recs, 500, Some(2000));
        print(
            &format!("free 3D hinge 100 Hz {label}, after the first window"),
            first,
        );
        print(&format!("free 3D hinge 100 Hz {label}, from 20 s"), late);
        let (lo, hi) = rms_e_o_range(&recs, 500);
        println!("  RMS e_o per window {lo:.3}-{hi:.3} m/s^2");
        if label == "noise only" {
            for s in late {
                assert!(s.rmse < 1.0, "{label}: {s:?}");
            }
        }
    }
    for (rate, windows) in [(40.0, [500, 200]), (250.0, [500, 1250])] {
        let recs = records(&hinge, rate, 60.0, noisy(1));
        for w in windows {
            let from = ((20.0 * rate) as usize).max(w);
            print(
                &format!(
                    "free 3D hinge {rate} Hz MEMS s_w {w}, from {:.1} s",
                    from as f64 / rate
                ),
                both(&recs, w, Some(from)),
            );
        }
    }
}

fn scale_acc(recs: &mut [Record], scale: [f64; 2]) {
    for r in recs.iter_mut() {
        for (i, seg) in [Segment::Thigh, Segment::Shank].into_iter().enumerate() {
            if let Some(a) = r.sample.imu[seg.index()].acc.as_mut() {
                *a *= scale[i];
            }
        }
    }
}

fn knee_walk(seed: u64, rate: f64) -> Vec<Record> {
    KneeSimulator::new(KneeScenario {
        walking: WalkingConfig {
            seed,
            imu_rate_hz: rate,
            mounting: Mounting::Random,
            ..WalkingConfig::default()
        },
        ..KneeScenario::default()
    })
    .unwrap()
    .collect()
}

/// limbfuse's knee scenario (random mountings and positions, default
/// sensors) at 40 and 250 Hz with the default window (500 samples) and with
/// 5 s, and the walking simulator with sensors aligned with their segments
/// (the degenerate case for axis solvers that start from the sensor axes).
#[test]
fn other_rates_and_aligned_sensors_on_simulated_walks() {
    for seed in [3, 4] {
        let sim100 = knee_walk(seed, 100.0);
        print(
            &format!("knee sim seed {seed} 100 Hz s_w 500, from 10 s"),
            both(&sim100, 500, Some(1000)),
        );
        let (lo, hi) = rms_e_o_range(&sim100, 500);
        println!("  RMS e_o per window {lo:.3}-{hi:.3} m/s^2");
        for (rate, windows) in [(40.0, [500, 200]), (250.0, [500, 1250])] {
            let recs = knee_walk(seed, rate);
            for w in windows {
                let from = ((10.0 * rate) as usize).max(w);
                let s = both(&recs, w, Some(from));
                print(
                    &format!(
                        "knee sim seed {seed} {rate} Hz s_w {w}, from {:.1} s",
                        from as f64 / rate
                    ),
                    s,
                );
                for (m, s) in s.iter().enumerate() {
                    assert!(
                        s.rmse < 6.0 && s.offset_free < 2.0,
                        "seed {seed} {rate} Hz s_w {w} method {m}: {s:?}"
                    );
                }
            }
        }
        let aligned: Vec<Record> = WalkingSimulator::new(WalkingConfig {
            seed,
            mounting: Mounting::Aligned,
            ..WalkingConfig::default()
        })
        .unwrap()
        .collect();
        let s = both(&aligned, 500, Some(1000));
        print(
            &format!("walking sim seed {seed}, sensors aligned with the segments, from 10 s"),
            s,
        );
        for (m, s) in s.iter().enumerate() {
            assert!(
                s.rmse < 4.0 && s.offset_free < 1.5,
                "aligned seed {seed} method {m}: {s:?}"
            );
        }
    }
}

/// Accelerometer scale errors of +25 % and -20 % on both sensors and on one:
/// a common scale is absorbed by the positions (eq 3 scales with `o`, and
/// eq 5 is a ratio), so the angle is unchanged to within 0.5 deg; a scale
/// error on one sensor is the relative scale `r` of eq 3
/// (`knee_selfalign::acc_scale`, [`issue_15_one_accelerometer_scale_error_is_identified`]).
#[test]
fn accelerometer_scale_errors() {
    for seed in [3, 4] {
        let base = knee_walk(seed, 100.0);
        let reference = both(&base, 500, Some(1000));
        print(
            &format!("knee sim seed {seed}, no added scale error, from 10 s"),
            reference,
        );
        for scale in [
            [1.25, 1.25],
            [0.8, 0.8],
            [1.25, 1.0],
            [1.0, 1.25],
            [0.8, 1.0],
            [1.0, 0.8],
        ] {
            let mut recs = base.clone();
            scale_acc(&mut recs, scale);
            let s = both(&recs, 500, Some(1000));
            print(
                &format!("knee sim seed {seed}, accelerometer scale {scale:?}, from 10 s"),
                s,
            );
            let mut ksa = KneeSelfAlign::new(KneeSelfAlignParams::default()).unwrap();
            knee_out(&mut ksa, &recs);
            if scale[0] == scale[1] {
                assert!(ksa.acc_trusted());
                for m in 0..2 {
                    assert!(
                        (s[m].rmse - reference[m].rmse).abs() < 0.5,
                        "{scale:?} method {m}: {s:?}"
                    );
                }
            } else {
                // issue_15_one_accelerometer_scale_error_is_identified
                assert!(
                    ksa.acc_trusted(),
                    "{scale:?}: accelerometer angle not trusted"
                );
            }
        }
    }
    let hinge = free_hinge(None);
    for scale in [[1.25, 1.25], [0.8, 0.8], [1.25, 1.0], [1.0, 0.8]] {
        let recs = records(
            &hinge,
            100.0,
            60.0,
            Some(SensorErrors {
                seed: 1,
                acc_scale: scale,
                bias: [1.0, 1.0],
            }),
        );
        print(
            &format!("free 3D hinge MEMS, accelerometer scale {scale:?}, from 20 s"),
            both(&recs, 500, Some(2000)),
        );
    }
}

fn diag(est: &KneeSelfAlign, recs: &[Record], name: &str) -> Vec<Option<f64>> {
    use limbfuse_estimators::knee_selfalign::KneeDiag;
    let i = KneeDiag::NAMES.iter().position(|n| *n == name).unwrap();
    let mut est = est.clone();
    recs.iter()
        .map(|r| est.step(&r.sample).unwrap().diag[i])
        .collect()
}

/// Issue 15 item 3: a scale error of +25 % or -20 % on ONE accelerometer
/// broke eq 3 (`|a_T - Gamma_T| = |a_S - Gamma_S|` off by up to 0.25 g): the
/// accelerometer angle failed the trust test on every window and both
/// methods fell back on the high-passed gyro angle, 21.1 / 32.6 deg RMSE on
/// the knee simulator seeds 3 / 4 (zero = the trial mean). Now the relative
/// scale `r` is identified with the positions and applied in eqs 3 and 7:
/// the angle is that of the unscaled recording to within 0.5 deg, and
/// `diag_acc_scale_ratio` reads the scale ratio (times the simulated
/// sensors' own relative scale, the unscaled run's ratio) to 1 %.
#[test]
fn issue_15_one_accelerometer_scale_error_is_identified() {
    let fresh = KneeSelfAlign::new(KneeSelfAlignParams::default()).unwrap();
    for seed in [3, 4] {
        let base = knee_walk(seed, 100.0);
        let reference = both(&base, 500, Some(1000));
        let r0 = diag(&fresh, &base, "acc_scale_ratio")
            .last()
            .copied()
            .flatten()
            .unwrap();
        for scale in [[1.25, 1.0], [1.0, 1.25], [0.8, 1.0], [1.0, 0.8]] {
            let mut recs = base.clone();
            scale_acc(&mut recs, scale);
            let s = both(&recs, 500, Some(1000));
            let r = diag(&fresh, &recs, "acc_scale_ratio")
                .last()
                .copied()
                .flatten()
                .unwrap();
            print(
                &format!("knee sim seed {seed}, accelerometer scale {scale:?}, r {r:.4} (unscaled {r0:.4}), from 10 s"),
                s,
            );
            let expected = r0 * scale[0] / scale[1];
            assert!(
                (r / expected - 1.0).abs() < 0.01,
                "{scale:?}: r {r} vs {expected}"
            );
            for m in 0..2 {
                assert!(
                    (s[m].rmse - reference[m].rmse).abs() < 0.5,
                    "seed {seed} {scale:?} method {m}: {:?} vs {:?}",
                    s[m],
                    reference[m]
                );
            }
        }
    }
}

/// Issue 15 item 3: on free 3D hinge motion with accelerometer biases the
/// eq-3 positions of each window landed somewhere else (`Gamma` as small as
/// the bias mismatch), and with them the zero of the angle: 23.2 (22.0) deg
/// with the accelerometer biases alone, 9.05 (6.50) with all MEMS errors on
/// seed 2, from 20 s. With the relative scale of eq 3 alone the positions
/// still moved (offset-free 3.4 / 2.7 deg); fused over the windows by their
/// information (`knee_selfalign::position_fusion`) the angle's shape is
/// within 2 deg (offset-free) for both methods.
#[test]
fn issue_15_free_3d_hinge_positions_fused_over_windows() {
    let hinge = free_hinge(None);
    for (label, errs) in [
        ("acc bias", only_noise([0.0, 1.0])),
        ("MEMS seed 2", noisy(2)),
    ] {
        let recs = records(&hinge, 100.0, 60.0, errs);
        let s = both(&recs, 500, Some(2000));
        print(&format!("free 3D hinge 100 Hz {label}, from 20 s"), s);
        let fresh = KneeSelfAlign::new(KneeSelfAlignParams::default()).unwrap();
        let fused = diag(&fresh, &recs, "position_windows")
            .last()
            .copied()
            .flatten();
        println!("  windows fused at the end: {fused:?}");
        for (m, s) in s.iter().enumerate() {
            assert!(
                s.offset_free < 2.0 && s.rmse < 8.0,
                "{label} method {m}: {s:?}"
            );
        }
    }
}

/// Issue 15 item 3: when a window gives new axis sides, eq 4 restarts; the
/// accelerometer angle is that of the sample two steps back, whose gyro
/// angle the restart had not kept, so the first two outputs were the bare
/// gyro integral from 0 (58 deg off on the shared 1.6 m/s walk at 40 Hz;
/// here ~61 deg on a walk-like hinge at 40 Hz, s_w = 200). Now the gyro
/// angles of the last samples are integrated with the new axes: the first
/// output is corrected (knee-selfalign: Algorithm 1's first gain
/// `1 / 1.2`, so within 20 % of the angle; knee-gyro-axis: exact).
#[test]
fn issue_15_first_outputs_after_identification_are_corrected() {
    let mut hinge = free_hinge(None);
    hinge.motion = HingeMotion::WalkLike;
    let recs = records(&hinge, 40.0, 30.0, None);
    let p = KneeSelfAlignParams {
        window: 200,
        ..KneeSelfAlignParams::default()
    };
    let mut ksa = KneeSelfAlign::new(p).unwrap();
    let mut kga = KneeGyroAxis::new(KneeGyroAxisParams {
        axes: p,
        ..KneeGyroAxisParams::default()
    })
    .unwrap();
    for (m, out) in [knee_out(&mut ksa, &recs), knee_out(&mut kga, &recs)]
        .iter()
        .enumerate()
    {
        let first = out.iter().position(|x| x.is_some()).unwrap();
        for k in first..first + 3 {
            let truth = recs[k].reference.joint[Joint::Knee.index()].unwrap();
            let e = wrap(out[k].unwrap() - truth);
            println!(
                "method {m} sample {k}: true {:.1} deg, error {:.1} deg",
                truth.to_degrees(),
                e.to_degrees()
            );
            assert!(truth.to_degrees() > 20.0, "the check needs a flexed knee");
            assert!(
                e.abs() < 0.2 * truth.abs(),
                "method {m} sample {k}: error {e} of {truth}"
            );
        }
    }
}
