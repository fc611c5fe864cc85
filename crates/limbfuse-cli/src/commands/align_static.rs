//! `limbfuse align --procedure static-rotation [--calibration CAL] TRIAL -o OUT`
//! (paper 004 section 3.3): rotations from the calibration recording (or the
//! calibration segment at the start of TRIAL), applied to TRIAL.

use anyhow::{Context, Result};
use limbfuse_core::Record;
use limbfuse_io::{TrialReader, TrialWriter};
use limbfuse_signal::align::apply_rotations;
use limbfuse_workflows::trial_alignment::align_static_rotation;

use crate::cli::AlignArgs;

/// Runs the procedure and writes the aligned trial.
pub fn run(a: &AlignArgs) -> Result<()> {
    let mut reader = TrialReader::open(&a.trial)?;
    let mut meta = reader.meta().clone();
    let layout = *reader.layout();
    // (the `# g:` line first, named with the trial)
    meta.gravity()
        .map_err(|e| anyhow::anyhow!("{}: {e}", a.trial.display()))?;
    let mut records: Vec<Record> = super::read_records(&mut reader)?;
    let imu_cal = match &a.imu_calibration {
        Some(path) => {
            let (cal, frame) = super::calibrate::load_for_trial(path, &a.trial, &meta, &layout)?;
            records.iter_mut().for_each(|r| cal.apply(r));
            cal.annotate(&mut meta, &super::calibrate::file_name(path), frame);
            Some(cal)
        }
        None => None,
    };
    let (cal_records, cal_name) = match &a.calibration {
        Some(p) => {
            let mut r = TrialReader::open(p)?;
            let mut rec = super::read_records(&mut r)?;
            // The same sensors, raw: the same IMU calibration.
            if let Some(c) = &imu_cal {
                rec.iter_mut().for_each(|r| c.apply(r));
            }
            (rec, p.display().to_string())
        }
        None => (records.clone(), a.trial.display().to_string()),
    };
    let al = align_static_rotation(&cal_records, &cal_name, &layout, &mut meta)
        .with_context(|| format!("{cal_name}: static-rotation alignment"))?;
    let n_segments = al.rotations.iter().flatten().count();
    let mut out = super::create_file(&a.output)?;
    let mut w = TrialWriter::for_path(&a.output, &mut out, &meta, layout)
        .with_context(|| format!("{}: cannot write", a.output.display()))?;
    for r in &records {
        w.write(&apply_rotations(r, &al.rotations))
            .with_context(|| format!("{}: cannot write", a.output.display()))?;
    }
    w.finish()
        .with_context(|| format!("{}: cannot write", a.output.display()))?;
    super::commit(out)?;
    eprintln!(
        "aligned {} sensors with the static-rotation procedure (quiet {:.1}-{:.1} s) -> {}",
        n_segments,
        al.quiet.0,
        al.quiet.1,
        a.output.display()
    );
    Ok(())
}
