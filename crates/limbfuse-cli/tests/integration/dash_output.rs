//! `-o -`: standard output for `estimate` and `params`; every other command
//! writes a file, and used to create one named `-` (a stray `-` parameter
//! file had been committed to this repository that way). Now refused,
//! exit 1, nothing created.

use crate::support::limbfuse;

#[test]
fn dash_output_is_stdout_or_refused() {
    let tmp = tempfile::tempdir().unwrap();
    let dir = tmp.path();
    let o = limbfuse(&["params", "--method", "local", "-o", "-"], dir);
    assert_eq!(o.status.code(), Some(0));
    assert!(String::from_utf8_lossy(&o.stdout).contains("method = \"local\""));
    assert!(!dir.join("-").exists());
    assert_eq!(
        limbfuse(
            &["simulate", "walking", "--duration", "3", "-o", "w.csv"],
            dir
        )
        .status
        .code(),
        Some(0)
    );
    for args in [
        &["simulate", "walking", "--duration", "2", "-o", "-"][..],
        &["align", "w.csv", "-o", "-"],
        &["resample", "w.csv", "--rate", "50", "-o", "-"],
        &[
            "gait-library",
            "build",
            "--speeds",
            "0.6:0.7:0.1",
            "-o",
            "-",
        ],
    ] {
        let o = limbfuse(args, dir);
        assert_eq!(o.status.code(), Some(1), "{args:?}");
        let err = String::from_utf8_lossy(&o.stderr);
        assert!(
            err.contains("output `-`: this command writes a file"),
            "{args:?}: {err}"
        );
        assert!(!dir.join("-").exists(), "{args:?} created a file named -");
    }
}
