//! `limbfuse align TRIAL -o ALIGNED`: sensor-to-segment rotations from walking data.

use anyhow::{bail, Context, Result};
use limbfuse_core::{Record, Segment};
use limbfuse_io::{TrialReader, TrialWriter};
use limbfuse_signal::align::{apply_alignment, estimate_alignment, AlignOptions};

use crate::cli::AlignArgs;

fn parse_mean_angles(items: &[String]) -> Result<[f64; 4]> {
    let mut out = [0.0; 4];
    for item in items {
        let (seg, deg) = item.split_once('=').with_context(|| {
            format!("--mean-angle: expected SEGMENT=DEGREES (e.g. thigh=7), found `{item}`")
        })?;
        let s = Segment::ALL
            .into_iter()
            .find(|s| s.name() == seg.trim())
            .with_context(|| {
                format!(
                    "--mean-angle: unknown segment `{seg}` (expected trunk, thigh, shank or foot)"
                )
            })?;
        let v: f64 = deg
            .trim()
            .parse()
            .ok()
            .filter(|v: &f64| v.is_finite())
            .with_context(|| {
                format!("--mean-angle: expected a number of degrees after `{seg}=`, found `{deg}`")
            })?;
        out[s.index()] = v.to_radians();
    }
    Ok(out)
}

/// Reads the trial, estimates the rotations, writes the aligned trial.
pub fn run(a: &AlignArgs) -> Result<()> {
    if a.joint_axis {
        return super::align_joint_axis::run(a);
    }
    if a.procedure == crate::cli::AlignProcedure::StaticRotation {
        return super::align_static::run(a);
    }
    let opts = AlignOptions {
        hinge: a.hinge,
        partial: a.partial,
        mean_angle_rad: parse_mean_angles(&a.mean_angle)?,
        ..AlignOptions::default()
    };
    let reader = TrialReader::open(&a.trial)?;
    let mut meta = reader.meta().clone();
    let layout = *reader.layout();
    if !layout.gyr.iter().any(|&g| g) {
        bail!("{}: the trial has no gyroscope channels (`<segment>_gyr_x` ...), which alignment needs", a.trial.display());
    }
    let mut records: Vec<Record> = reader.collect::<Result<_, _>>()?;
    if let Some(path) = &a.imu_calibration {
        let (cal, frame) = super::calibrate::load_for_trial(path, &a.trial, &meta, &layout)?;
        records.iter_mut().for_each(|r| cal.apply(r));
        cal.annotate(&mut meta, &super::calibrate::file_name(path), frame);
    }
    let alignment = estimate_alignment(&records, &opts)
        .with_context(|| format!("aligning {}", a.trial.display()))?;
    alignment.annotate(&mut meta);
    let mut out = super::create_file(&a.output)?;
    let mut w = TrialWriter::new(&mut out, &meta, layout)
        .with_context(|| format!("{}: cannot write", a.output.display()))?;
    for r in &records {
        w.write(&apply_alignment(r, &alignment))
            .with_context(|| format!("{}: cannot write", a.output.display()))?;
    }
    w.finish()
        .with_context(|| format!("{}: cannot write", a.output.display()))?;
    super::commit(out)?;
    for (k, v) in alignment.metadata() {
        if k.ends_with("_axis")
            || k.ends_with("_zero")
            || k.ends_with("_skipped")
            || k.ends_with("_align_quat")
        {
            println!("{k}: {v}");
        }
    }
    eprintln!(
        "aligned {} samples -> {}",
        records.len(),
        a.output.display()
    );
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::parse_mean_angles;

    #[test]
    fn mean_angles_parse() {
        let m = parse_mean_angles(&["thigh=7".into(), "foot=-15".into()]).unwrap();
        assert!(
            (m[1] - 7f64.to_radians()).abs() < 1e-15 && (m[3] + 15f64.to_radians()).abs() < 1e-15
        );
        assert!(parse_mean_angles(&["knee=3".into()]).is_err());
        assert!(parse_mean_angles(&["thigh".into()]).is_err());
        assert!(parse_mean_angles(&["thigh=x".into()]).is_err());
    }
}
