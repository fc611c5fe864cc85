//! Knee-rig importer: the shared trials (skipped when `../shared/data` is
//! absent) and bad input in small temporary files.
//!
//! Figures for docs/IMPORTERS.md:
//! `cargo test -p limbfuse-io --test integration -- import_knee_rig:: --nocapture`

use std::path::{Path, PathBuf};

use limbfuse_core::{Joint, Segment};
use limbfuse_io::import::{import_knee_rig, ImportError};

fn data_dir() -> Option<PathBuf> {
    let dir = std::env::var_os("LIMBFUSE_DATA")
        .map(PathBuf::from)
        .unwrap_or_else(|| {
            PathBuf::from(concat!(env!("CARGO_MANIFEST_DIR"), "/../../../shared/data"))
        });
    if dir.join("knee-rig").is_dir() {
        Some(dir.join("knee-rig"))
    } else {
        println!("skipping: ../shared/data not found (set LIMBFUSE_DATA)");
        None
    }
}

fn pearson(a: &[f64], b: &[f64]) -> (f64, f64) {
    let n = a.len() as f64;
    let (ma, mb) = (a.iter().sum::<f64>() / n, b.iter().sum::<f64>() / n);
    let (mut sab, mut saa, mut sbb) = (0.0, 0.0, 0.0);
    for (x, y) in a.iter().zip(b) {
        sab += (x - ma) * (y - mb);
        saa += (x - ma) * (x - ma);
        sbb += (y - mb) * (y - mb);
    }
    // Correlation, and the slope of the regression of a on b.
    (sab / (saa * sbb).sqrt(), sab / sbb)
}

#[test]
fn shared_trials_import() {
    let Some(dir) = data_dir() else { return };
    let (thigh, shank, knee) = (
        Segment::Thigh.index(),
        Segment::Shank.index(),
        Joint::Knee.index(),
    );
    for k in 1..=5 {
        let path = dir.join(format!("Trial_0{k}.csv"));
        let trial = import_knee_rig(&path).unwrap();
        let r = &trial.records;
        let m = |key: &str| trial.meta.get(key).unwrap_or("?").to_string();
        assert_eq!(m("sample_rate_hz"), "250");
        assert!(r.len() > 38_000 && r[0].sample.t == 0.0);
        assert!(
            r.windows(2).all(|w| w[1].sample.t > w[0].sample.t),
            "t strictly increasing"
        );
        let duration = r.last().unwrap().sample.t;
        assert!(
            (duration - (r.len() - 1) as f64 * 0.004).abs() < 0.01,
            "no unexplained gaps"
        );
        let gyr_max = r
            .iter()
            .flat_map(|x| [x.sample.imu[thigh].gyr, x.sample.imu[shank].gyr])
            .flatten()
            .map(|g| g.amax())
            .fold(0.0, f64::max);
        assert!(
            gyr_max > 0.005 && gyr_max < 10.0,
            "gyro in rad/s: max {gyr_max}"
        );
        let knee_ref: Vec<f64> = r.iter().filter_map(|x| x.reference.joint[knee]).collect();
        let (lo, hi) = knee_ref
            .iter()
            .fold((f64::MAX, f64::MIN), |(l, h), &v| (l.min(v), h.max(v)));
        assert!(
            lo > (-0.5f64).to_radians() && hi > 0.5 && hi < 1.0,
            "flexion positive, rad: {lo}..{hi}"
        );
        let med: f64 = m("thigh_acc_norm_median_g").parse().unwrap();
        assert!(
            (1.1..1.4).contains(&med),
            "miscalibrated accelerometer kept: {med}"
        );

        // Sign check: gyro z difference vs knee_ref rate (central differences).
        let (mut dg, mut rate) = (Vec::new(), Vec::new());
        for w in r.windows(3) {
            let (a, b, c) = (&w[0], &w[1], &w[2]);
            if let (Some(g1), Some(g2), Some(k0), Some(k2)) = (
                b.sample.imu[thigh].gyr,
                b.sample.imu[shank].gyr,
                a.reference.joint[knee],
                c.reference.joint[knee],
            ) {
                dg.push(g1.z - g2.z);
                rate.push((k2 - k0) / (c.sample.t - a.sample.t));
            }
        }
        let (corr, slope) = pearson(&dg, &rate);
        assert!(corr < -0.8, "G1Z-G2Z vs knee_ref rate: r = {corr}");
        println!(
            "Trial_0{k}: {} rows, {duration:.3} s, inserted {}, missed-packet lines {} (+{} before the first sample), irregular {}, acc norm median thigh {} g shank {} g, knee_ref {:.1}..{:.1} deg, max |gyr| {gyr_max:.2} rad/s, r(G1Z-G2Z, d knee_ref/dt) = {corr:.3}, slope {slope:.3}",
            r.len(),
            m("inserted_missing_rows"),
            m("missed_packet_lines"),
            m("missed_packet_lines_before_first_sample"),
            m("irregular_intervals"),
            m("thigh_acc_norm_median_g"),
            m("shank_acc_norm_median_g"),
            lo.to_degrees(),
            hi.to_degrees()
        );
    }
}

const HEAD: &str = "LOG INTERVAL,4000,microseconds\nTOTAL LOG TIME,1,seconds\nHIP_CENTER_POS,780\nKNEE_CENTER_POS,390\nTRANSFER #,TIME,TIME DELTA,G1X,G1Y,G1Z,A1X,A1Y,A1Z,G2X,G2Y,G2Z,A2X,A2Y,A2Z,HIP STEPPER,KNEE STEPPER,ABS KNEE ANGLE,GAIT STAGE,IMPULSE HIT\n";

fn row(n: u32, time: u64) -> String {
    format!("{n},{time},4000,57.29578,0.00,-57.29578,0.00,0.00,-1.00,0.00,0.00,0.00,0.00,0.50,0.00,779,390,10.00,9,0\n")
}

fn write(dir: &tempfile::TempDir, text: &str) -> PathBuf {
    let path = dir.path().join("Trial_99.csv");
    std::fs::write(&path, text).unwrap();
    path
}

fn import_err(text: &str) -> String {
    let dir = tempfile::tempdir().unwrap();
    let path = write(&dir, text);
    let e: ImportError = import_knee_rig(&path).expect_err("bad input must fail");
    let msg = e.to_string();
    assert!(msg.contains("Trial_99.csv"), "names the file: {msg}");
    msg
}

#[test]
fn dropouts_become_missing_rows() {
    let mut text = String::from(HEAD);
    text += "Missed Packet(s)\n";
    text += &row(0, 1_000_000);
    text += &row(1, 1_003_999); // jitter within tolerance: no row inserted
    text += "Missed Packet(s)\n";
    text += &row(4, 1_016_000); // 3 intervals: 2 missing rows
    text += &row(5, 1_020_001);
    text += "Missed Packet(s)\n"; // no timing gap follows: counted only
    text += &row(6, 1_024_000);
    let dir = tempfile::tempdir().unwrap();
    let trial = import_knee_rig(&write(&dir, &text)).unwrap();
    let t: Vec<f64> = trial.records.iter().map(|r| r.sample.t).collect();
    let expected = [0.0, 0.003999, 0.007999, 0.011999, 0.016, 0.020001, 0.024];
    assert_eq!(t.len(), expected.len());
    for (a, b) in t.iter().zip(expected) {
        assert!((a - b).abs() < 1e-9, "{t:?}");
    }
    for (i, r) in trial.records.iter().enumerate() {
        let missing = i == 2 || i == 3;
        assert_eq!(r.sample.imu[1].gyr.is_none(), missing);
        assert_eq!(r.reference.joint[1].is_none(), missing);
    }
    let r0 = &trial.records[0];
    let g = r0.sample.imu[Segment::Thigh.index()].gyr.unwrap();
    assert!(
        (g.x - 1.0).abs() < 1e-6 && (g.z + 1.0).abs() < 1e-6,
        "deg/s -> rad/s: {g:?}"
    );
    let a = r0.sample.imu[Segment::Thigh.index()].acc.unwrap();
    assert!((a.z + 9.81).abs() < 1e-12, "g -> m/s^2: {a:?}");
    assert!((r0.reference.joint[1].unwrap() - 10f64.to_radians()).abs() < 1e-12);
    let m = |k: &str| trial.meta.get(k).unwrap().to_string();
    assert_eq!(m("inserted_missing_rows"), "2");
    assert_eq!(m("missed_packet_lines"), "2");
    assert_eq!(m("missed_packet_lines_without_gap"), "1");
    assert_eq!(m("missed_packet_lines_before_first_sample"), "1");
    assert_eq!(m("irregular_intervals"), "0");
    assert_eq!(m("rig_knee_center_pos"), "390");
    assert!(
        !trial.layout.gyr[0]
            && trial.layout.gyr[1]
            && trial.layout.acc[2]
            && trial.layout.joint_ref[1]
    );
}

#[test]
fn malformed_number_names_line_and_column() {
    let text = format!(
        "{HEAD}{}{}",
        row(0, 0),
        row(1, 4000).replacen("0.00", "0.x0", 1)
    );
    let msg = import_err(&text);
    assert!(
        msg.contains(":7:") && msg.contains("column 5 (`G1Y`)") && msg.contains("finite number"),
        "{msg}"
    );
}

#[test]
fn truncated_row_names_line_and_column() {
    let text = format!("{HEAD}{}0,4000,4000,1.0,2.0\n", row(0, 0));
    let msg = import_err(&text);
    assert!(
        msg.contains(":7:") && msg.contains("column 6 (`G1Z`)") && msg.contains("truncated"),
        "{msg}"
    );
}

/// An audit found a row with one cell removed (or one added) in the middle
/// imported with exit 0: every later value of the row under the wrong
/// name (`A1X` holding `A1Y`'s value, `A2Z` the hip stepper's). A row must
/// have the header's cells; a trailing separator is still accepted.
#[test]
fn a_row_with_a_cell_too_few_or_too_many_is_refused() {
    let short = row(1, 4000).replacen(",0.00,0.00,-1.00,", ",0.00,-1.00,", 1);
    let msg = import_err(&format!("{HEAD}{}{short}", row(0, 0)));
    assert!(
        msg.contains(":7:")
            && msg.contains("column 20 (`IMPULSE HIT`)")
            && msg.contains("19 cell(s)"),
        "{msg}"
    );
    let long = row(1, 4000).replacen(",0.00,0.00,-1.00,", ",0.00,0.00,0.00,-1.00,", 1);
    let msg = import_err(&format!("{HEAD}{}{long}", row(0, 0)));
    assert!(
        msg.contains(":7:")
            && msg.contains("column 21")
            && msg.contains("21 cells (a cell too many)"),
        "{msg}"
    );
    // a row ending in the separator is the header's cells and an empty one
    let dir = tempfile::tempdir().unwrap();
    let trailing = row(1, 4000).replace('\n', ",\n");
    let path = write(&dir, &format!("{HEAD}{}{trailing}", row(0, 0)));
    assert_eq!(import_knee_rig(&path).unwrap().records.len(), 2);
}

/// A column named twice (`G1Y` renamed `G1X`) was reported only as `G1Y`
/// missing; the message now also names the duplicate and both places.
#[test]
fn a_column_named_twice_is_named() {
    let text = format!("{}{}", HEAD.replace(",G1X,G1Y,", ",G1X,G1X,"), row(0, 0));
    let msg = import_err(&text);
    assert!(
        msg.contains(":5:")
            && msg.contains("missing column `G1Y`")
            && msg.contains("column `G1X` is there twice (columns 4 and 5"),
        "{msg}"
    );
}

#[test]
fn missing_header_column() {
    let text = format!("{}{}", HEAD.replace(",G2Z,", ",G2Q,"), row(0, 0));
    let msg = import_err(&text);
    assert!(msg.contains(":5:") && msg.contains("`G2Z`"), "{msg}");
}

#[test]
fn empty_file() {
    let msg = import_err("");
    assert!(
        msg.contains(":1:") && msg.contains("empty") && msg.contains("LOG INTERVAL"),
        "{msg}"
    );
    let msg = import_err(HEAD);
    assert!(msg.contains("no data rows"), "{msg}");
}

#[test]
fn time_going_backwards() {
    let text = format!("{HEAD}{}{}{}", row(0, 8000), row(1, 12000), row(2, 11000));
    let msg = import_err(&text);
    assert!(
        msg.contains(":8:") && msg.contains("column 2 (`TIME`)") && msg.contains("must increase"),
        "{msg}"
    );
}

#[test]
fn missing_log_interval() {
    let msg = import_err(&format!(
        "{}{}",
        HEAD.replacen("LOG INTERVAL,4000", "LOG INTERVAL,fast", 1),
        row(0, 0)
    ));
    assert!(msg.contains(":1:") && msg.contains("column 2"), "{msg}");
    let msg = import_err(&format!(
        "{}{}",
        HEAD.lines().skip(1).collect::<Vec<_>>().join("\n") + "\n",
        row(0, 0)
    ));
    assert!(msg.contains("LOG INTERVAL"), "{msg}");
}

/// An audit: `LOG INTERVAL,1` over a log whose TIME steps by 4000 us was
/// trusted: 51 987 empty rows were inserted between 14 real ones and the
/// trial said 1 MHz, without a word.
#[test]
fn a_log_interval_the_time_column_contradicts_is_refused() {
    let rows: String = (0..14).map(|k| row(k, 4000 * k as u64)).collect();
    let msg = import_err(&format!(
        "{}{rows}",
        HEAD.replacen("LOG INTERVAL,4000", "LOG INTERVAL,1", 1)
    ));
    assert!(
        msg.contains(":1:") && msg.contains("says 1 us, but the TIME column steps by 4000 us"),
        "{msg}"
    );
}

#[test]
fn missing_file() {
    let e = import_knee_rig(Path::new("/nonexistent/Trial_99.csv")).unwrap_err();
    assert!(e.to_string().contains("Trial_99.csv"));
}

#[test]
fn odd_input_never_panics() {
    let huge = format!("{HEAD}{}{}", row(0, 0), row(1, 1_000_000_000_000_000_000));
    let cases = [
        ",,,,\n\n,,".to_string(),
        "LOG INTERVAL,0.000001,microseconds\nTIME\n0\n1e300\n".to_string(),
        "LOG INTERVAL,4000,microseconds\nTIME,G1X\n".to_string(),
        format!("{HEAD}Missed Packet(s)\nMissed Packet(s)\n"),
        huge,
        format!("{HEAD}{}", row(0, 0).replace("10.00", "")),
        String::from_utf8_lossy(&[0xff, 0xfe, b',', b'\n']).into_owned(),
    ];
    let dir = tempfile::tempdir().unwrap();
    for text in cases {
        let path = write(&dir, &text);
        if let Err(e) = import_knee_rig(&path) {
            assert!(e.to_string().contains("Trial_99.csv:"), "{e}");
        }
    }
    let path = dir.path().join("bin.csv");
    std::fs::write(&path, [0xffu8, 0xfe, 0x00, b'\n']).unwrap();
    let msg = import_knee_rig(&path).unwrap_err().to_string();
    assert!(msg.contains("bin.csv:1:") && msg.contains("UTF-8"), "{msg}");
}
