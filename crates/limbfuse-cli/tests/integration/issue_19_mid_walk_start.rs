//! `gait-events` on a recording that starts mid-walk: the shared gaitmap
//! walk with its first 2-4 s of rows removed. Each foot's events before its
//! axis sign was decided (its first stride) used to be lost: 2-3 initial
//! and 2 final contacts missed at every cut. They are now replayed and
//! reported late (docs/GAIT_EVENTS.md, "Events before the axis sign"); a
//! foot already in swing at the first row (cuts at 2.5-4.0 s), or after a
//! gap in its readings, ends that swing with an initial contact once
//! `min_swing_time` of it was seen (before, the detector waited for a
//! rest). `lowback-speed` on the HA001 straight walk cut the same way:
//! its last test. Skipped when `../shared/data` is absent.

use crate::s02_support::run_ok;
use crate::support::shared_data;

/// `src` without the data rows at `from <= t < to` (s); comments and the
/// column header kept.
fn without_rows(src: &str, from: f64, to: f64) -> String {
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
            !(from..to).contains(&t)
        };
        if keep {
            out += line;
            out += "\n";
        }
    }
    out
}

/// `trial` (file text) written to `dir`, estimated with `method` and
/// evaluated: `evaluate --json`.
fn evaluate(dir: &std::path::Path, method: &str, trial: &str) -> serde_json::Value {
    std::fs::write(dir.join("variant.csv"), trial).unwrap();
    run_ok(
        &["estimate", "--method", method, "variant.csv", "-o", "e.csv"],
        dir,
    );
    serde_json::from_slice(&run_ok(
        &["evaluate", "variant.csv", "e.csv", "--json"],
        dir,
    ))
    .unwrap()
}

#[test]
fn issue_19_a_recording_that_starts_mid_walk() {
    let Some(trial) = shared_data("gaitmap-foot-walk/trial.csv") else {
        return;
    };
    let src = std::fs::read_to_string(trial).unwrap();
    let tmp = tempfile::tempdir().unwrap();
    for start in [2.0, 2.5, 3.0, 3.5, 4.0] {
        let v = evaluate(tmp.path(), "gait-events", &without_rows(&src, 0.0, start));
        for kind in ["initial_contact", "final_contact"] {
            assert_eq!(v[kind]["missed"], 0, "cut at {start} s: {v}");
            // No extra event (until 2026-12-05 one final contact, the full
            // walk's turning step at 16.2 s).
            assert_eq!(v[kind]["extra"], 0, "cut at {start} s: {v}");
            assert!(
                v[kind]["p95_abs_ms"].as_f64().unwrap() <= 13.0,
                "cut at {start} s: {v}"
            );
        }
    }
}

/// 0.5 s and 2 s of rows missing mid-walk: the foot that comes back in
/// swing ends it with its initial contact (before: 1 missed in each), and
/// the phase does not split that swing from a toe off before the gap
/// (phase accuracy 93.7-93.8 %, as without the gap; 92.8-92.9 % with the
/// stale toe off).
#[test]
fn issue_19_a_foot_back_from_a_gap_in_swing() {
    let Some(trial) = shared_data("gaitmap-foot-walk/trial.csv") else {
        return;
    };
    let src = std::fs::read_to_string(trial).unwrap();
    let tmp = tempfile::tempdir().unwrap();
    for (from, to) in [(6.0, 6.5), (6.0, 8.0)] {
        let v = evaluate(tmp.path(), "gait-events", &without_rows(&src, from, to));
        assert_eq!(v["initial_contact"]["missed"], 0, "gap {from}-{to} s: {v}");
        assert_eq!(v["initial_contact"]["extra"], 0, "gap {from}-{to} s: {v}");
        assert!(
            v["phase_accuracy_pct"].as_f64().unwrap() >= 93.5,
            "gap {from}-{to} s: {v}"
        );
    }
}

/// `lowback-speed` on the HA001 straight walk cut mid-walk (rows before
/// 4, 5 and 6 s removed): the gravity estimate starts from walking samples
/// and is not settled for the first steps, which put a constant into the
/// vertical acceleration and a parabola into each step's excursion (cut at
/// 5 s: the first steps 4.4 against 3.7 cm). Each step's mean vertical
/// acceleration is now removed (periodic gait): stride speed MAE 0.026 /
/// 0.032 / 0.031 m/s, against 0.035 / 0.047 / 0.048 before (0.028 on the
/// whole recording).
#[test]
fn issue_19_lowback_walk_cut_mid_walk() {
    let Some(trial) = shared_data("mobgap-lowerback/HA001-test5-trial1.csv") else {
        return;
    };
    let src = std::fs::read_to_string(trial).unwrap();
    let tmp = tempfile::tempdir().unwrap();
    for start in [4.0, 5.0, 6.0] {
        let v = evaluate(tmp.path(), "lowback-speed", &without_rows(&src, 0.0, start));
        let mae = v["speed_mae_mps"].as_f64().unwrap();
        assert!(mae <= 0.035, "cut at {start} s: {v}");
        assert!(
            v["n_strides"].as_u64().unwrap() >= 4,
            "cut at {start} s: {v}"
        );
    }
}

/// `imm-bslip --imm-config continuous` on the shared 0.85 m/s B-SLIP trial
/// started mid-stride (its first 0.3 or 0.9 s removed). The bank starts at
/// mid-stance on `first_side`, true of the uncut trial only; it never
/// re-synchronised: 43.0 % and 35.9 % phase accuracy with a 0.4-1.0 m/s
/// library (uncut 97.2 %). It is now restarted at the first lateral sway
/// extremum (docs/GAIT_IMM.md, "Restart after a gap or a mid-stride
/// start"): 89.3 % and 91.0 %; the uncut trial keeps its 97.2 % (the bank
/// agrees with the sway and goes on). This test's 0.7-0.9 m/s library:
/// bare 38.4 / 83.5 %.
#[test]
fn issue_19_imm_continuous_on_a_bslip_trial_started_mid_stride() {
    let Some(path) = shared_data("independent-sim/bslip-v0.85-s21.csv") else {
        eprintln!("skipped: ../shared/data/independent-sim is absent");
        return;
    };
    let src = std::fs::read_to_string(path).unwrap();
    let d = tempfile::tempdir().unwrap();
    let p = d.path();
    run_ok(
        &[
            "gait-library",
            "build",
            "--speeds",
            "0.7:0.9:0.1",
            "--leg-length",
            "0.95",
            "--mass",
            "70",
            "-o",
            "lib.json",
        ],
        p,
    );
    let mut report = Vec::new();
    let mut failed = false;
    for (cut, target) in [(0.0, 96.0), (0.3, 88.0), (0.9, 88.0)] {
        std::fs::write(p.join("variant.csv"), without_rows(&src, 0.0, cut)).unwrap();
        run_ok(
            &[
                "estimate",
                "--method",
                "imm-bslip",
                "--library",
                "lib.json",
                "--imm-config",
                "continuous",
                "variant.csv",
                "-o",
                "e.csv",
            ],
            p,
        );
        let v: serde_json::Value =
            serde_json::from_slice(&run_ok(&["evaluate", "variant.csv", "e.csv", "--json"], p))
                .unwrap();
        let acc = v["phase_accuracy_pct"].as_f64().unwrap();
        let bad = acc < target;
        failed |= bad;
        report.push(format!(
            "first {cut} s removed: {acc:.1} % (target {target}){}",
            if bad { "  <-- FAIL" } else { "" }
        ));
    }
    assert!(!failed, "\n{}", report.join("\n"));
}
