//! `limbfuse report`, session 29 (docs/REPORT.md): `evaluate`'s scoring
//! options (`--window`, `--offset-free`, `--max-lag`) on the report,
//! `evaluate`'s notes beside the table, and the y range of a plot whose
//! estimate starts far off (a start transient).

use std::path::Path;

use crate::cli_report::{by_id, parse};
use crate::s02_support::run_ok;
use crate::support::{assert_user_error, edit_cells, limbfuse};

fn read(dir: &Path, name: &str) -> String {
    std::fs::read_to_string(dir.join(name)).unwrap()
}

/// HTML text back to plain text (the report escapes with `svg::esc`).
fn unescape(s: &str) -> String {
    s.replace("&#39;", "'")
        .replace("&quot;", "\"")
        .replace("&lt;", "<")
        .replace("&gt;", ">")
        .replace("&amp;", "&")
}

/// The texts of the `<li>` of `evaluate-notes`, without the estimate names.
fn notes(html: &str) -> Vec<String> {
    let Some(start) = html.find(r#"id="evaluate-notes""#) else {
        return Vec::new();
    };
    let list = &html[start..start + html[start..].find("</ul>").unwrap()];
    list.split("<li ")
        .skip(1)
        .map(|li| {
            let text = &li[li.find('>').unwrap() + 1..li.find("</li>").unwrap()];
            let text = text.rsplit("</code>: ").next().unwrap();
            unescape(text)
        })
        .collect()
}

/// The RMSE cell of `channel` in column `col` of `rmse-table`.
fn rmse_cell(html: &str, channel: &str, col: usize) -> String {
    let table = &html[html.find(r#"id="rmse-table""#).unwrap()..];
    let table = &table[..table.find("</table>").unwrap()];
    let row = &table[table.find(&format!(r#"data-channel="{channel}""#)).unwrap()..];
    let row = &row[..row.find("</tr>").unwrap()];
    row.split("<td>")
        .skip(2)
        .nth(col)
        .unwrap()
        .split('<')
        .next()
        .unwrap()
        .to_string()
}

/// A simulated walk reported with `--window 5:15 --offset-free --max-lag 3`:
/// before, `report` refused the flags (clap: unknown argument) and its table
/// was always every sample, no offset removal, no lag. Now each RMSE cell
/// is `evaluate --json` with the same flags, the page states them (note
/// `scoring`, the gait-cycle note, the recorded command) and lists
/// `evaluate`'s notes on them (offset-free, the lags) as `evaluate` prints them.
#[test]
fn report_scores_with_evaluates_options_and_states_them() {
    let tmp = tempfile::tempdir().unwrap();
    let dir = tmp.path();
    run_ok(
        &[
            "simulate",
            "walking",
            "--duration",
            "20",
            "--seed",
            "3",
            "-o",
            "w.csv",
        ],
        dir,
    );
    for m in ["local", "global"] {
        run_ok(
            &[
                "estimate",
                "--method",
                m,
                "w.csv",
                "-o",
                &format!("{m}.csv"),
            ],
            dir,
        );
    }
    let flags = ["--window", "5:15", "--offset-free", "--max-lag", "3"];
    let mut args = vec!["report", "w.csv", "local.csv", "global.csv", "-o", "r.html"];
    args.extend(flags);
    run_ok(&args, dir);
    let html = read(dir, "r.html");
    let tags = parse(&html);
    let scoring = by_id(&tags, "scoring");
    assert_eq!(scoring.attrs["data-window"], "5:15 s");
    assert_eq!(scoring.attrs["data-offset-free"], "true");
    assert_eq!(scoring.attrs["data-max-lag"], "3");
    assert!(html.contains(
        "limbfuse report w.csv local.csv global.csv -o r.html --window 5:15 --offset-free --max-lag 3"
    ));
    assert!(
        html.contains("Scored as the tables:"),
        "the gait-cycle note"
    );
    let page_notes = notes(&html);
    for (col, m) in ["local", "global"].iter().enumerate() {
        let est = format!("{m}.csv");
        let mut a = vec!["evaluate", "w.csv", est.as_str(), "--json"];
        a.extend(flags);
        let v: serde_json::Value = serde_json::from_slice(&run_ok(&a, dir)).unwrap();
        for c in ["trunk", "thigh", "knee"] {
            let want = format!("{:.3}", v["rmse_deg"][c].as_f64().unwrap());
            assert_eq!(rmse_cell(&html, c, col), want, "{m} {c}");
        }
        let plain = run_ok(&["evaluate", "w.csv", &est, "--json"], dir);
        let plain: serde_json::Value = serde_json::from_slice(&plain).unwrap();
        assert_ne!(
            plain["rmse_deg"]["trunk"], v["rmse_deg"]["trunk"],
            "the flags change it"
        );
        // evaluate's text notes are on the page, word for word
        a.retain(|x| *x != "--json");
        let text = String::from_utf8(run_ok(&a, dir)).unwrap();
        for line in text
            .lines()
            .filter(|l| l.starts_with("offset-free:") || l.starts_with("synchronised:"))
        {
            assert!(
                page_notes.iter().any(|n| n == line),
                "{line} not in {page_notes:?}"
            );
        }
    }
    // Without flags: the note says every sample, and the command has none.
    run_ok(&["report", "w.csv", "local.csv", "-o", "p.html"], dir);
    let plain = read(dir, "p.html");
    assert!(plain.contains("every sample, no window; no offset removal; no lag"));
    assert!(plain.contains("limbfuse report w.csv local.csv -o p.html\n"));
}

/// The flags' values are checked as `evaluate` checks them, and a flag
/// that applies to no estimate of the report is refused as `evaluate`
/// refuses it (exit 1, naming the flag).
#[test]
fn report_refuses_scoring_options_as_evaluate_does() {
    let tmp = tempfile::tempdir().unwrap();
    let dir = tmp.path();
    run_ok(
        &[
            "simulate",
            "walking",
            "--duration",
            "6",
            "--gait-reference",
            "-o",
            "w.csv",
        ],
        dir,
    );
    run_ok(
        &["estimate", "--method", "local", "w.csv", "-o", "l.csv"],
        dir,
    );
    run_ok(
        &[
            "estimate",
            "--method",
            "gait-events",
            "w.csv",
            "-o",
            "g.csv",
        ],
        dir,
    );
    let report = |extra: &[&str], est: &str| {
        let mut a = vec!["report", "w.csv", est, "-o", "r.html"];
        a.extend(extra);
        limbfuse(&a, dir)
    };
    assert_user_error(
        &report(&["--window", "9:2"], "l.csv"),
        &["--window", "not after its start"],
    );
    assert_user_error(
        &report(&["--window", "x"], "l.csv"),
        &["--window: expected START:END"],
    );
    assert_user_error(
        &report(&["--max-lag", "100000"], "l.csv"),
        &["--max-lag 100000", "longer than half the trial"],
    );
    assert_user_error(
        &report(&["--window", "100:200"], "l.csv"),
        &["no sample of the trial inside the window"],
    );
    assert_user_error(
        &report(&["--offset-free"], "g.csv"),
        &[
            "--offset-free: applies to angle errors only",
            "scored for gait events",
        ],
    );
    assert!(!dir.join("r.html").exists());
    // --window applies to gait events: accepted, and stated in their note
    assert_eq!(report(&["--window", "1:5"], "g.csv").status.code(), Some(0));
    let html = read(dir, "r.html");
    assert!(html.contains("Window 1:5 s (<code>--window</code>)"));
    // on a trial without an event reference nothing is scored: refused
    crate::support::without_references(dir, "w.csv", "n.csv");
    let o = limbfuse(
        &[
            "report",
            "n.csv",
            "g.csv",
            "-o",
            "n.html",
            "--window",
            "1:5",
            "--allow-trial-mismatch",
        ],
        dir,
    );
    assert_user_error(
        &o,
        &[
            "--window: applies to angle errors only",
            "no contact or speed reference",
        ],
    );
}

/// `evaluate`'s notes beside the table: on a knee-FES trial, `sdre`'s
/// thigh is the trial's own (fixed) thigh, which `evaluate` leaves out of
/// the mean RMSE and says so; the report showed the mean without a word.
#[test]
fn report_shows_evaluates_notes_beside_the_table() {
    let tmp = tempfile::tempdir().unwrap();
    let dir = tmp.path();
    run_ok(
        &["simulate", "knee-fes", "--duration", "4", "-o", "f.csv"],
        dir,
    );
    run_ok(
        &["estimate", "--method", "sdre", "f.csv", "-o", "s.csv"],
        dir,
    );
    run_ok(&["report", "f.csv", "s.csv", "-o", "r.html"], dir);
    let html = read(dir, "r.html");
    let text = String::from_utf8(run_ok(&["evaluate", "f.csv", "s.csv"], dir)).unwrap();
    let mean = text.lines().find(|l| l.starts_with("mean RMSE:")).unwrap();
    let without = &mean[mean.find("(without").unwrap() + 1..mean.len() - 1];
    assert!(without.starts_with("without thigh"), "{mean}");
    assert!(
        notes(&html).contains(&format!("mean RMSE {without}")),
        "{:?}",
        notes(&html)
    );
}

/// The shared S02 walk after `align` (no quiet standing: segment zeros
/// assumed) with `chain` and `global`: `evaluate` notes the assumed zero,
/// which explains the 15-25 deg shank and foot offsets; the report now
/// says it once for both, and with `--offset-free` (which removes it) not.
#[test]
fn s02_report_notes_aligns_assumed_zero_as_evaluate_does() {
    let tmp = tempfile::tempdir().unwrap();
    let dir = tmp.path();
    if !crate::s02_support::aligned_s02(dir) {
        return;
    }
    for m in ["chain", "global"] {
        run_ok(
            &[
                "estimate",
                "--method",
                m,
                "s02al.csv",
                "-o",
                &format!("{m}.csv"),
            ],
            dir,
        );
    }
    let text = String::from_utf8(run_ok(&["evaluate", "s02al.csv", "chain.csv"], dir)).unwrap();
    let note = text
        .lines()
        .find(|l| l.starts_with("note: `align`"))
        .expect("evaluate's note");
    run_ok(
        &[
            "report",
            "s02al.csv",
            "chain.csv",
            "global.csv",
            "-o",
            "r.html",
        ],
        dir,
    );
    let n = notes(&read(dir, "r.html"));
    assert_eq!(n.iter().filter(|x| *x == note).count(), 1, "{n:?}");
    run_ok(
        &[
            "report",
            "s02al.csv",
            "chain.csv",
            "global.csv",
            "-o",
            "o.html",
            "--offset-free",
        ],
        dir,
    );
    let n = notes(&read(dir, "o.html"));
    assert!(!n.iter().any(|x| x.starts_with("note: `align`")), "{n:?}");
    assert!(n.iter().any(|x| x.starts_with("offset-free:")), "{n:?}");
}

/// An estimate whose trunk starts 90 deg off and decays over 1 s of a
/// 20 s walk: the whole-trial plot's y range ran to 90 deg and the walk
/// (+-10 deg) was a flat line. Now the range is the reference's and the
/// estimates' after the start, the clipped start is shaded and the note
/// names the estimate; the thigh, without a transient, is as before.
#[test]
fn a_start_transient_does_not_set_the_y_range() {
    let tmp = tempfile::tempdir().unwrap();
    let dir = tmp.path();
    run_ok(
        &["simulate", "walking", "--duration", "20", "-o", "w.csv"],
        dir,
    );
    // (started on the first sample, the start before 2026-12-06, so that
    // every row has an estimate to put the transient on)
    std::fs::write(dir.join("first.toml"), "first_sample_start = true\n").unwrap();
    run_ok(
        &[
            "estimate",
            "--method",
            "local",
            "--params",
            "first.toml",
            "w.csv",
            "-o",
            "l.csv",
        ],
        dir,
    );
    let text = read(dir, "l.csv");
    let edited = edit_cells(&text, |row, name, cell| {
        (name == "trunk" && row < 100).then(|| {
            let v: f64 = cell.parse().unwrap();
            format!("{}", v + (90f64).to_radians() * (1.0 - row as f64 / 100.0))
        })
    });
    std::fs::write(dir.join("t.csv"), edited).unwrap();
    run_ok(&["report", "w.csv", "t.csv", "l.csv", "-o", "r.html"], dir);
    let html = read(dir, "r.html");
    let tags = parse(&html);
    let note = by_id(&tags, "clip-note-trunk");
    let until: f64 = note.attrs["data-clip-until-s"].parse().unwrap();
    assert!(until > 0.5 && until < 1.0, "{until}");
    let start = html.find(r#"id="clip-note-trunk""#).unwrap();
    let sentence = &html[start..start + html[start..].find("</p>").unwrap()];
    assert!(
        sentence.contains("the first 1.0 s of <code>t.csv</code>"),
        "{sentence}"
    );
    // the plot's y range (viewBox, in 1/y-scale deg) stays within the walk's
    let svg = &html[html.find(r#"id="plot-angle-trunk""#).unwrap()..];
    let ys: f64 = svg["data-y-scale=\"".len() + svg.find("data-y-scale=\"").unwrap()..]
        .split('"')
        .next()
        .unwrap()
        .parse()
        .unwrap();
    let vb = svg[svg.find("data-full=\"").unwrap() + "data-full=\"".len()..]
        .split('"')
        .next()
        .unwrap()
        .split(' ')
        .map(|v| v.parse::<f64>().unwrap())
        .collect::<Vec<_>>();
    assert!(vb[3] / ys < 40.0, "y span {} deg", vb[3] / ys);
    assert!(svg[..svg.find("</svg></svg>").unwrap()].contains(r#"<rect class="clipped""#));
    assert!(!html.contains(r#"id="clip-note-thigh""#));
}
