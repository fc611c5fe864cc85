//! `limbfuse import --format gaittoolbox|knee-rig INPUT -o trial.csv`.

use anyhow::{Context, Result};
use limbfuse_core::Side;
use limbfuse_io::import::{import_gaittoolbox_with, import_knee_rig, GaittoolboxOptions};
use limbfuse_io::TrialWriter;

use crate::cli::{ImportArgs, ImportFormat, LegArg};

/// Converts a recording into a trial file.
pub fn run(a: &ImportArgs) -> Result<()> {
    super::refuse_overwrites(
        &[
            ("", Some(&a.input)),
            ("--calibration", a.calibration.as_deref()),
        ],
        &[("-o", Some(&a.output))],
    )?;
    let leg = a.leg.map(|l| match l {
        LegArg::Left => Side::Left,
        LegArg::Right => Side::Right,
    });
    let mut trial = match a.format {
        ImportFormat::Gaittoolbox => {
            let opts = GaittoolboxOptions {
                leg,
                ..GaittoolboxOptions::default()
            };
            import_gaittoolbox_with(&a.input, &opts)?
        }
        ImportFormat::KneeRig => {
            if a.leg.is_some() {
                anyhow::bail!(
                    "--leg applies to --format gaittoolbox only (a knee-rig log has one knee)"
                );
            }
            import_knee_rig(&a.input)?
        }
    };
    if let Some(path) = &a.calibration {
        let (cal, frame) =
            super::calibrate::load_for_trial(path, &a.input, &trial.meta, &trial.layout)?;
        for r in trial.records.iter_mut() {
            cal.apply(r);
        }
        cal.annotate(&mut trial.meta, &super::calibrate::file_name(path), frame);
    }
    let mut out = super::create_file(&a.output)?;
    let mut w = TrialWriter::for_path(&a.output, &mut out, &trial.meta, trial.layout)
        .with_context(|| format!("{}: cannot write", a.output.display()))?;
    for r in &trial.records {
        w.write(r)
            .with_context(|| format!("{}: cannot write", a.output.display()))?;
    }
    w.finish()
        .with_context(|| format!("{}: cannot write", a.output.display()))?;
    super::commit(out)?;
    eprintln!(
        "imported {} samples -> {}",
        trial.records.len(),
        a.output.display()
    );
    Ok(())
}
