//! `limbfuse report` through the binary (issue 17 item 3): the HTML's
//! structure (every plot element, tables equal to `evaluate`), no external
//! resource, the estimate headers' commands, and the size bound.

use std::collections::BTreeMap;
use std::path::Path;
use std::process::Command;

fn limbfuse(args: &[&str], dir: &Path) -> String {
    let o = Command::new(env!("CARGO_BIN_EXE_limbfuse"))
        .args(args)
        .current_dir(dir)
        .output()
        .expect("the binary runs");
    assert_eq!(
        o.status.code(),
        Some(0),
        "limbfuse {args:?}: {}",
        String::from_utf8_lossy(&o.stderr)
    );
    String::from_utf8_lossy(&o.stdout).into_owned()
}

/// One start tag: name and attributes.
#[derive(Debug)]
pub(crate) struct Tag {
    pub name: String,
    pub attrs: BTreeMap<String, String>,
}

/// A small HTML tokenizer: the start tags in order, checking that every
/// non-void element is closed in order (inside `<script>`/`<style>` the
/// text is skipped). Enough for the report, which limbfuse writes itself.
pub(crate) fn parse(html: &str) -> Vec<Tag> {
    const VOID: [&str; 6] = ["meta", "input", "br", "rect", "path", "line"];
    let mut tags = Vec::new();
    let mut open: Vec<String> = Vec::new();
    let mut rest = html;
    while let Some(i) = rest.find('<') {
        rest = &rest[i + 1..];
        if let Some(r) = rest.strip_prefix("!DOCTYPE") {
            rest = &r[r.find('>').unwrap() + 1..];
            continue;
        }
        let end = rest.find('>').expect("tag closed");
        let body = &rest[..end];
        rest = &rest[end + 1..];
        if let Some(name) = body.strip_prefix('/') {
            let top = open
                .pop()
                .unwrap_or_else(|| panic!("</{name}> with nothing open"));
            assert_eq!(top, name, "</{name}> closes <{top}>");
            continue;
        }
        let self_closing = body.ends_with('/');
        let body = body.trim_end_matches('/');
        let name: String = body.chars().take_while(|c| !c.is_whitespace()).collect();
        let mut attrs = BTreeMap::new();
        let mut a = &body[name.len()..];
        while let Some(eq) = a.find("=\"") {
            let key = a[..eq].trim().to_string();
            let close = a[eq + 2..].find('"').expect("attribute closed");
            attrs.insert(key, a[eq + 2..eq + 2 + close].to_string());
            a = &a[eq + 2 + close + 1..];
        }
        if name == "script" || name == "style" {
            let close = format!("</{name}>");
            let k = rest.find(&close).expect("script/style closed");
            rest = &rest[k + close.len()..];
        } else if !self_closing && !VOID.contains(&name.as_str()) {
            open.push(name.clone());
        }
        tags.push(Tag { name, attrs });
    }
    assert!(open.is_empty(), "unclosed: {open:?}");
    tags
}

pub(crate) fn by_id<'a>(tags: &'a [Tag], id: &str) -> &'a Tag {
    tags.iter()
        .find(|t| t.attrs.get("id").map(String::as_str) == Some(id))
        .unwrap_or_else(|| panic!("no element #{id}"))
}

/// The `data-series` of the line paths inside the plot `id`.
pub(crate) fn series_of(html: &str, id: &str) -> Vec<String> {
    let start = html.find(&format!("id=\"{id}\"")).unwrap();
    let end = start + html[start..].find("</svg></svg>").unwrap();
    parse(&format!("<svg {}", &html[start..end + 12]))
        .iter()
        .filter(|t| t.name == "path" && t.attrs.get("class").is_some_and(|c| c.starts_with("line")))
        .map(|t| t.attrs["data-series"].clone())
        .collect()
}

#[test]
fn report_has_every_plot_the_evaluate_numbers_and_the_commands() {
    let d = tempfile::tempdir().unwrap();
    let p = d.path();
    limbfuse(
        &[
            "simulate",
            "walking",
            "--duration",
            "20",
            "--seed",
            "3",
            "-o",
            "trial.csv",
        ],
        p,
    );
    let methods = ["mjls", "local", "gyro-integration"];
    for m in methods {
        limbfuse(
            &[
                "estimate",
                "--method",
                m,
                "trial.csv",
                "-o",
                &format!("{m}.csv"),
            ],
            p,
        );
        let head = std::fs::read_to_string(p.join(format!("{m}.csv"))).unwrap();
        let expected = format!("# command: limbfuse estimate --method {m} trial.csv -o {m}.csv\n");
        assert!(
            head.contains(&expected),
            "{m}: no command line in the header"
        );
    }
    limbfuse(
        &[
            "report",
            "trial.csv",
            "mjls.csv",
            "local.csv",
            "gyro-integration.csv",
            "-o",
            "r.html",
        ],
        p,
    );
    let html = std::fs::read_to_string(p.join("r.html")).unwrap();
    let tags = parse(&html);

    // Self-contained: no external resource of any kind.
    for bad in [
        "<link",
        "src=",
        "href=\"http",
        "url(",
        "@import",
        "fetch(",
        "XMLHttpRequest",
    ] {
        assert!(!html.contains(bad), "the report loads something: {bad}");
    }
    assert_eq!(tags.iter().filter(|t| t.name == "script").count(), 1);

    // Every angle over time and over the gait cycle, with the reference and each estimate.
    for c in ["trunk", "thigh", "shank", "foot", "hip", "knee", "ankle"] {
        let a = by_id(&tags, &format!("plot-angle-{c}"));
        assert_eq!(a.attrs["data-plot"], "angle");
        assert!(a.attrs["class"].contains("time"));
        assert_eq!(
            series_of(&html, &format!("plot-angle-{c}")),
            ["reference", "est-0", "est-1", "est-2"]
        );
        assert_eq!(
            series_of(&html, &format!("plot-cycle-{c}")),
            ["est-0", "est-1", "est-2"]
        );
    }
    for id in [
        "window-controls",
        "win-start",
        "win-end",
        "win-all",
        "rmse-table",
        "error-table",
        "command-list",
    ] {
        by_id(&tags, id);
    }
    // Gait events detected from the shank gyro, one cycle per simulated stride
    // (stride time 120 / cadence, the simulator's speed law at 1 m/s).
    let ev = by_id(&tags, "gait-events");
    assert_eq!(ev.attrs["data-source"], "gyro");
    let law = limbfuse_sim::gait_curves::SpeedLaw {
        speed: 1.0,
        height: 1.75,
    };
    let stride = 1.0 / law.stride_frequency();
    let median: f64 = ev.attrs["data-median-s"].parse().unwrap();
    assert!(
        (median - stride).abs() < 0.03 * stride,
        "median cycle {median} s, stride {stride} s"
    );
    let cycles: f64 = ev.attrs["data-cycles"].parse().unwrap();
    assert!(cycles >= (20.0 / stride).floor() - 3.0, "{cycles} cycles");

    // The RMSE table holds evaluate's numbers.
    let table_start = html.find("id=\"rmse-table\"").unwrap();
    let table = &html[table_start..table_start + html[table_start..].find("</table>").unwrap()];
    for (col, m) in methods.iter().enumerate() {
        let json = limbfuse(&["evaluate", "trial.csv", &format!("{m}.csv"), "--json"], p);
        for c in ["trunk", "knee"] {
            let key = format!("\"{c}\":");
            let v: f64 = json[json.find("rmse_deg").unwrap()..]
                .split(&key)
                .nth(1)
                .unwrap()
                .split([',', '}'])
                .next()
                .unwrap()
                .trim()
                .parse()
                .unwrap();
            let row_start = table.find(&format!("data-channel=\"{c}\"")).unwrap();
            let row = &table[row_start..row_start + table[row_start..].find("</tr>").unwrap()];
            let cells: Vec<&str> = row
                .split("<td>")
                .skip(2)
                .map(|c| c.split('<').next().unwrap())
                .collect();
            assert_eq!(cells[col], format!("{v:.3}"), "{m} {c}");
        }
    }
    // The commands section lists the report command and each estimate's command.
    let cmds = &html[html.find("id=\"command-list\"").unwrap()..];
    assert!(cmds
        .contains("limbfuse report trial.csv mjls.csv local.csv gyro-integration.csv -o r.html"));
    assert!(cmds.contains("limbfuse estimate --method local trial.csv -o local.csv"));
    assert!(cmds.contains("limbfuse-sim walking"), "trial source");
}

#[test]
fn a_ten_minute_trial_with_five_estimates_stays_under_five_megabytes() {
    let d = tempfile::tempdir().unwrap();
    let p = d.path();
    limbfuse(
        &[
            "simulate",
            "walking",
            "--duration",
            "600",
            "-o",
            "trial.csv",
        ],
        p,
    );
    let methods = [
        "local",
        "mjls",
        "global",
        "gyro-integration",
        "accel-inclination",
    ];
    let mut args = vec!["report".to_string(), "trial.csv".to_string()];
    for m in methods {
        limbfuse(
            &[
                "estimate",
                "--method",
                m,
                "trial.csv",
                "-o",
                &format!("{m}.csv"),
            ],
            p,
        );
        args.push(format!("{m}.csv"));
    }
    args.extend(["-o".into(), "r.html".into()]);
    limbfuse(&args.iter().map(String::as_str).collect::<Vec<_>>(), p);
    let size = std::fs::metadata(p.join("r.html")).unwrap().len();
    assert!(size < 5_000_000, "{size} bytes");
    // Decimated: each line has at most 2 x 2000 points, yet the extremes survive.
    let html = std::fs::read_to_string(p.join("r.html")).unwrap();
    assert!(html.contains("60000 samples"), "summary");
    eprintln!("10-min report: {size} bytes");
}

#[test]
fn bad_input_is_a_user_error_naming_the_file() {
    let d = tempfile::tempdir().unwrap();
    let p = d.path();
    limbfuse(
        &[
            "simulate",
            "walking",
            "--duration",
            "4",
            "--seed",
            "1",
            "-o",
            "a.csv",
        ],
        p,
    );
    limbfuse(
        &[
            "simulate",
            "walking",
            "--duration",
            "4",
            "--seed",
            "2",
            "-o",
            "b.csv",
        ],
        p,
    );
    limbfuse(
        &["estimate", "--method", "mjls", "b.csv", "-o", "eb.csv"],
        p,
    );
    let o = Command::new(env!("CARGO_BIN_EXE_limbfuse"))
        .args(["report", "a.csv", "eb.csv", "-o", "r.html"])
        .current_dir(p)
        .output()
        .unwrap();
    assert_eq!(o.status.code(), Some(1));
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(err.contains("eb.csv"), "{err}");
    assert!(!p.join("r.html").exists());
    let o = Command::new(env!("CARGO_BIN_EXE_limbfuse"))
        .args(["report", "a.csv", "missing.csv", "-o", "r.html"])
        .current_dir(p)
        .output()
        .unwrap();
    assert_eq!(o.status.code(), Some(1));
    assert!(String::from_utf8_lossy(&o.stderr).contains("missing.csv"));
}

/// A recording without references (most real recordings: no motion
/// capture) gave a page with no plot at all ("No angle channel has both a
/// reference in the trial and an estimate"), found by a 1-hour trial's
/// 15 KB report. Every estimated angle is now plotted, its reference drawn
/// when the trial has one.
#[test]
fn a_trial_without_references_still_shows_its_estimates() {
    let tmp = tempfile::tempdir().unwrap();
    let dir = tmp.path();
    limbfuse(
        &["simulate", "walking", "--duration", "4", "-o", "w.csv"],
        dir,
    );
    crate::support::without_references(dir, "w.csv", "noref.csv");
    limbfuse(
        &["estimate", "--method", "local", "noref.csv", "-o", "e.csv"],
        dir,
    );
    limbfuse(&["report", "noref.csv", "e.csv", "-o", "r.html"], dir);
    let html = std::fs::read_to_string(dir.join("r.html")).unwrap();
    let tags = parse(&html);
    for c in ["trunk", "thigh", "shank", "foot", "hip", "knee", "ankle"] {
        by_id(&tags, &format!("plot-angle-{c}"));
        assert_eq!(series_of(&html, &format!("plot-angle-{c}")), ["est-0"]);
    }
    assert!(
        html.contains("No reference in the trial for trunk, thigh"),
        "note"
    );
}

/// An audit of reports on real recordings: an estimate of another trial
/// reported with `--allow-trial-mismatch` left no trace in the page (and the
/// refusal did not name the flag); one estimate given twice gave two
/// identical columns; the FES note said "activation = stimulation" whatever
/// the estimate's model.
#[test]
fn report_says_what_evaluate_says_and_refuses_a_repeat() {
    let d = tempfile::tempdir().unwrap();
    let p = d.path();
    for (seed, name) in [("1", "a.csv"), ("2", "b.csv")] {
        limbfuse(
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
            p,
        );
    }
    limbfuse(
        &["estimate", "--method", "local", "b.csv", "-o", "eb.csv"],
        p,
    );
    let run = |args: &[&str]| {
        Command::new(env!("CARGO_BIN_EXE_limbfuse"))
            .args(args)
            .current_dir(p)
            .output()
            .unwrap()
    };
    let o = run(&["report", "a.csv", "eb.csv", "-o", "r.html"]);
    assert_eq!(o.status.code(), Some(1));
    assert!(String::from_utf8_lossy(&o.stderr).contains("--allow-trial-mismatch"));
    limbfuse(
        &[
            "report",
            "--allow-trial-mismatch",
            "a.csv",
            "eb.csv",
            "-o",
            "r.html",
        ],
        p,
    );
    let html = std::fs::read_to_string(p.join("r.html")).unwrap();
    assert!(
        html.contains(r#"<p class="warning">warning: eb.csv was made from the trial `b.csv`"#)
            && html.contains("(evaluated anyway, as asked)"),
        "the page says so"
    );
    let o = run(&["report", "b.csv", "eb.csv", "./eb.csv", "-o", "r2.html"]);
    assert_eq!(o.status.code(), Some(1));
    assert!(
        String::from_utf8_lossy(&o.stderr).contains("give each estimate once"),
        "{}",
        String::from_utf8_lossy(&o.stderr)
    );
    assert!(!p.join("r2.html").exists());
    limbfuse(
        &["simulate", "knee-fes", "--duration", "2", "-o", "fes.csv"],
        p,
    );
    limbfuse(
        &["estimate", "--method", "sdre", "fes.csv", "-o", "s.csv"],
        p,
    );
    limbfuse(&["report", "fes.csv", "s.csv", "-o", "f.html"], p);
    let html = std::fs::read_to_string(p.join("f.html")).unwrap();
    assert!(
        html.contains("Activation in each estimate&#39;s model: s.csv: a_ke = u_ke")
            || html.contains("Activation in each estimate's model: s.csv: a_ke = u_ke"),
        "the note reads the estimate's own activation line"
    );
}
