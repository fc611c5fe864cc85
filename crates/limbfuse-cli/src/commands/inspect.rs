//! `limbfuse inspect TRIAL... [--json]`: what trial files hold and which methods can
//! run on it, before estimating anything.

use anyhow::Result;
use limbfuse_eval::fixed_thigh::thigh_motion_notes;
use limbfuse_eval::{summarise, TrialSummary};
use limbfuse_io::time_repair::time_problems;
use limbfuse_io::{FileError, TrialMeta, TrialReader};
use limbfuse_methods::{availability, metadata_settings, Availability};
use limbfuse_workflows::align_verdict::{align_verdict, AlignVerdict};

use crate::cli::InspectArgs;

/// Prints each trial's time base, inputs, unit checks and the methods that
/// can run on it (each built with its defaults, as `estimate` would build
/// it without `--params`), as text or one JSON array (`--json`). A file
/// that cannot be read is an error (exit 1) after the others were printed.
pub fn run(a: &InspectArgs) -> Result<()> {
    let mut json = Vec::new();
    let mut failed = 0usize;
    for path in &a.trials {
        let inspected = TrialReader::open(path).and_then(|mut reader| {
            let meta = reader.meta().clone();
            let layout = *reader.layout();
            summarise(&mut reader).map(|s| (meta, layout, s))
        });
        let (meta, layout, s) = match inspected {
            Ok(x) => x,
            Err(e) => {
                let e = with_time_problems(path, e);
                if a.trials.len() == 1 {
                    return Err(e);
                }
                eprintln!("error: {e:#}");
                failed += 1;
                continue;
            }
        };
        let label = path.display().to_string();
        let mut methods = availability(&meta, &layout);
        limbfuse_eval::data_limits::limit_by_data(&mut methods, &s, &meta);
        let read = metadata_settings(&meta, &methods);
        let motion = thigh_motion_notes(s.thigh_spread_deg, &methods);
        let align = align_verdict(path, &meta, &layout, s.rows, &methods, None);
        if a.json {
            json.push(to_json(path, &label, &s, &methods, &read, &motion, &align));
        } else {
            let hint = limbfuse_methods::availability::needs_a_model(&methods)
                .then(|| limbfuse_methods::availability::model_file_hint(path))
                .flatten();
            print_text(&label, &meta, &s, methods, hint, &align);
            for (title, lines) in [
                (
                    "what the metadata sets (or its defaults, when it says nothing):",
                    read,
                ),
                ("what the thigh's motion says about them:", motion),
            ] {
                if !lines.is_empty() {
                    println!("{title}");
                    for l in lines {
                        println!("  {l}");
                    }
                }
            }
        }
    }
    if a.json {
        println!("{}", serde_json::to_string_pretty(&json)?);
    }
    if failed > 0 {
        anyhow::bail!(
            "{failed} of {} trial files could not be read (above)",
            a.trials.len()
        );
    }
    Ok(())
}

/// A time column that does not increase: the first row that breaks it
/// (the error), then what `repair-time` would drop over the whole file.
fn with_time_problems(path: &std::path::Path, e: FileError) -> anyhow::Error {
    if !matches!(e, FileError::TimeNotIncreasing { .. }) {
        return e.into();
    }
    match time_problems(path) {
        Ok(r) => {
            let command = format!(
                "limbfuse repair-time {} -o OUT",
                super::shell_word(&path.display().to_string())
            );
            anyhow::Error::new(e).context(format!(
                "{}: its time does not increase on every row: {}",
                path.display(),
                r.would_drop(&command, super::repair_time::RANGES_SHOWN)
            ))
        }
        Err(_) => e.into(),
    }
}

/// The JSON form of one trial (the keys of Python's `limbfuse.inspect`).
fn to_json(
    path: &std::path::Path,
    label: &str,
    s: &TrialSummary,
    methods: &[(limbfuse_methods::MethodName, Availability)],
    read: &[String],
    motion: &[String],
    align: &AlignVerdict,
) -> serde_json::Value {
    // (the reasons with the model file's hint, as Python's)
    let reasons = limbfuse_methods::availability::inspect_reasons(methods, path);
    let methods: serde_json::Map<String, serde_json::Value> = methods
        .iter()
        .zip(reasons)
        .map(|((m, a), why)| (m.name().to_string(), serde_json::json!([a.kind(), why])))
        .collect();
    let inputs: serde_json::Map<String, serde_json::Value> = s
        .inputs
        .iter()
        .map(|g| (g.name.clone(), g.missing_rows.into()))
        .collect();
    serde_json::json!({
        "trial": label,
        "rows": s.rows,
        "span": s.span.map(|(a, b)| [a, b]),
        "median_step": s.median_step,
        "stated_hz": s.stated_hz,
        "gaps": s.gaps,
        "longest_step": s.longest_step.map(|(a, b)| [a, b]),
        "inputs": inputs,
        "warnings": s.warnings,
        "methods": methods,
        "metadata_settings": read,
        "thigh_spread_deg": s.thigh_spread_deg,
        "data_notes": motion,
        "align": {
            "needed": align.needed,
            "possible": align.possible,
            "reason": align.reason,
        },
    })
}

/// The text form of one trial.
fn print_text(
    label: &str,
    meta: &TrialMeta,
    s: &TrialSummary,
    methods: Vec<(limbfuse_methods::MethodName, Availability)>,
    model_hint: Option<String>,
    align: &AlignVerdict,
) {
    print!("{}", describe(label, meta, s));
    let (mut runs, mut settings, mut not, mut no_data) =
        (Vec::new(), Vec::new(), Vec::new(), Vec::new());
    for (m, a) in methods {
        match a {
            Availability::Runs { after_align: false } => runs.push(m.name().to_string()),
            Availability::Runs { after_align: true } => runs.push(match &align.reason {
                None => format!(
                    "{} (after `limbfuse align`: it reads aligned frames)",
                    m.name()
                ),
                Some(_) => format!(
                    "{} (reads aligned frames, but `limbfuse align` cannot align this trial: below)",
                    m.name()
                ),
            }),
            Availability::NeedsSetting(why) => settings.push(format!("  {:<18} {why}", m.name())),
            Availability::MissingColumns(why) => not.push(format!("  {:<18} {why}", m.name())),
            Availability::NoData(why) => no_data.push(format!("  {:<18} {why}", m.name())),
        }
    }
    if let Some(h) = model_hint {
        settings.push(format!("  (sdre, ekf: {h})"));
    }
    println!(
        "methods that run on it with their defaults: {}",
        or_none(&runs.join(", "))
    );
    if let Some(line) = align.line() {
        println!("{line}");
    }
    for (title, lines) in [
        (
            "methods with the columns they need, but not their defaults' settings:",
            settings,
        ),
        ("methods missing columns they need:", not),
        (
            "methods with their columns and settings that the data rule out:",
            no_data,
        ),
    ] {
        if !lines.is_empty() {
            println!("{title}");
            for l in lines {
                println!("{l}");
            }
        }
    }
}

/// A time in seconds as read: to the microsecond, trailing zeros dropped
/// (an audit: `t = 0 to 19.990000000000002 s`).
fn seconds(v: f64) -> String {
    let text = format!("{v:.6}");
    let text = text.trim_end_matches('0').trim_end_matches('.');
    if text == "-0" {
        "0".into()
    } else {
        text.to_string()
    }
}

/// `text`, or `none` when empty.
fn or_none(text: &str) -> &str {
    if text.is_empty() {
        "none"
    } else {
        text
    }
}

/// The summary's text (everything but the methods).
fn describe(label: &str, meta: &TrialMeta, s: &TrialSummary) -> String {
    let mut out = String::new();
    let mut line = |l: String| {
        out += &l;
        out.push('\n');
    };
    let span = s.span.map_or("no rows".to_string(), |(a, b)| {
        format!("t = {} to {} s", seconds(a), seconds(b))
    });
    line(format!("{label}: {} rows, {span}", s.rows));
    if let Some(step) = s.median_step {
        let stated = match (s.stated_hz, meta.get("sample_rate_hz")) {
            (Some(hz), _) => format!("the file states {hz} Hz"),
            // (an audit: `# sample_rate_hz: abc` read as no rate at all)
            (None, Some(text)) => format!("the file's `# sample_rate_hz: {text}` is not a rate"),
            (None, None) => "the file states no rate".into(),
        };
        line(format!(
            "  sample step: median {step:.6} s ({:.2} Hz; {stated})",
            1.0 / step
        ));
        line(match (s.gaps, s.longest_step) {
            (0, _) => "  gaps: none (no step over 1.5 median steps)".into(),
            (n, Some((at, len))) => format!(
                "  gaps: {n} step{} over 1.5 median steps, the longest {} s after t = {} s",
                if n == 1 { "" } else { "s" },
                seconds(len),
                seconds(at)
            ),
            (n, None) => format!("  gaps: {n}"),
        });
    }
    let frames = match meta.get("imu_frame") {
        Some(f) => f,
        None if limbfuse_methods::raw_frames::declares_raw_frames(meta) => {
            "raw sensor frames (said in `# sensors:`)"
        }
        None => "not stated (SPEC: aligned to the segments)",
    };
    line(format!(
        "  leg: {}; IMU frames: {frames}",
        meta.get("leg").unwrap_or("not stated (SPEC: right)")
    ));
    if s.inputs.is_empty() {
        line("  inputs: none (no IMU, encoder, CoM or stimulation column)".into());
    } else {
        let rows = s.rows.max(1) as f64;
        let names: Vec<String> = s
            .inputs
            .iter()
            .map(|g| match g.missing_rows {
                0 => g.name.clone(),
                m => format!(
                    "{} ({:.1} % of rows missing)",
                    g.name,
                    100.0 * m as f64 / rows
                ),
            })
            .collect();
        line(format!("  inputs: {}", names.join(", ")));
    }
    let warnings = &s.warnings;
    if warnings.is_empty() {
        let imus = s
            .inputs
            .iter()
            .any(|g| g.name.ends_with(" acc") || g.name.ends_with(" gyr"));
        line(format!(
            "  units: t in s{} as far as the data show (docs/ROBUST_INPUT.md, 2e)",
            if imus {
                ", IMUs in m/s^2 and rad/s"
            } else {
                ""
            }
        ));
    }
    for w in warnings {
        line(format!("  warning: {w}"));
    }
    out
}
