//! Issue 15 item 3: `knee-selfalign` and `knee-gyro-axis` under the
//! conditions of real recordings, each against a known truth: free 3D hinge
//! motion with consumer-MEMS sensor errors, 40 and 250 Hz, accelerometer
//! scale errors of +25 % / -20 % on one and on both sensors, a 60 s still
//! period, and sensors aligned with their segments.
//!
//! Figures: `cargo test --release -p limbfuse-estimators --test
//! knee_real_conditions -- --nocapture --test-threads 1`.

mod knee_hinge;

use knee_hinge::{records, rot, Hinge, HingeMotion, SensorErrors, Still};
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
            assert_eq!(ksa.geometry().copied(), held, "geometry re-identified while still");
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
        assert!(s.rmse < 3.0 && drift.abs() < 5.0, "method {m}: {s:?} drift {drift}");
    }
}

#[test]
fn measure_free_hinge_rates_and_scales() {
    let hinge = free_hinge(None);
    let only = |bias| Some(SensorErrors { seed: 1, acc_scale: [1.0, 1.0], bias });
    for (label, errs) in [("MEMS seed 1", noisy(1)), ("MEMS seed 2", noisy(2)), ("noise only", only([0.0, 0.0])), ("noise + gyro bias", only([1.0, 0.0])), ("noise + acc bias", only([0.0, 1.0]))] {
        let recs = records(&hinge, 100.0, 60.0, errs);
        print(&format!("free 3D hinge 100 Hz {label}"), both(&recs, 500, None));
    }
    for (rate, windows) in [(40.0, [500, 200]), (250.0, [500, 1250])] {
        let recs = records(&hinge, rate, 60.0, noisy(1));
        for w in windows {
            print(
                &format!("free 3D hinge {rate} Hz MEMS s_w {w}"),
                both(&recs, w, Some((10.0 * rate) as usize).max(Some(w))),
            );
        }
    }
    for scale in [[1.25, 1.0], [1.0, 1.25], [1.25, 1.25], [0.8, 1.0], [1.0, 0.8], [0.8, 0.8], [1.25, 0.8]] {
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
        print(&format!("free 3D hinge acc scale {scale:?}"), both(&recs, 500, None));
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

#[test]
fn measure_walking_rates_scales_aligned() {
    for seed in [3, 4] {
        for (rate, windows) in [(100.0, [500, 500]), (40.0, [500, 200]), (250.0, [500, 1250])] {
            let recs = knee_walk(seed, rate);
            for w in windows {
                print(&format!("knee sim seed {seed} {rate} Hz s_w {w}"), both(&recs, w, Some((10.0 * rate) as usize).max(Some(w))));
            }
        }
        let base = knee_walk(seed, 100.0);
        for scale in [[1.25, 1.0], [1.0, 1.25], [1.25, 1.25], [0.8, 1.0], [1.0, 0.8], [0.8, 0.8]] {
            let mut recs = base.clone();
            scale_acc(&mut recs, scale);
            print(&format!("knee sim seed {seed} acc scale {scale:?}"), both(&recs, 500, None));
        }
        let aligned: Vec<Record> = WalkingSimulator::new(WalkingConfig {
            seed,
            mounting: Mounting::Aligned,
            ..WalkingConfig::default()
        })
        .unwrap()
        .collect();
        print(&format!("walking sim seed {seed} aligned sensors"), both(&aligned, 500, None));
    }
}

#[test]
fn measure_still_period() {
    for motion in [HingeMotion::Free3d, HingeMotion::WalkLike] {
        let mut hinge = free_hinge(Some(Still {
            start_s: 20.0,
            still_s: 60.0,
        }));
        hinge.motion = motion;
        let recs = records(&hinge, 100.0, 102.0, noisy(1));
        let axes = KneeSelfAlignParams::default();
        let mut ksa = KneeSelfAlign::new(axes).unwrap();
        let mut kga = KneeGyroAxis::new(KneeGyroAxisParams::default()).unwrap();
        let outs = [knee_out(&mut ksa, &recs), knee_out(&mut kga, &recs)];
        for (m, out) in outs.iter().enumerate() {
            let pre = score(&errors(out, &recs, 500, 2000));
            let still = score(&errors(out, &recs, 2100, 8000));
            let post = score(&errors(out, &recs, 8200, recs.len()));
            let e_still = errors(out, &recs, 2100, 8000);
            let drift = e_still.last().unwrap() - e_still.first().unwrap();
            println!(
                "still {:?} method {m}: before {:.3} ({:.3}), still {:.3} ({:.3}) drift {:.3} deg, after {:.3} ({:.3})",
                matches!(motion, HingeMotion::Free3d),
                pre.rmse,
                pre.offset_free,
                still.rmse,
                still.offset_free,
                drift.to_degrees(),
                post.rmse,
                post.offset_free
            );
        }
        let g = ksa.geometry().unwrap();
        println!("geometry after: {:?} {:?}", g.axis, g.position);
    }
}

fn d(e: &limbfuse_core::Estimate, name: &str) -> f64 {
    use limbfuse_estimators::knee_selfalign::KneeDiag;
    let i = KneeDiag::NAMES.iter().position(|n| *n == name).unwrap();
    e.diag[i].unwrap_or(f64::NAN)
}

#[test]
fn debug_windows() {
    let which = std::env::var("KR_CASE").unwrap_or_default();
    let (hinge, rate, errs, window) = match which.as_str() {
        "still" => {
            let mut h = free_hinge(Some(Still { start_s: 20.0, still_s: 60.0 }));
            h.motion = HingeMotion::WalkLike;
            (h, 100.0, noisy(1), 500)
        }
        "250" => (free_hinge(None), 250.0, noisy(1), 500),
        "scale" => (free_hinge(None), 100.0, Some(SensorErrors { seed: 1, acc_scale: [1.25, 1.0], bias: [1.0, 1.0] }), 500),
        "noise" => (free_hinge(None), 100.0, Some(SensorErrors { seed: 1, acc_scale: [1.0, 1.0], bias: [0.0, 0.0] }), 500),
        "mems" => (free_hinge(None), 100.0, noisy(1), 500),
        "" => return,
        _ => (free_hinge(None), 100.0, None, 500),
    };
    let recs = records(&hinge, rate, if which == "still" { 102.0 } else { 60.0 }, errs);
    let truth = [hinge.mount[0].transpose() * Vector3::z(), hinge.mount[1].transpose() * Vector3::z()];
    let mut est = KneeSelfAlign::new(KneeSelfAlignParams { window, ..Default::default() }).unwrap();
    let mut sum = 0.0;
    let mut cnt = 0;
    for (k, r) in recs.iter().enumerate() {
        let e = est.step(&r.sample).unwrap();
        if let Some(x) = e.joint[Joint::Knee.index()] {
            sum += wrap(x - r.reference.joint[1].unwrap()).powi(2);
            cnt += 1;
        }
        if (k + 1) % window == 0 || k % 100 == 0 && which == "still" {
            let jt = Vector3::new(d(&e, "j_thigh_x"), d(&e, "j_thigh_y"), d(&e, "j_thigh_z"));
            let js = Vector3::new(d(&e, "j_shank_x"), d(&e, "j_shank_y"), d(&e, "j_shank_z"));
            println!(
                "k {k} t {:.1} status {} jT.true {:.3} jS.true {:.3} conf {:.2} comm {} trust {} src {} spread {:.4} info {:.4} ej {:.3} eo {:.3} err {:.1} rmse {:.1} alpha_acc {:.1} gyro {:.1} kf_x {:.1}",
                r.sample.t,
                d(&e, "window_status"),
                jt.dot(&truth[0]),
                js.dot(&truth[1]),
                d(&e, "sign_confidence"),
                d(&e, "sign_committed"),
                d(&e, "acc_trusted"),
                d(&e, "axis_source"),
                d(&e, "acc_gyro_spread"),
                d(&e, "information"),
                d(&e, "rms_e_j"),
                d(&e, "rms_e_o"),
                e.joint[1].map_or(f64::NAN, |x| wrap(x - r.reference.joint[1].unwrap()).to_degrees()),
                (sum / cnt.max(1) as f64).sqrt().to_degrees(),
                d(&e, "alpha_acc").to_degrees(),
                d(&e, "alpha_gyro").to_degrees(),
                d(&e, "kf_x").to_degrees(),
            );
        }
    }
}
