//! The paper 004 part of `limbfuse demo`: a simulated knee-FES trial (leg
//! extension, P2-R, 30 s) estimated by `sdre`, `ekf` and `rmx`.

use std::fmt::Write as _;
use std::path::Path;

use anyhow::Result;
use limbfuse_eval::{AngleMetrics, EvalOptions};
use limbfuse_io::TrialReader;
use limbfuse_methods::{MethodName, MethodSpec};
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
    for method in [MethodName::Sdre, MethodName::Ekf, MethodName::Rmx] {
        let m = method.name();
        let reader = TrialReader::open(&trial)?;
        let mut est = crate::methods::build_for(&MethodSpec::defaults(method)?, &reader)?;
        let path = out.join(format!("estimate-knee-fes-{m}.csv"));
        let mut metrics = AngleMetrics::new(m, EvalOptions::default());
        let command = format!(
            "limbfuse estimate --method {m} trial-knee-fes.csv -o estimate-knee-fes-{m}.csv"
        );
        super::estimate::run_to_file(
            est.as_mut(),
            reader,
            &path,
            m,
            &command,
            &mut [&mut metrics],
        )?;
        estimates.push(path);
        let e = metrics.evaluation();
        super::warn_resets(m, e.resets.as_ref());
        let knee = e
            .rmse(limbfuse_core::sample::AngleChannel::Joint(
                limbfuse_core::Joint::Knee,
            ))
            .map_or("-".into(), |v| format!("{:.2}", v.to_degrees()));
        let _ = write!(table, "{m:>10}");
        let _ = write!(row, "{knee:>10}");
    }
    let text = format!(
        "knee-FES leg extension (paper 004), subject P2-R, 30 s, seed {seed}: {}\n{table}\n{row}\n",
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
