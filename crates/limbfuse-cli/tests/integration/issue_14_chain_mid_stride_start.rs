//! Audit against kept-back recordings (2026-12-03, docs/RESULTS.md): `chain`
//! on a recording that starts mid-stride. The gaittoolbox S02 walk, aligned
//! (`limbfuse align`), with its first 1.50 or 1.55 s removed: the start-up
//! replay ended 34-87 deg from the window's own angles, the filter stated
//! 0.4 deg of uncertainty and never recovered (pass-2 offset-free RMSE
//! thigh / shank / foot 12.6 / 11.9 / 18.1 deg and 8.2 / 10.7 / 77.9 deg
//! against 2.3 / 2.6 / 2.6 on the whole recording). Such a replay is now
//! refused and the start-up window begins again (2.3 / 3.5 / 4.1 and
//! 2.8 / 3.1 / 3.7 deg). Skipped when `../shared/data` is absent.

use std::path::Path;

use crate::s02_support::{aligned_s02, leg_rmse, run_ok};

/// `src` without its first `rows` data rows (metadata and header kept).
fn cut(src: &Path, dst: &Path, rows: usize) {
    let text = std::fs::read_to_string(src).unwrap();
    let mut out = String::new();
    let mut data = 0usize;
    let mut header_seen = false;
    for line in text.lines() {
        if line.starts_with('#') || !header_seen {
            header_seen |= !line.starts_with('#');
        } else {
            data += 1;
            if data <= rows {
                continue;
            }
        }
        out += line;
        out += "\n";
    }
    std::fs::write(dst, out).unwrap();
}

#[test]
fn issue_14_chain_mid_stride_start() {
    let tmp = tempfile::tempdir().unwrap();
    let dir = tmp.path();
    if !aligned_s02(dir) {
        return;
    }
    for rows in [150, 155] {
        let trial = format!("cut{rows}.csv");
        let est = format!("cut{rows}-chain.csv");
        cut(&dir.join("s02al.csv"), &dir.join(&trial), rows);
        run_ok(&["estimate", "--method", "chain", &trial, "-o", &est], dir);
        let rmse = leg_rmse(dir, &trial, &est, "4.40:8.72");
        for (seg, rmse) in ["thigh", "shank", "foot"].into_iter().zip(rmse) {
            println!("first {rows} rows cut: {seg} {rmse:.3} deg");
            assert!(rmse < 6.0, "cut {rows}: {seg} RMSE {rmse:.2} deg");
        }
    }
}
