//! `limbfuse align --procedure static-rotation [--calibration CAL] TRIAL -o OUT`
//! (paper 004 section 3.3): rotations from the calibration recording (or the
//! calibration segment at the start of TRIAL), applied to TRIAL.

use anyhow::{Context, Result};
use limbfuse_core::{Record, Segment};
use limbfuse_io::{TrialReader, TrialWriter};
use limbfuse_signal::align::apply_rotations;
use limbfuse_signal::align::static_rotation::{
    quat_wxyz, static_rotation_alignment, StaticRotationOptions,
};

use crate::cli::AlignArgs;

/// Runs the procedure and writes the aligned trial.
pub fn run(a: &AlignArgs) -> Result<()> {
    let reader = TrialReader::open(&a.trial)?;
    let mut meta = reader.meta().clone();
    let layout = *reader.layout();
    let g = meta
        .gravity()
        .map_err(|e| anyhow::anyhow!("{}: {e}", a.trial.display()))?;
    let mut records: Vec<Record> = reader.collect::<Result<_, _>>()?;
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
            let r = TrialReader::open(p)?;
            let mut rec = r.collect::<Result<Vec<_>, _>>()?;
            // The same sensors, raw: the same IMU calibration.
            if let Some(c) = &imu_cal {
                rec.iter_mut().for_each(|r| c.apply(r));
            }
            (rec, p.display().to_string())
        }
        None => (records.clone(), a.trial.display().to_string()),
    };
    let segments: Vec<Segment> = Segment::ALL
        .into_iter()
        .filter(|s| layout.acc[s.index()] && layout.gyr[s.index()])
        .collect();
    let opts = StaticRotationOptions {
        g,
        ..StaticRotationOptions::default()
    };
    let al = static_rotation_alignment(&cal_records, &segments, &opts)
        .with_context(|| format!("{cal_name}: static-rotation alignment"))?;
    meta.set("align_method", "static-rotation (paper 004 section 3.3)");
    meta.set("align_calibration", &cal_name);
    meta.set(
        "align_quiet",
        format!("{:.2}-{:.2} s", al.quiet.0, al.quiet.1),
    );
    for s in &segments {
        let i = s.index();
        if let Some(r) = al.rotations[i] {
            let q = quat_wxyz(&r);
            meta.set(
                format!("{}_align_quat", s.name()),
                format!("{:.9} {:.9} {:.9} {:.9}", q[0], q[1], q[2], q[3]),
            );
            meta.set(
                format!("{}_align_rotations", s.name()),
                al.positive_rotations[i],
            );
            meta.set(
                format!("{}_align_z_correction_deg", s.name()),
                format!("{:.3}", al.z_correction[i].to_degrees()),
            );
        }
    }
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
        segments.len(),
        al.quiet.0,
        al.quiet.1,
        a.output.display()
    );
    Ok(())
}
