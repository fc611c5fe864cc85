//! The flexion side's skewness evidence per window against the size of the
//! knee's motion in that window, on the shared recordings (2026-12-05;
//! figures only, ignored): docs/RESULTS.md "Flexion side: a trusted window,
//! small motions, S02's level from a late start".
//!
//! `cargo test --release -p limbfuse-estimators --test integration --
//! knee_flexion_evidence:: --nocapture --include-ignored`.

use crate::shared_data_support::{data_dir, read};
use limbfuse_core::{Estimator, Record};
use limbfuse_estimators::knee_selfalign::angle::gyro_angle_rate;
use limbfuse_estimators::knee_selfalign::sign::gyro_angle_moments;
use limbfuse_estimators::knee_selfalign::window::{Ring, Slot};
use limbfuse_estimators::knee_selfalign::{KneeSelfAlign, KneeSelfAlignParams, WindowStatus};
use limbfuse_io::import::{import_gaittoolbox, import_knee_rig};

use crate::knee_selfalign_real::slot;

/// One window: skewness in the sense of the axes the estimator chose, range
/// of the gyro angle (deg), its standard deviation (deg).
type WindowSkew = (f64, f64, f64);

/// [`WindowSkew`] of every identified, uncommitted window.
fn windows(records: &[Record], window: usize) -> Vec<WindowSkew> {
    let mut est = KneeSelfAlign::new(KneeSelfAlignParams {
        window,
        ..Default::default()
    })
    .unwrap();
    let mut out = Vec::new();
    for (i, r) in records.iter().enumerate() {
        let (n, committed) = (est.windows(), est.sign_state().1);
        est.step(&r.sample).unwrap();
        if est.windows() == n || committed || est.last_window().0 != WindowStatus::Identified {
            continue;
        }
        let g = *est.geometry().unwrap();
        let mut ring = Ring::new(window);
        records[i + 1 - window..=i]
            .iter()
            .for_each(|r| ring.push(slot(r)));
        let (m2, m3) = gyro_angle_moments(&ring, &g);
        let (mut a, mut lo, mut hi) = (0.0f64, 0.0f64, 0.0f64);
        for k in 1..ring.len() {
            let (s0, s1) = (ring.get(k - 1), ring.get(k));
            let rate = |s: &Slot| gyro_angle_rate(&s.gyr[0], &s.gyr[1], &g.axis[0], &g.axis[1]);
            a += 0.5 * (rate(s0) + rate(s1)) * (s1.t - s0.t);
            (lo, hi) = (lo.min(a), hi.max(a));
        }
        let skew = if m2 > 0.0 { m3 / m2.powf(1.5) } else { 0.0 };
        out.push((skew, (hi - lo).to_degrees(), m2.sqrt().to_degrees()));
    }
    out
}

#[test]
#[ignore]
fn skewness_against_motion_size() {
    let Some(dir) = data_dir(&["knee-rig", "gaittoolbox-s02-walk", "independent-sim"]) else {
        return;
    };
    let mut runs: Vec<(String, Vec<WindowSkew>)> = Vec::new();
    for k in 1..=5 {
        let records = import_knee_rig(&dir.join(format!("knee-rig/Trial_0{k}.csv")))
            .unwrap()
            .records;
        for w in [500, 1250] {
            runs.push((format!("rig0{k} w{w}"), windows(&records, w)));
        }
    }
    let s02 = import_gaittoolbox(&dir.join("gaittoolbox-s02-walk"))
        .unwrap()
        .records;
    for w in [300, 500] {
        runs.push((format!("s02 w{w}"), windows(&s02, w)));
    }
    for name in ["walk-v0.7-s300", "walk-v1.2-s301", "walk-v1.6-s302"] {
        let records = read(&dir.join(format!("independent-sim/{name}.csv")));
        runs.push((name.to_string(), windows(&records, 500)));
    }
    let bins = [(0.0, 5.0), (5.0, 10.0), (10.0, 20.0), (20.0, f64::INFINITY)];
    let mut tally = [(0usize, 0usize, 0.0f64, 0.0f64); 4];
    for (name, ws) in &runs {
        let (mut sum, mut min, mut wsum, mut wmin) = (0.0f64, f64::INFINITY, 0.0f64, f64::INFINITY);
        for &(skew, range, sd) in ws {
            println!("{name}: skew {skew:+.3} range {range:.1} deg sd {sd:.1} deg");
            sum += skew;
            wsum += skew * sd * sd;
            (min, wmin) = (min.min(sum), wmin.min(wsum));
            let b = bins
                .iter()
                .position(|&(lo, hi)| range >= lo && range < hi)
                .unwrap();
            tally[b].0 += 1;
            tally[b].2 += skew;
            if skew < 0.0 {
                tally[b].1 += 1;
                tally[b].3 += skew;
            }
        }
        println!(
            "{name}: {} windows, skewness sum {sum:.2} (lowest running {min:.2}); weighted by m2 (deg^2) {wsum:.1} (lowest running {wmin:.1})",
            ws.len()
        );
    }
    for (b, (n, neg, s, sneg)) in bins.iter().zip(tally) {
        println!(
            "range {:.0}-{:.0} deg: {n} windows, {neg} with negative skewness (sum {sneg:.2}); all: sum {s:.2}",
            b.0, b.1
        );
    }
}
