mod knee_hinge;
use knee_hinge::{records, rot, Hinge, HingeMotion, SensorErrors, Still};
use limbfuse_core::{Estimator, Joint, Record, Segment};
use limbfuse_estimators::knee_gyro_axis::{KneeGyroAxis, KneeGyroAxisParams};

use limbfuse_estimators::knee_selfalign::{KneeSelfAlign, KneeSelfAlignParams};
use limbfuse_sim::{KneeScenario, KneeSimulator, Mounting, WalkingConfig};
use nalgebra::Vector3;
use std::sync::atomic::Ordering;

fn hinge(still: Option<Still>, motion: HingeMotion) -> Hinge {
    Hinge {
        mount: [
            rot(Vector3::new(0.3, -1.0, 0.6), 2.1),
            rot(Vector3::new(-0.8, 0.2, 0.5), -1.4),
        ],
        point: [
            Vector3::new(0.0, 0.21, 0.08),
            Vector3::new(0.0, -0.19, 0.06),
        ],
        motion,
        still,
    }
}
fn wrap(x: f64) -> f64 {
    let t = std::f64::consts::TAU;
    x - t * ((x + std::f64::consts::PI) / t).floor()
}
fn sc(out: &[Option<f64>], recs: &[Record], from: usize, to: usize) -> (f64, f64) {
    let e: Vec<f64> = out
        .iter()
        .zip(recs)
        .take(to)
        .skip(from)
        .filter_map(|(e, r)| Some(wrap(e.as_ref()? - r.reference.joint[Joint::Knee.index()]?)))
        .collect();
    let n = e.len().max(1) as f64;
    let m = e.iter().sum::<f64>() / n;
    let ms = e.iter().map(|x| x * x).sum::<f64>() / n;
    (
        ms.sqrt().to_degrees(),
        (ms - m * m).max(0.0).sqrt().to_degrees(),
    )
}
fn both(recs: &[Record], from: usize, to: usize) -> String {
    let mut a = KneeSelfAlign::new(KneeSelfAlignParams::default()).unwrap();
    let mut b = KneeGyroAxis::new(KneeGyroAxisParams::default()).unwrap();
    let k = Joint::Knee.index();
    let oa: Vec<_> = recs
        .iter()
        .map(|r| a.step(&r.sample).unwrap().joint[k])
        .collect();
    let ob: Vec<_> = recs
        .iter()
        .map(|r| b.step(&r.sample).unwrap().joint[k])
        .collect();
    let (x, y) = (sc(&oa, recs, from, to), sc(&ob, recs, from, to));
    format!("{:.2}({:.2})/{:.2}({:.2})", x.0, x.1, y.0, y.1)
}
fn knee_walk(seed: u64) -> Vec<Record> {
    KneeSimulator::new(KneeScenario {
        walking: WalkingConfig {
            seed,
            mounting: Mounting::Random,
            ..WalkingConfig::default()
        },
        ..KneeScenario::default()
    })
    .unwrap()
    .collect()
}
#[test]
fn scratch() {
    let noisy = |seed, scale, bias| {
        Some(SensorErrors {
            seed,
            acc_scale: scale,
            bias,
        })
    };
    let still = records(
        &hinge(
            Some(Still {
                start_s: 20.0,
                still_s: 60.0,
            }),
            HingeMotion::WalkLike,
        ),
        100.0,
        102.0,
        noisy(1, [1.0, 1.0], [1.0, 1.0]),
    );
    let h = hinge(None, HingeMotion::Free3d);
    let f1 = records(&h, 100.0, 60.0, noisy(1, [1.0, 1.0], [1.0, 1.0]));
    let f2 = records(&h, 100.0, 60.0, noisy(2, [1.0, 1.0], [1.0, 1.0]));
    let fb = records(&h, 100.0, 60.0, noisy(1, [1.0, 1.0], [0.0, 1.0]));
    let fs = records(&h, 100.0, 60.0, noisy(1, [1.25, 1.0], [1.0, 1.0]));
    let k3 = knee_walk(3);
    let k4 = knee_walk(4);
    let mut k3s = k3.clone();
    for r in k3s.iter_mut() {
        if let Some(a) = r.sample.imu[Segment::Thigh.index()].acc.as_mut() {
            *a *= 1.25;
        }
    }
    let mut k4s = k4.clone();
    for r in k4s.iter_mut() {
        if let Some(a) = r.sample.imu[Segment::Shank.index()].acc.as_mut() {
            *a *= 0.8;
        }
    }
    for (thr, fus) in [(0.0, true)] {
        println!("thr {thr} fusion {fus}: still {} | f1 {} | f2 {} | accbias {} | f1 1.25 {} | k3 {} | k4 {} | k3 T1.25 {} | k4 S0.8 {}",
            both(&still, 2100, 8100), both(&f1, 2000, 6000), both(&f2, 2000, 6000), both(&fb, 2000, 6000), both(&fs, 2000, 6000),
            both(&k3, 1000, 6000), both(&k4, 1000, 6000), both(&k3s, 1000, 6000), both(&k4s, 1000, 6000));
    }
}
#[test]
fn scratch_first() {
    for seed in [1u64, 2, 3, 4, 5] {
        let recs: Vec<Record> = KneeSimulator::new(KneeScenario {
            walking: WalkingConfig {
                seed,
                imu_rate_hz: 40.0,
                mounting: Mounting::Random,
                ..WalkingConfig::default()
            },
            ..KneeScenario::default()
        })
        .unwrap()
        .collect();
        let mut a = KneeSelfAlign::new(KneeSelfAlignParams::default()).unwrap();
        let mut b = KneeGyroAxis::new(KneeGyroAxisParams::default()).unwrap();
        let k = Joint::Knee.index();
        let oa: Vec<_> = recs
            .iter()
            .map(|r| a.step(&r.sample).unwrap().joint[k])
            .collect();
        let ob: Vec<_> = recs
            .iter()
            .map(|r| b.step(&r.sample).unwrap().joint[k])
            .collect();
        let first = oa.iter().position(|x| x.is_some()).unwrap();
        let firstb = ob.iter().position(|x| x.is_some()).unwrap();
        let line: Vec<String> = (0..4)
            .map(|i| {
                let t = recs[first + i].reference.joint[k].unwrap();
                format!(
                    "true {:.1} ksa {:.1} kga {:.1}",
                    t.to_degrees(),
                    oa[first + i].unwrap().to_degrees(),
                    ob[first + i].unwrap().to_degrees()
                )
            })
            .collect();
        println!("seed {seed} first {first} {firstb}: {}", line.join(" | "));
    }
}
#[test]
fn scratch_first_hinge() {
    for (motion, w) in [
        (HingeMotion::WalkLike, 500usize),
        (HingeMotion::WalkLike, 200),
        (HingeMotion::WalkLike, 300),
        (HingeMotion::Free3d, 500),
    ] {
        let recs = records(&hinge(None, motion), 40.0, 30.0, None);
        let p = KneeSelfAlignParams {
            window: w,
            ..Default::default()
        };
        let mut a = KneeSelfAlign::new(p).unwrap();
        let mut b = KneeGyroAxis::new(KneeGyroAxisParams {
            axes: p,
            ..Default::default()
        })
        .unwrap();
        let k = Joint::Knee.index();
        let oa: Vec<_> = recs
            .iter()
            .map(|r| a.step(&r.sample).unwrap().joint[k])
            .collect();
        let ob: Vec<_> = recs
            .iter()
            .map(|r| b.step(&r.sample).unwrap().joint[k])
            .collect();
        let first = oa.iter().position(|x| x.is_some()).unwrap();
        let line: Vec<String> = (0..4)
            .map(|i| {
                let t = recs[first + i].reference.joint[k].unwrap();
                format!(
                    "true {:.1} ksa {:.1} kga {:.1}",
                    t.to_degrees(),
                    oa[first + i].unwrap().to_degrees(),
                    ob[first + i].unwrap().to_degrees()
                )
            })
            .collect();
        println!(
            "w {w} first {first}: {} trusted {}",
            line.join(" | "),
            a.acc_trusted()
        );
    }
}
