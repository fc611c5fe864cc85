//! `limbfuse align --joint-axis TRIAL -o axes.toml`: the knee joint axis and
//! joint position in the raw thigh and shank sensor frames, identified by
//! paper 002's constrained EKF over the whole trial as one window.

use std::fmt::Write as _;

use anyhow::{bail, Context, Result};
use limbfuse_core::{Estimator, Record};
use limbfuse_estimators::knee_selfalign::{
    KneeDiag, KneeSelfAlign, KneeSelfAlignParams, WindowStatus,
};
use limbfuse_io::TrialReader;

use crate::cli::AlignArgs;

/// Longest trial identified as one window (samples).
const MAX_WINDOW: usize = 100_000;

/// Identifies and writes the joint geometry.
pub fn run(a: &AlignArgs) -> Result<()> {
    let mut reader = TrialReader::open(&a.trial)?;
    let layout = *reader.layout();
    for (s, name) in [(1usize, "thigh"), (2, "shank")] {
        if !layout.gyr[s] || !layout.acc[s] {
            bail!(
                "{}: --joint-axis needs the raw {name} accelerometer and gyroscope (`{name}_acc_x` ... `{name}_gyr_z`)",
                a.trial.display()
            );
        }
    }
    let records: Vec<Record> = super::read_records(&mut reader)?;
    let n = records.len();
    if !(20..=MAX_WINDOW).contains(&n) {
        bail!(
            "{}: --joint-axis identifies the whole trial as one window and needs 20 to {MAX_WINDOW} samples, found {n}",
            a.trial.display()
        );
    }
    let params = KneeSelfAlignParams {
        window: n,
        order: a.order,
        ..KneeSelfAlignParams::default()
    };
    let mut est = KneeSelfAlign::new(params).map_err(|e| anyhow::anyhow!("--order: {e}"))?;
    let mut last = None;
    for r in &records {
        last = Some(
            est.step(&r.sample)
                .with_context(|| format!("{}", a.trial.display()))?,
        );
    }
    let Some(last) = last else {
        bail!("{}: no samples", a.trial.display());
    };
    let diag = |key: KneeDiag| last.diagnostic(key);
    let Some(g) = est.geometry_or_deferred() else {
        let why = match est.last_window().0 {
            WindowStatus::Unobservable => format!(
                "the motion does not determine the axes (information {:.2e} < {:.0e} (rad/s)^2): record some walking or knee flexion",
                diag(KneeDiag::Information).unwrap_or(0.0),
                params.min_information
            ),
            WindowStatus::TooFewSamples => format!(
                "too few samples with both IMUs complete and unsaturated ({})",
                diag(KneeDiag::WindowUsable).unwrap_or(0.0)
            ),
            _ => "the parameter EKF failed numerically".into(),
        };
        bail!("{}: no joint axis identified: {why}", a.trial.display());
    };
    let v = |x: [f64; 3]| format!("[{:.6}, {:.6}, {:.6}]", x[0], x[1], x[2]);
    let mut s = String::new();
    writeln!(s, "# limbfuse align --joint-axis (paper 002, constrained EKF, order {}, one window of {n} samples)", a.order)?;
    writeln!(s, "# trial = {:?}", a.trial.display().to_string())?;
    writeln!(s, "# axes: unit vectors in the raw sensor frames, both pointing to the same side, flexion positive")?;
    writeln!(
        s,
        "# positions: sensor relative to the knee centre, sensor frames (m)"
    )?;
    writeln!(
        s,
        "# relative accelerometer scale (thigh / shank) in eqs 3 and 7: {:.4} (1: not identified)",
        g.acc_scale
    )?;
    writeln!(s, "thigh_axis = {}", v(g.axis[0].into()))?;
    writeln!(s, "shank_axis = {}", v(g.axis[1].into()))?;
    writeln!(s, "thigh_position_m = {}", v(g.position[0].into()))?;
    writeln!(s, "shank_position_m = {}", v(g.position[1].into()))?;
    writeln!(
        s,
        "rms_e_j_rad_s = {:.6}",
        diag(KneeDiag::RmsEJ).unwrap_or(f64::NAN)
    )?;
    writeln!(
        s,
        "rms_e_o_m_s2 = {:.6}",
        diag(KneeDiag::RmsEO).unwrap_or(f64::NAN)
    )?;
    writeln!(
        s,
        "information = {:.6}",
        diag(KneeDiag::Information).unwrap_or(f64::NAN)
    )?;
    super::write_file(&a.output, &s)?;
    print!(
        "{}",
        s.lines()
            .filter(|l| !l.starts_with('#'))
            .collect::<Vec<_>>()
            .join("\n")
    );
    println!();
    eprintln!("joint axis from {n} samples -> {}", a.output.display());
    Ok(())
}
