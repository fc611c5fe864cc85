//! `evaluate --window` on a gait-event estimate: it was silently ignored
//! (the whole gaitmap walk scored: 56 initial contacts for `--window 0:10`);
//! it now scores the rows inside the window only. `--offset-free` and
//! `--max-lag`, which only mean something for angles, are refused (exit 1)
//! instead of ignored. Skipped when `../shared/data` is absent.

use crate::s02_support::{gaitmap_events, run_ok};
use crate::support::limbfuse;

#[test]
fn issue_19_event_evaluation_honours_the_window() {
    let tmp = tempfile::tempdir().unwrap();
    let dir = tmp.path();
    let Some(trial) = gaitmap_events(dir) else {
        return;
    };
    let trial = trial.as_str();
    let ic = |extra: &[&str]| -> (u64, u64) {
        let mut args = vec!["evaluate", trial, "ge.csv", "--json"];
        args.extend_from_slice(extra);
        let v: serde_json::Value = serde_json::from_slice(&run_ok(&args, dir)).unwrap();
        (
            v["initial_contact"]["n_reference"].as_u64().unwrap(),
            v["n_samples"].as_u64().unwrap(),
        )
    };
    let (all, rows) = ic(&[]);
    let (first, first_rows) = ic(&["--window", "0:10"]);
    let (rest, _) = ic(&["--window", "10:"]);
    assert_eq!((all, rows), (56, 7928));
    assert!(first > 0 && first < all, "{first} of {all} in 0-10 s");
    assert_eq!(first_rows, 2049, "rows at 0-10 s at 204.8 Hz");
    // An event at the cut becomes an unscored edge at most once.
    assert!(
        first + rest >= all - 1 && first + rest <= all,
        "{first} + {rest} vs {all}"
    );
    for flag in [&["--offset-free"][..], &["--max-lag", "3"]] {
        let mut args = vec!["evaluate", trial, "ge.csv"];
        args.extend_from_slice(flag);
        let o = limbfuse(&args, dir);
        assert_eq!(o.status.code(), Some(1), "{flag:?}");
        let err = String::from_utf8_lossy(&o.stderr);
        assert!(
            err.contains("to angle errors only; ge.csv is scored for gait events"),
            "{flag:?}: {err}"
        );
    }
}
