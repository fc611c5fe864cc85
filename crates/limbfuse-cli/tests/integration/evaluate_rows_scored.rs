//! `evaluate` names the channels scored on fewer rows than have a reference
//! (found 2026-12-06: on the real S02 pass 1, `local`'s thigh was scored on
//! 156 of the 311 rows, `chain`'s channels on 256, while the table and the
//! "mean RMSE" gave no hint that the two methods' figures cover different
//! rows; an estimate whose thigh never started printed only its foot).

use crate::s02_support::run_ok;

#[test]
fn evaluate_names_the_channels_an_estimate_leaves_empty_on_referenced_rows() {
    let d = tempfile::tempdir().unwrap();
    let p = d.path();
    run_ok(
        &[
            "simulate",
            "walking",
            "--duration",
            "4",
            "--seed",
            "3",
            "-o",
            "w.csv",
        ],
        p,
    );
    run_ok(
        &["estimate", "--method", "chain", "w.csv", "-o", "e.csv"],
        p,
    );
    let text = String::from_utf8(run_ok(&["evaluate", "w.csv", "e.csv"], p)).unwrap();
    // `chain` waits for its start-up window (docs/CHAIN.md): its first rows
    // are empty, so every channel is scored on fewer than the 400 rows
    assert!(
        text.contains("note: scored on fewer rows than have a reference (trunk, thigh, "),
        "{text}"
    );
    assert!(text.contains(" 300 of 400)"), "{text}");
    let json: serde_json::Value =
        serde_json::from_slice(&run_ok(&["evaluate", "w.csv", "e.csv", "--json"], p)).unwrap();
    let (scored, with_ref) = (
        json["rows_scored"]["thigh"].as_u64().unwrap(),
        json["rows_with_reference"]["thigh"].as_u64().unwrap(),
    );
    assert_eq!(with_ref, 400);
    assert!(scored > 100 && scored < 400, "{json}");
    // A window after the start scores every row it holds: no note.
    let text =
        String::from_utf8(run_ok(&["evaluate", "w.csv", "e.csv", "--window", "2:"], p)).unwrap();
    assert!(!text.contains("scored on fewer rows"), "{text}");
}
