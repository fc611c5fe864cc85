//! Outputs of the long commands (an audit, 2026-12-05): `montecarlo -o z.csv
//! --svg /nonexistent/x.svg` replaced `z.csv` and then failed, exit 1; `tune`
//! and `montecarlo` found a missing output folder only after their whole
//! run, and the message showed the temporary file's name; a range whose
//! END was off its grid stopped short without a word.

use crate::support::limbfuse;

#[test]
fn a_failing_plot_leaves_the_csv_as_it_was_and_fails_first() {
    let d = tempfile::tempdir().unwrap();
    let p = d.path();
    std::fs::write(p.join("z.csv"), "old\n").unwrap();
    let o = limbfuse(
        &[
            "montecarlo",
            "--runs",
            "1",
            "--levels",
            "0:0:1",
            "--duration",
            "2",
            "-o",
            "z.csv",
            "--svg",
            "missing/x.svg",
        ],
        p,
    );
    let e = String::from_utf8_lossy(&o.stderr);
    assert_eq!(o.status.code(), Some(1), "{e}");
    assert!(
        e.contains("missing/x.svg: the folder missing does not exist"),
        "{e}"
    );
    assert!(!e.contains(".tmp"), "{e}");
    assert!(
        !String::from_utf8_lossy(&o.stdout).contains("mean RMSE"),
        "the study ran first"
    );
    assert_eq!(std::fs::read_to_string(p.join("z.csv")).unwrap(), "old\n");
}

#[test]
fn tune_refuses_a_missing_output_folder_before_its_search() {
    let d = tempfile::tempdir().unwrap();
    let p = d.path();
    let o = limbfuse(
        &["simulate", "walking", "--duration", "5", "-o", "w.csv"],
        p,
    );
    assert!(o.status.success());
    let o = limbfuse(
        &[
            "tune",
            "--method",
            "mjls",
            "w.csv",
            "--window",
            "1:4",
            "-o",
            "missing/t.toml",
        ],
        p,
    );
    let e = String::from_utf8_lossy(&o.stderr);
    assert_eq!(o.status.code(), Some(1), "{e}");
    assert!(
        e.contains("-o missing/t.toml: the folder missing does not exist"),
        "{e}"
    );
    assert!(!e.contains("RMSE"), "the search ran first: {e}");
}

/// An audit: `--speeds 0.4:0.65:0.1` built 0.4-0.6 without a word (and
/// `--levels` likewise); an END off the START + k STEP grid is refused.
#[test]
fn a_range_whose_end_is_off_its_grid_is_refused() {
    let d = tempfile::tempdir().unwrap();
    let p = d.path();
    for (args, needle) in [
        (
            &[
                "gait-library",
                "build",
                "--speeds",
                "0.4:0.65:0.1",
                "-o",
                "l.json",
            ][..],
            "the last speed would be 0.6); give an END on that grid, e.g. 0.6 or 0.7",
        ),
        (
            &[
                "montecarlo",
                "--levels",
                "0:5:2",
                "--runs",
                "1",
                "-o",
                "m.csv",
            ][..],
            "the last level would be 4)",
        ),
    ] {
        let o = limbfuse(args, p);
        let e = String::from_utf8_lossy(&o.stderr);
        assert_eq!(o.status.code(), Some(1), "{e}");
        assert!(e.contains(needle), "{e}");
    }
}
