//! `limbfuse simulate walking --gait-reference` (issue 19): the walking
//! simulator's feet contacts and per-stride speed as reference columns, so
//! that `evaluate` scores `gait-events` and `lowback-speed` on a simulated
//! trial (`limbfuse_sim::gait_truth`).

use std::path::Path;

use crate::s02_support::run_ok;

fn json(dir: &Path, trial: &str, method: &str) -> serde_json::Value {
    run_ok(&["estimate", "--method", method, trial, "-o", "e.csv"], dir);
    serde_json::from_slice(&run_ok(&["evaluate", trial, "e.csv", "--json"], dir)).unwrap()
}

fn header(path: &Path) -> String {
    let text = std::fs::read_to_string(path).unwrap();
    text.lines()
        .find(|l| !l.starts_with('#'))
        .unwrap()
        .to_string()
}

#[test]
fn issue_19_simulated_walking_scores_gait_events_and_lowback_speed() {
    let d = tempfile::tempdir().unwrap();
    let p = d.path();
    run_ok(
        &[
            "simulate",
            "walking",
            "--duration",
            "20",
            "--seed",
            "2",
            "-o",
            "plain.csv",
        ],
        p,
    );
    assert!(!header(&p.join("plain.csv")).contains("contact_"));
    for leg in ["right", "left"] {
        run_ok(
            &[
                "simulate",
                "walking",
                "--duration",
                "20",
                "--seed",
                "2",
                "--leg",
                leg,
                "--gait-reference",
                "-o",
                "g.csv",
            ],
            p,
        );
        let h = header(&p.join("g.csv"));
        assert!(
            h.ends_with(",contact_left_ref,contact_right_ref,speed_ref"),
            "{h}"
        );
        let v = json(p, "g.csv", "gait-events");
        let (ic, fc) = (&v["initial_contact"], &v["final_contact"]);
        for e in [ic, fc] {
            assert_eq!(e["missed"], 0, "{leg}: {v}");
            assert_eq!(e["extra"], 0, "{leg}: {v}");
        }
        // The simulator's own offsets (docs/RESULTS.md, "gait-events on the
        // walking simulator"): its swing foot reaches the landmarks 28-35
        // ms (contact) and 48-53 ms (toe off) before the events it places.
        let ic_mean = ic["mean_ms"].as_f64().unwrap();
        let fc_mean = fc["mean_ms"].as_f64().unwrap();
        assert!((-45.0..-25.0).contains(&ic_mean), "{leg}: {v}");
        assert!((-65.0..-40.0).contains(&fc_mean), "{leg}: {v}");
        // Issue 19's targets (the seed's sensor errors move these by about 1 %:
        // seeds 2-5 give 0.4-1.6 %, 0.004-0.016 m/s).
        let length = v["stride_length_error_pct"].as_f64().unwrap();
        let speed = v["speed_mae_mps"].as_f64().unwrap();
        assert!(length <= 2.5 && speed <= 0.03, "{leg}: {v}");
        let v = json(p, "g.csv", "lowback-speed");
        assert_eq!(v["initial_contact"]["missed"], 0, "{leg}: {v}");
        assert_eq!(v["initial_contact"]["extra"], 0, "{leg}: {v}");
    }
}
