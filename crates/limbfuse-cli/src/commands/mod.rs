//! One module per subcommand.

mod align;
mod align_joint_axis;
mod align_static;
mod calibrate;
mod demo;
mod demo_fes;
mod estimate;
mod evaluate;
mod fes;
mod gait;
mod import;
mod inspect;
mod knee_demo;
mod method_list;
mod mirror;
mod montecarlo;
mod output_paths;
mod protocol;
mod repair_time;
mod report;
mod resample;
mod shell_word;
mod simulate;
mod simulate_knee;
mod tune;
mod tune_fes;

use std::path::Path;

use anyhow::{Context, Result};
use limbfuse_core::Record;
use limbfuse_io::AtomicFile;

use crate::cli::{Cli, Command, GaitLibraryCommand, SimulateCommand};
pub use output_paths::{refuse_input_as_output, refuse_missing_folder, refuse_overwrites};
pub use shell_word::{file_word, shell_word};

/// Runs the parsed command.
pub fn run(cli: Cli) -> Result<()> {
    crate::progress::set_quiet(cli.quiet);
    match cli.command {
        Command::Demo(a) => demo::run(&a),
        Command::Simulate(SimulateCommand::Walking(a)) => simulate::walking(&a),
        Command::Simulate(SimulateCommand::Knee(a)) => simulate_knee::run(&a),
        Command::Simulate(SimulateCommand::KneeFes(a)) => fes::simulate_knee(&a),
        Command::Simulate(SimulateCommand::FixedHip(a)) => fes::simulate_hip(&a),
        Command::Simulate(SimulateCommand::Bslip(a)) => gait::simulate(&a),
        Command::Simulate(SimulateCommand::Calibration(a)) => calibrate::simulate(&a),
        Command::Calibrate(a) => calibrate::run(&a),
        Command::GaitLibrary(GaitLibraryCommand::Build(a)) => gait::library_build(&a),
        Command::Import(a) => import::run(&a),
        Command::Estimate(a) => estimate::run(&a),
        Command::Evaluate(a) => evaluate::run(&a),
        Command::Inspect(a) => inspect::run(&a),
        Command::Report(a) => report::run(&a),
        Command::Montecarlo(a) => montecarlo::run(&a),
        Command::Align(a) => align::run(&a),
        Command::Mirror(a) => mirror::run(&a),
        Command::Resample(a) => resample::run(&a),
        Command::RepairTime(a) => repair_time::run(&a),
        Command::Tune(a) => tune::run(&a),
        Command::Methods => method_list::list(),
        Command::Params(a) => method_list::params(&a),
    }
}

/// Warns on stderr when a trial read whole has a time column or IMU
/// readings that do not look like SPEC units (`limbfuse_eval::
/// sample_interval`, `limbfuse_eval::sensor_units`), as `estimate` does
/// while it streams.
///
/// A `# sample_rate_hz:` that is not a positive number is an error naming
/// the file and the line.
pub fn warn_input_units(
    trial: &Path,
    meta: &limbfuse_io::TrialMeta,
    records: &[Record],
) -> anyhow::Result<()> {
    use limbfuse_core::runner::Observer;
    let mut intervals = limbfuse_eval::SampleIntervalWatch::checked_for_trial(meta)
        .map_err(|e| anyhow::anyhow!("{}: {e}", trial.display()))?;
    let mut units = limbfuse_eval::SensorUnitsWatch::default();
    let none = limbfuse_core::Estimate::empty(0.0);
    for r in records {
        // (the watches never fail)
        let _ = intervals.observe(r, &none);
        let _ = units.observe(r, &none);
    }
    warn_units(trial, &intervals, &units);
    Ok(())
}

/// Reads every record of `reader` (a command that reads a trial whole) and
/// says on stderr when its last line was left out, cut off mid-line
/// (`limbfuse_io::table::CutLine`, docs/ROBUST_INPUT.md 2o), as `estimate`
/// and `inspect` do.
pub fn read_records(reader: &mut limbfuse_io::TrialReader) -> Result<Vec<Record>> {
    let records = reader.by_ref().collect::<Result<Vec<_>, _>>()?;
    if let Some(cut) = reader.cut_last_line() {
        eprintln!("warning: {}", cut.message(reader.path()));
    }
    Ok(records)
}

/// Prints the unit checks' warnings (`limbfuse_eval::unit_warnings`) for
/// `trial` on stderr: one printer for `estimate` (streaming) and the
/// commands that read a trial whole.
pub fn warn_units(
    trial: &Path,
    intervals: &limbfuse_eval::SampleIntervalWatch,
    units: &limbfuse_eval::SensorUnitsWatch,
) {
    for w in limbfuse_eval::unit_warnings(intervals, units) {
        eprintln!("warning: {}: {w}", trial.display());
    }
}

/// Starts writing the output file `path` ([`AtomicFile`]: it appears only
/// when [`commit`] succeeds; on any error before, nothing is left behind).
pub fn create_file(path: &Path) -> Result<AtomicFile> {
    refuse_stdout(path)?;
    // (before the temporary file's name can appear in the message)
    refuse_missing_folder("", path)?;
    AtomicFile::create(path)
        .with_context(|| format!("{}: cannot create the output file", path.display()))
}

/// `-` names standard output only where a command streams to it
/// (`estimate -o -`, `params -o -`); elsewhere it would silently create a
/// file named `-`, so it is refused.
pub fn refuse_stdout(path: &Path) -> Result<()> {
    if crate::stdio::is_stdio(path) {
        anyhow::bail!(
            "output `-`: this command writes a file, not standard output (`-` is standard output for \
             `limbfuse estimate` and `limbfuse params` only); give a file name"
        );
    }
    Ok(())
}

/// Finishes an output file from [`create_file`]: renames it into place.
pub fn commit(file: AtomicFile) -> Result<()> {
    let path = file.path().to_path_buf();
    file.commit()
        .with_context(|| format!("{}: cannot write the output file", path.display()))
}

/// Writes a whole output file atomically (the CLI's `std::fs::write`).
pub fn write_file(path: &Path, contents: impl AsRef<[u8]>) -> Result<()> {
    refuse_stdout(path)?;
    AtomicFile::write(path, contents)
        .with_context(|| format!("{}: cannot write the output file", path.display()))
}

/// Prints the restart warning of issue 16 to stderr (the exit status stays
/// 0): `what` names the estimate (file or method).
pub fn warn_resets(what: &str, resets: Option<&limbfuse_eval::Resets>) {
    if let Some(r) = resets {
        eprintln!("warning: {what}: {r}");
    }
}

/// Refuses an input that `command` opens more than once when it is not a
/// regular file (a FIFO, a device, `/dev/stdin`): its second open would
/// wait forever for a writer, or read nothing (an audit: `evaluate FIFO
/// e.csv` hung, `report w.csv FIFO` blamed the FIFO's header). A path that
/// cannot be inspected is left to the reader's own error.
pub fn refuse_read_twice_from_a_stream(command: &str, paths: &[&Path]) -> Result<()> {
    for path in paths {
        if std::fs::metadata(path).is_ok_and(|m| !m.is_file()) {
            anyhow::bail!(
                "{}: a pipe or other non-regular file: `{command}` reads its inputs twice; \
                 write it to a file first",
                path.display()
            );
        }
    }
    Ok(())
}
