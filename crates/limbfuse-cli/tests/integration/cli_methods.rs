//! Issue 13, the method layer from the command line: `limbfuse methods`
//! lists every method, `limbfuse params --method X` writes a default file
//! that reads back to the defaults (bit-identical estimates), and a key that
//! does not belong to the method is an error naming file, line and key.

use std::process::Output;

use limbfuse_methods::MethodName;

use crate::support::limbfuse;

fn ok(o: &Output) -> String {
    let e = String::from_utf8_lossy(&o.stderr).into_owned();
    assert_eq!(o.status.code(), Some(0), "stderr: {e}");
    String::from_utf8_lossy(&o.stdout).into_owned()
}

fn user_error(o: &Output, needles: &[&str]) {
    let e = String::from_utf8_lossy(&o.stderr).into_owned();
    assert_eq!(o.status.code(), Some(1), "stderr: {e}");
    assert!(!e.contains("panicked"), "{e}");
    for n in needles {
        assert!(e.contains(n), "expected `{n}` in: {e}");
    }
}

#[test]
fn methods_lists_every_method() {
    let d = tempfile::tempdir().unwrap();
    let out = ok(&limbfuse(&["methods"], d.path()));
    for m in MethodName::ALL {
        assert!(out.contains(m.name()), "{} missing from:\n{out}", m.name());
    }
}

/// The trial each method runs on in this test.
fn trial_for(m: MethodName) -> &'static str {
    match m {
        MethodName::KneeSelfAlign | MethodName::KneeGyroAxis => "knee.csv",
        MethodName::Sdre | MethodName::Ekf | MethodName::Rmx => "fes.csv",
        _ => "walk.csv",
    }
}

#[test]
fn default_parameter_files_read_back_to_the_defaults() {
    let d = tempfile::tempdir().unwrap();
    let p = d.path();
    for args in [
        &["simulate", "walking", "--duration", "4", "-o", "walk.csv"][..],
        &["simulate", "knee", "--duration", "8", "-o", "knee.csv"],
        &["simulate", "knee-fes", "--duration", "3", "-o", "fes.csv"],
    ] {
        ok(&limbfuse(args, p));
    }
    for m in MethodName::ALL {
        if m == MethodName::ImmBslip {
            continue; // needs a library; covered by the unknown-key test
        }
        let name = m.name();
        let file = format!("{name}.toml");
        ok(&limbfuse(&["params", "--method", name, "-o", &file], p));
        let trial = trial_for(m);
        let plain = format!("{name}-plain.csv");
        let with = format!("{name}-params.csv");
        ok(&limbfuse(
            &["estimate", "--method", name, trial, "-o", &plain],
            p,
        ));
        ok(&limbfuse(
            &[
                "estimate", "--method", name, "--params", &file, trial, "-o", &with,
            ],
            p,
        ));
        // Equal but for the `# command:` line, which records the flags given.
        let read = |f: &str| -> Vec<String> {
            let text = std::fs::read_to_string(p.join(f)).unwrap();
            let lines: Vec<String> = text.lines().map(str::to_string).collect();
            assert_eq!(
                lines
                    .iter()
                    .filter(|l| l.starts_with("# command: limbfuse estimate"))
                    .count(),
                1,
                "{f}"
            );
            lines
                .into_iter()
                .filter(|l| !l.starts_with("# command:"))
                .collect()
        };
        let (a, b) = (read(&plain), read(&with));
        assert!(
            a == b,
            "{name}: the default parameter file changes the estimate"
        );
    }
}

#[test]
fn a_key_that_does_not_belong_to_the_method_is_an_error() {
    let d = tempfile::tempdir().unwrap();
    let p = d.path();
    ok(&limbfuse(
        &["simulate", "walking", "--duration", "2", "-o", "walk.csv"],
        p,
    ));
    for m in MethodName::ALL {
        let name = m.name();
        let file = format!("{name}.toml");
        std::fs::write(p.join(&file), "bogus_key = 1\n").unwrap();
        let o = limbfuse(
            &[
                "estimate", "--method", name, "--params", &file, "walk.csv", "-o", "e.csv",
            ],
            p,
        );
        user_error(&o, &[&format!("{file}:1:1"), "bogus_key"]);
    }
    // A key of another method: encoder_sigma is mjls's.
    std::fs::write(p.join("g.toml"), "encoder_sigma = 0.01\n").unwrap();
    let o = limbfuse(
        &[
            "estimate", "--method", "global", "--params", "g.toml", "walk.csv", "-o", "e.csv",
        ],
        p,
    );
    user_error(&o, &["g.toml", "encoder_sigma", "`mjls`"]);
    // A file written for another method.
    std::fs::write(p.join("k.toml"), "method = \"knee-selfalign\"\n").unwrap();
    let o = limbfuse(
        &[
            "estimate", "--method", "rmx", "--params", "k.toml", "walk.csv", "-o", "e.csv",
        ],
        p,
    );
    user_error(&o, &["k.toml", "knee-selfalign", "rmx"]);
}

#[test]
fn unknown_methods_are_user_errors_in_every_command() {
    let d = tempfile::tempdir().unwrap();
    let p = d.path();
    user_error(
        &limbfuse(&["params", "--method", "magic"], p),
        &["unknown method `magic`", "mjls"],
    );
    user_error(
        &limbfuse(&["tune", "--method", "magic", "t.csv", "-o", "x.toml"], p),
        &["unknown method `magic`"],
    );
}
