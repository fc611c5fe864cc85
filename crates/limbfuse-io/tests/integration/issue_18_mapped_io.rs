//! Issue 18 item 6 (the path around the filter): a trial file is read in
//! place from its mapping (`mmap`) and must read exactly as the same bytes
//! streamed (records, errors with their lines, the content hash); CSV
//! estimate rows written in blocks must be the bytes written row by row;
//! the Arrow writer, which lends its column buffers to each batch and takes
//! them back, must write every batch as the first.

use std::io::{Cursor, Write};
use std::path::Path;

use limbfuse_core::runner::{self, Observer};
use limbfuse_core::{Estimate, Estimator, EstimatorError, Outputs, Sample};
use limbfuse_io::{ContentHash, EstimateReader, EstimateWriter, TrialFingerprint, TrialReader};

/// A trial CSV over several hash steps (256 KiB): comments, a blank line,
/// CRLF ends, a quoted cell, empty cells, no line break at the end.
fn trial_text(rows: usize) -> String {
    let mut s = String::from("# format: limbfuse-trial/1\r\n# g: 9.81\n\nt,thigh_acc_x,thigh_acc_y,thigh_acc_z,thigh_gyr_x,thigh_gyr_y,thigh_gyr_z,knee_enc\n");
    for k in 0..rows {
        let x = (k as f64 * 0.37).sin();
        let enc = if k % 17 == 3 {
            String::new()
        } else {
            format!("{}", x * 0.123456789)
        };
        let quoted = if k == 5 {
            "\"0.5\"".to_string()
        } else {
            format!("{}", x / 3.0)
        };
        s += &format!(
            "{},{x},{},{quoted},{},{},{},{enc}{}",
            k as f64 * 0.01,
            9.81 + x,
            x * 2.0,
            -x,
            x * 1e-7,
            if k % 2 == 0 { "\r\n" } else { "\n" }
        );
    }
    s.truncate(s.trim_end().len());
    s
}

fn streamed(path: &Path) -> TrialReader {
    let bytes = std::fs::read(path).unwrap();
    TrialReader::from_reader(path, Box::new(Cursor::new(bytes))).unwrap()
}

#[test]
fn issue_18_a_mapped_csv_trial_reads_as_the_same_bytes_streamed() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("t.csv");
    std::fs::write(&path, trial_text(6000)).unwrap();
    assert!(std::fs::metadata(&path).unwrap().len() > 3 * (256 << 10));
    let mut mapped = TrialReader::open(&path).unwrap();
    let mut stream = streamed(&path);
    assert_eq!(mapped.meta().entries(), stream.meta().entries());
    let mut n = 0;
    while let Some(a) = stream.next_record().unwrap() {
        assert_eq!(mapped.content_hash(), None, "no hash before the end");
        assert_eq!(mapped.next_record().unwrap(), Some(a), "row {n}");
        n += 1;
    }
    assert_eq!(n, 6000);
    assert_eq!(mapped.next_record().unwrap(), None);
    let hash = mapped.content_hash().expect("a hash at the end");
    assert_eq!(Some(hash), stream.content_hash());
    assert_eq!(hash, ContentHash::of_bytes(&std::fs::read(&path).unwrap()));
    assert_eq!(hash, TrialFingerprint::of_file(&path).unwrap().hash);
}

#[test]
fn issue_18_a_mapped_csv_trial_fails_where_the_stream_fails() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("bad.csv");
    let text = trial_text(3000);
    // Line `at` (0-based) changed by `f`.
    let with_line = |at: usize, f: &dyn Fn(&str) -> String| {
        let mut lines: Vec<String> = text.split('\n').map(str::to_string).collect();
        lines[at] = f(&lines[at]);
        lines.join("\n")
    };
    for (what, bad) in [
        ("a bad cell", with_line(2990, &|l| l.replacen(',', "x,", 2))),
        (
            "a short row",
            with_line(2550, &|l| l[..l.find(',').unwrap()].to_string()),
        ),
        ("an unclosed quote", format!("{text}\n30.5,\"1,2,3,4,5,6,7")),
        ("no rows", "t,knee_enc\n\n".to_string()),
    ] {
        std::fs::write(&path, &bad).unwrap();
        let error = |mut r: TrialReader| loop {
            match r.next_record() {
                Ok(Some(_)) => {}
                Ok(None) => panic!("{what}: no error"),
                Err(e) => break e.to_string(),
            }
        };
        let a = error(TrialReader::open(&path).unwrap());
        let b = error(streamed(&path));
        assert_eq!(a, b, "{what}");
        assert!(a.contains("bad.csv:"), "{what}: {a}");
    }
}

/// Writes a time and the thigh gyro z rate, with a diagnostic that is
/// missing in some rows.
struct Echo;

impl Estimator for Echo {
    fn name(&self) -> &'static str {
        "echo"
    }
    fn outputs(&self) -> Outputs {
        let mut o = Outputs::default();
        o.segment[1] = true;
        o
    }
    fn describe_parameters(&self, out: &mut dyn std::fmt::Write) -> std::fmt::Result {
        writeln!(out, "gain: 1")
    }
    fn diagnostic_names(&self) -> &[&'static str] {
        &["rate", "count"]
    }
    fn reset(&mut self) {}
    fn step(&mut self, sample: &Sample) -> Result<Estimate, EstimatorError> {
        let mut e = Estimate::empty(sample.t);
        e.segment[1] = sample.imu[1].gyr.map(|g| g.z);
        // Missing in the second Arrow batch only (rows 8192..): a column
        // with nulls after a batch without.
        let k = (sample.t * 100.0).round() as i64;
        e.diag[0] = (!(9000..9100).contains(&k)).then_some(sample.t * 0.5);
        e.diag[1] = Some((k % 7) as f64);
        Ok(e)
    }
}

fn trial(dir: &Path, rows: usize) -> std::path::PathBuf {
    let path = dir.join("t.csv");
    std::fs::write(&path, trial_text(rows)).unwrap();
    path
}

/// The estimate file of `Echo` over `trial`, written by `writer`.
fn estimate_bytes(trial: &Path, writer: EstimateWriter<Cursor<Vec<u8>>>) -> Vec<u8> {
    let mut reader = TrialReader::open(trial).unwrap();
    let mut w = writer.recording_trial("t.csv");
    runner::run(&mut Echo, &mut reader, &mut [&mut w as &mut dyn Observer]).unwrap();
    w.stamp_trial_hash(reader.content_hash().unwrap()).unwrap();
    w.into_inner().unwrap().into_inner()
}

#[test]
fn issue_18_csv_estimate_rows_in_blocks_are_the_rows_written_one_by_one() {
    let dir = tempfile::tempdir().unwrap();
    let path = trial(dir.path(), 6000);
    let one_by_one = estimate_bytes(&path, EstimateWriter::new(Cursor::new(Vec::new())));
    let blocks = estimate_bytes(
        &path,
        EstimateWriter::new(Cursor::new(Vec::new())).in_blocks(),
    );
    assert!(one_by_one.len() > 3 * (64 << 10), "several blocks");
    assert_eq!(
        String::from_utf8(blocks).unwrap(),
        String::from_utf8(one_by_one).unwrap()
    );
}

#[test]
fn issue_18_every_arrow_batch_is_written_as_the_first() {
    let dir = tempfile::tempdir().unwrap();
    // Three batches of 8192 rows and a part.
    let path = trial(dir.path(), 3 * limbfuse_io::arrow_file::BATCH_ROWS + 500);
    let read = |p: &Path| {
        let mut r = EstimateReader::open(p).unwrap();
        std::iter::from_fn(|| r.next_estimate().unwrap())
            .map(|(_, e)| format!("{e:?}"))
            .collect::<Vec<_>>()
    };
    let mut files = Vec::new();
    for name in ["e.csv", "e.arrow"] {
        let out = dir.path().join(name);
        let mut file = std::fs::File::create(&out).unwrap();
        let bytes = estimate_bytes(
            &path,
            EstimateWriter::for_path(&out, Cursor::new(Vec::new())),
        );
        file.write_all(&bytes).unwrap();
        files.push(read(&out));
    }
    assert_eq!(
        files[0].len(),
        3 * limbfuse_io::arrow_file::BATCH_ROWS + 500
    );
    assert_eq!(files[1], files[0]);
    assert!(files[0][9050].contains("None"), "{}", files[0][9050]);
}
