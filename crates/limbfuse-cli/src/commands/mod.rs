//! One module per subcommand.

mod align;
mod align_joint_axis;
mod align_static;
mod demo;
mod demo_fes;
mod estimate;
mod evaluate;
mod fes;
mod gait;
mod import;
mod knee_demo;
mod method_list;
mod montecarlo;
mod protocol;
mod resample;
mod simulate;
mod simulate_knee;
mod tune;

use anyhow::Result;

use crate::cli::{Cli, Command, GaitLibraryCommand, SimulateCommand};

/// Runs the parsed command.
pub fn run(cli: Cli) -> Result<()> {
    match cli.command {
        Command::Demo(a) => demo::run(&a),
        Command::Simulate(SimulateCommand::Walking(a)) => simulate::walking(&a),
        Command::Simulate(SimulateCommand::Knee(a)) => simulate_knee::run(&a),
        Command::Simulate(SimulateCommand::KneeFes(a)) => fes::simulate_knee(&a),
        Command::Simulate(SimulateCommand::FixedHip(a)) => fes::simulate_hip(&a),
        Command::Simulate(SimulateCommand::Bslip(a)) => gait::simulate(&a),
        Command::GaitLibrary(GaitLibraryCommand::Build(a)) => gait::library_build(&a),
        Command::Import(a) => import::run(&a),
        Command::Estimate(a) => estimate::run(&a),
        Command::Evaluate(a) => evaluate::run(&a),
        Command::Montecarlo(a) => montecarlo::run(&a),
        Command::Align(a) => align::run(&a),
        Command::Resample(a) => resample::run(&a),
        Command::Tune(a) => tune::run(&a),
        Command::Methods => method_list::list(),
        Command::Params(a) => method_list::params(&a),
    }
}

/// Creates `path` for writing, naming it in the error.
pub fn create_file(path: &std::path::Path) -> Result<std::io::BufWriter<std::fs::File>> {
    use anyhow::Context;
    let f = std::fs::File::create(path)
        .with_context(|| format!("{}: cannot create the output file", path.display()))?;
    Ok(std::io::BufWriter::with_capacity(1 << 16, f))
}

/// Prints the restart warning of issue 16 to stderr (the exit status stays
/// 0): `what` names the estimate (file or method).
pub fn warn_resets(what: &str, resets: Option<&limbfuse_eval::Resets>) {
    if let Some(r) = resets {
        eprintln!("warning: {what}: {r}");
    }
}
