//! `limbfuse align TRIAL -o ALIGNED`: sensor-to-segment rotations from walking data.

use anyhow::{bail, Context, Result};
use limbfuse_core::{Record, Segment};
use limbfuse_io::{TrialReader, TrialWriter};
use limbfuse_signal::align::{apply_alignment, AlignOptions, Alignment};
use limbfuse_workflows::trial_alignment::{align_walking, TrialAlignmentError};

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
        // (an audit: `thigh=1e308` was reported as the library's option
        // `mean_angle_rad[1]` with 300 digits)
        if v.abs() > 180.0 {
            bail!(
                "--mean-angle {}={}: expected degrees within [-180, 180]",
                seg.trim(),
                limbfuse_methods::shown(v)
            );
        }
        out[s.index()] = v.to_radians();
    }
    Ok(out)
}

/// Reads the trial, estimates the rotations, writes the aligned trial.
pub fn run(a: &AlignArgs) -> Result<()> {
    check_calibration_flag(a)?;
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
    super::refuse_overwrites(
        &[
            ("", Some(&a.trial)),
            ("--calibration", a.calibration.as_deref()),
            ("--imu-calibration", a.imu_calibration.as_deref()),
        ],
        &[("-o", Some(&a.output))],
    )?;
    let mut reader = TrialReader::open(&a.trial)?;
    let mut meta = reader.meta().clone();
    let layout = *reader.layout();
    if !layout.gyr.iter().any(|&g| g) {
        bail!(
            "{}: {}",
            a.trial.display(),
            TrialAlignmentError::NoGyroscope
        );
    }
    let mut records: Vec<Record> = super::read_records(&mut reader)?;
    super::warn_input_units(&a.trial, &meta, &records)?;
    if let Some(path) = &a.imu_calibration {
        let (cal, frame) = super::calibrate::load_for_trial(path, &a.trial, &meta, &layout)?;
        records.iter_mut().for_each(|r| cal.apply(r));
        cal.annotate(&mut meta, &super::calibrate::file_name(path), frame);
    }
    let w = align_walking(&records, &layout, &mut meta, &opts)
        .with_context(|| format!("aligning {}", a.trial.display()))?;
    if let Some((gyro, acc, first_t)) = w.left_out {
        eprintln!(
            "warning: {}: {}",
            a.trial.display(),
            left_out_message(gyro, acc, first_t)
        );
    }
    if w.leg_replaced {
        eprintln!("warning: {}", w.leg_line);
    }
    if let Some(note) = &w.other_leg_raw {
        eprintln!("warning: {}: {note}", a.trial.display());
    }
    let (alignment, leg_line) = (w.alignment, w.leg_line);
    let mut out = super::create_file(&a.output)?;
    let mut w = TrialWriter::for_path(&a.output, &mut out, &meta, layout)
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
    print!("{}", confidence_table(&alignment));
    println!("{leg_line}");
    eprintln!(
        "aligned {} samples -> {}",
        records.len(),
        a.output.display()
    );
    Ok(())
}

/// `--calibration` is the static-rotation procedure's recording of quiet
/// standing and rotations: refused under the walking procedure and
/// `--joint-axis` (an audit: `align --calibration cal.toml` exited 0 with
/// the file ignored, while `estimate` / `import` take an IMU calibration
/// as `--calibration`), with `--imu-calibration` named when the file is an
/// IMU calibration (the wording of Python's `align`).
fn check_calibration_flag(a: &AlignArgs) -> Result<()> {
    let Some(path) = &a.calibration else {
        return Ok(());
    };
    let imu = is_imu_calibration_file(path);
    let static_rotation = a.procedure == crate::cli::AlignProcedure::StaticRotation;
    if a.joint_axis || !static_rotation {
        let hint = if imu {
            format!(
                "; {} is an IMU calibration file (`limbfuse calibrate`): give it as --imu-calibration",
                path.display()
            )
        } else {
            String::new()
        };
        bail!(
            "--calibration (the recording of quiet standing and rotations) is for --procedure \
             static-rotation, and this `align` {}{hint}",
            if a.joint_axis {
                "identifies the joint axis (--joint-axis)"
            } else {
                "runs the walking procedure (the default --procedure walking)"
            }
        );
    }
    if imu {
        bail!(
            "--calibration {}: an IMU calibration file (`limbfuse calibrate`), not the recording \
             of quiet standing and rotations --procedure static-rotation reads: give it as \
             --imu-calibration",
            path.display()
        );
    }
    Ok(())
}

/// Whether the file at `path` declares itself an IMU calibration
/// (`format = "limbfuse-imu-calibration/1"` within its first 4 KB).
fn is_imu_calibration_file(path: &std::path::Path) -> bool {
    use std::io::Read;
    let mut head = Vec::new();
    let read = std::fs::File::open(path).and_then(|f| f.take(4096).read_to_end(&mut head));
    read.is_ok()
        && String::from_utf8_lossy(&head).lines().any(|l| {
            let l = l.trim_start();
            l.starts_with("format")
                && l.contains(limbfuse_io::calibration::FORMAT.trim_end_matches(char::is_numeric))
        })
}

/// Per-sensor confidence: share of the gyro energy on the chosen axis,
/// second/largest horizontal gyro energy (axis ratio), hinge residual, sign
/// margin, weight of the gyro-only axis (docs/ALIGNMENT.md, "Confidence and
/// refusals").
fn confidence_table(a: &Alignment) -> String {
    let mut t = format!(
        "walking data: {} samples ({} turning, {} not walking left out)\n\
         sensor  axis_energy  axis_ratio  hinge_res_rad_s  sign_margin  gyro_only\n",
        a.walking_samples, a.turning_samples, a.not_walking_samples
    );
    for s in Segment::ALL {
        if let Some(x) = &a.per_segment[s.index()] {
            let opt = |v: Option<f64>| v.map_or("-".to_string(), |v| format!("{v:.3}"));
            t += &format!(
                "{:6}  {:11.3}  {:>10}  {:>15}  {:11.3}  {:9.2}\n",
                s.name(),
                x.axis_energy_fraction,
                opt(x.axis_ratio),
                opt(x.hinge_residual),
                x.sign_margin,
                x.gyro_only_weight
            );
        }
    }
    t
}

/// Readings the gate left out of the alignment (the CLI's warning and the
/// Python `LimbfuseWarning`).
pub fn left_out_message(gyro: u64, acc: u64, first_t: f64) -> String {
    format!(
        "{gyro} gyroscope and {acc} accelerometer readings out of the sensors' range or \
         implausible (first at t = {} s) left out of the alignment, as `estimate` leaves them \
         out (the written trial keeps them)",
        limbfuse_methods::shown(first_t)
    )
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
