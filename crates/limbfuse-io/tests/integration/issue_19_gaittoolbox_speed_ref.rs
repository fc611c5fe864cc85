//! Issue 19 (walking speed validated on real recordings): the gaittoolbox
//! importer writes `speed_ref` from the Vicon pelvis on the straight parts,
//! so that `lowback-speed` (the pelvis IMU) and `gait-events` (the foot IMU)
//! can be scored on the S02 walk. Checked against the Vicon file read here
//! independently: over each straight part, the mean of `speed_ref` is the
//! pelvis's horizontal displacement over the part divided by its duration
//! (the parts are straight, so the heading projection loses almost nothing);
//! outside the parts the reference is empty. Skipped when `../shared/data`
//! is absent.

use limbfuse_io::import::import_gaittoolbox;

use crate::import_gaittoolbox::data_dir;

/// The PELV x, y columns of the Vicon file (m), one row per sample.
fn pelvis_xy(dir: &std::path::Path) -> Vec<[f64; 2]> {
    let text = std::fs::read_to_string(dir.join("vicon-right.csv")).unwrap();
    let mut lines = text.lines().filter(|l| !l.starts_with("//"));
    let header: Vec<&str> = lines.next().unwrap().split(',').collect();
    let col = |name: &str| header.iter().position(|h| *h == name).unwrap();
    let (x, y) = (col("PELV_1"), col("PELV_2"));
    lines
        .map(|l| {
            let cells: Vec<&str> = l.split(',').collect();
            [cells[x].parse().unwrap(), cells[y].parse().unwrap()]
        })
        .collect()
}

#[test]
fn issue_19_gaittoolbox_speed_ref_is_the_pelvis_walking_speed() {
    let Some(dir) = data_dir() else { return };
    let trial = import_gaittoolbox(&dir).unwrap();
    assert!(trial.layout.speed_ref);
    let speed: Vec<Option<f64>> = trial.records.iter().map(|r| r.reference.speed).collect();
    let pelvis = pelvis_xy(&dir);
    let parts: Vec<std::ops::Range<usize>> = trial
        .meta
        .get("straight_segments")
        .unwrap()
        .split(',')
        .map(|r| {
            let (a, b) = r.split_once("..").unwrap();
            a.parse().unwrap()..b.parse().unwrap()
        })
        .collect();
    assert_eq!(parts.len(), 2, "{parts:?}");
    let mut inside = vec![false; speed.len()];
    for part in &parts {
        let values: Vec<f64> = speed[part.clone()].iter().map(|v| v.unwrap()).collect();
        let mean = values.iter().sum::<f64>() / values.len() as f64;
        let (a, b) = (pelvis[part.start], pelvis[part.end - 1]);
        let chord = (b[0] - a[0]).hypot(b[1] - a[1]);
        let expected = chord / ((part.end - 1 - part.start) as f64 / 100.0);
        println!(
            "straight part {part:?}: mean speed_ref {mean:.4} m/s, Vicon chord {expected:.4} m/s"
        );
        assert!(
            (mean - expected).abs() < 0.01,
            "part {part:?}: mean speed_ref {mean} m/s, Vicon displacement / time {expected} m/s"
        );
        assert!((0.8..1.2).contains(&mean), "a walk at about 1 m/s: {mean}");
        inside[part.clone()].iter_mut().for_each(|b| *b = true);
    }
    for (k, v) in speed.iter().enumerate() {
        assert_eq!(v.is_some(), inside[k], "sample {k}: speed_ref {v:?}");
    }
}
