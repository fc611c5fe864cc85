//! `limbfuse demo`: simulate a walking trial, run every segment-angle
//! estimator on it and print the RMSE table; then the self-aligning knee
//! (paper 002), knee-FES (paper 004) and B-SLIP gait (paper 003) sections;
//! write `report.md` and the HTML reports (docs/REPORT.md).

use std::fmt::Write as _;
use std::path::{Path, PathBuf};

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
        leg: crate::cli::LegArg::Right,
        turn_every: None,
        turn_deg: 180.0,
        turn_s: 2.5,
        no_misalignment: false,
        gait_reference: false,
        cap: a.cap,
    };
    let summary = super::simulate::write_walking(&sim)?;
    println!("limbfuse demo: simulated {summary}");
    println!("trial: {}\n", trial_path.display());
    let mut evaluations = Vec::new();
    for method in MethodName::walking_demo() {
        evaluations.push(run_method(method, &trial_path, &a.out)?);
    }
    let table = rmse_table(&evaluations);
    print!("{table}");
    let estimates: Vec<_> = MethodName::walking_demo()
        .map(|m| a.out.join(format!("estimate-{}.csv", m.name())))
        .collect();
    let html = a.out.join("report.html");
    html_report(
        &trial_path,
        &estimates,
        &html,
        "walking trial and segment estimates",
    )?;
    let knee = super::knee_demo::run(a.seed, a.speed, &a.out)?;
    print!("\n{knee}");
    let fes = super::demo_fes::run(&a.out, a.seed)?;
    let gait = super::gait::demo(&a.out)?;
    let report = a.out.join("report.md");
    let mut markdown = report_markdown(a, &summary, &table);
    markdown.push_str(&format!(
        "\n## Self-aligning knee (paper 002)\n\n```\n{knee}```\n\
         \n## Knee-FES (paper 004)\n\n```\n{fes}```\n\
         \n## Gait phase and speed (paper 003)\n\n```\n{gait}```\n\
         \n## Files\n\n{FILES}"
    ));
    super::write_file(&report, markdown)?;
    println!("\nreport: {} (HTML: {})", report.display(), html.display());
    Ok(())
}

/// The files the demo writes, for report.md.
const FILES: &str = "\
- `trial.csv`: the simulated walking trial; `estimate-<method>.csv`: one per segment method.
- `report.html`: the walking trial against every segment estimate (plots, gait cycle, errors; docs/REPORT.md).
- `knee-selfalign.txt`: the self-aligning knee section above.
- `trial-knee-fes.csv`, `estimate-knee-fes-<method>.csv` (sdre, ekf, rmx; `sdre-plant` for sdre+, with its `sdre-plant.toml`), `report-knee-fes.html`.
- `bslip_trial.csv` (simulated B-SLIP walking, 0.7 m/s), `bslip_imm.csv` (the imm-bslip estimate), `report-bslip.html`.

Re-evaluate an estimate with `limbfuse evaluate TRIAL ESTIMATE` (e.g. `limbfuse evaluate trial.csv estimate-mjls.csv`,
`limbfuse evaluate bslip_trial.csv bslip_imm.csv`); redraw a report with `limbfuse report TRIAL ESTIMATE... -o FILE.html`.
";

/// Writes one of the demo's HTML reports and says so.
pub fn html_report(trial: &Path, estimates: &[PathBuf], out: &Path, what: &str) -> Result<()> {
    let command =
        super::report::command_line(trial, estimates, out, limbfuse_report::DEFAULT_BUCKETS);
    let input = limbfuse_report::ReportInput::new(trial, estimates, command);
    super::report::write(&input, out)?;
    println!("HTML report ({what}): {}", out.display());
    Ok(())
}

fn run_method(method: MethodName, trial: &Path, out: &Path) -> Result<Evaluation> {
    let name = method.name();
    let reader = TrialReader::open(trial)?;
    let mut est = methods::build_for(&MethodSpec::defaults(method)?, &reader)?;
    let est_path = out.join(format!("estimate-{name}.csv"));
    let mut metrics = AngleMetrics::new(name, EvalOptions::default());
    let command = format!("limbfuse estimate --method {name} trial.csv -o estimate-{name}.csv");
    super::estimate::run_to_file(
        est.as_mut(),
        reader,
        &est_path,
        name,
        &command,
        &mut [&mut metrics],
    )?;
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
         ## Segment angles (papers 000/001)\n\nTrial: {summary}\n\n\
         RMSE against the simulated truth (all samples; plots in `report.html`):\n\n```\n{table}```\n",
        a.seed, a.speed, a.duration
    )
}
