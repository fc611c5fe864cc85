//! `limbfuse mirror` and what a mirrored trial says about its sensors (an
//! audit, 2026-12-05): the simulator's `<seg>_mount_quat` lines were copied
//! unchanged, so `align`'s ideal answer no longer matched the mirrored
//! sensors; and the device orientations of the shared gaittoolbox recording
//! (Xsens, world z up) came out upside down (`R f`: +9.90 -> -9.90 m/s^2).

use std::path::Path;

use nalgebra::{Matrix3, Quaternion, UnitQuaternion, Vector3};

use crate::support::{limbfuse, shared_data};

fn ok(args: &[&str], dir: &Path) {
    let o = limbfuse(args, dir);
    assert!(
        o.status.success(),
        "{args:?}: {}",
        String::from_utf8_lossy(&o.stderr)
    );
}

/// (metadata lines, header, rows) of a trial CSV.
fn read(path: &Path) -> (Vec<String>, Vec<String>, Vec<Vec<Option<f64>>>) {
    let text = std::fs::read_to_string(path).unwrap();
    let meta: Vec<String> = text
        .lines()
        .filter(|l| l.starts_with('#'))
        .map(String::from)
        .collect();
    let mut body = text.lines().filter(|l| !l.starts_with('#'));
    let header: Vec<String> = body.next().unwrap().split(',').map(String::from).collect();
    let rows = body
        .map(|l| l.split(',').map(|c| c.parse::<f64>().ok()).collect())
        .collect();
    (meta, header, rows)
}

fn meta_numbers(meta: &[String], key: &str) -> Vec<f64> {
    let prefix = format!("# {key}: ");
    let line = meta
        .iter()
        .find(|l| l.starts_with(&prefix))
        .unwrap_or_else(|| panic!("no {key}"));
    line[prefix.len()..]
        .split_whitespace()
        .map(|v| v.parse().unwrap())
        .collect()
}

fn vector(header: &[String], row: &[Option<f64>], prefix: &str) -> Option<Vector3<f64>> {
    let at = |a: &str| {
        let i = header.iter().position(|h| h == &format!("{prefix}{a}"))?;
        row[i]
    };
    Some(Vector3::new(at("x")?, at("y")?, at("z")?))
}

fn quat(v: &[f64]) -> UnitQuaternion<f64> {
    UnitQuaternion::from_quaternion(Quaternion::new(v[0], v[1], v[2], v[3]))
}

#[test]
fn mirrored_mountings_describe_the_mirrored_sensors() {
    let d = tempfile::tempdir().unwrap();
    let p = d.path();
    ok(
        &[
            "simulate",
            "walking",
            "--duration",
            "3",
            "--seed",
            "5",
            "--mounting",
            "random",
            "-o",
            "raw.csv",
        ],
        p,
    );
    ok(
        &["mirror", "raw.csv", "--remount-seed", "7", "-o", "m.csv"],
        p,
    );
    let (meta, header, rows) = read(&p.join("raw.csv"));
    let (meta_m, header_m, rows_m) = read(&p.join("m.csv"));
    let s = Matrix3::from_diagonal(&Vector3::new(1.0, 1.0, -1.0));
    for seg in ["trunk", "thigh", "shank", "foot"] {
        let key = format!("{seg}_mount_quat");
        let (m, m2) = (
            quat(&meta_numbers(&meta, &key)),
            quat(&meta_numbers(&meta_m, &key)),
        );
        assert_ne!(m, m2, "{seg}: the mounting was copied unchanged");
        let mut worst = 0.0f64;
        for (r, r2) in rows.iter().zip(&rows_m) {
            let prefix = format!("{seg}_acc_");
            let (Some(f), Some(f2)) = (vector(&header, r, &prefix), vector(&header_m, r2, &prefix))
            else {
                continue;
            };
            // the mirrored segment frame sees the mirror image of what it saw
            worst = worst.max((m2 * f2 - s * (m * f)).norm());
        }
        assert!(worst < 1e-6, "{seg}: {worst} m/s^2");
    }
}

#[test]
fn mirrored_device_orientations_keep_the_world_up() {
    let Some(folder) = shared_data("gaittoolbox-s02-walk") else {
        eprintln!("skipped: ../shared/data/gaittoolbox-s02-walk is absent");
        return;
    };
    let d = tempfile::tempdir().unwrap();
    let p = d.path();
    let f = folder.display().to_string();
    ok(
        &["import", "--format", "gaittoolbox", &f, "-o", "gt.csv"],
        p,
    );
    ok(&["mirror", "gt.csv", "-o", "m.csv"], p);
    for file in ["gt.csv", "m.csv"] {
        let (_, header, rows) = read(&p.join(file));
        let (mut sum, mut n) = (Vector3::zeros(), 0.0);
        for r in &rows {
            let (Some(a), Some(w)) = (
                vector(&header, r, "trunk_acc_"),
                vector(&header, r, "trunk_quat_"),
            ) else {
                continue;
            };
            let qw = r[header.iter().position(|h| h == "trunk_quat_w").unwrap()].unwrap();
            sum += quat(&[qw, w.x, w.y, w.z]) * a;
            n += 1.0;
        }
        let mean = sum / n;
        assert!(mean.z > 9.0, "{file}: the world's vertical is {mean}");
    }
}

/// The independent simulator's sagittal `imu_mounts_m` (which `chain`
/// reads) is the mirror image's too: kept as it was (a first version of
/// this fix dropped it, and `chain` on the mirrored walk went 0.22 -> 0.35
/// deg).
#[test]
fn sagittal_mount_positions_survive_the_mirror() {
    let Some(walk) = shared_data("independent-sim/walk-v1.2-s301.csv") else {
        eprintln!("skipped: ../shared/data/independent-sim is absent");
        return;
    };
    let d = tempfile::tempdir().unwrap();
    let p = d.path();
    let w = walk.display().to_string();
    ok(&["mirror", &w, "-o", "m.csv"], p);
    let line = |text: &str| {
        text.lines()
            .find(|l| l.starts_with("# imu_mounts_m:"))
            .map(String::from)
    };
    let original = line(&std::fs::read_to_string(&walk).unwrap());
    assert!(original.is_some());
    assert_eq!(
        line(&std::fs::read_to_string(p.join("m.csv")).unwrap()),
        original
    );
}
