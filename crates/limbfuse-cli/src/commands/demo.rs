//! `limbfuse demo`: simulate a walking trial, run every segment-angle
//! estimator on it, print the RMSE table and write a report.

use std::fmt::Write as _;
use std::path::Path;

use anyhow::{Context, Result};
use limbfuse_core::sample::AngleChannel;
use limbfuse_eval::{AngleMetrics, EvalOptions, Evaluation};
use limbfuse_io::TrialReader;
use limbfuse_methods::{MethodName, MethodSpec};

use crate::cli::{DemoArgs, MountingArg, WalkingArgs};
use crate::methods;

/// Runs the demo.
pub fn run(a: &DemoArgs) -> Result<()> {
    crate::bounds::simulated_trial(a.duration, "the IMU rate", 100.0, a.cap.force)?;
    std::fs::create_dir_all(&a.out)
        .with_context(|| format!("{}: cannot create the demo directory", a.out.display()))?;
    let trial_path = a.out.join("trial.csv");
    let sim = WalkingArgs {
        output: trial_path.clone(),
        speed: a.speed,
        duration: a.duration,
        imu_rate: 100.0,
        seed: a.seed,
        mounting: MountingArg::Aligned,
        no_noise: false,
        no_out_of_plane: false,
        no_variability: false,
        no_misalignment: false,
        cap: a.cap,
    };
    let summary = super::simulate::write_walking(&sim)?;
    println!("limbfuse demo: simulated {summary}");
    println!("trial: {}\n", trial_path.display());
    let mut evaluations = Vec::new();
    for method in MethodName::walking_demo() {
        evaluations.push(run_method(method, &trial_path, &a.out)?);
    }
    let mut table = rmse_table(&evaluations);
    print!("{table}");
    let knee = super::knee_demo::run(a.seed, a.speed, &a.out)?;
    print!("\n{knee}");
    table.push_str(&super::demo_fes::run(&a.out, a.seed)?);
    super::gait::demo(&a.out)?;
    let report = a.out.join("report.md");
    let mut markdown = report_markdown(a, &summary, &table);
    markdown.push_str(&format!(
        "\n## Self-aligning knee (paper 002)\n\n```\n{knee}```\n"
    ));
    super::write_file(&report, markdown)?;
    println!("\nreport: {}", report.display());
    Ok(())
}

fn run_method(method: MethodName, trial: &Path, out: &Path) -> Result<Evaluation> {
    let name = method.name();
    let reader = TrialReader::open(trial)?;
    let mut est = methods::build_for(&MethodSpec::defaults(method)?, &reader)?;
    let est_path = out.join(format!("estimate-{name}.csv"));
    let mut metrics = AngleMetrics::new(name, EvalOptions::default());
    super::estimate::run_to_file(est.as_mut(), reader, &est_path, name, &mut [&mut metrics])?;
    Ok(metrics.evaluation())
}

/// RMSE (deg) per channel (rows) and method (columns).
pub fn rmse_table(evals: &[Evaluation]) -> String {
    let mut s = format!("{:<10}", "RMSE deg");
    for e in evals {
        let _ = write!(s, "{:>20}", e.method);
    }
    s.push('\n');
    for c in AngleChannel::ALL {
        let _ = write!(s, "{:<10}", c.name());
        for e in evals {
            let v = e
                .rmse(c)
                .map_or("-".into(), |v| format!("{:.2}", v.to_degrees()));
            let _ = write!(s, "{v:>20}");
        }
        s.push('\n');
    }
    let _ = write!(s, "{:<10}", "mean seg");
    for e in evals {
        let v = e
            .mean_rmse()
            .map_or("-".into(), |v| format!("{:.2}", v.to_degrees()));
        let _ = write!(s, "{v:>20}");
    }
    s.push('\n');
    s
}

fn report_markdown(a: &DemoArgs, summary: &str, table: &str) -> String {
    format!(
        "# limbfuse demo report\n\nCommand: `limbfuse demo --seed {} --speed {} --duration {}`\n\n\
         Trial: {summary}\n\nRMSE against the simulated truth (all samples):\n\n```\n{table}```\n\n\
         Files: `trial.csv` (simulated trial), `estimate-<method>.csv` (one per method).\n\
         Re-evaluate any of them with `limbfuse evaluate trial.csv estimate-<method>.csv`.\n",
        a.seed, a.speed, a.duration
    )
}
