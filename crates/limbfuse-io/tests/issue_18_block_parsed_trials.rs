//! Issue 18 item 6: a trial file parsed in blocks on every core
//! ([`TrialReader::open_parallel`]) gives the records, the error (the first
//! by file order, with its line and column) and the content hash of the
//! streaming reader ([`TrialReader::open`]), wherever in the file a bad or
//! unusual row is: in the first or a later chunk of a block, in a later
//! block (blocks are 1 MiB), at a block boundary.

use std::path::Path;

use limbfuse_core::Record;
use limbfuse_io::TrialReader;

/// Everything a reader gives: the records until the end or the first
/// error, the error's text, and the content hash.
#[derive(Debug, PartialEq)]
struct Reading {
    records: Vec<Record>,
    error: Option<String>,
    hash: Option<String>,
}

fn read(mut r: TrialReader) -> Reading {
    let mut records = Vec::new();
    let error = loop {
        match r.next_record() {
            Ok(Some(rec)) => records.push(rec),
            Ok(None) => break None,
            Err(e) => break Some(e.to_string()),
        }
    };
    Reading {
        records,
        error,
        hash: r.content_hash().map(|h| h.to_string()),
    }
}

fn both(path: &Path) -> (Reading, Reading) {
    let streamed = match TrialReader::open(path) {
        Ok(r) => read(r),
        Err(e) => Reading {
            records: Vec::new(),
            error: Some(e.to_string()),
            hash: None,
        },
    };
    let parallel = match TrialReader::open_parallel(path) {
        Ok(r) => read(r),
        Err(e) => Reading {
            records: Vec::new(),
            error: Some(e.to_string()),
            hash: None,
        },
    };
    (streamed, parallel)
}

const HEADER: &str = "t,thigh_acc_x,thigh_acc_y,thigh_acc_z,thigh_gyr_x,thigh_gyr_y,thigh_gyr_z,\
knee_enc,contact_right_ref,phase_ref,speed_ref,note";

/// `n` rows of about 200 bytes (so 12 000 rows span 3 blocks), with
/// 17-digit numbers, empty cells, contacts, phases and an unread column.
fn rows(n: usize) -> Vec<String> {
    let mut x: u64 = 0x9e37_79b9_7f4a_7c15;
    let mut next = || {
        x ^= x << 13;
        x ^= x >> 7;
        x ^= x << 17;
        (x >> 11) as f64 / (1u64 << 53) as f64 - 0.5
    };
    (0..n)
        .map(|k| {
            let t = k as f64 * 0.01;
            let v: Vec<String> = (0..7).map(|_| format!("{}", next() * 20.0)).collect();
            let contact = ["0", "1", ""][k % 3];
            let phase = ["SS1", "DS", "SS2", ""][k % 4];
            let enc = if k % 7 == 0 { String::new() } else { v[6].clone() };
            format!(
                "{t},{},{},{},{},{},{},{enc},{contact},{phase},{},x{k}",
                v[0], v[1], v[2], v[3], v[4], v[5], v[0]
            )
        })
        .collect()
}

fn file(dir: &Path, name: &str, head: &str, rows: &[String]) -> std::path::PathBuf {
    let path = dir.join(name);
    let mut text = String::from(head);
    for r in rows {
        text.push_str(r);
        text.push('\n');
    }
    std::fs::write(&path, text).unwrap();
    path
}

fn head() -> String {
    format!("# format: limbfuse-trial/1\n# rate_hz: 100\n{HEADER}\n")
}

/// Replaces cell `col` of row `row`.
fn set_cell(rows: &mut [String], row: usize, col: usize, text: &str) {
    let mut cells: Vec<String> = rows[row].split(',').map(str::to_string).collect();
    cells[col] = text.to_string();
    rows[row] = cells.join(",");
}

#[test]
fn issue_18_block_parsed_clean_trial_reads_like_the_streamed_one() {
    let d = tempfile::tempdir().unwrap();
    let rows = rows(12_000);
    let path = file(d.path(), "clean.csv", &head(), &rows);
    assert!(std::fs::metadata(&path).unwrap().len() > 2 << 20, "spans 3 blocks");
    let (s, p) = both(&path);
    assert_eq!(s.records.len(), 12_000);
    assert_eq!(s.error, None);
    assert!(s.hash.is_some());
    assert!(s == p, "the block-parsed reading differs from the streamed one");
}

#[test]
fn issue_18_block_parsed_bad_rows_fail_like_the_streamed_one() {
    let d = tempfile::tempdir().unwrap();
    let clean = rows(12_000);
    // (row, column, cell): early in a block, past the middle of a block (the
    // second thread's chunk), in a later block; every kind of bad cell.
    let cases: &[(usize, usize, &str)] = &[
        (3, 1, "banana"),
        (3500, 2, "1e999"),
        (4000, 3, "nan"),
        (4500, 0, ""),
        (5000, 0, "0.5"),
        (9000, 8, "0.5"),
        (9500, 9, "SS3"),
        (11_999, 4, "-"),
        (7000, 11, "\"a,b\""),
        (7000, 4, "\"1.5\""),
    ];
    for (k, &(row, col, cell)) in cases.iter().enumerate() {
        let mut rows = clean.clone();
        set_cell(&mut rows, row, col, cell);
        let path = file(d.path(), &format!("bad{k}.csv"), &head(), &rows);
        let (s, p) = both(&path);
        assert!(
            s == p,
            "case {k} ({row}, {col}, {cell:?}): streamed {:?} after {} rows, block-parsed {:?} after {} rows",
            s.error,
            s.records.len(),
            p.error,
            p.records.len()
        );
    }
}

#[test]
fn issue_18_block_parsed_reports_the_first_error_by_file_order() {
    let d = tempfile::tempdir().unwrap();
    let mut rows = rows(12_000);
    // A later row in the first chunk, an earlier one in the second chunk
    // is not possible: chunks are in file order; so two errors in different
    // chunks and blocks, the earlier must be reported with its line.
    set_cell(&mut rows, 9000, 2, "oops");
    set_cell(&mut rows, 4700, 5, "bad");
    let path = file(d.path(), "two.csv", &head(), &rows);
    let (s, p) = both(&path);
    assert!(s == p, "{:?} vs {:?}", s.error, p.error);
    let e = p.error.unwrap();
    // Header on line 3, row k on line k + 4.
    assert!(e.starts_with(&format!("{}:4704: column 6", path.display())), "{e}");
    assert_eq!(p.records.len(), 4700);
}

#[test]
fn issue_18_block_parsed_unusual_but_valid_files_read_like_the_streamed_ones() {
    let d = tempfile::tempdir().unwrap();
    let base = rows(12_000);
    let mut cases: Vec<(String, Vec<String>)> = Vec::new();
    // Blank lines, CRLF line ends, spaces around cells.
    let mut r = base.clone();
    r[10] = String::new();
    r[6000] = "   ".to_string();
    cases.push((head(), r));
    cases.push((
        head().replace('\n', "\r\n"),
        base.iter().map(|l| format!("{l}\r")).collect(),
    ));
    let mut r = base.clone();
    set_cell(&mut r, 5000, 1, " 1.25 ");
    cases.push((head(), r));
    // A time that does not increase (found on the parsed path).
    let mut r = base.clone();
    set_cell(&mut r, 8000, 0, "1.0");
    cases.push((head(), r));
    // A row of the wrong length; a quoted cell over two lines.
    let mut r = base.clone();
    r[6500].push_str(",extra");
    cases.push((head(), r));
    let mut r = base.clone();
    set_cell(&mut r, 3000, 11, "\"two\nlines\"");
    cases.push((head(), r));
    // No rows; no trailing line break; a line longer than a block.
    cases.push((head(), Vec::new()));
    let mut r = base.clone();
    set_cell(&mut r, 9999, 11, &"y".repeat(3 << 20));
    cases.push((head(), r));
    for (k, (h, r)) in cases.iter().enumerate() {
        let path = file(d.path(), &format!("odd{k}.csv"), h, r);
        let (s, p) = both(&path);
        assert!(
            s == p,
            "case {k}: streamed {:?} after {} rows, block-parsed {:?} after {} rows",
            s.error,
            s.records.len(),
            p.error,
            p.records.len()
        );
    }
    let path = d.path().join("no_newline.csv");
    let mut text = head();
    text.push_str(&base[..5000].join("\n"));
    std::fs::write(&path, text).unwrap();
    let (s, p) = both(&path);
    assert_eq!(s.records.len(), 5000);
    assert!(s == p);
}
