//! Issue 19 methods in `limbfuse report` (issue 17 item 3): a report of
//! `gait-events` or `lowback-speed` estimates showed no plot and said "the
//! trial has no reference" even on the gaitmap walk, which has contact and
//! speed references. It now has a gait-events panel (each foot's contact and
//! the walking speed against `contact_*_ref` / `speed_ref`) and the numbers
//! of `evaluate` for them. Skipped when `../shared/data` is absent.

use crate::cli_report::{by_id, parse, series_of};
use crate::s02_support::{gaitmap_events, run_ok};

#[test]
fn issue_19_report_of_gait_events_on_the_gaitmap_walk() {
    let tmp = tempfile::tempdir().unwrap();
    let dir = tmp.path();
    let Some(trial) = gaitmap_events(dir) else {
        return;
    };
    let trial = trial.as_str();
    run_ok(&["report", trial, "ge.csv", "-o", "r.html"], dir);
    let html = std::fs::read_to_string(dir.join("r.html")).unwrap();
    let tags = parse(&html);
    for id in [
        "panel-events",
        "plot-contact-left",
        "plot-contact-right",
        "plot-speed",
        "events-table",
    ] {
        by_id(&tags, id);
    }
    for id in ["plot-contact-left", "plot-contact-right", "plot-speed"] {
        assert_eq!(series_of(&html, id), ["ref", "e0"], "{id}");
    }
    assert!(!html.contains("has no reference to evaluate against"));
    // The table holds evaluate's numbers.
    let v: serde_json::Value =
        serde_json::from_slice(&run_ok(&["evaluate", trial, "ge.csv", "--json"], dir)).unwrap();
    let ic = &v["initial_contact"];
    let row = format!(
        "<td>{} / {} ({}, {})</td><td>{:.1} / {:.1}</td>",
        ic["n_matched"],
        ic["n_reference"],
        ic["missed"],
        ic["extra"],
        ic["median_abs_ms"].as_f64().unwrap(),
        ic["p95_abs_ms"].as_f64().unwrap()
    );
    assert!(html.contains(&row), "no {row} in the events table");
    // (the turning strides withheld, as `evaluate` says: 3 here)
    assert_eq!(v["n_withheld"], 3);
    let speed = format!(
        "<td>{:.3} ({:.3})</td><td>{} (3 more withheld: turning)</td>",
        v["speed_mae_mps"].as_f64().unwrap(),
        v["speed_bias_mps"].as_f64().unwrap(),
        v["n_strides"]
    );
    assert!(html.contains(&speed), "no {speed} in the events table");
    // the phase accuracy, and the strides the length error is over (an
    // audit: both missing; the 56 strides of the speed shown alone)
    let phase = format!("<td>{:.1}</td>", v["phase_accuracy_pct"].as_f64().unwrap());
    assert!(html.contains(&phase), "no {phase} in the events table");
    let length = format!(
        "<td>{:.2} ({})</td>",
        v["stride_length_error_pct"].as_f64().unwrap(),
        v["n_lengths"]
    );
    assert!(html.contains(&length), "no {length} in the events table");
    // the stance and swing time errors (session 32: evaluate had them, the
    // report's table did not)
    let ms = |k: &str| format!("{:.1}", v[k].as_f64().unwrap());
    let stance_swing = format!(
        "<td>{} ({}) / {} ({}) ({})</td>",
        ms("stance_time_mae_ms"),
        ms("stance_time_bias_ms"),
        ms("swing_time_mae_ms"),
        ms("swing_time_bias_ms"),
        v["n_stance_swing"]
    );
    assert!(
        html.contains(&stance_swing),
        "no {stance_swing} in the events table"
    );
}
