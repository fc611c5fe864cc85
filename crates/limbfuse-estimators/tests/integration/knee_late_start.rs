//! Knee methods on recordings that start later (2026-12-05): the regression
//! test of the S02 walk started in its turn, and the sweeps of start
//! offsets on the shared recordings (ignored: figures only).
//!
//! Figures: `cargo test --release -p limbfuse-estimators --test integration
//! -- knee_late_start:: --nocapture --include-ignored`.

use crate::knee_selfalign_real::pearson;
use crate::shared_data_support::{data_dir, read};
use limbfuse_core::{Estimator, Joint, Record};
use limbfuse_estimators::knee_gyro_axis::{KneeGyroAxis, KneeGyroAxisParams};
use limbfuse_estimators::knee_selfalign::angle::wrap;
use limbfuse_estimators::knee_selfalign::{KneeDiag, KneeSelfAlign, KneeSelfAlignParams};
use limbfuse_io::import::{import_gaittoolbox, import_knee_rig};

/// Absolute and offset-free RMSE (deg), correlation and count of the knee of
/// `est` run on `records` from `start` s, scored over `spans`, the estimate
/// taken `lag` samples later than the reference.
pub fn score(
    records: &[Record],
    est: &mut dyn Estimator,
    start: f64,
    spans: &[(f64, f64)],
    lag: usize,
) -> (f64, f64, f64, usize) {
    est.reset();
    let k = Joint::Knee.index();
    let recs: Vec<&Record> = records.iter().filter(|r| r.sample.t >= start).collect();
    let out: Vec<Option<f64>> = recs
        .iter()
        .map(|r| est.step(&r.sample).unwrap().joint[k])
        .collect();
    let mut d = Vec::new();
    let (mut e, mut r) = (Vec::new(), Vec::new());
    for (i, rec) in recs.iter().enumerate() {
        let t = rec.sample.t;
        if !spans.iter().any(|s| t >= s.0 && t <= s.1) || i + lag >= out.len() {
            continue;
        }
        if let (Some(a), Some(b)) = (out[i + lag], rec.reference.joint[k]) {
            d.push(wrap(a - b));
            e.push(a);
            r.push(b);
        }
    }
    let n = d.len();
    if n == 0 {
        return (f64::NAN, f64::NAN, f64::NAN, 0);
    }
    let nf = n as f64;
    let m = d.iter().sum::<f64>() / nf;
    let abs = (d.iter().map(|x| x * x).sum::<f64>() / nf)
        .sqrt()
        .to_degrees();
    let free = (d.iter().map(|x| (x - m) * (x - m)).sum::<f64>() / nf)
        .sqrt()
        .to_degrees();
    (abs, free, pearson(&e, &r), n)
}

/// The best of lags 0..=2 by offset-free RMSE.
fn best_lag(
    records: &[Record],
    est: &mut dyn Estimator,
    start: f64,
    spans: &[(f64, f64)],
) -> (f64, f64, f64, usize) {
    (0..=2)
        .map(|lag| score(records, est, start, spans, lag))
        .min_by(|a, b| a.1.total_cmp(&b.1))
        .unwrap()
}

fn starts() -> Vec<f64> {
    (0..=30).map(|i| i as f64 * 0.2).collect()
}

fn methods(p: KneeSelfAlignParams) -> [(&'static str, Box<dyn Estimator>); 2] {
    [
        ("ksa", Box::new(KneeSelfAlign::new(p).unwrap())),
        (
            "kga",
            Box::new(
                KneeGyroAxis::new(KneeGyroAxisParams {
                    axes: p,
                    ..Default::default()
                })
                .unwrap(),
            ),
        ),
    ]
}

/// The shared S02 walk started 0.8 and 1.8-2.6 s later, `s_w` = 300: the
/// first window (3 s) holds the start of the turn on the spot (3.6-4.4 s)
/// or all of it, so it shows no flexion axis (the upright prior's "no
/// flexion"); its eq-2 axes were taken, later windows kept their sides by
/// continuity and eq 4 integrated the turn about them: straight part 2
/// (4.4-8.72 s) offset-free 8.2 / 21.7 / 21.4 / 18.7 / 19.6 / 31.0 deg,
/// correlation 0.92 down to -0.74 (both methods). Such a first window is
/// now not taken (`KneeSelfAlign::defers`): 5.5 / 3.6 / 3.7 / 3.8 / 3.1 /
/// 0.6 deg, correlation >= 0.98 (3.3 from the walk's start).
#[test]
fn s02_started_in_its_turn_keeps_the_knee() {
    let Some(dir) = data_dir(&["gaittoolbox-s02-walk"]) else {
        return;
    };
    let records = import_gaittoolbox(&dir.join("gaittoolbox-s02-walk"))
        .unwrap()
        .records;
    let p = KneeSelfAlignParams {
        window: 300,
        ..Default::default()
    };
    for (name, mut est) in methods(p) {
        for start in [0.8, 1.8, 2.0, 2.2, 2.4, 2.6] {
            let (_, free, r, n) = best_lag(&records, est.as_mut(), start, &[(4.4, 8.72)]);
            println!("{name} from {start} s: part 2 offset-free {free:.2} deg, corr {r:.3}, n {n}");
            assert!(
                n > 0 && free < 6.0 && r > 0.95,
                "{name} from {start} s: offset-free {free} deg, corr {r}, n {n}"
            );
        }
    }
}

#[test]
#[ignore]
fn sweep_s02() {
    let Some(dir) = data_dir(&["gaittoolbox-s02-walk"]) else {
        return;
    };
    let records = import_gaittoolbox(&dir.join("gaittoolbox-s02-walk"))
        .unwrap()
        .records;
    for window in [300, 500] {
        let p = KneeSelfAlignParams {
            window,
            ..Default::default()
        };
        for (name, mut est) in methods(p) {
            for s in starts() {
                let a = best_lag(&records, est.as_mut(), s, &[(4.4, 8.72)]);
                let b = best_lag(&records, est.as_mut(), s, &[(0.45, 3.55), (4.4, 8.72)]);
                println!(
                    "S02 w{window} {name} start {s:.1}: part2 abs {:.2} free {:.2} r {:.3} n {} | both abs {:.2} free {:.2} n {}",
                    a.0, a.1, a.2, a.3, b.0, b.1, b.3
                );
            }
        }
    }
}

#[test]
#[ignore]
fn sweep_walks() {
    let Some(dir) = data_dir(&["independent-sim"]) else {
        return;
    };
    for name in ["walk-v0.7-s300", "walk-v1.2-s301", "walk-v1.6-s302"] {
        let records = read(&dir.join(format!("independent-sim/{name}.csv")));
        for (m, mut est) in methods(KneeSelfAlignParams::default()) {
            for s in starts() {
                let a = score(&records, est.as_mut(), s, &[(s + 10.0, 1e9)], 0);
                println!(
                    "{name} {m} start {s:.1}: abs {:.3} free {:.3} r {:.4} n {}",
                    a.0, a.1, a.2, a.3
                );
            }
        }
    }
}

#[test]
#[ignore]
fn sweep_rig() {
    let Some(dir) = data_dir(&["knee-rig"]) else {
        return;
    };
    for k in 1..=5 {
        let records = import_knee_rig(&dir.join(format!("knee-rig/Trial_0{k}.csv")))
            .unwrap()
            .records;
        let window = std::env::var("LATE_WINDOW")
            .ok()
            .and_then(|s| s.parse().ok())
            .unwrap_or(1250);
        let p = KneeSelfAlignParams {
            window,
            ..Default::default()
        };
        for (m, mut est) in methods(p) {
            let only: Option<f64> = std::env::var("LATE_START")
                .ok()
                .and_then(|s| s.parse().ok());
            for s in only.map_or_else(starts, |s| vec![s]) {
                let a = score(&records, est.as_mut(), s, &[(30.0, 1e9)], 0);
                println!(
                    "rig{k} {m} start {s:.1}: abs {:.3} free {:.3} r {:.4} n {}",
                    a.0, a.1, a.2, a.3
                );
            }
        }
    }
}

/// Per-window diagnostics of knee-selfalign on S02 from `LATE_START`.
#[test]
#[ignore]
fn diag_s02() {
    let Some(dir) = data_dir(&["gaittoolbox-s02-walk"]) else {
        return;
    };
    let records = import_gaittoolbox(&dir.join("gaittoolbox-s02-walk"))
        .unwrap()
        .records;
    let start: f64 = std::env::var("LATE_START")
        .ok()
        .and_then(|s| s.parse().ok())
        .unwrap_or(0.8);
    let window: usize = std::env::var("LATE_WINDOW")
        .ok()
        .and_then(|s| s.parse().ok())
        .unwrap_or(300);
    let mut est = KneeSelfAlign::new(KneeSelfAlignParams {
        window,
        ..Default::default()
    })
    .unwrap();
    let k = Joint::Knee.index();
    let mut last_w = 0.0;
    for r in records.iter().filter(|r| r.sample.t >= start) {
        let e = est.step(&r.sample).unwrap();
        let g = |d: KneeDiag| e.diagnostic(d).unwrap_or(f64::NAN);
        let w = g(KneeDiag::Windows);
        if w != last_w || (r.sample.t * 100.0).round() as i64 % 25 == 0 {
            println!(
                "t {:.2} w {} status {} src {} conf {:.2} comm {} trusted {} spread {:.3} ej {:.3} jT [{:.2} {:.2} {:.2}] jS [{:.2} {:.2} {:.2}] knee {:.1} ref {:.1} kfx {:.1}",
                r.sample.t,
                w,
                g(KneeDiag::WindowStatus),
                g(KneeDiag::AxisSource),
                g(KneeDiag::SignConfidence),
                g(KneeDiag::SignCommitted),
                g(KneeDiag::AccTrusted),
                g(KneeDiag::AccGyroSpread),
                g(KneeDiag::RmsEJ),
                g(KneeDiag::AXIS[0][0]),
                g(KneeDiag::AXIS[0][1]),
                g(KneeDiag::AXIS[0][2]),
                g(KneeDiag::AXIS[1][0]),
                g(KneeDiag::AXIS[1][1]),
                g(KneeDiag::AXIS[1][2]),
                e.joint[k].map_or(f64::NAN, f64::to_degrees),
                r.reference.joint[k].map_or(f64::NAN, f64::to_degrees),
                g(KneeDiag::KfX).to_degrees(),
            );
            last_w = w;
        }
    }
}
