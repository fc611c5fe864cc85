//! A trial whose time column is in milliseconds (what many loggers write)
//! read as seconds steps by 10 s at 100 Hz: before, `estimate` restarted
//! the filter at every sample and said only that. It now names the unit
//! (`limbfuse_eval::sample_interval`); the estimate is still written.

use crate::support::limbfuse;

/// `text` (a trial file) with every data row's `t` multiplied by `factor`.
fn scaled_time(text: &str, factor: f64) -> String {
    let mut header_seen = false;
    let mut out = String::new();
    for line in text.lines() {
        if line.starts_with('#') || !header_seen {
            header_seen |= !line.starts_with('#');
            out += line;
        } else {
            let (t, rest) = line.split_once(',').unwrap();
            let t: f64 = t.parse().unwrap();
            out += &format!("{},{rest}", t * factor);
        }
        out.push('\n');
    }
    out
}

#[test]
fn a_time_column_in_milliseconds_is_named() {
    let tmp = tempfile::tempdir().unwrap();
    let dir = tmp.path();
    let sim = limbfuse(
        &["simulate", "walking", "--duration", "3", "-o", "w.csv"],
        dir,
    );
    assert_eq!(sim.status.code(), Some(0));
    let text = std::fs::read_to_string(dir.join("w.csv")).unwrap();
    std::fs::write(dir.join("ms.csv"), scaled_time(&text, 1000.0)).unwrap();
    let stderr = |trial: &str| {
        let o = limbfuse(&["estimate", "--method", "mjls", trial, "-o", "e.csv"], dir);
        assert_eq!(o.status.code(), Some(0), "{trial}");
        String::from_utf8(o.stderr).unwrap()
    };
    let err = stderr("ms.csv");
    assert!(
        err.contains("warning: ms.csv: the time column `t` steps by a median 10 ")
            && err.contains("`# sample_rate_hz: 100`")
            && err.contains("it looks like milliseconds (divide `t` by 1000)"),
        "{err}"
    );
    assert!(!stderr("w.csv").contains("time column"));
}
