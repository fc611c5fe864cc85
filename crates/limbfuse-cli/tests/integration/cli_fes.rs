//! Paper 004 on the command line: simulate knee-fes / fixed-hip, estimate
//! with sdre, ekf, rmx; bad input (missing stimulation channel, unphysical
//! parameters, no model metadata) exits 1 with a clear message.

use std::process::Output;

use crate::support::limbfuse;

fn user_error(o: &Output, needles: &[&str]) {
    let e = String::from_utf8_lossy(&o.stderr);
    assert_eq!(o.status.code(), Some(1), "stderr: {e}");
    assert!(!e.contains("panicked"), "{e}");
    for n in needles {
        assert!(e.contains(n), "expected `{n}` in: {e}");
    }
}

fn ok(o: &Output) {
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
}

#[test]
fn knee_fes_round_trip_and_bad_input() {
    let d = tempfile::tempdir().unwrap();
    let p = d.path();
    ok(&limbfuse(
        &[
            "simulate",
            "knee-fes",
            "-o",
            "k.csv",
            "--subject",
            "P2-R",
            "--duration",
            "8",
        ],
        p,
    ));
    for m in ["sdre", "ekf", "rmx"] {
        ok(&limbfuse(
            &[
                "estimate",
                "--method",
                m,
                "k.csv",
                "-o",
                &format!("{m}.csv"),
            ],
            p,
        ));
        let o = limbfuse(&["evaluate", "k.csv", &format!("{m}.csv"), "--json"], p);
        ok(&o);
        let j: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
        let knee = j["rmse_deg"]["knee"].as_f64().unwrap();
        assert!(knee < 3.0, "{m}: knee RMSE {knee} deg");
    }
    let text = std::fs::read_to_string(p.join("k.csv")).unwrap();
    // Missing stimulation column.
    let mut lines = text.lines();
    let mut out = String::new();
    let mut drop_col = None;
    for l in lines.by_ref() {
        if l.starts_with('#') {
            out.push_str(l);
            out.push('\n');
            continue;
        }
        let cols: Vec<&str> = l.split(',').collect();
        drop_col = cols.iter().position(|c| *c == "u_ke");
        out.push_str(&without(&cols, drop_col.unwrap()));
        break;
    }
    for l in lines {
        out.push_str(&without(
            &l.split(',').collect::<Vec<_>>(),
            drop_col.unwrap(),
        ));
    }
    std::fs::write(p.join("nostim.csv"), out).unwrap();
    user_error(
        &limbfuse(
            &["estimate", "--method", "sdre", "nostim.csv", "-o", "x.csv"],
            p,
        ),
        &["nostim.csv", "u_ke"],
    );
    // Unphysical parameters.
    std::fs::write(
        p.join("neg.csv"),
        text.replace("# param.inertia: ", "# param.inertia: -"),
    )
    .unwrap();
    user_error(
        &limbfuse(
            &["estimate", "--method", "ekf", "neg.csv", "-o", "x.csv"],
            p,
        ),
        &["inertia", "> 0"],
    );
    std::fs::write(p.join("bad.toml"), "[model]\nmass = 0.0\n").unwrap();
    user_error(
        &limbfuse(
            &[
                "estimate", "--method", "sdre", "k.csv", "-o", "x.csv", "--params", "bad.toml",
            ],
            p,
        ),
        &["mass"],
    );
    // No model metadata.
    std::fs::write(
        p.join("nomodel.csv"),
        text.replace("# model: knee-fes\n", ""),
    )
    .unwrap();
    user_error(
        &limbfuse(
            &["estimate", "--method", "sdre", "nomodel.csv", "-o", "x.csv"],
            p,
        ),
        &["# model:"],
    );
}

fn without(cols: &[&str], i: usize) -> String {
    let mut c = cols.to_vec();
    c.remove(i);
    c.join(",") + "\n"
}

#[test]
fn fixed_hip_round_trip() {
    let d = tempfile::tempdir().unwrap();
    let p = d.path();
    ok(&limbfuse(
        &["simulate", "fixed-hip", "-o", "h.csv", "--duration", "6"],
        p,
    ));
    let text = std::fs::read_to_string(p.join("h.csv")).unwrap();
    assert!(text.contains("tau_hip_motor") && text.contains("u_hf"));
    ok(&limbfuse(
        &["estimate", "--method", "sdre", "h.csv", "-o", "s.csv"],
        p,
    ));
    let o = limbfuse(&["evaluate", "h.csv", "s.csv", "--json"], p);
    ok(&o);
    let j: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
    assert!(j["rmse_deg"]["hip"].as_f64().unwrap() < 1.0);
}

#[test]
fn static_rotation_alignment_of_randomly_mounted_sensors() {
    let d = tempfile::tempdir().unwrap();
    let p = d.path();
    ok(&limbfuse(
        &[
            "simulate",
            "knee-fes",
            "--mounting",
            "random",
            "--calibration",
            "cal.csv",
            "-o",
            "raw.csv",
            "--duration",
            "10",
        ],
        p,
    ));
    ok(&limbfuse(
        &[
            "align",
            "--procedure",
            "static-rotation",
            "--calibration",
            "cal.csv",
            "raw.csv",
            "-o",
            "al.csv",
        ],
        p,
    ));
    ok(&limbfuse(
        &["estimate", "--method", "sdre", "al.csv", "-o", "e.csv"],
        p,
    ));
    let o = limbfuse(&["evaluate", "al.csv", "e.csv", "--json"], p);
    ok(&o);
    let j: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
    let knee = j["rmse_deg"]["knee"].as_f64().unwrap();
    assert!(knee < 1.0, "knee RMSE after alignment {knee} deg");
    // The trial itself has no calibration segment (seated, stimulated from 2 s).
    user_error(
        &limbfuse(
            &[
                "align",
                "--procedure",
                "static-rotation",
                "raw.csv",
                "-o",
                "x.csv",
            ],
            p,
        ),
        &["raw.csv", "no calibration segment", "quiet standing"],
    );
}

#[test]
fn demo_runs_sdre_ekf_rmx_on_a_knee_fes_trial() {
    let d = tempfile::tempdir().unwrap();
    let o = limbfuse(&["demo", "--out", "out", "--duration", "10"], d.path());
    ok(&o);
    let stdout = String::from_utf8_lossy(&o.stdout);
    assert!(stdout.contains("knee-FES leg extension"), "{stdout}");
    let header = stdout
        .lines()
        .find(|l| l.contains("sdre") && l.contains("ekf") && l.contains("rmx"));
    assert!(header.is_some(), "{stdout}");
    for m in ["sdre", "ekf", "rmx"] {
        assert!(d
            .path()
            .join(format!("out/estimate-knee-fes-{m}.csv"))
            .exists());
    }
    let report = std::fs::read_to_string(d.path().join("out/report.md")).unwrap();
    assert!(report.contains("knee-FES"));
}

/// Issue 16 item 0: a run whose filter restarts is reported on stderr by
/// `estimate` (count and first time) and by `evaluate` (from the estimate
/// file's `diag_resets`), exit status 0; a nominal run prints no warning.
/// The divergent run uses an absurd tuning (`s = 1e-14`): the stiffness
/// exceeds what the bounded number of RK4 sub-steps can integrate.
#[test]
fn issue_16_estimate_and_evaluate_warn_on_resets() {
    let d = tempfile::tempdir().unwrap();
    let p = d.path();
    ok(&limbfuse(
        &["simulate", "knee-fes", "-o", "k.csv", "--duration", "3"],
        p,
    ));
    std::fs::write(
        p.join("bad.toml"),
        "method = \"sdre\"\n[tuning]\ns = [1e-14, 1e-14]\n",
    )
    .unwrap();
    let warned = |o: &Output, what: &str| {
        ok(o);
        let e = String::from_utf8_lossy(&o.stderr);
        assert!(
            e.contains("warning: ") && e.contains(what) && e.contains("restarted"),
            "{e}"
        );
        assert!(e.contains("first at t = 0.01 s"), "{e}");
    };
    let est = [
        "estimate", "--method", "sdre", "--params", "bad.toml", "k.csv", "-o", "bad.csv",
    ];
    warned(&limbfuse(&est, p), "sdre on k.csv");
    warned(&limbfuse(&["evaluate", "k.csv", "bad.csv"], p), "bad.csv");
    let o = limbfuse(&["evaluate", "k.csv", "bad.csv", "--json"], p);
    warned(&o, "bad.csv");
    let j: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
    assert!(j["resets"]["count"].as_u64().unwrap() > 0, "{j}");
    for m in ["sdre", "ekf"] {
        let out = format!("{m}.csv");
        for o in [
            limbfuse(&["estimate", "--method", m, "k.csv", "-o", &out], p),
            limbfuse(&["evaluate", "k.csv", &out, "--json"], p),
        ] {
            ok(&o);
            let e = String::from_utf8_lossy(&o.stderr);
            assert!(!e.contains("warning"), "{m}: {e}");
        }
    }
}

/// Issue 16 item 5 (brief fes2): a trial whose `u_ke` cells are blank for
/// 0.05 s is estimated with the last value held (`diag_held_inputs` counts
/// the 5 samples). Blank for 0.2 s (rows 150-169), `sdre` and `ekf` hold it
/// for 0.1 s, give no estimate on rows 160-169, restart at row 170 and say
/// so (until 2026-12-06 they exited 1 and estimated nothing of the trial).
#[test]
fn issue_16_stimulation_gap_is_held_then_restarted() {
    let d = tempfile::tempdir().unwrap();
    let p = d.path();
    ok(&limbfuse(
        &["simulate", "knee-fes", "-o", "k.csv", "--duration", "4"],
        p,
    ));
    let text = std::fs::read_to_string(p.join("k.csv")).unwrap();
    let blank = |rows: std::ops::Range<usize>| {
        let mut out = String::new();
        let mut col = None;
        let mut row = 0;
        for line in text.lines() {
            if line.starts_with('#') {
                out.push_str(line);
            } else if col.is_none() {
                col = line.split(',').position(|c| c == "u_ke");
                out.push_str(line);
            } else {
                let mut cells: Vec<&str> = line.split(',').collect();
                if rows.contains(&row) {
                    cells[col.unwrap()] = "";
                }
                out.push_str(&cells.join(","));
                row += 1;
            }
            out.push('\n');
        }
        out
    };
    std::fs::write(p.join("short.csv"), blank(150..155)).unwrap();
    std::fs::write(p.join("long.csv"), blank(150..170)).unwrap();
    for m in ["sdre", "ekf"] {
        ok(&limbfuse(
            &["estimate", "--method", m, "short.csv", "-o", "e.csv"],
            p,
        ));
        let e = std::fs::read_to_string(p.join("e.csv")).unwrap();
        let mut lines = e.lines().filter(|l| !l.starts_with('#'));
        let header: Vec<&str> = lines.next().unwrap().split(',').collect();
        let c = header
            .iter()
            .position(|h| *h == "diag_held_inputs")
            .unwrap();
        let last = lines
            .next_back()
            .unwrap()
            .split(',')
            .nth(c)
            .unwrap()
            .to_string();
        assert_eq!(last.parse::<f64>().unwrap(), 5.0, "{m}");
        let o = limbfuse(&["estimate", "--method", m, "long.csv", "-o", "e.csv"], p);
        ok(&o);
        let err = String::from_utf8_lossy(&o.stderr);
        assert!(
            err.contains("restarted 1 time") && err.contains("t = 1.7 s"),
            "{m}: {err}"
        );
        let e = std::fs::read_to_string(p.join("e.csv")).unwrap();
        let mut lines = e.lines().filter(|l| !l.starts_with('#'));
        let header: Vec<&str> = lines.next().unwrap().split(',').collect();
        let knee = header.iter().position(|h| *h == "knee").unwrap();
        for (row, line) in lines.enumerate().take(400) {
            let cell = line.split(',').nth(knee).unwrap();
            assert_eq!(cell.is_empty(), (160..170).contains(&row), "{m} row {row}");
        }
    }
}

/// Session 45: `simulate knee-fes` stimulated five extensions whatever the
/// duration, and a 600 s trial was 568 s of a resting leg without a word.
/// `--cycles N` sets the extensions (default 5, paper 004's 30 s trials);
/// a trial much longer than its cycles says the leg rests after them.
#[test]
fn knee_fes_cycles_set_the_extensions_and_a_long_rest_is_said() {
    let d = tempfile::tempdir().unwrap();
    let p = d.path();
    let onsets = |file: &str| -> usize {
        let text = std::fs::read_to_string(p.join(file)).unwrap();
        let mut rows = text.lines().filter(|l| !l.starts_with('#'));
        let header: Vec<&str> = rows.next().unwrap().split(',').collect();
        let c = header.iter().position(|h| *h == "u_ke").unwrap();
        let u: Vec<f64> = rows
            .map(|r| r.split(',').nth(c).unwrap().parse().unwrap_or(0.0))
            .collect();
        u.windows(2).filter(|w| w[0] <= 0.0 && w[1] > 0.0).count()
    };
    let run = |flags: &[&str], out: &str| {
        let mut args = vec!["simulate", "knee-fes", "--duration", "60", "-o", out];
        args.extend_from_slice(flags);
        let o = limbfuse(&args, p);
        ok(&o);
        String::from_utf8_lossy(&o.stderr).into_owned()
    };
    let said = run(&[], "five.csv");
    assert_eq!(onsets("five.csv"), 5);
    assert!(
        said.contains("note: the 5 extension cycles end at 32 s; the leg rests for the last 28 s"),
        "{said}"
    );
    let said = run(&["--cycles", "9"], "nine.csv");
    assert_eq!(onsets("nine.csv"), 9);
    assert!(!said.contains("note:"), "{said}");
    user_error(
        &limbfuse(
            &["simulate", "knee-fes", "--cycles", "601", "-o", "x.csv"],
            p,
        ),
        &["--cycles 601: outside the allowed range [0, 600] (6 s each)"],
    );
}
