//! Paper 004 commands: `simulate knee-fes`, `simulate fixed-hip`, and the
//! trial-dependent construction of `sdre`, `ekf`, `rmx` for `estimate`.

use anyhow::{bail, Context, Result};
use limbfuse_io::{TrialLayout, TrialMeta, TrialWriter};
use limbfuse_models::KneeSubject;
use limbfuse_sim::fixed_hip::{simulate_fixed_hip, FixedHipConfig};
use limbfuse_sim::knee_fes::{simulate_knee_fes, FesTrial, KneeFesConfig};

use crate::cli::{FixedHipArgs, KneeFesArgs};

/// Columns the FES simulators write.
pub fn fes_layout(hip: bool) -> TrialLayout {
    let mut l = TrialLayout::default();
    for i in [1, 2] {
        l.acc[i] = true;
        l.gyr[i] = true;
        l.segment_ref[i] = true;
    }
    l.encoder[1] = true;
    l.joint_ref[1] = true;
    l.stim[0] = true;
    if hip {
        l.encoder[0] = true;
        l.joint_ref[0] = true;
        l.segment_ref[0] = true;
        l.stim = [true; 4];
        l.motor_torque = [true, true, false];
    }
    l
}

/// Writes a simulated FES trial.
pub fn write_trial(
    path: &std::path::Path,
    source: &str,
    rate: f64,
    tr: &FesTrial,
    hip: bool,
) -> Result<()> {
    let mut meta = TrialMeta::trial_v1();
    meta.set("source", source);
    meta.set("sample_rate_hz", rate);
    meta.set("leg", "right");
    for (k, v) in &tr.metadata {
        meta.set(k.clone(), v);
    }
    if let Some(g) = tr.metadata.iter().find(|(k, _)| k == "param.g") {
        meta.set("g", &g.1);
    }
    let out = super::create_file(path)?;
    let mut w = TrialWriter::new(out, &meta, fes_layout(hip))
        .with_context(|| format!("{}: cannot write", path.display()))?;
    for r in &tr.records {
        w.write(r)
            .with_context(|| format!("{}: cannot write", path.display()))?;
    }
    w.finish()
        .with_context(|| format!("{}: cannot write", path.display()))?;
    Ok(())
}

/// The knee-FES configuration of the flags.
pub fn knee_config(a: &KneeFesArgs) -> Result<KneeFesConfig> {
    let Some(subject) = KneeSubject::parse(&a.subject) else {
        bail!(
            "--subject {}: unknown leg; use P1-L, P1-R, P2-L, P2-R, P3-L, P3-R or 1-6",
            a.subject
        );
    };
    Ok(KneeFesConfig {
        subject,
        duration_s: a.duration,
        rate_hz: a.rate,
        seed: a.seed,
        noise: !a.no_noise,
        gyro_drift: a.gyro_drift.to_radians(),
        activation_dynamics: !a.no_activation_dynamics,
        mounting: match a.mounting {
            crate::cli::MountingArg::Aligned => limbfuse_sim::Mounting::Aligned,
            crate::cli::MountingArg::Random => limbfuse_sim::Mounting::Random,
        },
        ..KneeFesConfig::default()
    })
}

/// `simulate knee-fes`.
pub fn simulate_knee(a: &KneeFesArgs) -> Result<()> {
    let cfg = knee_config(a)?;
    let tr = simulate_knee_fes(&cfg).context("simulate knee-fes")?;
    write_trial(&a.output, "limbfuse simulate knee-fes", a.rate, &tr, false)?;
    if let Some(cal) = &a.calibration {
        let c =
            limbfuse_sim::knee_fes::simulate_calibration(&cfg).context("simulate calibration")?;
        write_calibration(cal, a.rate, &c)?;
        eprintln!(
            "calibration (quiet standing + 4 hip rotations) -> {}",
            cal.display()
        );
    }
    eprintln!(
        "simulated {:.0} s of FES leg extension, subject {} (seed {}) -> {}",
        a.duration,
        cfg.subject.label(),
        a.seed,
        a.output.display()
    );
    Ok(())
}

/// `simulate fixed-hip`.
pub fn simulate_hip(a: &FixedHipArgs) -> Result<()> {
    let cfg = FixedHipConfig {
        duration_s: a.duration,
        rate_hz: a.rate,
        seed: a.seed,
        noise: !a.no_noise,
        gyro_drift: a.gyro_drift.to_radians(),
        ..FixedHipConfig::default()
    };
    let tr = simulate_fixed_hip(&cfg).context("simulate fixed-hip")?;
    write_trial(&a.output, "limbfuse simulate fixed-hip", a.rate, &tr, true)?;
    eprintln!(
        "simulated {:.0} s of fixed-hip swing (seed {}) -> {}",
        a.duration,
        a.seed,
        a.output.display()
    );
    Ok(())
}

/// Writes a calibration recording (thigh and shank IMUs with references).
fn write_calibration(path: &std::path::Path, rate: f64, tr: &FesTrial) -> Result<()> {
    let mut meta = TrialMeta::trial_v1();
    meta.set("sample_rate_hz", rate);
    for (k, v) in &tr.metadata {
        meta.set(k.clone(), v);
    }
    let mut layout = fes_layout(false);
    layout.encoder = [false; 3];
    layout.stim = [false; 4];
    let out = super::create_file(path)?;
    let mut w = TrialWriter::new(out, &meta, layout)
        .with_context(|| format!("{}: cannot write", path.display()))?;
    for r in &tr.records {
        w.write(r)
            .with_context(|| format!("{}: cannot write", path.display()))?;
    }
    w.finish()
        .with_context(|| format!("{}: cannot write", path.display()))?;
    Ok(())
}
