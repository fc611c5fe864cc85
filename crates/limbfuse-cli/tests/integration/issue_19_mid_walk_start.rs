//! `gait-events` on a recording that starts mid-walk: the shared gaitmap
//! walk with its first 2-4 s of rows removed. Each foot's events before its
//! axis sign was decided (its first stride) used to be lost: 2-3 initial
//! and 2 final contacts missed at every cut. They are now replayed and
//! reported late (docs/GAIT_EVENTS.md, "Events before the axis sign").
//! What may remain is one initial contact of a foot that is already in
//! swing at the first row: its swing has no start, so its end is not an
//! event (measured: cuts at 2.5-4.0 s). Skipped when `../shared/data` is
//! absent.

use crate::s02_support::run_ok;
use crate::support::shared_data;

/// `src` without the data rows before `start` (s); comments and the
/// column header kept.
fn cut_before(src: &str, start: f64) -> String {
    let mut out = String::new();
    let mut header_seen = false;
    for line in src.lines() {
        let keep = if line.starts_with('#') {
            true
        } else if !header_seen {
            header_seen = true;
            true
        } else {
            let t: f64 = line.split(',').next().unwrap().parse().unwrap();
            t >= start
        };
        if keep {
            out += line;
            out += "\n";
        }
    }
    out
}

#[test]
fn issue_19_a_recording_that_starts_mid_walk() {
    let Some(trial) = shared_data("gaitmap-foot-walk/trial.csv") else {
        return;
    };
    let src = std::fs::read_to_string(trial).unwrap();
    let tmp = tempfile::tempdir().unwrap();
    let dir = tmp.path();
    for start in [2.0, 2.5, 3.0, 3.5, 4.0] {
        std::fs::write(dir.join("cut.csv"), cut_before(&src, start)).unwrap();
        run_ok(
            &[
                "estimate",
                "--method",
                "gait-events",
                "cut.csv",
                "-o",
                "e.csv",
            ],
            dir,
        );
        let v: serde_json::Value =
            serde_json::from_slice(&run_ok(&["evaluate", "cut.csv", "e.csv", "--json"], dir))
                .unwrap();
        let missed = |kind: &str| v[kind]["missed"].as_u64().unwrap();
        assert_eq!(missed("final_contact"), 0, "cut at {start} s: {v}");
        let ic = missed("initial_contact");
        assert!(ic <= 1, "cut at {start} s: {v}");
        if start == 2.0 {
            // Both feet on the ground or at push-off at 2.0 s: every event.
            assert_eq!(ic, 0, "{v}");
            assert_eq!(v["initial_contact"]["n_reference"], 56, "{v}");
        }
        for kind in ["initial_contact", "final_contact"] {
            assert_eq!(
                v[kind]["extra"].as_u64().unwrap(),
                u64::from(kind == "final_contact"),
                "cut at {start} s: {v}"
            );
            assert!(
                v[kind]["p95_abs_ms"].as_f64().unwrap() <= 13.0,
                "cut at {start} s: {v}"
            );
        }
    }
}
