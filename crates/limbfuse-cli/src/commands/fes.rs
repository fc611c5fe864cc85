//! Paper 004 commands: `simulate knee-fes`, `simulate fixed-hip`, and the
//! trial-dependent construction of `sdre`, `ekf`, `rmx` for `estimate`.

use anyhow::{bail, Result};
use limbfuse_workflows::simulator_options::{activation_t_a_s, gyro_drift_rad_s};

use super::simulate::option_error;
use limbfuse_models::KneeSubject;
use limbfuse_sim::fixed_hip::FixedHipConfig;
use limbfuse_sim::knee_fes::KneeFesConfig;
use limbfuse_workflows::simulated_trials;

use crate::cli::{FixedHipArgs, KneeFesArgs};

/// The knee-FES configuration of the flags.
pub fn knee_config(a: &KneeFesArgs) -> Result<KneeFesConfig> {
    let gyro_drift = gyro_drift_rad_s(a.gyro_drift).map_err(option_error)?;
    let Some(subject) = KneeSubject::parse(&a.subject) else {
        bail!(
            "--subject {}: unknown leg; use P1-L, P1-R, P2-L, P2-R, P3-L, P3-R or 1-6",
            a.subject
        );
    };
    Ok(KneeFesConfig {
        subject,
        duration_s: a.duration,
        rate_hz: a.imu_rate,
        seed: a.seed,
        noise: !a.no_noise,
        gyro_drift,
        activation_dynamics: !a.no_activation_dynamics,
        cycles: a.cycles,
        mounting: match a.mounting {
            crate::cli::MountingArg::Aligned => limbfuse_sim::Mounting::Aligned,
            crate::cli::MountingArg::Random => limbfuse_sim::Mounting::Random,
        },
        ..KneeFesConfig::default()
    })
}

/// `simulate knee-fes`.
pub fn simulate_knee(a: &KneeFesArgs) -> Result<()> {
    super::refuse_overwrites(
        &[],
        &[
            ("-o", Some(&a.output)),
            ("--calibration", a.calibration.as_deref()),
        ],
    )?;
    crate::bounds::simulated_trial(a.duration, "--imu-rate", a.imu_rate, a.cap.force)?;
    let cfg = knee_config(a)?;
    let trial = simulated_trials::knee_fes(&cfg, "limbfuse simulate knee-fes")
        .map_err(super::simulate::simulation_error)?;
    let mut out = super::create_file(&a.output)?;
    simulated_trials::write_trial(&mut out, trial, &a.output)?;
    super::commit(out)?;
    if let Some(cal) = &a.calibration {
        let c = simulated_trials::knee_fes_calibration(&cfg)
            .map_err(super::simulate::simulation_error)?;
        let mut out = super::create_file(cal)?;
        simulated_trials::write_trial(&mut out, c, cal)?;
        super::commit(out)?;
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
    if let Some(note) = simulated_trials::knee_fes_rest_note(&cfg, "--cycles") {
        eprintln!("note: {note}");
    }
    Ok(())
}

/// `simulate fixed-hip`.
pub fn simulate_hip(a: &FixedHipArgs) -> Result<()> {
    crate::bounds::simulated_trial(a.duration, "--imu-rate", a.imu_rate, a.cap.force)?;
    let gyro_drift = gyro_drift_rad_s(a.gyro_drift).map_err(option_error)?;
    let activation_t_a = a
        .activation_t_a
        .map(activation_t_a_s)
        .transpose()
        .map_err(option_error)?;
    let cfg = FixedHipConfig {
        duration_s: a.duration,
        rate_hz: a.imu_rate,
        seed: a.seed,
        noise: !a.no_noise,
        gyro_drift,
        activation_t_a,
        ..FixedHipConfig::default()
    };
    let trial = simulated_trials::fixed_hip(&cfg).map_err(super::simulate::simulation_error)?;
    let mut out = super::create_file(&a.output)?;
    simulated_trials::write_trial(&mut out, trial, &a.output)?;
    super::commit(out)?;
    eprintln!(
        "simulated {:.0} s of fixed-hip swing (seed {}) -> {}",
        a.duration,
        a.seed,
        a.output.display()
    );
    Ok(())
}
