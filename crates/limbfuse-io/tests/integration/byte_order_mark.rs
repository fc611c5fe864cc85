//! A UTF-8 byte-order mark (`EF BB BF`) before the first line, as Excel's
//! "CSV UTF-8" and other Windows tools write it, is not part of the file's
//! text: before it was skipped, a trial file starting with one failed with
//! "missing required column `t`" (the mark became part of the first comment
//! line, which then no longer started with `#` and was taken as the
//! header). Found by a probe of real-world CSV variants (2026-12-04).

use std::io::{self, Read};
use std::path::Path;

use limbfuse_io::import::import_knee_rig;
use limbfuse_io::TrialReader;

const BOM: &str = "\u{feff}";
const TRIAL: &str = "# format: limbfuse-trial/1\n# g: 9.81\nt,knee_enc,thigh_ref\n0.00,0.1,0.2\n0.01,0.3,\n0.02,0.5,0.6\n";

/// A source that hands out one byte per `read` (the mark arrives in
/// three reads).
struct ByteByByte(io::Cursor<Vec<u8>>);

impl Read for ByteByByte {
    fn read(&mut self, buf: &mut [u8]) -> io::Result<usize> {
        let n = buf.len().min(1);
        self.0.read(&mut buf[..n])
    }
}

/// `t`, `knee_enc` and the gravity of every row, and the header's names.
fn rows(mut r: TrialReader) -> (Vec<(f64, Option<f64>)>, Option<String>) {
    let g = r.meta().get("g").map(String::from);
    let mut out = Vec::new();
    while let Some(rec) = r.next_record().expect("rows read") {
        out.push((rec.sample.t, rec.sample.encoder[1]));
    }
    (out, g)
}

fn from_text(text: &str, byte_by_byte: bool) -> TrialReader {
    let bytes = text.as_bytes().to_vec();
    let source: Box<dyn Read + Send> = if byte_by_byte {
        Box::new(ByteByByte(io::Cursor::new(bytes)))
    } else {
        Box::new(io::Cursor::new(bytes))
    };
    TrialReader::from_reader(Path::new("bom.csv"), source).expect("a trial with a BOM is read")
}

#[test]
fn a_byte_order_mark_before_the_comments_is_skipped() {
    let plain = rows(from_text(TRIAL, false));
    assert_eq!(plain.0.len(), 3);
    assert_eq!(plain.1.as_deref(), Some("9.81"));
    for byte_by_byte in [false, true] {
        let with = rows(from_text(&format!("{BOM}{TRIAL}"), byte_by_byte));
        assert_eq!(with, plain, "byte by byte: {byte_by_byte}");
    }
}

#[test]
fn a_byte_order_mark_before_the_header_is_skipped() {
    let text = "t,knee_enc\n0.0,1.0\n0.01,2.0\n";
    let plain = rows(from_text(text, false));
    let with = rows(from_text(&format!("{BOM}{text}"), true));
    assert_eq!(with, plain);
    assert_eq!(with.0.len(), 2);
}

#[test]
fn a_byte_order_mark_in_a_file_on_disk_is_skipped() {
    // (`open` maps a file instead of streaming it)
    let dir = tempfile::tempdir().unwrap();
    let plain_path = dir.path().join("plain.csv");
    let bom_path = dir.path().join("bom.csv");
    std::fs::write(&plain_path, TRIAL).unwrap();
    std::fs::write(&bom_path, format!("{BOM}{TRIAL}")).unwrap();
    let plain = rows(TrialReader::open(&plain_path).unwrap());
    let with = rows(TrialReader::open(&bom_path).expect("a trial with a BOM is read"));
    assert_eq!(with, plain);
}

#[test]
fn only_a_leading_mark_is_skipped() {
    // A mark anywhere else is a character of the text: a header cell
    // `\u{feff}t` is not `t`.
    let text = format!("# g: 9.81\n{BOM}t,knee_enc\n0.0,1.0\n");
    let read = TrialReader::from_reader(
        Path::new("bom.csv"),
        Box::new(io::Cursor::new(text.into_bytes())),
    );
    let Err(e) = read else {
        panic!("a mark before the header line is not skipped");
    };
    assert!(e.to_string().contains("`t`"), "{e}");
}

#[test]
fn the_knee_rig_importer_skips_a_byte_order_mark() {
    let head = "LOG INTERVAL,4000,microseconds\nTOTAL LOG TIME,1,seconds\nHIP_CENTER_POS,780\nKNEE_CENTER_POS,390\nTRANSFER #,TIME,TIME DELTA,G1X,G1Y,G1Z,A1X,A1Y,A1Z,G2X,G2Y,G2Z,A2X,A2Y,A2Z,HIP STEPPER,KNEE STEPPER,ABS KNEE ANGLE,GAIT STAGE,IMPULSE HIT\n";
    let row = |n: u32, time: u64| {
        format!("{n},{time},4000,57.29578,0.00,-57.29578,0.00,0.00,-1.00,0.00,0.00,0.00,0.00,0.50,0.00,779,390,10.00,9,0\n")
    };
    let text = format!("{head}{}{}", row(0, 1_000_000), row(1, 1_004_000));
    let dir = tempfile::tempdir().unwrap();
    let (plain, with) = (
        dir.path().join("Trial_98.csv"),
        dir.path().join("Trial_99.csv"),
    );
    std::fs::write(&plain, &text).unwrap();
    std::fs::write(&with, format!("{BOM}{text}")).unwrap();
    let a = import_knee_rig(&plain).unwrap();
    let b = import_knee_rig(&with).expect("a knee-rig file with a BOM is imported");
    assert_eq!(a.records.len(), 2);
    assert_eq!(a.records, b.records);
}
