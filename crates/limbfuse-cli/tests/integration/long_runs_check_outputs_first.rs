//! Outputs of the long commands (an audit, 2026-12-05): `montecarlo -o z.csv
//! --svg /nonexistent/x.svg` replaced `z.csv` and then failed, exit 1; `tune`
//! and `montecarlo` found a missing output folder only after their whole
//! run, and the message showed the temporary file's name.

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
