//! Assembling the page: sections in order, each plot an inline SVG with an
//! `id` and `data-*` attributes that tests (and readers of the source) can
//! find; style and script inline.

use std::fmt::Write as _;

use limbfuse_core::sample::AngleChannel;
use limbfuse_eval::gait_evaluation::evaluate_gait_files;
use limbfuse_eval::trial_check::check_trial;
use limbfuse_eval::{evaluate_files, EvalOptions, Evaluation};
use limbfuse_io::{EstimateReader, TrialFingerprint};

use crate::data::{file_name, Column, EstimateData, TrialData};
use crate::events_panel::{has_event_reference, is_event_estimate};
use crate::gait_cycle::{cycle_mean_sd, find_cycles};
use crate::header::header;
use crate::panels::{color, panels, wanted_diagnostic, Panel, TimePlot};
use crate::scoring::{error_column, Scoring};
use crate::strides_table::EstimateStrides;
use crate::svg::{esc, Band, Line, Plot};
use crate::time_base::TimeBase;
use crate::{ReportError, ReportInput};

const STYLE: &str = include_str!("report.css");
const SCRIPT: &str = include_str!("report.js");

/// The report's HTML.
pub fn render(input: &ReportInput) -> Result<String, ReportError> {
    if input.estimates.is_empty() {
        return Err(ReportError::NoEstimate);
    }
    for (k, b) in input.estimates.iter().enumerate() {
        let same = |a: &&std::path::PathBuf| limbfuse_io::file_identity::same_file(a, b);
        if let Some(a) = input.estimates[..k].iter().find(same) {
            return Err(ReportError::RepeatedEstimate {
                first: a.display().to_string(),
                second: b.display().to_string(),
            });
        }
    }
    let stop = || match input.cancel.is_some_and(|f| f()) {
        true => Err(ReportError::Cancelled),
        false => Ok(()),
    };
    let trial = TrialData::read(&input.trial)?;
    stop()?;
    let checks = check_trials(input)?;
    let angle_trial = trial.reference.iter().any(Option::is_some);
    let mut evals = Vec::new();
    let mut gait_evals = Vec::new();
    let mut event_evals = Vec::new();
    let mut strides = Vec::new();
    let mut estimates = Vec::new();
    for path in &input.estimates {
        stop()?;
        if angle_trial {
            let options = EvalOptions {
                allow_trial_mismatch: input.allow_trial_mismatch,
                window: input.scoring.window,
                offset_free: input.scoring.offset_free,
                max_lag: input.scoring.max_lag,
            };
            evals.push(evaluate_files(&input.trial, path, options)?);
        } else if trial.phase_ref.is_some() {
            gait_evals.push(evaluate_gait_files(
                &input.trial,
                path,
                input.allow_trial_mismatch,
            )?);
        }
        stop()?;
        let e = EstimateData::read(path, wanted_diagnostic)?;
        let n_estimate = e
            .angle
            .iter()
            .flatten()
            .map(Vec::len)
            .next()
            .unwrap_or_else(|| {
                e.phase
                    .as_ref()
                    .or(e.speed.as_ref())
                    .or(e.diag.values().next())
                    .map_or(trial.t.len(), Vec::len)
            });
        if n_estimate != trial.t.len() {
            return Err(ReportError::Length {
                estimate: path.display().to_string(),
                n_estimate,
                trial: input.trial.display().to_string(),
                n_trial: trial.t.len(),
            });
        }
        if is_event_estimate(&e) {
            // The rows of `evaluate --strides`, with the references when the
            // events are scored against them: one scoring for both tables.
            let scored = has_event_reference(&trial).then_some(input.trial.as_path());
            let (ev, s) = EstimateStrides::read(
                estimates.len(),
                scored,
                path,
                input.allow_trial_mismatch,
                &input.scoring.window,
            )?;
            strides.push(s);
            if scored.is_some() {
                event_evals.push((estimates.len(), ev));
            }
        }
        estimates.push(e);
    }
    crate::error_section::check_scoring(
        input,
        &evals,
        &estimates,
        &event_evals,
        !gait_evals.is_empty(),
    )?;
    let labels: Vec<String> = unique_labels(&estimates);
    for (e, l) in estimates.iter_mut().zip(&labels) {
        e.label = l.clone();
    }
    let rate = trial.sample_rate().unwrap_or(100.0);
    let time_base = TimeBase::new(&trial.t);
    let tp = TimePlot {
        t: &time_base.relative,
        gaps: &time_base.gaps,
        buckets: input.buckets,
        x_scale: if rate > 1000.0 { 1e6 } else { 1e3 },
    };
    let mut body = String::new();
    header(
        &mut body,
        (&trial, &time_base),
        &estimates,
        (rate, input.buckets),
        &checks,
    );
    stop()?;
    angle_section(&mut body, &trial, &estimates, &tp);
    stop()?;
    cycle_section(&mut body, &trial, &estimates, (&evals, &input.scoring));
    stop()?;
    let event_estimates: Vec<bool> = estimates.iter().map(is_event_estimate).collect();
    let nothing_scored: Vec<Option<String>> = evals
        .iter()
        .zip(&estimates)
        .map(|(ev, e)| {
            limbfuse_eval::evaluation::nothing_scored(
                ev,
                e.angle.iter().any(Option::is_some),
                &input.scoring.window,
                &input.trial.display().to_string(),
                &e.path.display().to_string(),
            )
        })
        .collect();
    crate::error_section::error_section(
        &mut body,
        (&labels, &nothing_scored),
        (&evals, &input.scoring, &trial.meta),
        &gait_evals,
        (&event_estimates, &event_evals),
        trial.speed_from_com,
    );
    stop()?;
    panel_section(&mut body, &panels(&trial, &estimates, &tp, &strides));
    command_section(&mut body, input, &trial, &estimates);
    Ok(format!(
        "<!DOCTYPE html>\n<html lang=\"en\"><head><meta charset=\"utf-8\"><meta name=\"viewport\" content=\"width=device-width\"><title>limbfuse report: {}</title><style>{STYLE}</style></head><body>{body}<script>{SCRIPT}</script></body></html>\n",
        esc(&trial.name())
    ))
}

/// Each estimate's trial check, made whatever the trial holds (an audit
/// 2026-12-05: it was made only by the evaluations, so an estimate of
/// another trial passed silently when the trial had no reference to
/// evaluate against): an estimate recording another trial is refused
/// unless `allow_trial_mismatch`; returns the warnings to show.
fn check_trials(input: &ReportInput) -> Result<Vec<String>, ReportError> {
    let trial_hash = TrialFingerprint::of_file(&input.trial)?.hash;
    let mut warnings = Vec::new();
    for path in &input.estimates {
        let reader = EstimateReader::open(path)?;
        let check = check_trial(
            &input.trial,
            trial_hash,
            &reader,
            input.allow_trial_mismatch,
        )?;
        warnings.extend(check.warning());
    }
    Ok(warnings)
}

/// Legend labels: file names, with the directory added where two are equal.
fn unique_labels(estimates: &[EstimateData]) -> Vec<String> {
    estimates
        .iter()
        .map(|e| {
            let dup = estimates.iter().filter(|o| o.label == e.label).count() > 1;
            if dup {
                e.path.display().to_string()
            } else {
                e.label.clone()
            }
        })
        .collect()
}

fn degrees(c: &Column) -> Column {
    c.iter().map(|v| v.map(f64::to_degrees)).collect()
}

/// The channels with a reference and at least one estimate.
fn compared_channels(trial: &TrialData, estimates: &[EstimateData]) -> Vec<(usize, AngleChannel)> {
    AngleChannel::ALL
        .iter()
        .enumerate()
        .filter(|(k, _)| {
            trial.reference[*k].is_some() && estimates.iter().any(|e| e.angle[*k].is_some())
        })
        .map(|(k, c)| (k, *c))
        .collect()
}

/// The channels at least one estimate gives (with or without a reference).
fn estimated_channels(estimates: &[EstimateData]) -> Vec<(usize, AngleChannel)> {
    AngleChannel::ALL
        .iter()
        .enumerate()
        .filter(|(k, _)| estimates.iter().any(|e| e.angle[*k].is_some()))
        .map(|(k, c)| (k, *c))
        .collect()
}

/// Every estimated angle over time, against its reference when the trial
/// has one (a recording without motion capture still shows its estimates:
/// the page showed nothing there before).
fn angle_section(s: &mut String, trial: &TrialData, estimates: &[EstimateData], tp: &TimePlot) {
    s.push_str(r#"<section id="angles" data-section="angles"><h2>Angles over time</h2>"#);
    let channels = estimated_channels(estimates);
    if channels.is_empty() {
        s.push_str(r#"<p class="note">No estimate gives an angle.</p></section>"#);
        return;
    }
    let unreferenced: Vec<&str> = channels
        .iter()
        .filter(|(k, _)| trial.reference[*k].is_none())
        .map(|(_, c)| c.name())
        .collect();
    if !unreferenced.is_empty() {
        let _ = write!(
            s,
            r#"<p class="note">No reference in the trial for {}: the estimates alone.</p>"#,
            esc(&unreferenced.join(", "))
        );
    }
    for (k, c) in channels {
        let reference = trial.reference[k].as_ref().map(degrees);
        let est: Vec<(usize, Column)> = estimates
            .iter()
            .enumerate()
            .filter_map(|(i, e)| Some((i, degrees(e.angle[k].as_ref()?))))
            .collect();
        let mut lines = Vec::new();
        if let Some(r) = &reference {
            lines.push((
                "reference".to_string(),
                format!("{}_ref", c.name()),
                "#000".to_string(),
                r,
                false,
            ));
        }
        for (i, col) in &est {
            lines.push((
                format!("est-{i}"),
                estimates[*i].label.clone(),
                color(*i),
                col,
                false,
            ));
        }
        let est_cols: Vec<&Column> = est.iter().map(|(_, col)| col).collect();
        let clip = crate::y_range::start_clip(tp.t, reference.as_ref(), &est_cols);
        let mut plot = tp.plot(
            format!("plot-angle-{}", c.name()),
            "angle",
            format!("{} angle", c.name()),
            "deg",
            lines,
        );
        plot.y_clip = clip.clone();
        figure(s, &plot, c.name());
        if let Some(clip) = clip {
            let names: Vec<String> = clip
                .exceeding
                .iter()
                .map(|&j| format!("<code>{}</code>", esc(&estimates[est[j].0].label)))
                .collect();
            let settle = crate::y_range::settle_s(tp.t.last().copied().unwrap_or(0.0));
            let _ = write!(
                s,
                r#"<p class="note clip-note" id="clip-note-{}" data-clip-until-s="{:.3}">y range clipped to the reference and the estimates after the first {:.1} s: the first {:.1} s of {} exceed it (values from {:.1} to {:.1} deg; shaded). Zoom into 0 to {:.1} s to see them whole.</p>"#,
                c.name(),
                clip.until_s,
                settle,
                clip.until_s,
                names.join(", "),
                clip.all[0],
                clip.all[1],
                clip.until_s.max(0.1) * 1.5
            );
        }
    }
    s.push_str("</section>");
}

fn figure(s: &mut String, plot: &Plot, channel: &str) {
    let _ = write!(
        s,
        r#"<figure data-channel="{}">{}{}</figure>"#,
        esc(channel),
        plot.render(),
        plot.legend()
    );
}

fn cycle_section(
    s: &mut String,
    trial: &TrialData,
    estimates: &[EstimateData],
    (evals, scoring): (&[Evaluation], &Scoring),
) {
    s.push_str(r#"<section id="gait-cycle" data-section="gait-cycle"><h2>Error over the normalised gait cycle</h2>"#);
    let channels = compared_channels(trial, estimates);
    let cycles = match find_cycles(trial) {
        Ok(mut c) if !channels.is_empty() => {
            // (`--window`: the cycles wholly inside it, as the tables)
            let w = &scoring.window;
            c.cycles
                .retain(|&(a, b)| w.contains(trial.t[a]) && w.contains(trial.t[b]));
            if c.cycles.is_empty() {
                let _ = write!(
                    s,
                    r#"<p class="note" id="gait-events" data-source="none">No whole gait cycle inside the window {} (<code>--window</code>).</p></section>"#,
                    esc(&w.to_string())
                );
                return;
            }
            c
        }
        Ok(_) => {
            s.push_str(r#"<p class="note" id="gait-events" data-source="none">No angle channel to show over the gait cycle.</p></section>"#);
            return;
        }
        Err(why) => {
            let _ = write!(
                s,
                r#"<p class="note" id="gait-events" data-source="none">No gait cycle: {}.</p></section>"#,
                esc(&why)
            );
            return;
        }
    };
    let mut durations: Vec<f64> = cycles
        .cycles
        .iter()
        .map(|&(a, b)| trial.t[b] - trial.t[a])
        .collect();
    durations.sort_by(f64::total_cmp);
    let median_s = durations[durations.len() / 2];
    let _ = write!(
        s,
        r#"<p class="note" id="gait-events" data-source="{}" data-cycles="{}" data-median-s="{:.4}">{}; {} cycles (median {:.3} s){}. Error = estimate - reference, interpolated at 0, 1, ..., 100 % of each cycle; line = mean, band = mean +- sd over the cycles.{}</p>"#,
        match &cycles.source {
            crate::gait_cycle::EventSource::Contact(_) => "contact",
            crate::gait_cycle::EventSource::Gyro(_) => "gyro",
        },
        cycles.cycles.len(),
        median_s,
        esc(&cycles.source.describe()),
        cycles.cycles.len(),
        median_s,
        if cycles.rejected > 0 {
            format!(
                " ({} left out: duration off the median by more than 50 %)",
                cycles.rejected
            )
        } else {
            String::new()
        },
        if scoring.given().is_empty() {
            String::new()
        } else {
            format!(" Scored as the tables: {}.", scoring.describe())
        }
    );
    for (k, c) in channels {
        let Some(r) = &trial.reference[k] else {
            continue;
        };
        let mut plot = Plot {
            id: format!("plot-cycle-{}", c.name()),
            kind: "cycle".into(),
            title: format!("{} error over the gait cycle", c.name()),
            x_label: "gait cycle (%)".into(),
            y_label: "deg".into(),
            x_scale: 10.0,
            zoomable: false,
            lines: Vec::new(),
            bands: Vec::new(),
            y_clip: None,
        };
        for (i, e) in estimates.iter().enumerate() {
            let Some(a) = &e.angle[k] else { continue };
            let err = error_column(a, r, c, evals.get(i));
            let ms = cycle_mean_sd(&trial.t, &err, &cycles.cycles);
            plot.bands.push(Band {
                key: format!("est-{i}"),
                color: color(i),
                points: ms.iter().map(|(p, m, sd)| (*p, m - sd, m + sd)).collect(),
            });
            plot.lines.push(Line {
                key: format!("est-{i}"),
                label: e.label.clone(),
                color: color(i),
                points: ms.iter().map(|(p, m, _)| (*p, Some(*m))).collect(),
                dashed: false,
            });
        }
        figure(s, &plot, c.name());
    }
    s.push_str("</section>");
}

fn panel_section(s: &mut String, panels: &[Panel]) {
    s.push_str(r#"<section id="methods" data-section="methods"><h2>Method panels</h2>"#);
    if panels.is_empty() {
        s.push_str(r#"<p class="note">No method-specific panel applies (panels: IMM weights, knee-axis convergence, FES stimulation, gait events and walking speed).</p>"#);
    }
    for p in panels {
        let _ = write!(
            s,
            r#"<div class="panel" id="{}" data-panel="{}"><h3>{}</h3><p class="note">{}</p>"#,
            esc(&p.id),
            esc(&p.kind),
            esc(&p.title),
            p.note
        );
        for plot in &p.plots {
            figure(s, plot, "");
        }
        s.push_str(&p.table);
        s.push_str("</div>");
    }
    s.push_str("</section>");
}

fn command_section(
    s: &mut String,
    input: &ReportInput,
    trial: &TrialData,
    estimates: &[EstimateData],
) {
    s.push_str(r#"<section id="commands" data-section="commands"><h2>How these files were made</h2><pre id="command-list">"#);
    let _ = writeln!(s, "# this report\n{}", esc(&input.command));
    let _ = writeln!(
        s,
        "\n# trial {}: {}",
        esc(&trial.name()),
        esc(trial.meta.get("source").unwrap_or("no `# source:` line"))
    );
    for (k, e) in estimates.iter().enumerate() {
        match e.meta.get(limbfuse_io::estimate_file::COMMAND_KEY) {
            Some(c) => {
                // (an audit: run from the report's folder, an estimate's
                // command failed, the trial being elsewhere)
                let note = if k == 0 {
                    " (an estimate records its files by name: run it in the trial's folder)"
                } else {
                    ""
                };
                let _ = writeln!(s, "\n# {}{note}\n{}", esc(&e.label), esc(c));
            }
            None => {
                let _ = writeln!(
                    s,
                    "\n# {}: no `# command:` line (written before limbfuse recorded it); same method with the parameters below:\nlimbfuse estimate --method {} {} -o {}",
                    esc(&e.label),
                    esc(&e.method),
                    esc(&trial.name()),
                    esc(&file_name(&e.path))
                );
            }
        }
    }
    s.push_str("</pre>");
    let _ = write!(
        s,
        "<details><summary>Header of <code>{}</code></summary><pre>",
        esc(&trial.name())
    );
    for (k, v) in trial.meta.entries() {
        let _ = writeln!(s, "# {}: {}", esc(k), esc(v));
    }
    s.push_str("</pre></details>");
    for e in estimates {
        let _ = write!(
            s,
            "<details><summary>Header of <code>{}</code></summary><pre>",
            esc(&e.label)
        );
        for (k, v) in e.meta.entries() {
            let _ = writeln!(s, "# {}: {}", esc(k), esc(v));
        }
        s.push_str("</pre></details>");
    }
    s.push_str("</section>");
}
