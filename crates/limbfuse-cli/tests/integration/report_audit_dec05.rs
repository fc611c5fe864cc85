//! `limbfuse report`, audit 2026-12-05: a trial whose time does not start
//! near 0 (plotted from its first sample), the trial check on a trial
//! without references, gaps in time, a constant series' y window, and an
//! estimate that scores nothing.

use std::path::Path;

use crate::support::{edit_cells, limbfuse, without_references};

/// Runs `limbfuse args` in `dir`, which must succeed.
fn ok(args: &[&str], dir: &Path) {
    let o = limbfuse(args, dir);
    assert_eq!(
        o.status.code(),
        Some(0),
        "limbfuse {args:?}: {}",
        String::from_utf8_lossy(&o.stderr)
    );
}

fn read(dir: &Path, name: &str) -> String {
    std::fs::read_to_string(dir.join(name)).expect("written")
}

/// The `d` of the paths of `series` in plot `id`, in order.
fn paths_of(html: &str, id: &str, series: &str) -> Vec<String> {
    let start = html.find(&format!(r#"id="{id}""#)).expect("the plot");
    let plot = &html[start..start + html[start..].find("</figure>").expect("its figure")];
    plot.split(&format!(r#"data-series="{series}""#))
        .skip(1)
        .filter_map(|rest| {
            let d = rest.split(r#"d=""#).nth(1)?;
            Some(d[..d.find('"')?].to_string())
        })
        .collect()
}

/// Every `data-full` (the plots' data boxes) of the page, in order.
fn data_boxes(html: &str) -> Vec<&str> {
    html.split(r#"data-full=""#)
        .skip(1)
        .map(|r| &r[..r.find('"').unwrap_or(0)])
        .collect()
}

/// A trial with `t` shifted by 100000 s or by a Unix time was drawn over
/// 24 s instead of 30, or not at all: plots now use time since the first
/// sample, the same coordinates as the unshifted trial, and say where 0 is.
#[test]
fn a_trial_starting_late_is_plotted_from_its_first_sample() {
    let tmp = tempfile::tempdir().unwrap();
    let dir = tmp.path();
    ok(
        &["simulate", "walking", "--duration", "6", "-o", "w.csv"],
        dir,
    );
    let text = read(dir, "w.csv");
    ok(
        &["estimate", "--method", "local", "w.csv", "-o", "e.csv"],
        dir,
    );
    ok(&["report", "w.csv", "e.csv", "-o", "r.html"], dir);
    let plain = read(dir, "r.html");
    for (offset, shown) in [(1e5, "100000.000"), (1.7e9, "1700000000.000")] {
        let shifted = edit_cells(&text, |_, name, cell| {
            (name == "t").then(|| format!("{:.6}", cell.parse::<f64>().unwrap() + offset))
        });
        std::fs::write(dir.join("off.csv"), shifted).unwrap();
        let _ = std::fs::remove_file(dir.join("eo.csv"));
        let _ = std::fs::remove_file(dir.join("ro.html"));
        ok(
            &["estimate", "--method", "local", "off.csv", "-o", "eo.csv"],
            dir,
        );
        ok(&["report", "off.csv", "eo.csv", "-o", "ro.html"], dir);
        let html = read(dir, "ro.html");
        for c in ["thigh", "knee", "ankle"] {
            let id = format!("plot-angle-{c}");
            assert_eq!(
                paths_of(&html, &id, "reference"),
                paths_of(&plain, &id, "reference"),
                "{id} at +{offset} s"
            );
        }
        assert_eq!(data_boxes(&html), data_boxes(&plain), "+{offset} s");
        assert!(
            html.contains(&format!("t = 0 is {shown} s in the trial")),
            "the page states the origin"
        );
        assert!(html.contains(r#"id="win-start" type="number" step="any" value="0""#));
        assert!(html.contains(r#"id="win-end" type="number" step="any" value="5.990""#));
    }
    assert!(!plain.contains("t = 0 is"), "nothing to say at 0");
}

/// The trial check was made only by the evaluations: a trial without
/// references took an estimate of another trial silently.
#[test]
fn an_estimate_of_another_trial_is_refused_without_references_too() {
    let tmp = tempfile::tempdir().unwrap();
    let dir = tmp.path();
    for (seed, name) in [("1", "a.csv"), ("2", "b.csv")] {
        ok(
            &[
                "simulate",
                "walking",
                "--duration",
                "3",
                "--seed",
                seed,
                "-o",
                name,
            ],
            dir,
        );
    }
    without_references(dir, "a.csv", "noref.csv");
    ok(
        &["estimate", "--method", "local", "b.csv", "-o", "eb.csv"],
        dir,
    );
    let o = limbfuse(&["report", "noref.csv", "eb.csv", "-o", "r.html"], dir);
    let err = String::from_utf8_lossy(&o.stderr);
    assert_eq!(o.status.code(), Some(1), "{err}");
    assert!(
        err.contains("--allow-trial-mismatch") && err.contains("eb.csv"),
        "{err}"
    );
    assert!(!dir.join("r.html").exists());
    ok(
        &[
            "report",
            "--allow-trial-mismatch",
            "noref.csv",
            "eb.csv",
            "-o",
            "r.html",
        ],
        dir,
    );
    let html = read(dir, "r.html");
    assert!(html.contains(r#"<p class="warning">warning: eb.csv was made from the trial `b.csv`"#));
    // its own estimate passes, once warned about nothing
    ok(
        &["estimate", "--method", "local", "noref.csv", "-o", "ea.csv"],
        dir,
    );
    ok(&["report", "noref.csv", "ea.csv", "-o", "ra.html"], dir);
    assert!(!read(dir, "ra.html").contains(r#"class="warning""#));
}

/// Rows 1001-1300 removed (a 3 s gap): the summary said nothing and the
/// lines went straight across.
#[test]
fn gaps_in_time_are_stated_and_break_the_lines() {
    let tmp = tempfile::tempdir().unwrap();
    let dir = tmp.path();
    ok(
        &["simulate", "walking", "--duration", "20", "-o", "w.csv"],
        dir,
    );
    let text = read(dir, "w.csv");
    let header = text.lines().position(|l| l.starts_with("t,")).unwrap();
    let kept: Vec<&str> = text
        .lines()
        .enumerate()
        .filter(|(i, _)| !(header + 1001..=header + 1300).contains(i))
        .map(|(_, l)| l)
        .collect();
    std::fs::write(dir.join("gap.csv"), kept.join("\n") + "\n").unwrap();
    ok(
        &["estimate", "--method", "local", "gap.csv", "-o", "e.csv"],
        dir,
    );
    ok(&["report", "gap.csv", "e.csv", "-o", "r.html"], dir);
    let html = read(dir, "r.html");
    assert!(
        html.contains(r#"<span id="time-gaps" data-gaps="1" data-longest-s="3.010">1 gap in time"#),
        "{}",
        &html[html.find(r#"id="summary""#).unwrap()..][..400]
    );
    for series in ["reference", "est-0"] {
        let d = &paths_of(&html, "plot-angle-knee", series)[0];
        assert_eq!(
            d.matches('M').count(),
            2,
            "{series}: two runs, none across the gap"
        );
    }
    // a trial without gaps says nothing
    ok(
        &["estimate", "--method", "local", "w.csv", "-o", "ew.csv"],
        dir,
    );
    ok(&["report", "w.csv", "ew.csv", "-o", "rw.html"], dir);
    assert!(!read(dir, "rw.html").contains("time-gaps"));
}

/// An estimate with every value cell empty gave an empty RMSE table;
/// `evaluate` says why it scores nothing, and now the page does too.
#[test]
fn an_estimate_that_scores_nothing_says_why() {
    let tmp = tempfile::tempdir().unwrap();
    let dir = tmp.path();
    ok(
        &["simulate", "walking", "--duration", "3", "-o", "w.csv"],
        dir,
    );
    ok(
        &["estimate", "--method", "local", "w.csv", "-o", "e.csv"],
        dir,
    );
    let empty = edit_cells(&read(dir, "e.csv"), |_, name, _| {
        (name != "t").then(String::new)
    });
    std::fs::write(dir.join("empty.csv"), empty).unwrap();
    let o = limbfuse(&["evaluate", "w.csv", "empty.csv"], dir);
    assert_eq!(o.status.code(), Some(1));
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(err.contains("none of the 300 samples"), "{err}");
    ok(&["report", "w.csv", "empty.csv", "-o", "r.html"], dir);
    let html = read(dir, "r.html");
    assert!(
        html.contains(r#"<p class="warning" id="nothing-scored-0" data-estimate="empty.csv">w.csv: none of the 300 samples"#),
        "{}",
        &html[html.find(r#"id="errors""#).unwrap()..][..600]
    );
    assert!(!html.contains(r#"id="rmse-table""#), "no empty table");
    // with a scored estimate beside it, its table stays
    ok(
        &["report", "w.csv", "e.csv", "empty.csv", "-o", "r2.html"],
        dir,
    );
    let html = read(dir, "r2.html");
    assert!(html.contains(r#"id="rmse-table""#) && html.contains(r#"id="nothing-scored-1""#));
}

/// The fixed thigh of a knee-FES trial: the script's y refit keeps the
/// plot's 1-deg window (`data-min-y-span`, in y units).
#[test]
fn a_constant_series_keeps_its_window() {
    let tmp = tempfile::tempdir().unwrap();
    let dir = tmp.path();
    ok(
        &["simulate", "knee-fes", "--duration", "4", "-o", "fes.csv"],
        dir,
    );
    ok(
        &["estimate", "--method", "sdre", "fes.csv", "-o", "s.csv"],
        dir,
    );
    ok(&["report", "fes.csv", "s.csv", "-o", "r.html"], dir);
    let html = read(dir, "r.html");
    let start = html.find(r#"id="plot-angle-thigh""#).unwrap();
    let tag = &html[html[..start].rfind('<').unwrap()..][..600];
    assert!(
        tag.contains(r#"data-y-scale="10000" data-min-y-span="10000""#),
        "{tag}"
    );
}

/// The recorded commands paste into a shell (an audit: a name with a space,
/// `<`, `&` or a quote was written bare), and the report says an
/// estimate's command names files only.
#[test]
fn recorded_commands_quote_what_a_shell_would_split() {
    let d = tempfile::tempdir().unwrap();
    let p = d.path();
    ok(
        &[
            "simulate",
            "walking",
            "--duration",
            "3",
            "-o",
            "my walk.csv",
        ],
        p,
    );
    ok(
        &[
            "estimate",
            "--method",
            "local",
            "my walk.csv",
            "-o",
            "it's.csv",
        ],
        p,
    );
    let est = read(p, "it's.csv");
    assert!(
        est.contains(r"# command: limbfuse estimate --method local 'my walk.csv' -o 'it'\''s.csv'"),
        "{}",
        est.lines()
            .find(|l| l.starts_with("# command"))
            .unwrap_or("")
    );
    ok(&["report", "my walk.csv", "it's.csv", "-o", "r.html"], p);
    let html = read(p, "r.html");
    assert!(
        html.contains("limbfuse report &#39;my walk.csv&#39;")
            || html.contains("limbfuse report 'my walk.csv'"),
        "report command"
    );
    assert!(
        html.contains("run it in the trial&#39;s folder")
            || html.contains("run it in the trial's folder")
    );
}

/// An `imm-bslip` estimate written with `--diagnostics none` keeps its
/// phase and speed plots and says why the weights are missing (an audit:
/// "No method-specific panel applies").
#[test]
fn an_imm_estimate_without_diagnostics_keeps_its_phase_and_speed() {
    let d = tempfile::tempdir().unwrap();
    let p = d.path();
    ok(
        &[
            "gait-library",
            "build",
            "--speeds",
            "0.6:0.8:0.1",
            "-o",
            "lib.json",
        ],
        p,
    );
    ok(
        &[
            "simulate",
            "bslip",
            "--speed",
            "0.7",
            "--library",
            "lib.json",
            "--duration",
            "4",
            "-o",
            "b.csv",
        ],
        p,
    );
    ok(
        &[
            "estimate",
            "--method",
            "imm-bslip",
            "--library",
            "lib.json",
            "--diagnostics",
            "none",
            "b.csv",
            "-o",
            "nd.csv",
        ],
        p,
    );
    ok(&["report", "b.csv", "nd.csv", "-o", "r.html"], p);
    let html = read(p, "r.html");
    assert!(html.contains(r#"id="panel-imm-0""#), "the panel");
    assert!(
        html.contains(r#"id="plot-imm-phase-track-0""#),
        "the phase track"
    );
    assert!(
        !html.contains(r#"id="plot-imm-gait-0""#),
        "no weights to plot"
    );
    assert!(html.contains("has no IMM weights"), "says why");
}
