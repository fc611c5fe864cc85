//! Gaittoolbox importer: the shared walking trial (skipped when
//! `../shared/data` is absent) and bad input in small temporary folders.
//!
//! Figures for docs/IMPORTERS.md:
//! `cargo test -p limbfuse-io --test integration -- import_gaittoolbox:: --nocapture`

use std::ops::Range;
use std::path::{Path, PathBuf};

use limbfuse_core::{Joint, Record, Segment};
use limbfuse_io::import::{
    import_gaittoolbox, import_gaittoolbox_with, GaittoolboxOptions, ImportedTrial,
};
use limbfuse_io::{TrialReader, TrialWriter};
use nalgebra::{Matrix3, Quaternion, UnitQuaternion, Vector3};

/// The shared S02 folder, or `None` with a skip message.
pub(crate) fn data_dir() -> Option<PathBuf> {
    let dir = std::env::var_os("LIMBFUSE_DATA")
        .map(PathBuf::from)
        .unwrap_or_else(|| {
            PathBuf::from(concat!(env!("CARGO_MANIFEST_DIR"), "/../../../shared/data"))
        });
    if dir.join("gaittoolbox-s02-walk").is_dir() {
        Some(dir.join("gaittoolbox-s02-walk"))
    } else {
        println!("skipping: ../shared/data not found (set LIMBFUSE_DATA)");
        None
    }
}

/// Name, getter, allowed band of the minimum and of the maximum (deg).
type Band = (
    &'static str,
    fn(&Record) -> Option<f64>,
    (f64, f64),
    (f64, f64),
);

fn straight_parts(trial: &ImportedTrial) -> Vec<Range<usize>> {
    let text = trial.meta.get("straight_segments").unwrap();
    text.split(',')
        .map(|r| {
            let (a, b) = r.split_once("..").unwrap();
            a.parse().unwrap()..b.parse().unwrap()
        })
        .collect()
}

fn median(mut v: Vec<f64>) -> f64 {
    v.sort_by(f64::total_cmp);
    v[v.len() / 2]
}

/// Correlation of the best 3-axis linear fit of `gyr[k + lag]` to `rate[k]` over `idx`.
fn fit_corr(gyr: &[Vector3<f64>], rate: &[f64], idx: &[usize], lag: i64) -> f64 {
    let ks: Vec<usize> = idx
        .iter()
        .copied()
        .filter(|&k| (0..gyr.len() as i64).contains(&(k as i64 + lag)))
        .collect();
    let (mut ata, mut atb) = (Matrix3::zeros(), Vector3::zeros());
    for &k in &ks {
        let g = gyr[(k as i64 + lag) as usize];
        ata += g * g.transpose();
        atb += g * rate[k];
    }
    let w = ata.lu().solve(&atb).unwrap();
    let pred: Vec<f64> = ks
        .iter()
        .map(|&k| gyr[(k as i64 + lag) as usize].dot(&w))
        .collect();
    let obs: Vec<f64> = ks.iter().map(|&k| rate[k]).collect();
    let n = pred.len() as f64;
    let (mp, mo) = (pred.iter().sum::<f64>() / n, obs.iter().sum::<f64>() / n);
    let cov: f64 = pred
        .iter()
        .zip(&obs)
        .map(|(p, o)| (p - mp) * (o - mo))
        .sum();
    let vp: f64 = pred.iter().map(|p| (p - mp).powi(2)).sum();
    let vo: f64 = obs.iter().map(|o| (o - mo).powi(2)).sum();
    cov / (vp * vo).sqrt()
}

#[test]
fn shared_trial_imports_with_normal_gait_ranges() {
    let Some(dir) = data_dir() else { return };
    let trial = import_gaittoolbox(&dir).unwrap();
    let r = &trial.records;
    assert_eq!(r.len(), 955);
    assert_eq!(trial.meta.get("sample_rate_hz"), Some("100"));
    assert!(r[0].sample.t == 0.0 && r.windows(2).all(|w| w[1].sample.t > w[0].sample.t));
    assert!((r[954].sample.t - 9.54).abs() < 1e-9);
    let l = &trial.layout;
    assert!(l.acc == [true; 4] && l.gyr == [true; 4] && l.quat == [true; 4]);
    assert_eq!(
        l.segment_ref,
        [false, true, true, true],
        "no trunk reference"
    );
    assert_eq!(l.joint_ref, [false, true, true]);

    // Units: accelerometer norm median about g, gyro rates of walking, unit quaternions.
    for s in Segment::ALL {
        let i = s.index();
        let acc = median(
            r.iter()
                .map(|x| x.sample.imu[i].acc.unwrap().norm())
                .collect(),
        );
        let gyr = r
            .iter()
            .map(|x| x.sample.imu[i].gyr.unwrap().norm())
            .fold(0.0, f64::max);
        let q = r[500].sample.imu[i].quat.unwrap();
        assert!((q.iter().map(|c| c * c).sum::<f64>() - 1.0).abs() < 1e-12);
        println!(
            "{}: acc norm median {acc:.2} m/s^2, max |gyr| {gyr:.2} rad/s",
            s.name()
        );
        assert!(
            (9.3..10.8).contains(&acc) && (2.0..15.0).contains(&gyr),
            "{}: {acc} {gyr}",
            s.name()
        );
    }
    // Xsens quaternion: w first, sensor -> world (z up): the specific force in
    // world coordinates averages to (0, 0, g).
    for s in Segment::ALL {
        let mut mean = Vector3::zeros();
        for x in r {
            let (q, a) = (
                x.sample.imu[s.index()].quat.unwrap(),
                x.sample.imu[s.index()].acc.unwrap(),
            );
            let q = UnitQuaternion::from_quaternion(Quaternion::new(q[0], q[1], q[2], q[3]));
            mean += q * a / r.len() as f64;
        }
        println!(
            "{}: mean specific force in the Xsens world frame {:.2?}",
            s.name(),
            mean.as_slice()
        );
        assert!(
            mean.xy().norm() < 0.3 && (mean.z - 9.85).abs() < 0.2,
            "{mean:?}"
        );
    }
    let all_acc = median(
        r.iter()
            .flat_map(|x| x.sample.imu.iter().map(|m| m.acc.unwrap().norm()))
            .collect(),
    );
    println!("acc norm median over the 4 IMUs: {all_acc:.3} m/s^2");
    assert!((9.6..10.3).contains(&all_acc));

    // Straight parts: the walk out, and the walk back after the turn (~330-500).
    let parts = straight_parts(&trial);
    println!(
        "straight parts (samples): {parts:?}; foot offset {} deg",
        trial.meta.get("foot_offset_deg").unwrap()
    );
    assert_eq!(parts.len(), 2);
    assert!(parts[0].start < 100 && (300..400).contains(&parts[0].end));
    assert!((400..520).contains(&parts[1].start) && parts[1].end > 800);
    let off: f64 = trial.meta.get("foot_offset_deg").unwrap().parse().unwrap();
    assert!(
        (70.0..90.0).contains(&off),
        "ankle->toe vector points forward and down when flat: {off}"
    );

    // Reference ranges on the straight parts against normal gait
    // (Winter 2009; Perry & Burnfield 2010; see docs/IMPORTERS.md).
    let bands: [Band; 5] = [
        (
            "thigh",
            |x| x.reference.segment[Segment::Thigh.index()],
            (-35.0, -10.0),
            (15.0, 35.0),
        ),
        (
            "shank",
            |x| x.reference.segment[Segment::Shank.index()],
            (-70.0, -45.0),
            (10.0, 35.0),
        ),
        (
            "foot",
            |x| x.reference.segment[Segment::Foot.index()],
            (-85.0, -45.0),
            (15.0, 45.0),
        ),
        (
            "knee",
            |x| x.reference.joint[Joint::Knee.index()],
            (-10.0, 10.0),
            (50.0, 75.0),
        ),
        (
            "ankle",
            |x| x.reference.joint[Joint::Ankle.index()],
            (-35.0, -10.0),
            (5.0, 25.0),
        ),
    ];
    for (name, get, min_band, max_band) in bands {
        for p in &parts {
            let v: Vec<f64> = r[p.clone()]
                .iter()
                .map(|x| get(x).unwrap().to_degrees())
                .collect();
            let (lo, hi) = v
                .iter()
                .fold((f64::MAX, f64::MIN), |(l, h), &x| (l.min(x), h.max(x)));
            println!("{name} on {p:?}: {lo:.1} .. {hi:.1} deg");
            assert!((min_band.0..min_band.1).contains(&lo), "{name} min {lo}");
            assert!((max_band.0..max_band.1).contains(&hi), "{name} max {hi}");
        }
    }

    // IMU lag: the 3-axis gyro fit to the reference rate is best when the IMU is advanced ~2 samples.
    let idx: Vec<usize> = parts.iter().flat_map(|p| p.clone()).collect();
    for s in [Segment::Thigh, Segment::Shank, Segment::Foot] {
        let gyr: Vec<Vector3<f64>> = r
            .iter()
            .map(|x| x.sample.imu[s.index()].gyr.unwrap())
            .collect();
        let ang: Vec<f64> = r
            .iter()
            .map(|x| x.reference.segment[s.index()].unwrap())
            .collect();
        let rate: Vec<f64> = (0..ang.len())
            .map(|k| (ang[(k + 1).min(954)] - ang[k.saturating_sub(1)]) * 50.0)
            .collect();
        let corr: Vec<(i64, f64)> = (-4..=6)
            .map(|lag| (lag, fit_corr(&gyr, &rate, &idx, lag)))
            .collect();
        let (best, rb) = corr
            .iter()
            .copied()
            .fold((0, f64::MIN), |b, c| if c.1 > b.1 { c } else { b });
        // Sub-sample peak by a parabola through the best lag and its neighbours.
        let at = |lag: i64| corr.iter().find(|c| c.0 == lag).map_or(rb, |c| c.1);
        let (a, b, c) = (at(best - 1), rb, at(best + 1));
        let peak = best as f64 + 0.5 * (a - c) / (a - 2.0 * b + c);
        println!(
            "{}: gyro-fit r = {:.4} at lag 0, best lag {best} (parabolic {peak:.2}) r = {rb:.4}",
            s.name(),
            at(0)
        );
        if s == Segment::Shank {
            assert!((1..=3).contains(&best), "shank IMU lag {best}");
        }
        assert!(rb > 0.95);
    }
}

#[test]
fn shared_trial_round_trips_through_a_trial_file() {
    let Some(dir) = data_dir() else { return };
    let trial = import_gaittoolbox(&dir).unwrap();
    let tmp = tempfile::tempdir().unwrap();
    let path = tmp.path().join("trial.csv");
    let mut w = TrialWriter::new(
        std::fs::File::create(&path).unwrap(),
        &trial.meta,
        trial.layout,
    )
    .unwrap();
    for rec in &trial.records {
        w.write(rec).unwrap();
    }
    w.finish().unwrap();
    let mut reader = TrialReader::open(&path).unwrap();
    assert_eq!(reader.layout(), &trial.layout);
    assert_eq!(reader.meta().get("format"), Some("limbfuse-trial/1"));
    assert_eq!(
        reader.meta().get("foot_offset_rad"),
        trial.meta.get("foot_offset_rad")
    );
    let mut n = 0;
    while let Some(rec) = reader.next_record().unwrap() {
        let orig = &trial.records[n];
        assert!((rec.sample.t - orig.sample.t).abs() < 1e-12);
        assert_eq!(rec.reference.joint, orig.reference.joint);
        n += 1;
    }
    assert_eq!(n, trial.records.len());
}

#[test]
fn shared_trial_imu_shift_option() {
    let Some(dir) = data_dir() else { return };
    let base = import_gaittoolbox(&dir).unwrap();
    let opts = GaittoolboxOptions {
        shift_imu_samples: 2,
        ..Default::default()
    };
    let shifted = import_gaittoolbox_with(&dir, &opts).unwrap();
    assert_eq!(shifted.records.len(), base.records.len());
    assert_eq!(shifted.records[10].sample.imu, base.records[12].sample.imu);
    assert_eq!(shifted.records[10].reference, base.records[10].reference);
    assert!(shifted.records[953].sample.imu.iter().all(|m| m.is_empty()));
    assert_eq!(shifted.meta.get("imu_shift_samples"), Some("2"));
}

// ---- bad input in small synthetic folders ----

const IMU_HEAD: &str = "// fs=100 nSamples=3\nori_1,ori_2,ori_3,ori_4,acc_1,acc_2,acc_3,gyr_1,gyr_2,gyr_3,mag_1,mag_2,mag_3\n";
const IMU_ROW: &str = "1,0,0,0,0.1,0.2,9.8,0.01,0.02,0.03,0.5,0.5,0.5\n";
const VICON_HEAD: &str = "// fs=100  nSamples=3\n// posUnit=m\nPELV_1,PELV_2,PELV_3,RFEP_1,RFEP_2,RFEP_3,RFEO_1,RFEO_2,RFEO_3,RTIO_1,RTIO_2,RTIO_3,RTOE_1,RTOE_2,RTOE_3\n";

fn vicon_row(k: usize) -> String {
    let y = 0.01 * k as f64;
    format!("0,{y},1,0,{y},0.9,0,{y},0.5,0,{y},0.1,0.15,{y},0.05\n")
}

/// A 3-sample folder; `edit(file name, text)` may change a file's text.
fn folder(edit: impl Fn(&str, String) -> String) -> tempfile::TempDir {
    let dir = tempfile::tempdir().unwrap();
    for s in ["Pelvis", "R_UpLeg", "R_LowLeg", "R_Foot"] {
        let name = format!("imu-{s}.csv");
        let text = edit(&name, format!("{IMU_HEAD}{IMU_ROW}{IMU_ROW}{IMU_ROW}"));
        std::fs::write(dir.path().join(name), text).unwrap();
    }
    let text = edit(
        "vicon-right.csv",
        format!(
            "{VICON_HEAD}{}{}{}",
            vicon_row(0),
            vicon_row(1),
            vicon_row(2)
        ),
    );
    std::fs::write(dir.path().join("vicon-right.csv"), text).unwrap();
    dir
}

fn err(dir: &tempfile::TempDir) -> String {
    import_gaittoolbox(dir.path())
        .expect_err("bad input must fail")
        .to_string()
}

#[test]
fn tiny_valid_folder_imports_without_foot_zero() {
    let dir = folder(|_, t| t);
    let trial = import_gaittoolbox(dir.path()).unwrap();
    assert_eq!(trial.records.len(), 3);
    assert!(
        trial.meta.get("straight_segments") == Some("")
            && !trial.layout.segment_ref[Segment::Foot.index()]
    );
    let thigh = trial.records[1].reference.segment[Segment::Thigh.index()].unwrap();
    assert!(thigh.abs() < 1e-9, "vertical thigh is 0: {thigh}");
    assert_eq!(
        trial.records[0].sample.imu[0].gyr,
        Some(Vector3::new(0.01, 0.02, 0.03))
    );
}

#[test]
fn malformed_number_names_line_and_column() {
    let dir = folder(|n, t| {
        if n == "vicon-right.csv" {
            t.replacen(",0.9,", ",0.9x,", 1)
        } else {
            t
        }
    });
    let msg = err(&dir);
    assert!(
        msg.contains("vicon-right.csv:4:") && msg.contains("column 6 (`RFEP_3`)"),
        "{msg}"
    );
    assert!(
        msg.contains("finite number") && msg.contains("`0.9x`"),
        "{msg}"
    );
}

#[test]
fn truncated_row_names_line_and_column() {
    let dir = folder(|n, t| {
        if n == "imu-R_Foot.csv" {
            t.replacen(IMU_ROW, "1,0,0,0,0.1\n", 1)
        } else {
            t
        }
    });
    let msg = err(&dir);
    assert!(
        msg.contains("imu-R_Foot.csv:3:") && msg.contains("column 6 (`acc_2`)"),
        "{msg}"
    );
    assert!(msg.contains("truncated"), "{msg}");
}

#[test]
fn missing_header_column() {
    let dir = folder(|n, t| {
        if n == "imu-R_UpLeg.csv" {
            t.replace("gyr_3,", "gyr_x,")
        } else {
            t
        }
    });
    let msg = err(&dir);
    assert!(
        msg.contains("imu-R_UpLeg.csv:2:") && msg.contains("missing column `gyr_3`"),
        "{msg}"
    );
}

#[test]
fn empty_file() {
    let dir = folder(|n, t| {
        if n == "imu-Pelvis.csv" {
            String::new()
        } else {
            t
        }
    });
    let msg = err(&dir);
    assert!(
        msg.contains("imu-Pelvis.csv:1:") && msg.contains("no header row"),
        "{msg}"
    );
}

#[test]
fn sample_counts_must_agree() {
    let dir = folder(|n, t| {
        if n == "imu-R_LowLeg.csv" {
            t + IMU_ROW
        } else {
            t
        }
    });
    let msg = err(&dir);
    assert!(
        msg.contains("imu-R_LowLeg.csv:6:")
            && msg.contains("4 samples")
            && msg.contains("3 samples"),
        "{msg}"
    );
}

#[test]
fn nan_is_a_missing_sample_and_zero_quaternion_an_error() {
    let dir = folder(|n, t| {
        if n == "imu-R_Foot.csv" {
            t.replacen("0.01,", "NaN,", 1)
        } else {
            t
        }
    });
    let trial = import_gaittoolbox(dir.path()).unwrap();
    let foot = &trial.records[0].sample.imu[Segment::Foot.index()];
    assert!(foot.gyr.is_none() && foot.acc.is_some());
    let dir = folder(|n, t| {
        if n == "imu-R_Foot.csv" {
            t.replacen("1,0,0,0,", "0,0,0,0,", 1)
        } else {
            t
        }
    });
    let msg = err(&dir);
    assert!(
        msg.contains("imu-R_Foot.csv:3:") && msg.contains("`ori_1`") && msg.contains("quaternion"),
        "{msg}"
    );
}

#[test]
fn missing_folder() {
    let msg = import_gaittoolbox(Path::new("/nonexistent/gaittoolbox"))
        .unwrap_err()
        .to_string();
    assert!(msg.contains("/nonexistent/gaittoolbox"), "{msg}");
}

#[test]
fn bad_comment_values() {
    let dir = folder(|n, t| {
        if n == "vicon-right.csv" {
            t.replace("posUnit=m", "posUnit=in")
        } else {
            t
        }
    });
    let msg = err(&dir);
    assert!(
        msg.contains("vicon-right.csv:2:") && msg.contains("posUnit=in"),
        "{msg}"
    );
    let dir = folder(|n, t| {
        if n == "imu-R_Foot.csv" {
            t.replace("fs=100", "fs=120")
        } else {
            t
        }
    });
    let msg = err(&dir);
    assert!(
        msg.contains("imu-R_Foot.csv:1:") && msg.contains("100 Hz"),
        "{msg}"
    );
}
