//! The estimate file records its trial (`# trial:`, `# trial_hash:`), and an
//! [`AtomicFile`] output appears only when the run succeeds.

use std::fmt;
use std::io::Cursor;
use std::path::Path;

use limbfuse_core::estimator::Outputs;
use limbfuse_core::runner::{self, Observer};
use limbfuse_core::{Estimate, Estimator, EstimatorError, Sample};
use limbfuse_io::{AtomicFile, ContentHash, EstimateReader, EstimateWriter, TrialReader};

/// Echoes the sample time as the thigh angle.
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
    fn describe_parameters(&self, out: &mut dyn fmt::Write) -> fmt::Result {
        writeln!(out, "gain: 1")
    }
    fn reset(&mut self) {}
    fn step(&mut self, sample: &Sample) -> Result<Estimate, EstimatorError> {
        let mut e = Estimate::empty(sample.t);
        e.segment[1] = Some(sample.t);
        Ok(e)
    }
}

const TRIAL: &str = "# format: limbfuse-trial/1\nt,thigh_ref\n0,0\n0.01,0.1\n0.02,0.2\n";

#[test]
fn the_estimate_header_records_the_trial_name_and_hash() {
    let dir = tempfile::tempdir().unwrap();
    let trial = dir.path().join("walk.csv");
    std::fs::write(&trial, TRIAL).unwrap();
    let mut reader = TrialReader::open(&trial).unwrap();
    let mut w = EstimateWriter::new(Cursor::new(Vec::new())).recording_trial("walk.csv");
    runner::run(&mut Echo, &mut reader, &mut [&mut w as &mut dyn Observer]).unwrap();
    let hash = reader.content_hash().expect("read to the end");
    assert_eq!(hash, ContentHash::of_bytes(TRIAL.as_bytes()));
    w.stamp_trial_hash(hash).unwrap();
    let bytes = w.into_inner().unwrap().into_inner();
    let text = String::from_utf8(bytes).unwrap();
    assert!(
        text.starts_with(&format!(
            "# method: echo\n# gain: 1\n# trial: walk.csv\n# trial_hash: {hash}\nt,thigh\n0.0,0.0\n"
        )),
        "{text}"
    );
    let out = dir.path().join("e.csv");
    std::fs::write(&out, &text).unwrap();
    let er = EstimateReader::open(&out).unwrap();
    assert_eq!(er.recorded_trial(), Some("walk.csv"));
    assert_eq!(
        er.recorded_trial_hash().and_then(ContentHash::parse),
        Some(hash)
    );
}

#[test]
fn a_failing_run_leaves_no_output_file() {
    let dir = tempfile::tempdir().unwrap();
    let trial = dir.path().join("bad.csv");
    // The third row is short (a short last line without a line break is a
    // recording cut off and is left out since 2026-12-07; this one has one).
    std::fs::write(&trial, "t,thigh_ref\n0,0\n0.01,0.1\n0.02\n").unwrap();
    let out = dir.path().join("e.csv");
    let run = |path: &Path| -> Result<(), Box<dyn std::error::Error>> {
        let mut reader = TrialReader::open(&trial)?;
        let mut w = EstimateWriter::new(AtomicFile::create(path)?).recording_trial("bad.csv");
        runner::run(&mut Echo, &mut reader, &mut [&mut w as &mut dyn Observer])?;
        let hash = reader.content_hash().ok_or("not at the end")?;
        w.stamp_trial_hash(hash)?;
        w.into_inner()?.commit()?;
        Ok(())
    };
    assert!(run(&out).is_err());
    let names: Vec<_> = std::fs::read_dir(dir.path())
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    assert_eq!(names, vec!["bad.csv".to_string()]);
}
