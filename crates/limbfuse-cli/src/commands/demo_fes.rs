//! The paper 004 part of `limbfuse demo`: a simulated knee-FES trial (leg
//! extension, P2-R, 30 s) estimated by `sdre`, `ekf` and `rmx` (the thesis
//! estimators, as `estimate` runs them on a limbfuse trial), and `sdre+`:
//! `sdre` with the plant's muscle activation and the IMU biases as states
//! (ours, issue 16; `[states]` in a parameter file the demo writes beside
//! the trial), so that the table shows what the model gives once it
//! matches the simulated plant.

use std::fmt::Write as _;
use std::path::Path;

use anyhow::Result;
use limbfuse_eval::{AngleMetrics, EvalOptions};
use limbfuse_io::TrialReader;
use limbfuse_methods::{MethodFlags, MethodName, MethodSpec};
use limbfuse_sim::knee_fes::KneeFesConfig;
use limbfuse_workflows::simulated_trials;

/// Simulates the knee-FES trial into `out`, runs the three methods, prints
/// and returns the knee RMSE table, writes `report-knee-fes.html`.
pub fn run(out: &Path, seed: u64) -> Result<String> {
    let cfg = KneeFesConfig {
        subject: limbfuse_models::KneeSubject::P2R,
        seed,
        ..KneeFesConfig::default()
    };
    let sim = simulated_trials::knee_fes(&cfg, "limbfuse demo (knee-fes)")?;
    let trial = out.join("trial-knee-fes.csv");
    let mut file = super::create_file(&trial)?;
    simulated_trials::write_trial(&mut file, sim, &trial)?;
    super::commit(file)?;
    let mut table = format!("{:<10}", "RMSE deg");
    let mut row = format!("{:<10}", "knee");
    let mut estimates = Vec::new();
    let plant_file = out.join(PLANT_PARAMS);
    let mut file = super::create_file(&plant_file)?;
    std::io::Write::write_all(&mut file, PLANT_STATES.as_bytes())?;
    super::commit(file)?;
    let plant = MethodSpec::from_parts(
        MethodName::Sdre,
        Some((PLANT_STATES, &plant_file)),
        &MethodFlags::default(),
    )?;
    for (label, spec) in [
        ("sdre", MethodSpec::defaults(MethodName::Sdre)?),
        ("ekf", MethodSpec::defaults(MethodName::Ekf)?),
        ("rmx", MethodSpec::defaults(MethodName::Rmx)?),
        ("sdre+", plant),
    ] {
        let m = spec.method().name();
        let plant_run = label != m;
        let reader = TrialReader::open(&trial)?;
        let mut est = crate::methods::build_for(&spec, &reader)?;
        let stem = if plant_run { "sdre-plant" } else { m };
        let path = out.join(format!("estimate-knee-fes-{stem}.csv"));
        let mut metrics = AngleMetrics::new(m, EvalOptions::default());
        let params = if plant_run {
            format!(" --params {PLANT_PARAMS}")
        } else {
            String::new()
        };
        let command = format!(
            "limbfuse estimate --method {m}{params} trial-knee-fes.csv -o estimate-knee-fes-{stem}.csv"
        );
        super::estimate::run_to_file(
            est.as_mut(),
            reader,
            &path,
            m,
            &command,
            &mut [&mut metrics],
        )?;
        if !plant_run {
            // (the HTML report labels estimates by method: `sdre+` stays in the table)
            estimates.push(path);
        }
        let e = metrics.evaluation();
        super::warn_resets(m, e.resets.as_ref());
        let knee = e
            .rmse(limbfuse_core::sample::AngleChannel::Joint(
                limbfuse_core::Joint::Knee,
            ))
            .map_or("-".into(), |v| format!("{:.2}", v.to_degrees()));
        let _ = write!(table, "{label:>10}");
        let _ = write!(row, "{knee:>10}");
    }
    let text = format!(
        "knee-FES leg extension (paper 004), subject P2-R, 30 s, seed {seed}: {}\n{table}\n{row}\n\
         sdre, ekf: the thesis estimators (no muscle activation state; the simulated plant has one); \
         sdre+: sdre with the activation and the IMU biases as states (ours, --params {PLANT_PARAMS}; \
         docs/FES_ESTIMATION.md)\n",
        trial.display()
    );
    print!("\n{text}");
    super::demo::html_report(
        &trial,
        &estimates,
        &out.join("report-knee-fes.html"),
        "knee-FES trial",
    )?;
    Ok(text)
}

/// The parameter file of `sdre+`, written beside the trial.
const PLANT_PARAMS: &str = "sdre-plant.toml";

/// `sdre` with the simulated plant's activation and the IMU biases as
/// states (docs/FES_ESTIMATION.md, `[states]`).
const PLANT_STATES: &str = "method = \"sdre\"\n\
# sdre with the plant's muscle activation and the IMU biases as states (limbfuse demo)\n\
[states]\nactivation = true\ngyro_bias = true\nacc_bias = true\n";
