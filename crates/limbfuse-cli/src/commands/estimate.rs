//! `limbfuse estimate --method NAME TRIAL -o OUT`: flags -> method spec ->
//! estimator -> runner -> estimate file.

use std::path::Path;

use anyhow::{Context, Result};
use limbfuse_core::runner::{self, Observer, RecordSource};
use limbfuse_core::{Estimator, OfflineEstimator};
use limbfuse_eval::{
    AccRailWatch, ClippedSwingWatch, FixedThighWatch, GaitWatch, KneeWatch, RejectionWatch,
    ResetWatch, SampleIntervalWatch, SensorUnitsWatch, SpeedRangeWatch,
};
use limbfuse_io::{Calibration, DiagnosticColumns, EstimateWriter, TrialReader};

use limbfuse_methods::MethodSpec;
use limbfuse_workflows::imm_library_extension;

use crate::cli::EstimateArgs;
use crate::exit::Internal;
use crate::methods;
use crate::progress::Progress;
use crate::stdio::{self, FlushingStdin, SharedStdout};

/// The message of a run that found nothing: (trial, method, samples, what
/// became of the output).
/// Runs one estimator over a trial file, streaming; `-` as the trial reads
/// standard input, `-` as the output writes standard output as rows arrive
/// (docs/STREAMING.md). `imm-bslip --imm-config continuous` on a trial
/// walking outside its library's speeds runs twice: the first run's speeds
/// say which gaits are missing, the second runs over the extended family
/// (`limbfuse_workflows::imm_library_extension`; files only).
pub fn run(a: &EstimateArgs) -> Result<()> {
    super::refuse_overwrites(
        &[
            ("", Some(&a.trial)),
            ("--params", a.params.as_deref()),
            ("--library", a.library.as_deref()),
            ("--calibration", a.calibration.as_deref()),
        ],
        &[("-o", Some(&a.output))],
    )?;
    let spec = methods::resolve(&a.method, a.params.as_deref(), &methods::flags(a))?;
    let stdout = stdio::is_stdio(&a.output).then(SharedStdout::new);
    let reader = if stdio::is_stdio(&a.trial) {
        TrialReader::from_reader(
            Path::new(stdio::STDIN_LABEL),
            Box::new(FlushingStdin::new(stdout.clone())),
        )?
    } else {
        TrialReader::open(&a.trial)?
    }
    .with_late_rows(a.late_rows.rule());
    let est = methods::build_for(&spec, &reader)?;
    methods::report_body(&spec, &reader)?;
    let range = methods::library_speed_range(&spec, &reader)?;
    let (meta, layout) = (reader.meta().clone(), *reader.layout());
    let streamed = stdio::is_stdio(&a.trial) || stdout.is_some();
    let mut pass = estimate_pass(a, &spec, reader, est, stdout, range)?;
    if let Some(watch) = &pass.speed_range {
        if streamed {
            if imm_library_extension::wanted(&spec, watch).is_some() {
                eprintln!(
                    "{}: the library is extended to a trial's speeds only when the trial and the \
                     estimate are files (not `-`: a streamed trial or estimate cannot be run again)",
                    spec.method()
                );
            }
        } else if let Some(ext) = imm_library_extension::extend_for_trial(
            &spec,
            &meta,
            &layout,
            watch,
            &limbfuse_sim::bslip::search::SearchSettings::default(),
        )
        .with_context(|| a.trial.display().to_string())?
        {
            eprintln!("{}: {}", spec.method(), ext.message);
            if let Some(est) = ext.estimator {
                let reader = TrialReader::open(&a.trial)?.with_late_rows(a.late_rows.rule());
                pass = estimate_pass(a, &spec, reader, est, None, Some(ext.range))?;
            }
        }
    }
    pass.report.warn(spec.method().name());
    if let Some(w) = &pass.moving_thigh {
        eprintln!("warning: {w}");
    }
    if let Some(line) = &pass.verdict {
        eprintln!("{line}");
    }
    if let Some(note) = pass.speed_range.as_ref().and_then(SpeedRangeWatch::note) {
        eprintln!("{}: {note}", spec.method());
    }
    let written = if stdio::is_stdio(&a.output) {
        "standard output".to_string()
    } else {
        a.output.display().to_string()
    };
    eprintln!(
        "{}: {} samples -> {written}",
        spec.method(),
        pass.report.n_samples
    );
    Ok(())
}

/// What one run of `estimate` over the trial found.
struct Pass {
    report: RunReport,
    /// knee-selfalign's verdict line.
    verdict: Option<String>,
    speed_range: Option<SpeedRangeWatch>,
    /// knee-kinematic on a trial whose thigh moves: the warning.
    moving_thigh: Option<String>,
}

/// One run of `est` over the trial `reader` reads into the output file (or
/// standard output); `range`: the imm-bslip library's speeds, watched.
/// Errors (and removes the output) when a gait method found no gait or
/// knee-selfalign refused.
fn estimate_pass(
    a: &EstimateArgs,
    spec: &MethodSpec,
    mut reader: TrialReader,
    mut est: Box<dyn limbfuse_core::Estimator + Send>,
    stdout: Option<SharedStdout>,
    range: Option<(f64, f64)>,
) -> Result<Pass> {
    let mut smoothed = if a.smooth {
        Some(
            limbfuse_methods::smoothed_chain::build_smoothed(
                spec,
                reader.meta(),
                reader.layout(),
                Default::default(),
            )
            .with_context(|| reader.path().display().to_string())?,
        )
    } else {
        None
    };
    let mut backfilled = if a.backfill {
        Some(
            limbfuse_methods::knee_backfill::build_backfilled(spec, reader.meta(), reader.layout())
                .with_context(|| reader.path().display().to_string())?,
        )
    } else {
        None
    };
    let knee_window = methods::knee_window(spec, &reader)?;
    let diagnostics = match &a.diagnostics {
        Some(text) => DiagnosticColumns::parse(text)?,
        None => DiagnosticColumns::All,
    };
    // Checked before the run, so that a wrong name leaves no output behind.
    diagnostics.resolve(est.name(), est.diagnostic_names())?;
    // No estimator looks at the truth: its cells are not parsed.
    reader.skip_references();
    let calibration = match &a.calibration {
        Some(path) => Some(
            super::calibrate::load_for_trial(path, reader.path(), reader.meta(), reader.layout())?
                .0,
        ),
        None => None,
    };
    let outputs = est.outputs();
    // Gait methods (contacts, or a speed without a CoM model): a recording
    // in which they find no gait is an error, not an empty estimate.
    let gait_method = limbfuse_eval::gait_watch::is_gait_method(&outputs);
    let mut gait = GaitWatch::for_diagnostics(est.diagnostic_names());
    let mut any_output = limbfuse_eval::output_watch::AnyOutputWatch::default();
    let mut knee = KneeWatch::for_diagnostics(est.diagnostic_names());
    let mut speed_range = range.map(|(lo, hi)| SpeedRangeWatch::new(lo, hi));
    let mut thigh = spec
        .method()
        .info()
        .assumes_fixed_thigh
        .then(FixedThighWatch::default);
    let label = spec.method().name();
    let report = {
        let mut extra: Vec<&mut dyn Observer> = vec![&mut gait, &mut any_output];
        if let Some(w) = thigh.as_mut() {
            extra.push(w);
        }
        if let Some(k) = knee.as_mut() {
            extra.push(k);
        }
        if let Some(w) = speed_range.as_mut() {
            extra.push(w);
        }
        let engine = match (smoothed.as_mut(), backfilled.as_mut()) {
            (Some(s), _) => Engine::Offline(s),
            (None, Some(b)) => Engine::Offline(b),
            (None, None) => Engine::Online(est.as_mut()),
        };
        match stdout {
            Some(out) => run_to_stdout(
                engine,
                reader,
                out,
                label,
                &command_line(a),
                &mut extra,
                calibration.as_ref(),
                diagnostics,
            )?,
            None => run_to_file_calibrated(
                engine,
                reader,
                &a.output,
                label,
                &command_line(a),
                &mut extra,
                calibration.as_ref(),
                diagnostics,
            )?,
        }
    };
    let mut verdict = None;
    if let Some(k) = &knee {
        match k.verdict(knee_window) {
            Ok(line) => {
                let before = match backfilled.as_ref().map(|b| b.filled()) {
                    Some(Some((t0, t1))) => {
                        format!("; knee backfilled over {t0:.2}-{t1:.2} s (gyro angle)")
                    }
                    Some(None) => String::new(),
                    None => "; no knee angle before it (`--backfill` fills it offline)".into(),
                };
                verdict = Some(format!("{}: {line}{before}", spec.method()))
            }
            Err(why) => {
                report.warn(label);
                if !stdio::is_stdio(&a.output) {
                    let _ = std::fs::remove_file(&a.output);
                }
                anyhow::bail!(
                    "{}: `{}`: {why}; no estimate written",
                    a.trial.display(),
                    spec.method()
                );
            }
        }
    }
    // Nothing found: an error, and the output file removed (standard output
    // cannot be taken back).
    let nothing = (gait_method && !gait.found) || !any_output.found;
    if nothing {
        report.warn(label);
        let kept = if stdio::is_stdio(&a.output) {
            "the estimate written to standard output holds none"
        } else {
            let _ = std::fs::remove_file(&a.output);
            "no estimate written"
        };
        let (trial, name) = (a.trial.display().to_string(), spec.method().name());
        let mut why = if gait_method && !gait.found {
            gait.no_gait_message(&trial, name, report.n_samples, kept)
        } else {
            limbfuse_eval::output_watch::no_output_message(
                &trial,
                name,
                report.n_samples,
                any_output.span_s(),
                kept,
            )
        };
        // A parameter far from its default (`shoe_gamma = 1e12`) finds
        // nothing either: name the file that set them.
        if let Some(p) = &a.params {
            why += &format!(
                " (the method's settings came from --params {}; `limbfuse params {}` writes the defaults)",
                p.display(),
                spec.method().name()
            );
        }
        anyhow::bail!(why);
    }
    let moving_thigh = thigh
        .as_ref()
        .and_then(|w| w.warning(label, &report.trial.display().to_string()));
    Ok(Pass {
        report,
        verdict,
        speed_range,
        moving_thigh,
    })
}

/// The `# command:` line of an estimate file: the flags given, with file
/// names only (like `# trial:`, so that the same run in another directory
/// writes the same file).
fn command_line(a: &EstimateArgs) -> String {
    let name = super::file_word;
    let mut c = format!("limbfuse estimate --method {}", a.method);
    if let Some(p) = &a.params {
        c += &format!(" --params {}", name(p));
    }
    let opt = |c: &mut String, flag: &str, v: Option<String>| {
        if let Some(v) = v {
            *c += &format!(" --{flag} {v}");
        }
    };
    opt(&mut c, "window", a.window.map(|v| v.to_string()));
    opt(&mut c, "order", a.order.map(|v| v.to_string()));
    opt(&mut c, "library", a.library.as_deref().map(name));
    opt(&mut c, "kappa", a.kappa.map(|v| v.to_string()));
    opt(
        &mut c,
        "rescale-height",
        a.rescale_height.map(|v| v.to_string()),
    );
    opt(&mut c, "imm-weights", a.imm_weights.clone());
    opt(&mut c, "imm-touchdown", a.imm_touchdown.clone());
    opt(&mut c, "imm-config", a.imm_config.clone());
    opt(&mut c, "imm-extend-library", a.imm_extend_library.clone());
    opt(&mut c, "leg-length", a.leg_length.map(|v| v.to_string()));
    opt(&mut c, "mass", a.mass.map(|v| v.to_string()));
    opt(&mut c, "calibration", a.calibration.as_deref().map(name));
    if a.smooth {
        c += " --smooth";
    }
    if a.backfill {
        c += " --backfill";
    }
    opt(&mut c, "diagnostics", a.diagnostics.clone());
    if a.late_rows == crate::cli::LateRowsArg::Drop {
        c += " --late-rows drop";
    }
    c + &format!(" {} -o {}", name(&a.trial), name(&a.output))
}

/// Runs an estimator over an opened trial into an estimate file, with a
/// progress bar and the `extra` observers; records `command` in the
/// header; warns on stderr when the estimator restarted during the run
/// (issue 16) or sensor readings were rejected as out of range (issue 18);
/// returns the number of samples.
///
/// The estimate file records its trial (`# trial:`, `# trial_hash:`; the
/// trial is hashed as it is read) and appears only if the whole run succeeds.
pub fn run_to_file(
    est: &mut dyn Estimator,
    reader: TrialReader,
    output: &Path,
    label: &str,
    command: &str,
    extra: &mut [&mut dyn Observer],
) -> Result<u64> {
    let all = DiagnosticColumns::All;
    let run = run_to_file_calibrated(
        Engine::Online(est),
        reader,
        output,
        label,
        command,
        extra,
        None,
        all,
    )?;
    run.warn(label);
    Ok(run.n_samples)
}

/// [`run_to_file`] with an IMU calibration applied to every record read
/// (docs/CALIBRATION.md), writing the `diagnostics` asked for; the caller
/// gives the run's warnings ([`RunReport::warn`]).
#[allow(clippy::too_many_arguments)]
fn run_to_file_calibrated(
    est: Engine<'_>,
    mut reader: TrialReader,
    output: &Path,
    label: &str,
    command: &str,
    extra: &mut [&mut dyn Observer],
    calibration: Option<&Calibration>,
    diagnostics: DiagnosticColumns,
) -> Result<RunReport> {
    let trial = reader.path().to_path_buf();
    let mut writer = EstimateWriter::for_path(output, super::create_file(output)?)
        .recording_trial(file_name(&trial))
        .recording_command(command)
        .with_diagnostics(diagnostics);
    let run = run_observed(est, &mut reader, &mut writer, label, extra, calibration)?;
    let hash = reader.content_hash().ok_or_else(|| {
        Internal(format!(
            "{}: the trial was not read to its end",
            trial.display()
        ))
    })?;
    let write_err = || format!("{}: cannot write the output file", output.display());
    writer.stamp_trial_hash(hash).with_context(write_err)?;
    super::commit(writer.into_inner().with_context(write_err)?)?;
    Ok(run)
}

/// [`run_to_file_calibrated`] writing to standard output as the rows
/// arrive. The header cannot hold the trial's hash (it is written before
/// the trial ends): it says `# trial_hash: streamed`, and the hash goes to
/// stderr at the end; the caller gives the run's warnings.
#[allow(clippy::too_many_arguments)]
fn run_to_stdout(
    est: Engine<'_>,
    mut reader: TrialReader,
    output: SharedStdout,
    label: &str,
    command: &str,
    extra: &mut [&mut dyn Observer],
    calibration: Option<&Calibration>,
    diagnostics: DiagnosticColumns,
) -> Result<RunReport> {
    let trial = reader.path().to_path_buf();
    let mut writer = EstimateWriter::new(output)
        .streaming_trial(file_name(&trial))
        .recording_command(command)
        .with_diagnostics(diagnostics);
    let run = run_observed(est, &mut reader, &mut writer, label, extra, calibration)?;
    writer
        .into_inner()
        .context("standard output: cannot write the estimate")?;
    if let Some(hash) = reader.content_hash() {
        eprintln!(
            "note: {} has the content hash {hash} (not in the streamed estimate's header, \
             which was written before the trial ended)",
            trial.display()
        );
    }
    Ok(run)
}

/// The file name of `path` (its display form if it has none).
fn file_name(path: &Path) -> String {
    path.file_name().map_or_else(
        || path.display().to_string(),
        |n| n.to_string_lossy().into_owned(),
    )
}

/// The estimator of a run: real-time (one estimate per sample, at once) or
/// offline (`--smooth`: estimates final once later samples were seen).
pub enum Engine<'a> {
    /// A streaming estimator.
    Online(&'a mut dyn Estimator),
    /// An offline estimator (a smoother).
    Offline(&'a mut dyn OfflineEstimator),
}

/// What a run found besides its estimates.
struct RunReport {
    trial: std::path::PathBuf,
    n_samples: u64,
    resets: ResetWatch,
    rejections: RejectionWatch,
    clipped_swings: ClippedSwingWatch,
    rails: AccRailWatch,
    intervals: SampleIntervalWatch,
    units: SensorUnitsWatch,
    /// `--late-rows drop`: the rows dropped.
    late_rows: Option<limbfuse_io::LateRowLog>,
    /// The trial's last line, left out because it was cut off.
    cut_last_line: Option<String>,
}

impl RunReport {
    /// Warns on stderr when the estimator restarted during the run (issue
    /// 16) or sensor readings were rejected as out of range (issue 18).
    fn warn(&self, label: &str) {
        let trial = &self.trial;
        super::warn_resets(
            &format!("{label} on {}", trial.display()),
            self.resets.resets().as_ref(),
        );
        if let Some(r) = self.rejections.rejected() {
            eprintln!("warning: {label} on {}: {r}", trial.display());
        }
        if let Some(c) = self.clipped_swings.clipped() {
            eprintln!("warning: {label} on {}: {c}", trial.display());
        }
        if let Some(r) = self.rails.rails() {
            eprintln!("warning: {label} on {}: {r}", trial.display());
        }
        if let Some(m) = self.late_rows.as_ref().and_then(|l| l.message()) {
            eprintln!("warning: {label} on {}: {m}", trial.display());
        }
        if let Some(m) = &self.cut_last_line {
            eprintln!("warning: {m}");
        }
        super::warn_units(trial, &self.intervals, &self.units);
    }
}

/// The records of a trial with an IMU calibration applied to each.
struct Calibrated<'a> {
    reader: &'a mut TrialReader,
    calibration: &'a Calibration,
}

impl RecordSource for Calibrated<'_> {
    type Error = limbfuse_io::FileError;

    fn read_into(&mut self, record: &mut limbfuse_core::Record) -> Result<bool, Self::Error> {
        let more = self.reader.read_into(record)?;
        if more {
            self.calibration.apply(record);
        }
        Ok(more)
    }
}

/// Runs `est` over every record of `reader` (calibrated if asked) into
/// `writer`, with a progress bar and the `extra` observers.
fn run_observed<W: std::io::Write>(
    est: Engine<'_>,
    reader: &mut TrialReader,
    writer: &mut EstimateWriter<W>,
    label: &str,
    extra: &mut [&mut dyn Observer],
    calibration: Option<&Calibration>,
) -> Result<RunReport> {
    let trial = reader.path().to_path_buf();
    let mut progress = Progress::new(label);
    let mut resets = ResetWatch::default();
    let mut rejections = RejectionWatch::default();
    let mut clipped_swings = ClippedSwingWatch::default();
    let mut rails = {
        let meta = reader.meta();
        let full_scale = limbfuse_methods::gated::sensor_ranges(meta)
            .map_err(|e| anyhow::anyhow!("{}: {e}", trial.display()))?
            .acc_full_scale_m_s2
            .unwrap_or(f64::INFINITY);
        let stated = meta.get(limbfuse_methods::gated::ACC_RANGE_KEY).is_some();
        AccRailWatch::new(full_scale, stated)
    };
    let mut intervals = SampleIntervalWatch::checked_for_trial(reader.meta())
        .map_err(|e| anyhow::anyhow!("{}: {e}", trial.display()))?;
    let mut units = SensorUnitsWatch::default();
    let summary = {
        let mut observers: Vec<&mut dyn Observer> = Vec::with_capacity(8 + extra.len());
        observers.push(writer);
        observers.push(&mut progress);
        observers.push(&mut resets);
        observers.push(&mut rejections);
        observers.push(&mut clipped_swings);
        observers.push(&mut rails);
        observers.push(&mut intervals);
        observers.push(&mut units);
        for o in extra.iter_mut() {
            observers.push(&mut **o);
        }
        // Records are large: the reader parses each straight into the
        // runner's one record, calibrated in place.
        let summary = match (calibration, est) {
            (None, Engine::Online(est)) => runner::run_from(est, reader, &mut observers),
            (Some(calibration), Engine::Online(est)) => runner::run_from(
                est,
                &mut Calibrated {
                    reader,
                    calibration,
                },
                &mut observers,
            ),
            (None, Engine::Offline(est)) => {
                runner::run_offline(est, reader.by_ref(), &mut observers)
            }
            (Some(c), Engine::Offline(est)) => {
                let source = reader.by_ref().map(|r| {
                    r.map(|mut rec| {
                        c.apply(&mut rec);
                        rec
                    })
                });
                runner::run_offline(est, source, &mut observers)
            }
        };
        if summary.is_err() {
            // (a time column in milliseconds or sensors in other units are
            // likely causes of a failure)
            super::warn_units(&trial, &intervals, &units);
        }
        summary.with_context(|| format!("estimating {} with {label}", trial.display()))?
    };
    Ok(RunReport {
        trial,
        n_samples: summary.n_samples,
        resets,
        rejections,
        clipped_swings,
        rails,
        intervals,
        units,
        late_rows: reader.late_rows().copied(),
        cut_last_line: reader.cut_last_line().map(|c| c.message(reader.path())),
    })
}
