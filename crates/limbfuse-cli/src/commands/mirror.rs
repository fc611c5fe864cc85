//! `limbfuse mirror TRIAL -o OTHER_LEG [--remount-seed N]`: the recording as
//! the mirror-image leg's sensors read it (docs/ALIGNMENT.md, "Both legs").

use anyhow::{Context, Result};
use limbfuse_core::{Leg, Record};
use limbfuse_io::{TrialReader, TrialWriter};
use limbfuse_signal::align::mirror::{
    mirror_record_in, remount_rotations_both_legs, world_reflection,
};
use limbfuse_signal::align::mirror_truth::mirror_truth_lines;
use limbfuse_signal::recording_variants::remount_both_legs;

use crate::cli::MirrorArgs;

/// Reads the trial, mirrors (and re-mounts) every sensor, writes the result.
pub fn run(a: &MirrorArgs) -> Result<()> {
    super::refuse_input_as_output(&a.trial, &a.output)?;
    let mut reader = TrialReader::open(&a.trial)?;
    let mut meta = reader.meta().clone();
    let mut layout = *reader.layout();
    let has_imu = |l: &limbfuse_io::TrialLayout| {
        (0..4).any(|i| l.acc[i] || l.gyr[i] || l.quat[i] || l.other_acc[i] || l.other_gyr[i])
    };
    if !has_imu(&layout) {
        anyhow::bail!(
            "{}: no IMU channel to mirror (`mirror` turns the accelerometer, gyroscope and \
             orientation columns into the other leg's; this trial has none)",
            a.trial.display()
        );
    }
    let records: Vec<Record> = super::read_records(&mut reader)?;
    let declared = meta.get("leg").map(str::to_string);
    let leg = match declared.as_deref().map(Leg::parse) {
        None => Leg::Right,
        Some(Some(l)) => l,
        Some(None) => anyhow::bail!(
            "{}: metadata `leg`: expected right or left, found `{}`",
            a.trial.display(),
            declared.unwrap_or_default()
        ),
    };
    let other = match leg {
        Leg::Right => Leg::Left,
        Leg::Left => Leg::Right,
    };
    meta.set("leg", other.name());
    // Two-leg recordings: the other leg's columns are named after the
    // recorded leg now (`foot_right_...` on a mirrored right-leg trial).
    layout.leg = other;
    let two_legs = (0..4).any(|i| layout.other_acc[i] || layout.other_gyr[i]);
    let world = world_reflection(&records);
    meta.set(
        "mirrored",
        format!(
            "from {} ({} leg): sensors mirrored across the sagittal plane (acc (x, y, -z), gyro (-x, -y, z), {}; two legs: both mirrored, contact references swapped){}{}",
            a.trial.display(),
            leg.name(),
            world.formula(),
            a.remount_seed
                .map_or(String::new(), |s| format!(", re-mounted at random (seed {s})")),
            if two_legs {
                format!(
                    "; the columns without a leg suffix are now the {} leg's, the `_{}_` ones the \
                     {} leg's (description lines above this one describe the recording before \
                     mirroring)",
                    other.name(),
                    leg.name(),
                    leg.name()
                )
            } else {
                String::new()
            }
        ),
    );
    // A two-leg recording's own description of its columns no longer holds.
    if let Some(legs) = meta.get("legs").map(str::to_string) {
        meta.set("legs", format!("(before `limbfuse mirror`) {legs}"));
    }
    if let Some(seed) = a.remount_seed {
        meta.set(
            "imu_frame",
            "raw sensor frames (re-mounted at random by limbfuse mirror)",
        );
        if meta.get("mounting").is_some() {
            meta.set(
                "mounting",
                format!("random (re-mounted by limbfuse mirror, seed {seed})"),
            );
        }
    }
    let remount = a.remount_seed.map(remount_rotations_both_legs);
    // The simulator's truth of each sensor (mounting, biases, positions)
    // follows the readings (an audit: copied unchanged, it no longer
    // described them).
    let dropped = mirror_truth_lines(&mut meta, remount.as_ref().map(|(own, _)| own));
    if !dropped.is_empty() {
        eprintln!(
            "warning: {}: left out metadata lines that could not be mirrored: {}",
            a.trial.display(),
            dropped.join(", ")
        );
    }
    let mut out = super::create_file(&a.output)?;
    let mut w = TrialWriter::for_path(&a.output, &mut out, &meta, layout)
        .with_context(|| format!("{}: cannot write", a.output.display()))?;
    for r in &records {
        let m = mirror_record_in(r, world);
        let m = match &remount {
            Some((own, other)) => remount_both_legs(&m, own, other),
            None => m,
        };
        w.write(&m)
            .with_context(|| format!("{}: cannot write", a.output.display()))?;
    }
    w.finish()
        .with_context(|| format!("{}: cannot write", a.output.display()))?;
    super::commit(out)?;
    eprintln!(
        "mirrored {} samples ({} leg -> {} leg) -> {}",
        records.len(),
        leg.name(),
        other.name(),
        a.output.display()
    );
    Ok(())
}
