//! A recording cut off while it was written (a logger switched off, a copy
//! of a file still being written): its last line has fewer cells than the
//! header and no line break. Every reader stopped there with "expected 3
//! cells ..., found 2", so a long recording gave no estimate at all (a file
//! output is written only when the whole run succeeds). That line is now
//! left out and reported (`TrialReader::cut_last_line`); a short line with a
//! line break, or anywhere else, is still an error.

use std::path::Path;

use limbfuse_io::{ContentHash, TrialReader};

const WHOLE: &str =
    "# sample_rate_hz: 100\nt,thigh_ref,knee_enc\n0,0.1,0.2\n0.01,0.1,0.2\n0.02,0.1,0.2\n";

/// The times read, the cut line reported (line, cells found, expected) and
/// the hash; or the error.
type Read = Result<(Vec<f64>, Option<(u64, usize, usize)>, ContentHash), String>;

/// The times read from `text` through a stream and through a mapped file,
/// with the cut line each reported and the hash each gave.
fn read_both(text: &str) -> Vec<Read> {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("cut.csv");
    std::fs::write(&path, text).unwrap();
    let readers = [
        TrialReader::from_reader(
            Path::new("cut.csv"),
            Box::new(std::io::Cursor::new(text.to_string())),
        ),
        TrialReader::open(&path),
    ];
    readers
        .into_iter()
        .map(|r| {
            let mut r = r.map_err(|e| e.to_string())?;
            let mut t = Vec::new();
            while let Some(rec) = r.next_record().map_err(|e| e.to_string())? {
                t.push(rec.sample.t);
            }
            let cut = r.cut_last_line().map(|c| (c.line, c.found, c.expected));
            Ok((t, cut, r.content_hash().expect("read to the end")))
        })
        .collect()
}

#[test]
fn a_last_line_cut_short_without_a_line_break_is_left_out() {
    let whole = read_both(WHOLE);
    for cut_at in ["0.03,0.1", "0.03,0.", "0.03", "0.0"] {
        let text = format!("{WHOLE}{cut_at}");
        for (read, whole) in read_both(&text).into_iter().zip(&whole) {
            let (t, cut, hash) = read.unwrap();
            assert_eq!(t, [0.0, 0.01, 0.02], "{cut_at}");
            let found = cut_at.split(',').count();
            assert_eq!(cut, Some((6, found, 3)), "{cut_at}");
            // the hash is the whole file's, cut line included
            assert_ne!(&hash, &whole.as_ref().unwrap().2);
        }
    }
    // stream and mapped file agree on the hash
    let text = format!("{WHOLE}0.03,0.1");
    let both = read_both(&text);
    assert_eq!(both[0].as_ref().unwrap().2, both[1].as_ref().unwrap().2);
    // a whole file reports nothing
    assert!(whole.iter().all(|r| r.as_ref().unwrap().1.is_none()));
}

#[test]
fn a_short_line_with_a_line_break_or_before_the_end_is_still_an_error() {
    for text in [
        format!("{WHOLE}0.03,0.1\n"),
        format!("{WHOLE}0.03,0.1\n0.04,0.1,0.2"),
        "t,thigh_ref,knee_enc\n0,0.1\n0.01,0.1,0.2\n".to_string(),
    ] {
        for read in read_both(&text) {
            let e = read.unwrap_err();
            assert!(
                e.contains("expected 3 cells (as many as header columns), found 2"),
                "{e}"
            );
        }
    }
    // a last line with every cell and no line break is a row, as before
    for read in read_both(&format!("{WHOLE}0.03,0.1,0.2")) {
        let (t, cut, _) = read.unwrap();
        assert_eq!((t.len(), cut), (4, None));
    }
}
