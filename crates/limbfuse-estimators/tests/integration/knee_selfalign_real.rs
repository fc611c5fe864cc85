//! The self-aligning knee estimator (paper 002) on the real recordings of
//! `../shared/data` (the knee rig and the gaittoolbox trial; skipped with a
//! message when that folder is absent, `LIMBFUSE_DATA` overrides the path):
//! one test per failure cause found on them (issue 15), each of which
//! failed before its fix.
//!
//! Figures: `cargo test --release -p limbfuse-estimators --test integration
//! -- knee_selfalign_real:: --nocapture`.

use std::path::PathBuf;

use limbfuse_core::{Estimator, Joint, Record};
use limbfuse_estimators::knee_gyro_axis::{KneeGyroAxis, KneeGyroAxisParams};
use limbfuse_estimators::knee_selfalign::window::{identify, Ring, Slot, WindowOutcome};
use limbfuse_estimators::knee_selfalign::{KneeSelfAlign, KneeSelfAlignParams};
use limbfuse_io::import::{import_gaittoolbox, import_knee_rig};

pub(crate) fn data_dir() -> Option<PathBuf> {
    let dir = std::env::var_os("LIMBFUSE_DATA")
        .map(PathBuf::from)
        .unwrap_or_else(|| {
            PathBuf::from(concat!(env!("CARGO_MANIFEST_DIR"), "/../../../shared/data"))
        });
    if dir.join("knee-rig").is_dir() && dir.join("gaittoolbox-s02-walk").is_dir() {
        Some(dir)
    } else {
        println!("skipping: ../shared/data (knee-rig, gaittoolbox-s02-walk) not found (set LIMBFUSE_DATA)");
        None
    }
}

pub(crate) fn rig(dir: &std::path::Path, k: usize) -> Vec<Record> {
    import_knee_rig(&dir.join(format!("knee-rig/Trial_0{k}.csv")))
        .unwrap()
        .records
}

/// The rig's windows: 5 s (1250 samples at 250 Hz), as docs/RESULTS.md.
fn rig_params() -> KneeSelfAlignParams {
    KneeSelfAlignParams {
        window: 1250,
        ..Default::default()
    }
}

pub(crate) fn slot(r: &Record) -> Slot {
    let (t, s) = (r.sample.imu[1], r.sample.imu[2]);
    Slot {
        t: r.sample.t,
        gyr: [t.gyr.unwrap_or_default(), s.gyr.unwrap_or_default()],
        acc: [t.acc.unwrap_or_default(), s.acc.unwrap_or_default()],
        gyr_ok: t.gyr.is_some() && s.gyr.is_some(),
        acc_ok: t.acc.is_some() && s.acc.is_some(),
    }
}

/// Pearson correlation of two equally long series.
pub(crate) fn pearson(a: &[f64], b: &[f64]) -> f64 {
    let n = a.len() as f64;
    let (ma, mb) = (a.iter().sum::<f64>() / n, b.iter().sum::<f64>() / n);
    let (mut sab, mut saa, mut sbb) = (0.0, 0.0, 0.0);
    for (x, y) in a.iter().zip(b) {
        sab += (x - ma) * (y - mb);
        saa += (x - ma) * (x - ma);
        sbb += (y - mb) * (y - mb);
    }
    sab / (saa * sbb).sqrt()
}

/// Knee estimate and reference over the samples with both, from `from_s` to
/// `to_s`, the estimate taken `lag` samples later than the reference.
pub(crate) fn paired(
    records: &[Record],
    params: KneeSelfAlignParams,
    span: (f64, f64),
    lag: usize,
) -> (Vec<f64>, Vec<f64>) {
    paired_with(records, &mut KneeSelfAlign::new(params).unwrap(), span, lag)
}

/// [`paired`] for any knee estimator (reset first).
fn paired_with(
    records: &[Record],
    est: &mut dyn Estimator,
    span: (f64, f64),
    lag: usize,
) -> (Vec<f64>, Vec<f64>) {
    est.reset();
    let k = Joint::Knee.index();
    let out: Vec<Option<f64>> = records
        .iter()
        .map(|r| est.step(&r.sample).unwrap().joint[k])
        .collect();
    let (mut e, mut r) = (Vec::new(), Vec::new());
    for (i, rec) in records.iter().enumerate() {
        let t = rec.sample.t;
        if t < span.0 || t > span.1 || i + lag >= out.len() {
            continue;
        }
        if let (Some(a), Some(b)) = (out[i + lag], rec.reference.joint[k]) {
            e.push(a);
            r.push(b);
        }
    }
    (e, r)
}

/// Cause 3 (knee rig): in the first window the relative axis sign was taken
/// from the accelerometer angle even where that angle does not follow the
/// gyro angle (the rig's accelerometers read 1.24 g at rest and the motion
/// is slow: joint-centre accelerations far below the errors), so trials 2, 4
/// and 5 started with the wrong pair (`j_T ~ -z`, `j_S ~ +z`; the README's
/// check uses G1Z - G2Z). Now an untrusted window takes the pair whose gyro
/// angle varies less (thigh and shank swing together).
#[test]
fn rig_first_window_pairs_the_z_axes() {
    let Some(dir) = data_dir() else { return };
    let p = rig_params();
    for k in 1..=5 {
        let records = rig(&dir, k);
        let mut ring = Ring::new(p.window);
        for r in &records[..p.window] {
            ring.push(slot(r));
        }
        let WindowOutcome::Identified { geometry: g, .. } =
            identify(&mut ring, None, None, false, false, &p)
        else {
            panic!("trial {k}: first window not identified");
        };
        println!("Trial_0{k}: j_T {:.2?}, j_S {:.2?}", g.axis[0], g.axis[1]);
        assert!(
            g.axis[0].z.abs() > 0.9 && g.axis[1].z.abs() > 0.9,
            "trial {k}: {g:?}"
        );
        assert!(
            g.axis[0].z * g.axis[1].z > 0.0,
            "trial {k}: wrong pair {g:?}"
        );
    }
}

/// Cause 4 (knee rig): later windows re-chose the pair and the flexion side
/// from the accelerometer angle (changing sides restarts eq 4's integral),
/// committed it on chance evidence (confidence 0.71 from a window whose
/// accelerometer angle scattered by tens of degrees), and Algorithm 1 pulled
/// the angle towards that meaningless accelerometer angle: correlation with
/// the rig angle 0.008 (trial 1, before). Now the sides are kept unless a
/// trusted window says otherwise, and the angle is the high-passed gyro
/// angle while the accelerometer angle is not trusted. The issue-15 target:
/// |correlation| >= 0.95. Trial 2 (the longest-failing: -0.056 before).
#[test]
fn rig_trial_2_correlates_with_the_rig_angle() {
    let Some(dir) = data_dir() else { return };
    let records = rig(&dir, 2);
    let mut est = KneeSelfAlign::new(rig_params()).unwrap();
    let mut flips = 0;
    let mut last_axes: Option<[f64; 2]> = None;
    let k = Joint::Knee.index();
    let (mut e, mut r) = (Vec::new(), Vec::new());
    for rec in &records {
        let out = est.step(&rec.sample).unwrap();
        if let Some(g) = est.geometry() {
            let z = [g.axis[0].z, g.axis[1].z];
            if let Some(old) = last_axes {
                flips += usize::from(old[0] * z[0] < 0.0 || old[1] * z[1] < 0.0);
            }
            last_axes = Some(z);
        }
        if let (Some(a), Some(b)) = (out.joint[k], rec.reference.joint[k]) {
            e.push(a);
            r.push(b);
        }
    }
    let c = pearson(&e, &r);
    println!("Trial_02: corr {c:.4}, side changes {flips}");
    assert_eq!(flips, 0);
    assert!(c.abs() >= 0.95, "{c}");
}

/// Cause 5 (gaittoolbox right knee, s_w = 300): the flexion side came from
/// the mean accelerometer angle, which does not follow the gyro angle there
/// (hinge residual 0.55 rad/s, thigh and shank axes 30 deg apart in the
/// world), and Algorithm 1 pulled the angle towards it: offset-free RMSE
/// 87.6 deg on straight part 2 (4.4-8.72 s), correlation 0.09. Now the side
/// comes from the skewness of the gyro angle (the knee flexes away from full
/// extension) and the drift from the high-pass. Best lag 0..=2 samples (the
/// Xsens streams trail the Vicon by ~2 samples, data README).
#[test]
fn gaittoolbox_knee_flexes_positive_and_follows_the_reference() {
    let Some(dir) = data_dir() else { return };
    let records = import_gaittoolbox(&dir.join("gaittoolbox-s02-walk"))
        .unwrap()
        .records;
    let p = KneeSelfAlignParams {
        window: 300,
        ..Default::default()
    };
    let best = (0..=2)
        .map(|lag| {
            let (e, r) = paired(&records, p, (4.4, 8.72), lag);
            let n = e.len() as f64;
            let d: Vec<f64> = e.iter().zip(&r).map(|(a, b)| a - b).collect();
            let m = d.iter().sum::<f64>() / n;
            let rmse = (d.iter().map(|x| (x - m) * (x - m)).sum::<f64>() / n)
                .sqrt()
                .to_degrees();
            (rmse, pearson(&e, &r), lag)
        })
        .min_by(|a, b| a.0.total_cmp(&b.0))
        .unwrap();
    println!(
        "gaittoolbox straight part 2: offset-free RMSE {:.3} deg, corr {:.4}, lag {} samples",
        best.0, best.1, best.2
    );
    assert!(best.1 > 0.9, "{best:?}");
    assert!(best.0 < 6.0, "{best:?}");
}

/// `knee-gyro-axis` (issue 15 item 4) on knee-rig trial 5: the relative gyro
/// rate about the identified axes, high-passed at 0.02 Hz (the rig's
/// accelerometer angle is not trusted): |correlation| >= 0.95 with the rig
/// angle, and the high-pass is what it uses.
#[test]
fn knee_gyro_axis_on_rig_trial_5() {
    let Some(dir) = data_dir() else { return };
    let records = rig(&dir, 5);
    let mut est = KneeGyroAxis::new(KneeGyroAxisParams {
        axes: rig_params(),
        ..Default::default()
    })
    .unwrap();
    let k = Joint::Knee.index();
    let (mut e, mut r) = (Vec::new(), Vec::new());
    for rec in &records {
        if let (Some(a), Some(b)) = (
            est.step(&rec.sample).unwrap().joint[k],
            rec.reference.joint[k],
        ) {
            e.push(a);
            r.push(b);
        }
    }
    let c = pearson(&e, &r);
    println!("knee-gyro-axis Trial_05: corr {c:.4}");
    assert!(c.abs() >= 0.95, "{c}");
}

/// Offset-free RMSE (deg), correlation and lag of `est` on the gaittoolbox
/// trial's straight part 2 (4.4-8.72 s), the lag of 0..=2 samples with the
/// smallest RMSE (the Xsens streams trail the Vicon by ~2 samples).
fn gaittoolbox_part_2(records: &[Record], est: &mut dyn Estimator) -> (f64, f64, usize) {
    (0..=2)
        .map(|lag| {
            let (e, r) = paired_with(records, est, (4.4, 8.72), lag);
            let n = e.len() as f64;
            let d: Vec<f64> = e.iter().zip(&r).map(|(a, b)| a - b).collect();
            let m = d.iter().sum::<f64>() / n;
            let rmse = (d.iter().map(|x| (x - m) * (x - m)).sum::<f64>() / n)
                .sqrt()
                .to_degrees();
            (rmse, pearson(&e, &r), lag)
        })
        .min_by(|a, b| a.0.total_cmp(&b.0))
        .unwrap()
}

/// Issue 15, gaittoolbox target (offset-free RMSE <= 4 deg on the straight
/// passes, lag <= 2 samples). Eq 2's hinge leaves 0.55 rad/s RMS on this
/// knee and its axes absorb the thigh's rotation about its long axis (42 %
/// of the thigh gyro's energy): 4.985 deg before, with paper 002's axes
/// (`axis_prior: None`, still printed). The upright-leg prior (ours,
/// `knee_selfalign::upright`) takes each axis as the dominant rotation
/// perpendicular to the segment's mean specific force, and keeps the
/// previous axes over the turn: 3.31 deg.
#[test]
fn issue_15_gaittoolbox_upright_axis_prior_within_4_deg() {
    let Some(dir) = data_dir() else { return };
    let records = import_gaittoolbox(&dir.join("gaittoolbox-s02-walk"))
        .unwrap()
        .records;
    let p = KneeSelfAlignParams {
        window: 300,
        ..Default::default()
    };
    let paper = gaittoolbox_part_2(
        &records,
        &mut KneeSelfAlign::new(KneeSelfAlignParams {
            axis_prior: None,
            ..p
        })
        .unwrap(),
    );
    let ours = gaittoolbox_part_2(&records, &mut KneeSelfAlign::new(p).unwrap());
    println!(
        "gaittoolbox part 2, offset-free RMSE / corr / lag: eq 2 alone {:.3} deg / {:.4} / {}, upright prior {:.3} deg / {:.4} / {}",
        paper.0, paper.1, paper.2, ours.0, ours.1, ours.2
    );
    assert!(ours.0 <= 4.0, "{ours:?}");
    assert!(ours.1 > 0.98, "{ours:?}");
}

/// Issue 15: `knee-gyro-axis` on the gaittoolbox trial with the upright
/// prior. Its own trust test (the inclination minus the gyro angle, smoothed
/// over a stride) passed by chance on the turn window and pulled the angle
/// to an inclination swinging ~100 deg per stride against the gyro angle
/// (63.9 deg on part 2); the inclination is now used only where
/// `knee-selfalign` trusts its full accelerometer angle too.
#[test]
fn issue_15_knee_gyro_axis_gaittoolbox_within_4_deg() {
    let Some(dir) = data_dir() else { return };
    let records = import_gaittoolbox(&dir.join("gaittoolbox-s02-walk"))
        .unwrap()
        .records;
    let mut est = KneeGyroAxis::new(KneeGyroAxisParams {
        axes: KneeSelfAlignParams {
            window: 300,
            ..Default::default()
        },
        ..Default::default()
    })
    .unwrap();
    let best = gaittoolbox_part_2(&records, &mut est);
    println!(
        "knee-gyro-axis gaittoolbox part 2: offset-free RMSE {:.3} deg, corr {:.4}, lag {}",
        best.0, best.1, best.2
    );
    assert!(best.0 <= 4.0, "{best:?}");
}

/// Generalisation audit (2026-12-05): the knee rig's trials started 5.5 or
/// 6.1 s later gave the knee angle negated on all five (offset-free 2.4 ->
/// 20 deg, correlation -0.99): with the relative sign never committed (the
/// rig's accelerometer angle is never trusted), the first window's
/// gyro-angle skewness chose the flexion side for the whole trial, and a
/// 5 s window is part of the rig's cycle. The skewness is now pooled over
/// the windows while the sign is open (`sign::FlexionEvidence`).
#[test]
fn rig_started_late_still_flexes_positive() {
    let Some(dir) = data_dir() else { return };
    let k = Joint::Knee.index();
    for trial in 1..=5 {
        let records = rig(&dir, trial);
        for start in [5.5, 6.1] {
            let mut est = KneeSelfAlign::new(rig_params()).unwrap();
            let (mut e, mut r) = (Vec::new(), Vec::new());
            for rec in records.iter().filter(|rec| rec.sample.t >= start) {
                let out = est.step(&rec.sample).unwrap();
                if rec.sample.t < 30.0 {
                    continue;
                }
                if let (Some(a), Some(b)) = (out.joint[k], rec.reference.joint[k]) {
                    e.push(a);
                    r.push(b);
                }
            }
            let c = pearson(&e, &r);
            println!("Trial_0{trial} from {start} s: corr {c:.4}");
            assert!(c >= 0.95, "Trial_0{trial} from {start} s: {c}");
        }
    }
}

/// Bisection of the rig's 2 s windows (2026-12-05): with `s_w` = 500 (2 s
/// at 250 Hz) the first window, nearly still (the rig starts at rest), has
/// no accelerometer evidence, so its gyro-angle skewness chose the flexion
/// side, but the pooled skewness (`sign::FlexionEvidence`) left it out; the
/// second window (the first rise and fall, skewness -0.58) alone then
/// flipped both axes for 2 s and the third flipped them back: the knee
/// negated over 4-6 s and eq 4 restarted twice (Trial_02 r 0.9850 ->
/// 0.9632, knee-gyro-axis Trial_02-05 r 0.984-0.987 -> 0.960-0.965). The
/// first window's skewness now counts in the pool: r as before the pooling.
#[test]
fn rig_first_window_flexion_side_is_pooled() {
    let Some(dir) = data_dir() else { return };
    let p = KneeSelfAlignParams {
        window: 500,
        ..Default::default()
    };
    for trial in 2..=5 {
        let records = rig(&dir, trial);
        let mut kga = KneeGyroAxis::new(KneeGyroAxisParams {
            axes: p,
            ..Default::default()
        })
        .unwrap();
        let mut ksa = KneeSelfAlign::new(p).unwrap();
        let mut runs: Vec<(&str, &mut dyn Estimator)> = vec![("kga", &mut kga)];
        if trial == 2 {
            // knee-selfalign loses Trial_03-05 after ~100 s at 2 s windows
            // for another reason (section "the window in seconds").
            runs.push(("ksa", &mut ksa));
        }
        for (name, est) in runs {
            let (e, r) = paired_with(&records, est, (0.0, f64::INFINITY), 0);
            let c = pearson(&e, &r);
            println!("Trial_0{trial} {name} s_w 500: corr {c:.4}");
            assert!(c >= 0.98, "Trial_0{trial} {name}: {c}");
        }
    }
}
