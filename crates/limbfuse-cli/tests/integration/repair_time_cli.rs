//! `limbfuse repair-time`: a recording whose time does not increase (a row
//! written twice, two rows in the wrong order, one stamp 0.5 s late) stops
//! every reader at the first such row; the repaired copy holds only rows of
//! the clean recording, in order, and runs.

use crate::support::limbfuse;

/// The data rows of a trial file (after the comment lines and the header).
fn data_rows(text: &str) -> Vec<String> {
    text.lines()
        .skip_while(|l| l.starts_with('#'))
        .skip(1)
        .map(str::to_string)
        .collect()
}

/// The clean trial's text with, at data rows `dup`, `swap` and `late`: the
/// row written twice, the row and the next in the wrong order, the row's
/// stamp 0.5 s late.
fn glitched(clean: &str, dup: usize, swap: usize, late: usize) -> String {
    let head: Vec<&str> = clean
        .lines()
        .take_while(|l| l.starts_with('#') || l.starts_with("t,"))
        .collect();
    let mut rows = data_rows(clean);
    let (t, rest) = rows[late].split_once(',').unwrap();
    rows[late] = format!("{},{rest}", t.parse::<f64>().unwrap() + 0.5);
    rows.swap(swap, swap + 1);
    rows.insert(dup + 1, rows[dup].clone());
    let mut out = head.join("\n");
    for r in rows {
        out.push('\n');
        out.push_str(&r);
    }
    out.push('\n');
    out
}

#[test]
fn a_glitched_time_column_is_refused_then_repaired_to_rows_of_the_clean_file() {
    let d = tempfile::tempdir().unwrap();
    let p = d.path();
    let o = limbfuse(
        &["simulate", "walking", "--duration", "8", "-o", "w.csv"],
        p,
    );
    assert!(o.status.success());
    let clean = std::fs::read_to_string(p.join("w.csv")).unwrap();
    let header_line = clean.lines().take_while(|l| l.starts_with('#')).count() + 1;
    std::fs::write(p.join("g.csv"), glitched(&clean, 100, 300, 500)).unwrap();
    // every reader stops at the duplicate (data row 101 = line header + 102)
    let o = limbfuse(&["estimate", "--method", "mjls", "g.csv", "-o", "e.csv"], p);
    let e = String::from_utf8_lossy(&o.stderr);
    assert_eq!(o.status.code(), Some(1), "{e}");
    let line = header_line + 102;
    assert!(
        e.contains(&format!(
            "g.csv:{line}: column 1 (`t`): time must increase strictly"
        )) && e.contains("`limbfuse repair-time`"),
        "{e}"
    );
    // `inspect` adds what the repair would drop over the whole file
    let o = limbfuse(&["inspect", "g.csv"], p);
    let e = String::from_utf8_lossy(&o.stderr);
    assert_eq!(o.status.code(), Some(1), "{e}");
    assert!(
        e.contains(&format!(
            "`limbfuse repair-time g.csv -o OUT` would drop 3 of its 801 rows: 1 exact duplicate \
             of the row before (line {line}); 2 time stamps out of order (line "
        )),
        "{e}"
    );
    let o = limbfuse(&["repair-time", "g.csv", "-o", "r.csv"], p);
    let e = String::from_utf8_lossy(&o.stderr);
    assert!(o.status.success(), "{e}");
    assert!(
        e.contains("798 of 801 rows kept")
            && e.contains(&format!(
                "dropped: 1 exact duplicate of the row before (line {line})"
            ))
            && e.contains("dropped: 2 time stamps out of order")
            && e.contains("largest step back in time: 0.49"),
        "{e}"
    );
    let repaired = std::fs::read_to_string(p.join("r.csv")).unwrap();
    assert!(repaired.contains("# time_repaired: 798 of 801 rows kept"));
    // the rows kept are rows of the clean file, cell for cell, in its order
    let (clean_rows, kept) = (data_rows(&clean), data_rows(&repaired));
    assert_eq!(kept.len(), 798);
    let mut at = clean_rows.iter();
    for row in &kept {
        assert!(at.any(|c| c == row), "not a clean row in order: {row}");
    }
    let o = limbfuse(&["estimate", "--method", "mjls", "r.csv", "-o", "e.csv"], p);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    // rows in the wrong order only: sorting gives the clean file's rows back
    let swapped = {
        let mut rows = data_rows(&clean);
        rows.swap(300, 301);
        let head: Vec<&str> = clean.lines().take(header_line).collect();
        format!("{}\n{}\n", head.join("\n"), rows.join("\n"))
    };
    std::fs::write(p.join("s.csv"), swapped).unwrap();
    let o = limbfuse(
        &[
            "repair-time",
            "s.csv",
            "-o",
            "s2.csv",
            "--out-of-order",
            "sort",
        ],
        p,
    );
    let e = String::from_utf8_lossy(&o.stderr);
    assert!(
        o.status.success() && e.contains("1 rows moved into time order"),
        "{e}"
    );
    let sorted = std::fs::read_to_string(p.join("s2.csv")).unwrap();
    assert_eq!(data_rows(&sorted), clean_rows);
}

/// Stamps jittering by more than half a period (rows in order): the warning
/// tells them from a clock jump and points to `--out-of-order sort`, which
/// keeps every row; a clock reset gets the other warning.
#[test]
fn jittered_stamps_and_a_clock_reset_get_their_own_warnings() {
    let d = tempfile::tempdir().unwrap();
    let p = d.path();
    let o = limbfuse(
        &["simulate", "walking", "--duration", "4", "-o", "w.csv"],
        p,
    );
    assert!(o.status.success());
    let clean = std::fs::read_to_string(p.join("w.csv")).unwrap();
    let head: Vec<&str> = clean
        .lines()
        .take_while(|l| l.starts_with('#') || l.starts_with("t,"))
        .collect();
    let rows = data_rows(&clean);
    let restamped = |f: &dyn Fn(usize, f64) -> f64| {
        let mut out = head.join("\n");
        for (k, r) in rows.iter().enumerate() {
            let (t, rest) = r.split_once(',').unwrap();
            out += &format!("\n{},{rest}", f(k, t.parse::<f64>().unwrap()));
        }
        out + "\n"
    };
    // 0, +6, -6, 0 ms in turn: a step back of 2 ms every fourth row
    let jitter = [0.0, 0.006, -0.006, 0.0];
    std::fs::write(p.join("j.csv"), restamped(&|k, t| t + jitter[k % 4])).unwrap();
    let o = limbfuse(&["repair-time", "j.csv", "-o", "j2.csv"], p);
    let e = String::from_utf8_lossy(&o.stderr);
    assert!(o.status.success(), "{e}");
    assert!(
        e.contains("every step back shorter than a sample period")
            && e.contains("`--out-of-order sort` keeps every row"),
        "{e}"
    );
    let o = limbfuse(
        &[
            "repair-time",
            "j.csv",
            "-o",
            "j3.csv",
            "--out-of-order",
            "sort",
        ],
        p,
    );
    let e = String::from_utf8_lossy(&o.stderr);
    assert!(
        o.status.success() && e.contains("400 of 400 rows kept"),
        "{e}"
    );
    // the clock starts again at 1 s after 3 s: a block, not jitter
    std::fs::write(
        p.join("c.csv"),
        restamped(&|k, t| if k >= 300 { t - 2.0 } else { t }),
    )
    .unwrap();
    let o = limbfuse(&["repair-time", "c.csv", "-o", "c2.csv"], p);
    let e = String::from_utf8_lossy(&o.stderr);
    assert!(
        o.status.success() && e.contains("% of the rows dropped: more than a glitch"),
        "{e}"
    );
}

#[test]
fn repair_time_writes_csv_and_copies_a_clean_file() {
    let d = tempfile::tempdir().unwrap();
    let p = d.path();
    let o = limbfuse(
        &["simulate", "walking", "--duration", "2", "-o", "w.csv"],
        p,
    );
    assert!(o.status.success());
    let o = limbfuse(&["repair-time", "w.csv", "-o", "w.arrow"], p);
    let e = String::from_utf8_lossy(&o.stderr);
    assert_eq!(o.status.code(), Some(1), "{e}");
    assert!(
        e.contains("-o w.arrow: `repair-time` writes a CSV trial file"),
        "{e}"
    );
    let o = limbfuse(&["repair-time", "w.csv", "-o", "w.csv"], p);
    assert_eq!(o.status.code(), Some(1));
    let o = limbfuse(&["repair-time", "w.csv", "-o", "c.csv"], p);
    let e = String::from_utf8_lossy(&o.stderr);
    assert!(
        o.status.success()
            && e.contains("the time already increases on every row; 200 rows copied"),
        "{e}"
    );
    let (a, b) = (
        std::fs::read_to_string(p.join("w.csv")).unwrap(),
        std::fs::read_to_string(p.join("c.csv")).unwrap(),
    );
    assert_eq!(data_rows(&a), data_rows(&b));
    // an Arrow input's rows come out as the CSV writer writes them (labels too)
    for (scenario, extra) in [
        ("walking", &["--duration", "2"][..]),
        ("bslip", &["--duration", "2"][..]),
    ] {
        for out in ["s.arrow", "s.csv"] {
            let mut args = vec!["simulate", scenario, "-o", out];
            args.extend_from_slice(extra);
            assert!(limbfuse(&args, p).status.success());
        }
        let o = limbfuse(&["repair-time", "s.arrow", "-o", "sa.csv"], p);
        assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
        let (csv, from_arrow) = (
            std::fs::read_to_string(p.join("s.csv")).unwrap(),
            std::fs::read_to_string(p.join("sa.csv")).unwrap(),
        );
        assert_eq!(data_rows(&csv), data_rows(&from_arrow), "{scenario}");
    }
}

/// A file cut off while it was written (its last line short, no line
/// break): `repair-time` copies it without that line and says so, as every
/// reader does (docs/ROBUST_INPUT.md 2o).
#[test]
fn a_cut_last_line_is_left_out_of_the_copy_with_a_warning() {
    let d = tempfile::tempdir().unwrap();
    let whole = "t,thigh_ref\n0,0.1\n0.01,0.2\n0.02,0.3\n";
    std::fs::write(d.path().join("cut.csv"), format!("{whole}0.0")).unwrap();
    let o = limbfuse(&["repair-time", "cut.csv", "-o", "copy.csv"], d.path());
    let e = String::from_utf8_lossy(&o.stderr);
    assert_eq!(o.status.code(), Some(0), "{e}");
    assert!(
        e.contains("the time already increases on every row; 3 rows copied")
            && e.contains("cut.csv:5: the last line has 1 of 2 cells and no line break"),
        "{e}"
    );
    let copy = std::fs::read_to_string(d.path().join("copy.csv")).unwrap();
    assert_eq!(data_rows(&copy), data_rows(whole));
}
