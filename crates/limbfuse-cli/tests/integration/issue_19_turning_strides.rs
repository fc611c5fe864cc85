//! Issue 19: `gait-events` gives a stride that turns faster than
//! `turn_rate` (15 deg/s) its time and events but no length or speed
//! (docs/GAIT_EVENTS.md "Turning strides"). On the shared gaitmap walk the
//! turn's right stride from 16.72 s came out 10 % long (0.68 m against
//! 0.62 m): the foot turned by about 100 deg, and the path of a sensor on
//! the shoe's side is not the heel marker's.

use std::path::Path;

use crate::cli_gait_events::succeed;
use crate::support::shared_data;

/// (stride time, length, turn rate) of every stride of `side` in `estimate`.
fn strides(estimate: &Path, side: &str) -> Vec<(f64, Option<f64>, f64)> {
    let text = std::fs::read_to_string(estimate).unwrap();
    let mut lines = text.lines().filter(|l| !l.starts_with('#'));
    let header: Vec<&str> = lines.next().unwrap().split(',').collect();
    let col = |name: String| header.iter().position(|h| *h == name).unwrap();
    let (time, length, turn) = (
        col(format!("diag_stride_time_{side}")),
        col(format!("diag_stride_length_{side}")),
        col(format!("diag_stride_turn_rate_{side}")),
    );
    lines
        .filter_map(|l| {
            let cells: Vec<&str> = l.split(',').collect();
            let time = cells[time].parse::<f64>().ok()?;
            Some((
                time,
                cells[length].parse::<f64>().ok(),
                cells[turn]
                    .parse::<f64>()
                    .expect("every stride has a turn rate"),
            ))
        })
        .collect()
}

fn json(out: &std::process::Output) -> serde_json::Value {
    serde_json::from_slice(&out.stdout).unwrap()
}

/// Exactly the strides turning faster than 15 deg/s have no length (the
/// turn's and the walk's end), the straight ones turn by less than 6 deg/s
/// (measured -5.5 to +4.3; two left strides by the turns 11-12), and `evaluate` scores 50 strides and says that 3
/// with a reference were withheld, whose removal lowers the length error
/// (2.47 -> 2.34 % measured); the stance and swing times keep all 53.
/// Without the rule (`turn_rate = 1e6`, the binary before 2026-12-07)
/// every stride has a length.
#[test]
fn issue_19_turning_strides_have_no_length_on_the_gaitmap_walk() {
    let Some(trial) = shared_data("gaitmap-foot-walk/trial.csv") else {
        return;
    };
    let d = tempfile::tempdir().unwrap();
    let tr = trial.to_str().unwrap();
    let rule_off = d.path().join("no-turn-rule.toml");
    std::fs::write(&rule_off, "turn_rate = 1e6\n").unwrap();
    succeed(
        &["estimate", "--method", "gait-events", tr, "-o", "e.csv"],
        d.path(),
    );
    succeed(
        &[
            "estimate",
            "--method",
            "gait-events",
            "--params",
            rule_off.to_str().unwrap(),
            tr,
            "-o",
            "off.csv",
        ],
        d.path(),
    );
    let limit = 15f64.to_radians();
    let mut turning = 0;
    for side in ["left", "right"] {
        let with_rule = strides(&d.path().join("e.csv"), side);
        let without = strides(&d.path().join("off.csv"), side);
        assert_eq!(with_rule.len(), without.len(), "{side}: the same strides");
        for (&(time, length, turn), &(time_off, length_off, turn_off)) in
            with_rule.iter().zip(&without)
        {
            assert_eq!((time, turn), (time_off, turn_off), "{side}");
            assert!(length_off.is_some(), "{side}: no rule, every length");
            if turn.abs() > limit {
                turning += 1;
                assert_eq!(length, None, "{side}: turns at {turn} rad/s");
            } else {
                assert_eq!(
                    length, length_off,
                    "{side}: a straight stride keeps its length"
                );
            }
        }
        // the kept strides: straight (-5.5 to +4.3 deg/s) but for two left
        // ones by the turns (11.9 and 11.0 deg/s)
        let curved = with_rule
            .iter()
            .filter(|s| s.1.is_some() && s.2.abs() >= 6f64.to_radians())
            .count();
        assert_eq!(curved, if side == "left" { 2 } else { 0 }, "{side}");
    }
    // the turn (right 25.6, 105.2, 25.5 deg/s; left 89.9) and the end of the
    // walk (right -28.5; left -82.1, -54.9)
    assert_eq!(turning, 7);
    let scored = json(&succeed(&["evaluate", tr, "e.csv", "--json"], d.path()));
    let before = json(&succeed(&["evaluate", tr, "off.csv", "--json"], d.path()));
    assert_eq!(scored["n_withheld"], 3, "{scored}");
    assert_eq!(before["n_withheld"], 0, "{before}");
    assert_eq!(
        (scored["n_lengths"].as_u64(), before["n_lengths"].as_u64()),
        (Some(50), Some(53))
    );
    assert_eq!(scored["n_stance_swing"], 53);
    let err = |j: &serde_json::Value| j["stride_length_error_pct"].as_f64().unwrap();
    assert!(
        err(&scored) < err(&before) - 0.1,
        "{} against {}",
        err(&scored),
        err(&before)
    );
    let text = succeed(&["evaluate", tr, "e.csv"], d.path());
    let text = String::from_utf8(text.stdout).unwrap();
    assert!(
        text.contains(
            "(not scored: 3 strides with a reference that the method withheld for a turn"
        ),
        "{text}"
    );
}
