//! The per-stride table of each gait-event estimate in `limbfuse report`'s
//! gait-events panel (docs/REPORT.md): one row per row of `limbfuse
//! evaluate TRIAL ESTIMATE --strides FILE`, with its numbers to 3 decimals,
//! empty cells where the CSV has none; on a simulated walk with gait
//! references and on the shared gaitmap walk (skipped when `../shared/data`
//! is absent).

use std::path::Path;

use crate::cli_report::{by_id, parse};
use crate::s02_support::{gaitmap_events, run_ok};

/// The cells of each body row of the table `id` in `html`.
fn table_rows(html: &str, id: &str) -> Vec<Vec<String>> {
    let start = html
        .find(&format!("id=\"{id}\""))
        .unwrap_or_else(|| panic!("no #{id}"));
    let body = &html[start..];
    let body = &body[body.find("<tbody>").unwrap() + 7..body.find("</tbody>").unwrap()];
    body.split("<tr>")
        .filter(|r| !r.is_empty())
        .map(|r| {
            r.trim_end_matches("</tr>")
                .split("<td>")
                .skip(1)
                .map(|c| c.trim_end_matches("</td>").to_string())
                .collect()
        })
        .collect()
}

/// The rows `evaluate --strides` writes for `estimate`, as the report
/// shows them: foot, IC, FC, stride time, (stance, swing time,) length,
/// speed, reference speed, speed error, (stance and swing time error in
/// ms,) and the withheld reason when `withheld`; stance and swing when a
/// stride has a final contact.
fn csv_rows(dir: &Path, trial: &str, estimate: &str, withheld: bool) -> Vec<Vec<String>> {
    run_ok(
        &["evaluate", trial, estimate, "--strides", "s.csv", "--json"],
        dir,
    );
    let text = std::fs::read_to_string(dir.join("s.csv")).unwrap();
    let mut lines = text.lines();
    let header: Vec<&str> = lines.next().unwrap().split(',').collect();
    let col = |name: &str| header.iter().position(|&h| h == name).unwrap();
    let rows: Vec<Vec<&str>> = lines.map(|l| l.split(',').collect()).collect();
    let phases = rows.iter().any(|r| !r[col("fc_s")].is_empty());
    rows.iter()
        .map(|r| {
            let num = |name: &str| r[col(name)].parse::<f64>().ok();
            let cell =
                |v: Option<f64>, p: usize| v.map_or_else(String::new, |v| format!("{v:.p$}"));
            let error_ms =
                |a: &str, b: &str| cell(num(a).zip(num(b)).map(|(a, b)| 1e3 * (a - b)), 1);
            let mut row = vec![r[col("foot")].to_string()];
            let mut names = vec!["ic_s", "fc_s", "stride_time_s"];
            if phases {
                names.extend(["stance_time_s", "swing_time_s"]);
            }
            names.extend(["stride_length_m", "speed_m_s", "speed_ref_m_s"]);
            for name in names {
                row.push(cell(num(name), 3));
            }
            row.push(cell(
                num("speed_m_s")
                    .zip(num("speed_ref_m_s"))
                    .map(|(a, b)| a - b),
                3,
            ));
            if phases {
                row.push(error_ms("stance_time_s", "stance_time_ref_s"));
                row.push(error_ms("swing_time_s", "swing_time_ref_s"));
            }
            if withheld {
                row.push(r[col("speed_withheld")].to_string());
            }
            row
        })
        .collect()
}

/// Reports `estimates` of `trial` and checks each one's stride table
/// against `evaluate --strides`; returns the row counts.
fn report_strides_equal_evaluate(
    dir: &Path,
    trial: &str,
    estimates: &[(&str, bool)],
) -> Vec<usize> {
    let mut args = vec!["report", trial];
    args.extend(estimates.iter().map(|e| e.0));
    args.extend(["-o", "r.html"]);
    run_ok(&args, dir);
    let html = std::fs::read_to_string(dir.join("r.html")).unwrap();
    let tags = parse(&html);
    let mut counts = Vec::new();
    for (k, (estimate, withheld)) in estimates.iter().enumerate() {
        let details = by_id(&tags, &format!("strides-{k}"));
        assert_eq!(details.name, "details");
        let want = csv_rows(dir, trial, estimate, *withheld);
        let got = table_rows(&html, &format!("strides-table-{k}"));
        assert_eq!(got.len(), want.len(), "{estimate}: rows");
        assert_eq!(details.attrs["data-strides"], want.len().to_string());
        for (i, (g, w)) in got.iter().zip(&want).enumerate() {
            assert_eq!(g, w, "{estimate}: row {i}");
        }
        counts.push(want.len());
    }
    counts
}

/// `g.csv` in `dir`: `duration` s of simulated walking with its contacts
/// and stride speeds as references (`--gait-reference`).
fn gait_reference_walk(dir: &Path, duration: &str) {
    let walk = "simulate walking --seed 2 --gait-reference -o g.csv --duration";
    let mut args: Vec<&str> = walk.split(' ').collect();
    args.push(duration);
    run_ok(&args, dir);
}

#[test]
fn report_stride_table_equals_evaluate_strides_on_a_simulated_walk() {
    let d = tempfile::tempdir().unwrap();
    let p = d.path();
    gait_reference_walk(p, "20");
    for (m, out) in [("gait-events", "ge.csv"), ("lowback-speed", "lb.csv")] {
        run_ok(&["estimate", "--method", m, "g.csv", "-o", out], p);
    }
    let counts = report_strides_equal_evaluate(p, "g.csv", &[("ge.csv", false), ("lb.csv", true)]);
    assert!(counts.iter().all(|&n| n > 10), "{counts:?}");
}

#[test]
fn report_stride_table_equals_evaluate_strides_on_the_gaitmap_walk() {
    let tmp = tempfile::tempdir().unwrap();
    let dir = tmp.path();
    let Some(trial) = gaitmap_events(dir) else {
        return;
    };
    // 60 strides, 30 per foot (docs/GAIT_EVENTS.md "Stride table")
    assert_eq!(
        report_strides_equal_evaluate(dir, &trial, &[("ge.csv", false)]),
        [60]
    );
}

#[test]
fn report_says_why_an_estimate_without_stride_columns_has_no_stride_table() {
    let d = tempfile::tempdir().unwrap();
    let p = d.path();
    gait_reference_walk(p, "10");
    let without_strides = "estimate --method gait-events --diagnostics none g.csv -o ge.csv";
    run_ok(&without_strides.split(' ').collect::<Vec<_>>(), p);
    run_ok(&["report", "g.csv", "ge.csv", "-o", "r.html"], p);
    let html = std::fs::read_to_string(p.join("r.html")).unwrap();
    let tags = parse(&html);
    let note = by_id(&tags, "strides-none-0");
    assert_eq!(note.attrs["data-estimate"], "ge.csv");
    assert!(!html.contains("id=\"strides-0\""));
}

#[test]
fn report_stride_table_without_references_has_no_reference_columns() {
    let d = tempfile::tempdir().unwrap();
    let p = d.path();
    for command in [
        "simulate walking --seed 2 --duration 10 -o w.csv",
        "estimate --method gait-events w.csv -o ge.csv",
    ] {
        run_ok(&command.split(' ').collect::<Vec<_>>(), p);
    }
    run_ok(&["report", "w.csv", "ge.csv", "-o", "r.html"], p);
    let html = std::fs::read_to_string(p.join("r.html")).unwrap();
    let rows = table_rows(&html, "strides-table-0");
    assert!(rows.len() > 4, "{} strides", rows.len());
    // foot, IC, FC, stride time, stance, swing, length, speed
    assert!(rows.iter().all(|r| r.len() == 8), "{rows:?}");
    assert!(html.contains("<th>stance s</th><th>swing s</th>"));
    assert!(!html.contains("<th>reference speed m/s</th>"));
    assert!(!html.contains("<th>stance error ms</th>"));
}
