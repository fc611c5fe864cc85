//! Figures of the paper 004 studies (default tunings): knee traces of one
//! leg-extension trial (like Fig. 12) and the fixed-hip estimation errors
//! (like Fig. 18). Writes `docs/figures/fes-knee-trial.svg` and
//! `docs/figures/fes-fixed-hip-errors.svg`.
//! `cargo run --release -p limbfuse-studies --example fes_figures`

use std::path::Path;

use clap::Parser;

use limbfuse_core::Estimator;
use limbfuse_estimators::fes::{FixedHipFilter, KneeFesFilter, RotationMatrixKnee};
use limbfuse_models::{FixedHipModel, FixedHipParams, KneeFesModel, KneeFesParams, KneeSubject};
use limbfuse_sim::fixed_hip::{simulate_fixed_hip, FixedHipConfig};
use limbfuse_sim::knee_fes::{simulate_knee_fes, KneeFesConfig};
use limbfuse_studies::fes_plot::write_traces_svg;

fn main() -> Result<(), String> {
    limbfuse_studies::example_args::NoArgs::parse();
    let subject = KneeSubject::P2R;
    let recs = simulate_knee_fes(&KneeFesConfig {
        subject,
        seed: 41,
        ..KneeFesConfig::default()
    })
    .map_err(|e| e.to_string())?
    .records;
    let m = KneeFesModel::new(KneeFesParams::subject(subject)).map_err(|e| e.to_string())?;
    let mut ests: Vec<(&str, Box<dyn Estimator>)> = vec![
        ("SDRE", Box::new(KneeFesFilter::sdre(m))),
        ("EKF", Box::new(KneeFesFilter::ekf(m))),
        ("RMX", Box::new(RotationMatrixKnee::new())),
    ];
    let mut series = vec![(
        "truth",
        recs.iter()
            .map(|r| (r.sample.t, r.reference.joint[1].unwrap_or(0.0).to_degrees()))
            .collect::<Vec<_>>(),
    )];
    for (name, e) in ests.iter_mut() {
        let pts = recs
            .iter()
            .filter_map(|r| {
                let est = e.step(&r.sample).ok()?;
                Some((r.sample.t, est.joint[1]?.to_degrees()))
            })
            .collect();
        series.push((name, pts));
    }
    write_traces_svg(
        Path::new("docs/figures/fes-knee-trial.svg"),
        "Knee angle, simulated FES leg extension (P2-R, trial 1)",
        "knee (deg)",
        &series,
    )?;
    let recs = simulate_fixed_hip(&FixedHipConfig::default())
        .map_err(|e| e.to_string())?
        .records;
    let hm = FixedHipModel::new(FixedHipParams::default()).map_err(|e| e.to_string())?;
    let mut series = Vec::new();
    for (name, mut e) in [
        ("SDRE", FixedHipFilter::sdre(hm)),
        ("EKF", FixedHipFilter::ekf(hm)),
    ] {
        let mut hip = Vec::new();
        let mut knee = Vec::new();
        for r in &recs {
            let est = e.step(&r.sample).map_err(|e| e.to_string())?;
            let t = r.sample.t;
            if let (Some(a), Some(b)) = (est.joint[0], r.reference.joint[0]) {
                hip.push((t, (a - b).to_degrees()));
            }
            if let (Some(a), Some(b)) = (est.joint[1], r.reference.joint[1]) {
                knee.push((t, (a - b).to_degrees()));
            }
        }
        series.push((
            if name == "SDRE" {
                "SDRE hip"
            } else {
                "EKF hip"
            },
            hip,
        ));
        series.push((
            if name == "SDRE" {
                "SDRE knee"
            } else {
                "EKF knee"
            },
            knee,
        ));
    }
    write_traces_svg(
        Path::new("docs/figures/fes-fixed-hip-errors.svg"),
        "Fixed-hip estimation error (seed 1, default tunings)",
        "error (deg)",
        &series,
    )?;
    println!("wrote docs/figures/fes-knee-trial.svg and docs/figures/fes-fixed-hip-errors.svg");
    Ok(())
}
