//! A file of another kind where a trial or a parameter file is expected
//! says what it is (an audit, 2026-12-05): a gait library given as a trial
//! was "duplicate column `rest_length:1.0`", an estimate given to `tune` "no
//! reference angle column", a calibration file given as `--params` "unknown
//! field `format`"; a parameter file or an FES model (`.toml`) given as a
//! trial "missing required column `t`" or "a JSON file" (its `[model]`
//! line; session 29).

use crate::support::limbfuse;

fn refused(args: &[&str], dir: &std::path::Path, needle: &str) {
    let o = limbfuse(args, dir);
    let e = String::from_utf8_lossy(&o.stderr);
    assert_eq!(o.status.code(), Some(1), "{args:?}: {e}");
    assert!(e.contains(needle), "{args:?}: expected `{needle}` in: {e}");
}

#[test]
fn each_kind_of_file_is_named_where_another_is_expected() {
    let d = tempfile::tempdir().unwrap();
    let p = d.path();
    for args in [
        &["simulate", "walking", "--duration", "4", "-o", "w.csv"][..],
        &["estimate", "--method", "local", "w.csv", "-o", "e.csv"],
        &[
            "gait-library",
            "build",
            "--speeds",
            "0.7:0.7:0.1",
            "-o",
            "lib.json",
        ],
        &["simulate", "calibration", "-o", "poses.csv"],
        &["calibrate", "poses.csv", "-o", "cal.toml"],
        &["params", "--method", "sdre", "-o", "sdre.toml"],
    ] {
        let o = limbfuse(args, p);
        assert!(
            o.status.success(),
            "{args:?}: {}",
            String::from_utf8_lossy(&o.stderr)
        );
    }
    refused(
        &["resample", "lib.json", "--rate", "50", "-o", "x.csv"],
        p,
        "lib.json:1: header: a JSON file (e.g. a gait library), not a CSV table",
    );
    refused(
        &["tune", "--method", "mjls", "e.csv", "--window", "0:3", "-o", "t.toml"],
        p,
        "an estimate file (`# method: local`), not a trial: give the trial it was made from (`w.csv`)",
    );
    refused(
        &[
            "estimate", "--method", "mjls", "--params", "cal.toml", "w.csv", "-o", "x.csv",
        ],
        p,
        "cal.toml: a sensor calibration file",
    );
    std::fs::write(
        p.join("model.toml"),
        "# knee-fes model parameters\n[model]\ninertia = 0.45\n",
    )
    .unwrap();
    for toml in ["cal.toml", "sdre.toml", "model.toml"] {
        refused(
            &["estimate", "--method", "mjls", toml, "-o", "x.csv"],
            p,
            "a TOML file (e.g. a parameter file or an FES model), not a CSV table",
        );
    }
}
