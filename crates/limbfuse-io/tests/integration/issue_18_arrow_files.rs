//! Issue 18 item 6: Arrow IPC trial and estimate files (`.arrow`,
//! `.feather`) hold the same table as the CSV files and read back to the
//! same records and estimates, bit for bit; what other tools write (integer
//! and text columns, LZ4) reads; bad files are errors naming the file,
//! row and column, never a panic.

use std::fmt;
use std::path::Path;
use std::sync::Arc;

use arrow_array::{ArrayRef, Float64Array, Int64Array, RecordBatch, StringArray};
use arrow_schema::{DataType, Field, Schema};
use limbfuse_core::estimator::Outputs;
use limbfuse_core::runner::{self, Observer};
use limbfuse_core::sample::GaitPhase;
use limbfuse_core::{Estimate, Estimator, EstimatorError, Record, Sample};
use limbfuse_io::{
    AtomicFile, ContentHash, EstimateReader, EstimateWriter, TrialFingerprint, TrialLayout,
    TrialMeta, TrialReader, TrialWriter,
};
use nalgebra::Vector3;

/// Records with irrational values, missing cells and gait-phase labels.
fn records(n: usize) -> Vec<Record> {
    (0..n)
        .map(|k| {
            let t = k as f64 * 0.01;
            let mut r = Record::default();
            r.sample.t = t;
            for (i, imu) in r.sample.imu.iter_mut().enumerate() {
                let x = (t * (1.0 + i as f64) * std::f64::consts::SQRT_2).sin();
                imu.acc = (k % 7 != i).then(|| Vector3::new(x * 3.1, 9.81 + x, x * 0.7));
                imu.gyr = Some(Vector3::new(x * 0.1, -x * 0.2, x * 2.3));
            }
            r.sample.encoder = [Some(t.sin()), (k % 5 != 0).then(|| t.cos()), Some(-t)];
            r.reference.segment = [Some(0.01 * t.sin()), Some(t.sin()), None, Some(0.3)];
            r.reference.joint = [Some(t.cos()), Some(-t.sin()), Some(0.2 * t.cos())];
            r.reference.phase = match k % 3 {
                0 => Some(GaitPhase::Ss1),
                1 => None,
                _ => Some(GaitPhase::Ds),
            };
            r
        })
        .collect()
}

fn layout() -> TrialLayout {
    let mut l = TrialLayout::walking();
    l.phase_ref = true;
    l
}

fn meta() -> TrialMeta {
    let mut m = TrialMeta::trial_v1();
    m.set("source", "test");
    m.set("g", "9.81");
    m.set("a_late_key", "comes last");
    m
}

fn write_trial(path: &Path, records: &[Record]) {
    let mut out = AtomicFile::create(path).unwrap();
    let mut w = TrialWriter::for_path(path, &mut out, &meta(), layout()).unwrap();
    for r in records {
        w.write(r).unwrap();
    }
    w.finish().unwrap();
    out.commit().unwrap();
}

fn read_all(path: &Path) -> (TrialMeta, TrialLayout, Vec<Record>) {
    let mut r = TrialReader::open(path).unwrap();
    let (meta, layout) = (r.meta().clone(), *r.layout());
    let recs = r.by_ref().map(Result::unwrap).collect();
    assert!(r.content_hash().is_some(), "hashed at the end");
    (meta, layout, recs)
}

#[test]
fn issue_18_arrow_trials_read_back_as_the_csv_trial_does() {
    let dir = tempfile::tempdir().unwrap();
    // More rows than one batch, so that batches are crossed.
    let recs = records(limbfuse_io::arrow_file::BATCH_ROWS + 123);
    let (csv, arrow) = (dir.path().join("t.csv"), dir.path().join("t.arrow"));
    write_trial(&csv, &recs);
    write_trial(&arrow, &recs);
    let from_csv = read_all(&csv);
    let from_arrow = read_all(&arrow);
    assert_eq!(from_arrow.0, meta(), "metadata in its order");
    assert_eq!(from_arrow.0, from_csv.0);
    assert_eq!(from_arrow.1, from_csv.1);
    assert_eq!(from_arrow.2.len(), recs.len());
    // Bit for bit (PartialEq on f64 would accept -0.0 == 0.0).
    assert_eq!(format!("{:?}", from_arrow.2), format!("{:?}", from_csv.2));
    assert_eq!(format!("{:?}", from_arrow.2), format!("{:?}", recs));
    let fp = TrialFingerprint::of_file(&arrow).unwrap();
    assert_eq!(fp.data_rows, recs.len() as u64);
    assert_eq!(
        fp.hash,
        ContentHash::of_bytes(&std::fs::read(&arrow).unwrap())
    );
}

/// Echoes the thigh gyro's z rate as the thigh angle, with a diagnostic.
struct Echo;

impl Estimator for Echo {
    fn name(&self) -> &'static str {
        "echo"
    }
    fn outputs(&self) -> Outputs {
        let mut o = Outputs::default();
        o.segment[1] = true;
        o.phase = true;
        o
    }
    fn describe_parameters(&self, out: &mut dyn fmt::Write) -> fmt::Result {
        writeln!(out, "gain: 1")
    }
    fn diagnostic_names(&self) -> &[&'static str] {
        &["rate"]
    }
    fn reset(&mut self) {}
    fn step(&mut self, sample: &Sample) -> Result<Estimate, EstimatorError> {
        let mut e = Estimate::empty(sample.t);
        e.segment[1] = sample.imu[1].gyr.map(|g| g.z);
        e.phase = (sample.t > 0.5).then_some(GaitPhase::Ss2);
        e.diag[0] = sample.imu[1].acc.map(|a| a.x);
        Ok(e)
    }
}

fn estimate(trial: &Path, out: &Path) -> Vec<(u64, Estimate)> {
    let mut reader = TrialReader::open(trial).unwrap();
    let mut file = AtomicFile::create(out).unwrap();
    let mut w = EstimateWriter::for_path(out, &mut file).recording_trial("t");
    runner::run(&mut Echo, &mut reader, &mut [&mut w as &mut dyn Observer]).unwrap();
    w.stamp_trial_hash(reader.content_hash().unwrap()).unwrap();
    w.into_inner().unwrap();
    file.commit().unwrap();
    let mut er = EstimateReader::open(out).unwrap();
    assert_eq!(er.method(), "echo");
    assert_eq!(er.meta().get("gain"), Some("1"));
    assert_eq!(
        er.recorded_trial_hash().and_then(ContentHash::parse),
        Some(ContentHash::of_bytes(&std::fs::read(trial).unwrap()))
    );
    assert_eq!(er.diagnostic_names().collect::<Vec<_>>(), ["rate"]);
    std::iter::from_fn(|| er.next_estimate().unwrap()).collect()
}

#[test]
fn issue_18_arrow_estimates_read_back_as_the_csv_estimates_do() {
    let dir = tempfile::tempdir().unwrap();
    let recs = records(300);
    let trial = dir.path().join("t.csv");
    write_trial(&trial, &recs);
    let csv = estimate(&trial, &dir.path().join("e.csv"));
    let arrow = estimate(&trial, &dir.path().join("e.feather"));
    assert_eq!(csv.len(), 300);
    let strip = |v: &[(u64, Estimate)]| format!("{:?}", v.iter().map(|x| &x.1).collect::<Vec<_>>());
    assert_eq!(strip(&arrow), strip(&csv));
    // Row numbers stand in for lines in an Arrow file.
    assert_eq!(arrow[0].0, 1);
    assert_eq!(arrow[299].0, 300);
}

fn write_batch(path: &Path, fields: Vec<Field>, columns: Vec<ArrayRef>) {
    let schema = Arc::new(Schema::new(fields));
    let batch = RecordBatch::try_new(schema.clone(), columns).unwrap();
    let file = std::fs::File::create(path).unwrap();
    let mut w = arrow_ipc::writer::FileWriter::try_new(file, &schema).unwrap();
    w.write(&batch).unwrap();
    w.finish().unwrap();
}

#[test]
fn issue_18_integer_and_text_columns_read_as_numbers() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("other_tool.arrow");
    write_batch(
        &path,
        vec![
            Field::new("t", DataType::Int64, false),
            Field::new("knee_enc", DataType::Utf8, true),
            Field::new("knee_ref", DataType::Float64, true),
        ],
        vec![
            Arc::new(Int64Array::from(vec![0, 1, 2])),
            Arc::new(StringArray::from(vec![Some("0.5"), None, Some(" ")])),
            Arc::new(Float64Array::from(vec![Some(1.0), None, Some(-0.0)])),
        ],
    );
    let (_, layout, recs) = read_all(&path);
    assert!(layout.encoder[1] && layout.joint_ref[1]);
    let got: Vec<_> = recs
        .iter()
        .map(|r| (r.sample.t, r.sample.encoder[1], r.reference.joint[1]))
        .collect();
    assert_eq!(
        got,
        [
            (0.0, Some(0.5), Some(1.0)),
            (1.0, None, None),
            (2.0, None, Some(-0.0))
        ]
    );
}

fn first_error(path: &Path) -> String {
    match TrialReader::open(path) {
        Err(e) => e.to_string(),
        Ok(r) => r
            .into_iter()
            .find_map(Result::err)
            .expect("an error")
            .to_string(),
    }
}

#[test]
fn issue_18_bad_arrow_files_are_errors_with_row_and_column() {
    let dir = tempfile::tempdir().unwrap();
    let nan = dir.path().join("nan.arrow");
    write_batch(
        &nan,
        vec![
            Field::new("t", DataType::Float64, false),
            Field::new("hip_enc", DataType::Float64, true),
        ],
        vec![
            Arc::new(Float64Array::from(vec![0.0, 0.01])),
            Arc::new(Float64Array::from(vec![0.1, f64::NAN])),
        ],
    );
    let e = first_error(&nan);
    assert!(
        e.contains("nan.arrow:2: column 2 (`hip_enc`)") && e.contains("finite"),
        "{e}"
    );

    let text = dir.path().join("text.arrow");
    write_batch(
        &text,
        vec![
            Field::new("t", DataType::Float64, false),
            Field::new("hip_enc", DataType::Utf8, true),
        ],
        vec![
            Arc::new(Float64Array::from(vec![0.0])),
            Arc::new(StringArray::from(vec!["ten"])),
        ],
    );
    let e = first_error(&text);
    assert!(
        e.contains("text.arrow:1: column 2 (`hip_enc`)") && e.contains("`ten`"),
        "{e}"
    );

    let back = dir.path().join("back.arrow");
    write_batch(
        &back,
        vec![Field::new("t", DataType::Float64, false)],
        vec![Arc::new(Float64Array::from(vec![0.0, 0.0]))],
    );
    assert!(first_error(&back).contains("must increase"));

    let binary = dir.path().join("binary.arrow");
    write_batch(
        &binary,
        vec![
            Field::new("t", DataType::Float64, false),
            Field::new("blob", DataType::Binary, true),
        ],
        vec![
            Arc::new(Float64Array::from(vec![0.0])),
            Arc::new(arrow_array::BinaryArray::from(vec![b"x".as_ref()])),
        ],
    );
    assert!(first_error(&binary).contains("`blob` has the Arrow type Binary"));

    // Every truncation of a valid file, and a CSV named .arrow: errors.
    let good = dir.path().join("good.arrow");
    write_trial(&good, &records(50));
    let bytes = std::fs::read(&good).unwrap();
    let cut = dir.path().join("cut.arrow");
    for n in (0..bytes.len()).step_by(97) {
        std::fs::write(&cut, &bytes[..n]).unwrap();
        let e = first_error(&cut);
        assert!(e.contains("cut.arrow"), "{n} bytes: {e}");
    }
    std::fs::write(&cut, "t,hip_enc\n0,1\n").unwrap();
    assert!(first_error(&cut).contains("Arrow IPC file"));
}

/// Every single-byte corruption of a small Arrow trial reads to records or
/// to an error naming the file: never a panic (arrow-ipc validates the
/// flatbuffers and the arrays it reads).
#[test]
fn issue_18_corrupted_arrow_bytes_are_errors_not_panics() {
    let dir = tempfile::tempdir().unwrap();
    let good = dir.path().join("good.arrow");
    write_trial(&good, &records(20));
    let bytes = std::fs::read(&good).unwrap();
    let bad = dir.path().join("bad.arrow");
    for (k, at) in (0..bytes.len()).step_by(7).enumerate() {
        let mut b = bytes.clone();
        b[at] ^= [0xff, 0x80, 0x01, 0x7f][k % 4];
        std::fs::write(&bad, &b).unwrap();
        let outcome = std::panic::catch_unwind(|| match TrialReader::open(&bad) {
            Err(e) => Err(e.to_string()),
            Ok(r) => r
                .collect::<Result<Vec<_>, _>>()
                .map(|_| ())
                .map_err(|e| e.to_string()),
        });
        match outcome {
            Ok(Ok(())) => {}
            Ok(Err(e)) => assert!(e.contains("bad.arrow"), "byte {at}: {e}"),
            Err(_) => panic!("byte {at}: reading panicked"),
        }
    }
}

/// Fuzz audit 27: a `Utf8` `knee_enc` cell holding `1e999` (it overflows to
/// infinity) was reported as "found `inf`", where the CSV reader shows
/// `1e999`. Now both show the cell's text.
#[test]
fn an_overflowing_text_cell_is_shown_as_written_as_in_csv() {
    let dir = tempfile::tempdir().unwrap();
    let arrow = dir.path().join("big.arrow");
    write_batch(
        &arrow,
        vec![
            Field::new("t", DataType::Float64, false),
            Field::new("knee_enc", DataType::Utf8, true),
        ],
        vec![
            Arc::new(Float64Array::from(vec![0.0, 0.01])),
            Arc::new(StringArray::from(vec!["0.5", "1e999"])),
        ],
    );
    let e = first_error(&arrow);
    assert!(
        e.contains("big.arrow:2: column 2 (`knee_enc`)") && e.contains("found `1e999`"),
        "{e}"
    );
    let csv = dir.path().join("big.csv");
    std::fs::write(&csv, "t,knee_enc\n0,0.5\n0.01,1e999\n").unwrap();
    let e = first_error(&csv);
    assert!(e.contains("found `1e999`"), "{e}");
}
