//! `limbfuse calibrate POSES.csv -o cal.toml`, `limbfuse simulate
//! calibration`, and the `--calibration` of `import`, `align`, `estimate`
//! (docs/CALIBRATION.md).

use std::path::Path;

use anyhow::{Context, Result};
use limbfuse_core::Record;
use limbfuse_io::calibration::CalibrationModel;
use limbfuse_io::provenance::{COMMAND_KEY, LIMBFUSE_VERSION, VERSION_KEY};
use limbfuse_io::{Calibration, TrialLayout, TrialMeta, TrialReader};
use limbfuse_signal::calibration::trial_calibration::for_trial;
use limbfuse_signal::calibration::{calibrate, CalibrationParams};
use limbfuse_sim::{PoseRecordingConfig, WalkingConfig};
use limbfuse_workflows::simulated_trials;

use crate::cli_calibration::{CalibrateArgs, CalibrationSimArgs, ModelArg};

/// `calibrate`: fits every sensor of the pose recording, writes the file.
pub fn run(a: &CalibrateArgs) -> Result<()> {
    super::refuse_input_as_output(&a.poses, &a.output)?;
    let reader = TrialReader::open(&a.poses)?;
    let gravity = match a.gravity {
        Some(g) => g,
        None => reader
            .meta()
            .gravity()
            .map_err(|e| anyhow::anyhow!("{}: {e}", a.poses.display()))?,
    };
    let meta = reader.meta().clone();
    let mut reader = reader;
    let records: Vec<Record> = super::read_records(&mut reader)?;
    // (hashed as it was read, like an estimate's trial)
    let source_hash = reader.content_hash();
    // (accelerometers in g would be fitted a scale of 9.81: say why first)
    super::warn_input_units(&a.poses, &meta, &records)?;
    // The flags by their names (an audit: `--min-pose 0` was "calibration
    // setting `min_pose_s`", `--min-pose 1e9` "the sensor moves throughout").
    crate::bounds::positive("--min-pose", a.min_pose, "seconds")?;
    crate::bounds::positive("--acc-std-max", a.acc_std_max, "m/s^2")?;
    crate::bounds::positive("--gyro-std-max", a.gyro_std_max, "rad/s")?;
    if let (Some(first), Some(last)) = (records.first(), records.last()) {
        let span = last.sample.t - first.sample.t;
        if a.min_pose > span {
            anyhow::bail!(
                "--min-pose {}: longer than the recording {} ({span} s): no pose can last that long",
                limbfuse_methods::shown(a.min_pose),
                a.poses.display()
            );
        }
    }
    let params = CalibrationParams {
        model: match a.model {
            ModelArg::Full => CalibrationModel::Full,
            ModelArg::Scale => CalibrationModel::Scale,
            ModelArg::Bias => CalibrationModel::Bias,
        },
        gravity,
        acc_std_max: a.acc_std_max,
        gyro_std_max: a.gyro_std_max,
        min_pose_s: a.min_pose,
        ..CalibrationParams::default()
    };
    let mut cal = calibrate(&records, &params)
        .with_context(|| format!("calibrating from {}", a.poses.display()))?;
    cal.source = a
        .poses
        .file_name()
        .map(|n| n.to_string_lossy().into_owned());
    let provenance = [
        (VERSION_KEY, LIMBFUSE_VERSION.to_string()),
        (COMMAND_KEY, command_line(a, params.model)),
        ("fit_settings", params.settings()),
        (
            "source_hash",
            source_hash.map_or_else(|| "unknown".into(), |h| h.to_string()),
        ),
    ];
    super::write_file(&a.output, cal.to_toml_with_provenance(&provenance))?;
    for (seg, c) in limbfuse_core::Segment::ALL.iter().zip(&cal.sensors) {
        let Some(c) = c else { continue };
        let b = c.acc_bias * (1000.0 / gravity);
        let (poses, rms, rejected) = c.fit.as_ref().map_or((0, f64::NAN, &[][..]), |f| {
            (f.poses, f.residual_rms, f.rejected.as_slice())
        });
        println!(
            "{}: {poses} poses, residual {:.2} mg, acc bias [{:.2}, {:.2}, {:.2}] mg, scale [{:.4}, {:.4}, {:.4}]",
            seg.name(),
            rms * 1000.0 / gravity,
            b.x,
            b.y,
            b.z,
            c.acc_matrix[(0, 0)],
            c.acc_matrix[(1, 1)],
            c.acc_matrix[(2, 2)],
        );
        for r in rejected {
            eprintln!("warning: {}: pose rejected: {r}", seg.name());
        }
    }
    eprintln!(
        "calibrated {} ({} model) -> {}",
        cal.sensor_names(),
        params.model.name(),
        a.output.display()
    );
    Ok(())
}

/// The `# command:` line of a calibration file: every flag of the fit, the
/// defaults included, with file names only (as an estimate's `# command:`).
fn command_line(a: &CalibrateArgs, model: CalibrationModel) -> String {
    let mut c = format!("limbfuse calibrate --model {}", model.name());
    if let Some(g) = a.gravity {
        c += &format!(" --gravity {g}");
    }
    c + &format!(
        " --acc-std-max {} --gyro-std-max {} --min-pose {} {} -o {}",
        a.acc_std_max,
        a.gyro_std_max,
        a.min_pose,
        super::file_word(&a.poses),
        super::file_word(&a.output)
    )
}

/// `simulate calibration`.
pub fn simulate(a: &CalibrationSimArgs) -> Result<()> {
    let cfg = PoseRecordingConfig {
        sensors: WalkingConfig {
            seed: a.seed,
            imu_rate_hz: a.imu_rate,
            noise: !a.no_noise,
            ..WalkingConfig::default()
        },
        poses: a.poses,
        hold_s: a.hold,
        transition_s: a.transition,
        lever_arm_m: a.lever_arm,
        wobble_pose: a.wobble_pose.map(|k| k.wrapping_sub(1)),
    };
    if a.wobble_pose == Some(0) {
        anyhow::bail!("--wobble-pose: poses are numbered from 1, found 0");
    }
    // The flags that make the duration, each named (an audit: `--poses 0`
    // and `--hold nan` were reported as `--duration`, a flag this command
    // does not have).
    if !(1..=14).contains(&a.poses) {
        anyhow::bail!(
            "--poses {}: expected 1 to 14 (the six faces, then the eight corners)",
            a.poses
        );
    }
    crate::bounds::positive("--hold", a.hold, "seconds")?;
    crate::bounds::positive("--transition", a.transition, "seconds")?;
    if let Some(k) = a.wobble_pose.filter(|k| *k > a.poses) {
        anyhow::bail!(
            "--wobble-pose {k}: expected a pose from 1 to {} (--poses; numbered from 1)",
            a.poses
        );
    }
    crate::bounds::simulated_length(
        "the recording's length (--poses x (--hold + --transition), s)",
        cfg.duration_s(),
        "--imu-rate",
        a.imu_rate,
        a.cap.force,
    )?;
    let trial =
        simulated_trials::calibration_poses(cfg).map_err(super::simulate::simulation_error)?;
    let mut out = super::create_file(&a.output)?;
    let n = simulated_trials::write_trial(&mut out, trial, &a.output)?;
    super::commit(out)?;
    eprintln!(
        "simulated a calibration recording: {} poses, {:.0} s, {n} samples (seed {}: the sensors of `simulate walking --seed {}`) -> {}",
        a.poses,
        cfg.duration_s(),
        a.seed,
        a.seed,
        a.output.display()
    );
    Ok(())
}

/// Reads the calibration file `path` for the trial `trial` (its metadata
/// and layout) and prepares it for the trial
/// (`limbfuse_signal::calibration::trial_calibration`: refused for a trial
/// calibrated already or an IMU not covered; rotated with an alignment),
/// printing its notes. Returns the calibration to apply and the frame it
/// acts in (for the metadata).
pub fn load_for_trial(
    path: &Path,
    trial: &Path,
    meta: &TrialMeta,
    layout: &TrialLayout,
) -> Result<(Calibration, &'static str)> {
    let cal = Calibration::read(path)?;
    let prepared = for_trial(cal, path, trial, meta, layout)?;
    for note in &prepared.notes {
        eprintln!("note: {note}");
    }
    Ok((prepared.calibration, prepared.frame))
}

/// File name of `path` for the metadata.
pub fn file_name(path: &Path) -> String {
    path.file_name().map_or_else(
        || path.display().to_string(),
        |n| n.to_string_lossy().into_owned(),
    )
}
