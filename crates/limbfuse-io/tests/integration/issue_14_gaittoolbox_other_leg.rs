//! Issue 14 ("a real recording of the other leg"): the gaittoolbox importer
//! read only the right leg (`imu-R_*.csv`, `vicon-right.csv`, `RFEP`...), so
//! a folder of the left leg could not be imported at all. Now the leg comes
//! from the folder's files (or `--leg`), and the Vicon file from its columns.
//! A left-leg folder made from the shared right-leg one by renaming files and
//! columns imports to the same records with `# leg: left`; a folder with both
//! legs imports the right one unless the left is asked for. Skipped (the
//! shared-data part) when `../shared/data` is absent.

use std::path::Path;

use limbfuse_core::Side;
use limbfuse_io::import::{import_gaittoolbox, import_gaittoolbox_with, GaittoolboxOptions};

/// `src`'s header row with every right-leg Vicon column renamed to the left's.
fn left_columns(text: &str) -> String {
    let mut out = String::new();
    let mut header_done = false;
    for line in text.lines() {
        if !header_done && !line.trim().is_empty() && !line.starts_with("//") {
            header_done = true;
            let renamed: Vec<String> = line
                .split(',')
                .map(|c| match c.strip_prefix('R') {
                    Some(rest)
                        if ["FEP", "FEO", "TIO", "TOE"]
                            .iter()
                            .any(|j| rest.starts_with(j)) =>
                    {
                        format!("L{rest}")
                    }
                    _ => c.to_string(),
                })
                .collect();
            out += &renamed.join(",");
        } else {
            out += line;
        }
        out += "\n";
    }
    out
}

/// Copies the right leg's files of `src` into `dst` as the left leg's.
fn as_left_leg(src: &Path, dst: &Path) {
    std::fs::copy(src.join("imu-Pelvis.csv"), dst.join("imu-Pelvis.csv")).unwrap();
    for s in ["UpLeg", "LowLeg", "Foot"] {
        std::fs::copy(
            src.join(format!("imu-R_{s}.csv")),
            dst.join(format!("imu-L_{s}.csv")),
        )
        .unwrap();
    }
    let vicon = std::fs::read_to_string(src.join("vicon-right.csv")).unwrap();
    std::fs::write(dst.join("vicon-left.csv"), left_columns(&vicon)).unwrap();
}

#[test]
fn issue_14_a_left_leg_folder_imports_as_the_right_one_does() {
    let Some(src) = crate::import_gaittoolbox::data_dir() else {
        return;
    };
    let right = import_gaittoolbox(&src).unwrap();
    let tmp = tempfile::tempdir().unwrap();
    as_left_leg(&src, tmp.path());
    let left = import_gaittoolbox(tmp.path()).unwrap();
    assert_eq!(left.meta.get("leg"), Some("left"));
    assert_eq!(right.meta.get("leg"), Some("right"));
    assert_eq!(left.layout, right.layout);
    assert!(
        left.records == right.records,
        "the same data, read as the left leg"
    );
    assert!(left
        .meta
        .get("reference_method")
        .is_some_and(|m| m.contains("LFEP->LFEO")));
}

#[test]
fn issue_14_a_folder_with_both_legs_imports_the_one_asked_for() {
    let Some(src) = crate::import_gaittoolbox::data_dir() else {
        return;
    };
    let tmp = tempfile::tempdir().unwrap();
    let dir = tmp.path();
    as_left_leg(&src, dir);
    for s in ["UpLeg", "LowLeg", "Foot"] {
        std::fs::copy(
            src.join(format!("imu-R_{s}.csv")),
            dir.join(format!("imu-R_{s}.csv")),
        )
        .unwrap();
    }
    // The toolbox's own Vicon file holds both legs' columns.
    let right = std::fs::read_to_string(src.join("vicon-right.csv")).unwrap();
    let left = left_columns(&right);
    let both: String = right
        .lines()
        .zip(left.lines())
        .map(|(r, l)| {
            if r.starts_with("//") {
                format!("{r}\n")
            } else {
                format!("{r},{l}\n")
            }
        })
        .collect();
    std::fs::remove_file(dir.join("vicon-left.csv")).unwrap();
    std::fs::write(dir.join("vicon.csv"), both).unwrap();
    let r = import_gaittoolbox(dir).unwrap();
    assert_eq!(r.meta.get("leg"), Some("right"));
    assert!(r
        .meta
        .get("segment_map")
        .is_some_and(|m| m.contains("import --leg left")));
    let opts = GaittoolboxOptions {
        leg: Some(Side::Left),
        ..GaittoolboxOptions::default()
    };
    let l = import_gaittoolbox_with(dir, &opts).unwrap();
    assert_eq!(l.meta.get("leg"), Some("left"));
    assert!(l.records == r.records, "both legs hold the same data here");
}

#[test]
fn issue_14_a_left_leg_folder_without_its_vicon_columns_is_an_error() {
    let Some(src) = crate::import_gaittoolbox::data_dir() else {
        return;
    };
    let tmp = tempfile::tempdir().unwrap();
    as_left_leg(&src, tmp.path());
    std::fs::remove_file(tmp.path().join("vicon-left.csv")).unwrap();
    std::fs::copy(
        src.join("vicon-right.csv"),
        tmp.path().join("vicon-right.csv"),
    )
    .unwrap();
    let e = import_gaittoolbox(tmp.path()).unwrap_err().to_string();
    assert!(e.contains("LFEP_1") && e.contains("left leg"), "{e}");
}
