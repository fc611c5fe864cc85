//! Provenance of the files `montecarlo` and `calibrate` write (session 28):
//! until now only estimate files recorded what made them (`# command:`,
//! `# trial:`, `# trial_hash:`); a `montecarlo` CSV or SVG and a
//! calibration file said nothing of the limbfuse, command, seeds, settings
//! or input that made them. Now each carries `# limbfuse_version:`,
//! `# command:` and its seeds or settings and input hash as comment lines
//! (docs/OUTPUTS.md section 3), which every reader skips: a file without
//! them (written before) reads as before.

use std::path::Path;
use std::process::Output;

use limbfuse_io::provenance::LIMBFUSE_VERSION;

use crate::support::{limbfuse, stderr};

fn ok(o: &Output) {
    assert_eq!(o.status.code(), Some(0), "stderr: {}", stderr(o));
}

fn read(dir: &Path, name: &str) -> String {
    std::fs::read_to_string(dir.join(name)).unwrap()
}

/// The `# key: value` comment lines of `text`, in order.
fn comments(text: &str) -> Vec<&str> {
    text.lines().filter_map(|l| l.strip_prefix("# ")).collect()
}

/// `montecarlo -o m.csv --svg m.svg` wrote `method,level_pct,...` and the
/// plot, nothing of the command or seeds. Now the CSV starts with the
/// provenance comments and then the table as before; the SVG has the same
/// lines in its `<metadata>`.
#[test]
fn montecarlo_csv_and_svg_record_the_command_and_seeds() {
    let d = tempfile::tempdir().unwrap();
    let p = d.path();
    ok(&limbfuse(
        &[
            "montecarlo",
            "--runs",
            "2",
            "--levels",
            "0:10:10",
            "--seed",
            "7",
            "--duration",
            "5",
            "-o",
            "m.csv",
            "--svg",
            "m.svg",
        ],
        p,
    ));
    let csv = read(p, "m.csv");
    let command = "command: limbfuse montecarlo --runs 2 --levels 0:10:10 --seed 7 --speed 1 \
                   --duration 5 -o m.csv --svg m.svg";
    let version = format!("limbfuse_version: {LIMBFUSE_VERSION}");
    assert_eq!(comments(&csv)[..2], [version.as_str(), command], "{csv}");
    assert!(
        comments(&csv)[2].starts_with("trial_seeds: 7 to 8 "),
        "{csv}"
    );
    // Past the comments, the table as it always was.
    let table: Vec<&str> = csv.lines().filter(|l| !l.starts_with('#')).collect();
    assert_eq!(table[0], "method,level_pct,mean_rmse_deg,std_rmse_deg,runs");
    assert_eq!(table.len(), 1 + 3 * 2, "{csv}");
    for row in &table[1..] {
        assert_eq!(row.split(',').count(), 5, "{row}");
        assert!(row.ends_with(",2"), "{row}");
    }
    let svg = read(p, "m.svg");
    let meta = svg
        .split_once("<metadata id=\"limbfuse-provenance\">")
        .and_then(|(_, rest)| rest.split_once("</metadata>"))
        .map(|(m, _)| m)
        .unwrap_or_else(|| panic!("no provenance metadata in {}", &svg[..300]));
    assert!(meta.contains(&version) && meta.contains(command), "{meta}");
    assert!(svg.starts_with("<svg") && svg.trim_end().ends_with("</svg>"));
}

/// The default pose recording of seed 3's sensors and its calibration
/// `cal.toml`.
fn calibrated(p: &Path) -> String {
    ok(&limbfuse(
        &["simulate", "calibration", "--seed", "3", "-o", "poses.csv"],
        p,
    ));
    ok(&limbfuse(
        &[
            "calibrate",
            "poses.csv",
            "--acc-std-max",
            "0.06",
            "-o",
            "cal.toml",
        ],
        p,
    ));
    read(p, "cal.toml")
}

/// `calibrate poses.csv -o cal.toml` recorded the recording's file name
/// (`source`) only: not the limbfuse, the flags, the static-test
/// thresholds it used or which bytes it read. Now four comment lines say
/// so; the file still loads in `estimate --calibration`, and so does the
/// same file without them (one written before), with the same estimate.
#[test]
fn a_calibration_file_records_its_settings_and_recording() {
    let d = tempfile::tempdir().unwrap();
    let p = d.path();
    let text = calibrated(p);
    let hash = limbfuse_io::content_hash::of_file(&p.join("poses.csv")).unwrap();
    let c = comments(&text);
    assert_eq!(
        c[2..6],
        [
            format!("limbfuse_version: {LIMBFUSE_VERSION}").as_str(),
            "command: limbfuse calibrate --model full --acc-std-max 0.06 --gyro-std-max 0.03 \
             --min-pose 1 poses.csv -o cal.toml",
            "fit_settings: model=full gravity=9.81 window_s=0.5 acc_std_max=0.06 \
             gyro_std_max=0.03 hold_rate_max=0.3 min_pose_s=1 distinct_rad=0.2617993877991494 \
             min_eigenvalue=0.001 max_residual=0.05",
            format!("source_hash: {hash}").as_str(),
        ],
        "{text}"
    );
    assert!(text.contains("source = \"poses.csv\""), "{text}");
    // An old file: the same without the provenance lines.
    let old: String = text
        .lines()
        .filter(|l| !c[2..6].iter().any(|k| l.strip_prefix("# ") == Some(*k)))
        .map(|l| format!("{l}\n"))
        .collect();
    assert_eq!(old.lines().count() + 4, text.lines().count());
    std::fs::write(p.join("old.toml"), old).unwrap();
    ok(&limbfuse(
        &[
            "simulate",
            "walking",
            "--duration",
            "3",
            "--seed",
            "3",
            "-o",
            "walk.csv",
        ],
        p,
    ));
    let estimate = |cal: &str, out: &str| {
        ok(&limbfuse(
            &[
                "estimate",
                "--method",
                "mjls",
                "--calibration",
                cal,
                "walk.csv",
                "-o",
                out,
            ],
            p,
        ));
        read(p, out)
            .lines()
            .filter(|l| !l.starts_with('#'))
            .collect::<Vec<_>>()
            .join("\n")
    };
    assert_eq!(
        estimate("cal.toml", "new.csv"),
        estimate("old.toml", "old.csv")
    );
}
