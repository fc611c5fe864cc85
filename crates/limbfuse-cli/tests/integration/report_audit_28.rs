//! `limbfuse report`, audit 2026-12-05 (every shared recording's report
//! opened in Chromium, docs/REPORT.md): the gait events and walking speeds
//! of the independent walks, which `evaluate` scores against the CoM
//! velocity, went unscored in the report; the initial-contacts plot spoke
//! of a reference on trials without one.

use crate::cli_report::{by_id, parse, series_of};
use crate::s02_support::run_ok;
use crate::support::shared_data;

/// The title text of plot `id`.
pub(crate) fn title_of(html: &str, id: &str) -> String {
    let start = html.find(&format!(r#"id="{id}""#)).expect("the plot");
    let plot = &html[start..start + html[start..].find("</svg></svg>").expect("its end")];
    let t = plot.split(r#"class="title""#).nth(1).expect("a title");
    let t = &t[t.find('>').unwrap() + 1..];
    t[..t.find('<').unwrap()].to_string()
}

/// The independent simulator's walk at 1.2 m/s (no `speed_ref`, no
/// contact reference, a CoM velocity `com_vx` .. `com_vz`): `evaluate`
/// scores `gait-events` and `lowback-speed` on it, their stride speeds
/// against the horizontal CoM speed (`limbfuse_eval::speed_from_com`). The
/// report said "The trial has no contact or speed reference ... to score
/// [them] against", had no events table and drew the speeds alone. Now it
/// has `evaluate`'s numbers, says which reference they are against, and
/// draws that speed as the reference of `plot-speed`.
#[test]
fn report_scores_walking_speed_against_the_com_velocity_as_evaluate_does() {
    let Some(trial) = shared_data("independent-sim/walk-v1.2-s301.csv") else {
        return;
    };
    let tmp = tempfile::tempdir().unwrap();
    let dir = tmp.path();
    let trial = trial.to_str().unwrap();
    for (m, out) in [("gait-events", "ge.csv"), ("lowback-speed", "lb.csv")] {
        run_ok(&["estimate", "--method", m, trial, "-o", out], dir);
    }
    run_ok(&["report", trial, "ge.csv", "lb.csv", "-o", "r.html"], dir);
    let html = std::fs::read_to_string(dir.join("r.html")).unwrap();
    let tags = parse(&html);
    by_id(&tags, "events-table");
    assert!(
        !html.contains("The trial has no contact or speed reference"),
        "the report says there is no reference to score against"
    );
    assert!(html.contains("its horizontal CoM speed"));
    for est in ["ge.csv", "lb.csv"] {
        let v: serde_json::Value =
            serde_json::from_slice(&run_ok(&["evaluate", trial, est, "--json"], dir)).unwrap();
        let n = v["n_strides"].as_u64().unwrap();
        assert!(n > 20, "{est}: {n} strides scored by evaluate");
        let speed = format!(
            "<td>{:.3} ({:.3})</td><td>{n}</td>",
            v["speed_mae_mps"].as_f64().unwrap(),
            v["speed_bias_mps"].as_f64().unwrap(),
        );
        assert!(
            html.contains(&speed),
            "{est}: no {speed} in the events table"
        );
    }
    assert_eq!(series_of(&html, "plot-speed"), ["ref", "e0", "e1"]);
}

/// A simulated walk without gait references and its `lowback-speed`
/// estimate: the initial-contacts plot draws the estimate's contacts alone,
/// but its title read "initial contacts (reference up, estimated down;
/// either foot)". Now it says the trial has no contact reference; with one
/// (`--gait-reference`) the title is as before.
#[test]
fn initial_contacts_title_names_no_reference_when_the_trial_has_none() {
    let tmp = tempfile::tempdir().unwrap();
    let dir = tmp.path();
    for (name, extra) in [("w.csv", None), ("g.csv", Some("--gait-reference"))] {
        let mut args = vec!["simulate", "walking", "--duration", "12", "-o", name];
        args.extend(extra);
        run_ok(&args, dir);
        let est = format!("lb-{name}");
        let html_name = format!("{name}.html");
        run_ok(
            &["estimate", "--method", "lowback-speed", name, "-o", &est],
            dir,
        );
        run_ok(&["report", name, &est, "-o", &html_name], dir);
        let html = std::fs::read_to_string(dir.join(&html_name)).unwrap();
        let title = title_of(&html, "plot-initial-contacts");
        let series = series_of(&html, "plot-initial-contacts");
        if extra.is_none() {
            assert_eq!(series, ["e0"]);
            assert!(!title.contains("reference up"), "{title}");
            assert!(title.contains("no contact_*_ref"), "{title}");
        } else {
            assert_eq!(series, ["ref", "e0"]);
            assert!(title.contains("reference up"), "{title}");
        }
    }
}
