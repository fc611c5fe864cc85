//! A fresh-user audit (session 28), item 12: `align` of a two-leg
//! recording (split from `ux_audit_28` to keep files short).

use std::path::Path;
use std::process::Output;

use crate::support::{limbfuse, shared_data};

fn stderr(o: &Output) -> String {
    String::from_utf8_lossy(&o.stderr).into_owned()
}

fn stdout(o: &Output) -> String {
    String::from_utf8_lossy(&o.stdout).into_owned()
}

/// Runs `args` in `dir` and expects success.
fn ok(args: &[&str], dir: &Path) -> Output {
    let o = limbfuse(args, dir);
    assert!(o.status.success(), "{args:?}: {}", stderr(&o));
    o
}

/// A copy of the trial `from` with the foot IMU's columns repeated as the
/// left foot's (`foot_left_...`): a two-leg recording.
fn with_left_foot(dir: &Path, from: &str, to: &str) {
    let text = std::fs::read_to_string(dir.join(from)).unwrap();
    let header = text.lines().position(|l| l.starts_with("t,")).unwrap();
    let names: Vec<&str> = text.lines().nth(header).unwrap().split(',').collect();
    let foot: Vec<usize> = (0..names.len())
        .filter(|&i| names[i].starts_with("foot_acc_") || names[i].starts_with("foot_gyr_"))
        .collect();
    let mut out = String::new();
    for (i, l) in text.lines().enumerate() {
        out += l;
        if i == header {
            for &k in &foot {
                out += &format!(",{}", names[k].replacen("foot_", "foot_left_", 1));
            }
        } else if i > header {
            let cells: Vec<&str> = l.split(',').collect();
            for &k in &foot {
                out += &format!(",{}", cells[k]);
            }
        }
        out.push('\n');
    }
    std::fs::write(dir.join(to), out).unwrap();
}

/// Item 12: `align` of the gaitmap two-foot walk aligned `foot_` only,
/// left `foot_left_` raw, kept "RAW sensor frames" in `# sensors:`, and
/// `inspect` of the output said "IMU frames: not stated". Now the output's
/// `# imu_frame:` lists the aligned and the raw IMUs, `# sensors:` points
/// to it (and `# legs:`, which says "RAW sensor frames" too and was kept
/// as recorded), and `align` warns how to align the other leg.
#[test]
fn two_leg_alignment_states_which_imus_are_raw() {
    let d = tempfile::tempdir().unwrap();
    let p = d.path();
    ok(
        &[
            "simulate",
            "walking",
            "--duration",
            "12",
            "--mounting",
            "random",
            "-o",
            "raw.csv",
        ],
        p,
    );
    with_left_foot(p, "raw.csv", "two.csv");
    let o = ok(&["align", "two.csv", "-o", "a.csv"], p);
    let e = stderr(&o);
    assert!(
        e.contains("warning: two.csv:") && e.contains("foot_left stays in its raw sensor frame"),
        "{e}"
    );
    assert!(e.contains("--leg left"), "{e}");
    let text = std::fs::read_to_string(p.join("a.csv")).unwrap();
    let frame = text
        .lines()
        .find(|l| l.starts_with("# imu_frame:"))
        .unwrap();
    assert!(
        frame.contains("trunk, thigh, shank, foot; raw sensor frames (not aligned): foot_left"),
        "{frame}"
    );
    // A one-leg trial keeps its metadata as before.
    ok(&["align", "raw.csv", "-o", "b.csv"], p);
    let text = std::fs::read_to_string(p.join("b.csv")).unwrap();
    assert!(!text.contains("not aligned"), "{text}");
    if let Some(gaitmap) = shared_data("gaitmap-foot-walk/trial.csv") {
        let o = ok(&["align", gaitmap.to_str().unwrap(), "-o", "g.csv"], p);
        assert!(
            stderr(&o).contains("foot_left stays in its raw sensor frame"),
            "{}",
            stderr(&o)
        );
        let text = std::fs::read_to_string(p.join("g.csv")).unwrap();
        let sensors = text.lines().find(|l| l.starts_with("# sensors:")).unwrap();
        assert!(
            sensors.ends_with("[as recorded; after limbfuse align: see imu_frame]"),
            "{sensors}"
        );
        // `# legs:` says "RAW sensor frames" too: annotated alike (it was
        // left as recorded).
        let legs = text.lines().find(|l| l.starts_with("# legs:")).unwrap();
        assert!(
            legs.contains("RAW sensor frames")
                && legs.ends_with("[as recorded; after limbfuse align: see imu_frame]"),
            "{legs}"
        );
        let out = stdout(&ok(&["inspect", "g.csv"], p));
        assert!(!out.contains("IMU frames: not stated"), "{out}");
        assert!(
            out.contains("raw sensor frames (not aligned): foot_left"),
            "{out}"
        );
    }
}
