//! `limbfuse align TRIAL -o ALIGNED`: sensor-to-segment rotations from walking data.

use anyhow::{bail, Context, Result};
use limbfuse_core::{Leg, Record, Segment};
use limbfuse_io::{TrialMeta, TrialReader, TrialWriter};
use limbfuse_signal::align::{apply_alignment, estimate_alignment, AlignOptions, Alignment};

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
    super::refuse_overwrites(
        &[
            ("", Some(&a.trial)),
            ("--calibration", a.calibration.as_deref()),
            ("--imu-calibration", a.imu_calibration.as_deref()),
        ],
        &[("-o", Some(&a.output))],
    )?;
    let reader = TrialReader::open(&a.trial)?;
    let mut meta = reader.meta().clone();
    let layout = *reader.layout();
    if !layout.gyr.iter().any(|&g| g) {
        bail!("{}: the trial has no gyroscope channels (`<segment>_gyr_x` ...), which alignment needs", a.trial.display());
    }
    let mut records: Vec<Record> = reader.collect::<Result<_, _>>()?;
    super::warn_input_units(&a.trial, &meta, &records);
    if let Some(path) = &a.imu_calibration {
        let (cal, frame) = super::calibrate::load_for_trial(path, &a.trial, &meta, &layout)?;
        records.iter_mut().for_each(|r| cal.apply(r));
        cal.annotate(&mut meta, &super::calibrate::file_name(path), frame);
    }
    // The axes come from the readings `estimate` would keep: an audit found
    // one 1e308 gyro cell made `align` blame the sensor's placement ("axis
    // undetermined"). The written trial keeps every reading.
    let mut gate = limbfuse_core::SampleGate::new(limbfuse_methods::gated::sensor_ranges(&meta)?);
    let screened: Vec<Record> = records
        .iter()
        .map(|r| Record {
            sample: gate.screen(&r.sample),
            ..*r
        })
        .collect();
    let rej = gate.rejections();
    if rej.gyro + rej.acc > 0 {
        eprintln!(
            "warning: {}: {} gyroscope and {} accelerometer readings out of the sensors' range or \
             implausible (first at t = {} s) left out of the alignment, as `estimate` leaves them \
             out (the written trial keeps them)",
            a.trial.display(),
            rej.gyro,
            rej.acc,
            rej.first_t.unwrap_or(f64::NAN)
        );
    }
    let alignment = estimate_alignment(&screened, &opts)
        .with_context(|| format!("aligning {}", a.trial.display()))?;
    alignment.annotate(&mut meta);
    let leg_line = leg_report(&mut meta, &alignment);
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

/// The detected leg against the trial's `# leg:` line; a detected leg that
/// differs replaces it (the declared one is kept as `leg_declared`).
fn leg_report(meta: &mut TrialMeta, a: &Alignment) -> String {
    let declared = meta.get("leg").map(str::to_string);
    let Some(d) = a.leg else {
        return "leg: not detected (no thigh or shank sensor aligned)".into();
    };
    let what = format!("score {:+.2}; right > 0, left < 0", d.score);
    match (d.leg, declared.as_deref().and_then(Leg::parse)) {
        (None, _) => format!(
            "leg: undetermined from the data ({what}); trial says {}",
            declared.as_deref().unwrap_or("nothing")
        ),
        (Some(l), Some(dl)) if l == dl => {
            format!("leg: {} (detected, {what}; as the trial says)", l.name())
        }
        (Some(l), _) => {
            let line = format!(
                "leg: {} (detected, {what}); the trial says {}: `leg` set to {}, the declared value kept as `leg_declared`",
                l.name(),
                declared.as_deref().unwrap_or("nothing"),
                l.name()
            );
            if let Some(dv) = declared {
                meta.set("leg_declared", dv);
                eprintln!("warning: {line}");
            }
            meta.set("leg", l.name());
            line
        }
    }
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
