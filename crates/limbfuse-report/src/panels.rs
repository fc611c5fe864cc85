//! Method-specific panels, chosen by the columns present (not by method
//! name): the `imm-bslip` weights (`diag_w_gNN_PHASE`), the
//! `knee-selfalign` joint axes (`diag_j_thigh_*`, `diag_j_shank_*`), and
//! for FES trials the stimulation (`u_*`), activation (`a_*`) and the
//! `sdre` / `ekf` angle uncertainty (`diag_p11`); the gait events and
//! walking speed of `gait-events` / `lowback-speed` ([`crate::events_panel`]).

use std::fmt::Write as _;

use crate::data::{Column, EstimateData, TrialData};
use crate::decimate::min_max;
use crate::strides_table::EstimateStrides;
use crate::svg::{esc, Line, Plot};
use crate::time_base::{break_at_gaps, TimeGap};

/// Colours of successive lines (Tableau 10).
pub const PALETTE: [&str; 10] = [
    "#1f77b4", "#ff7f0e", "#2ca02c", "#d62728", "#9467bd", "#8c564b", "#e377c2", "#7f7f7f",
    "#bcbd22", "#17becf",
];

/// The colour of line `k`: the [`PALETTE`], then (audit 2026-12-05: the
/// 11th estimate took the first one's colour) hues a golden angle apart,
/// each distinct from every other line's.
pub fn color(k: usize) -> String {
    match PALETTE.get(k) {
        Some(c) => c.to_string(),
        None => {
            let hue = ((k - PALETTE.len()) as f64 * 137.508 + 15.0) % 360.0;
            let lightness = [38, 52, 30][(k - PALETTE.len()) % 3];
            format!("hsl({hue:.1},70%,{lightness}%)")
        }
    }
}

/// One panel: a heading, a sentence, plots and an optional table (HTML).
#[derive(Debug, Clone)]
pub struct Panel {
    /// Element id.
    pub id: String,
    /// `data-panel` value.
    pub kind: String,
    /// Heading.
    pub title: String,
    /// What the panel shows (HTML).
    pub note: String,
    /// Plots.
    pub plots: Vec<Plot>,
    /// A table (HTML), possibly empty.
    pub table: String,
}

/// Whether a diagnostic column is drawn by some panel (the others are not read).
pub fn wanted_diagnostic(name: &str) -> bool {
    is_weight(name)
        || name.starts_with("j_thigh_")
        || name.starts_with("j_shank_")
        || matches!(
            name,
            "speed_mean" | "sign_confidence" | "p11" | "activation" | "ic" | "ic_right" | "ic_left"
        )
}

fn is_weight(name: &str) -> bool {
    parse_weight(name).is_some()
}

/// `w_gNN_PHASE` -> (gait NN, phase index 0..3).
fn parse_weight(name: &str) -> Option<(usize, usize)> {
    let rest = name.strip_prefix("w_g")?;
    let (gait, phase) = rest.split_once('_')?;
    let phase = ["ss1", "ds", "ss2"].iter().position(|p| *p == phase)?;
    Some((gait.parse().ok()?, phase))
}

/// A time plot of columns sampled at `t`, decimated to `buckets`, the
/// lines broken at `gaps`.
pub struct TimePlot<'a> {
    /// Sample times (s since the first sample, [`crate::time_base`]).
    pub t: &'a [f64],
    /// The gaps in `t` (no line is drawn across one).
    pub gaps: &'a [TimeGap],
    /// Display buckets.
    pub buckets: usize,
    /// x units per second.
    pub x_scale: f64,
}

impl TimePlot<'_> {
    /// A zoomable plot of `(key, label, colour, column, dashed)` lines.
    pub fn plot(
        &self,
        id: String,
        kind: &str,
        title: String,
        y_label: &str,
        lines: Vec<(String, String, String, &Column, bool)>,
    ) -> Plot {
        Plot {
            id,
            kind: kind.into(),
            title,
            x_label: "time (s)".into(),
            y_label: y_label.into(),
            x_scale: self.x_scale,
            zoomable: true,
            lines: lines
                .into_iter()
                .map(|(key, label, color, col, dashed)| Line {
                    key,
                    label,
                    color,
                    points: break_at_gaps(min_max(self.t, col, self.buckets), self.gaps),
                    dashed,
                })
                .collect(),
            bands: Vec::new(),
            y_clip: None,
        }
    }
}

/// Every panel for this trial and these estimates;
/// `strides`: the stride tables of the gait-event estimates, for their panel.
pub fn panels(
    trial: &TrialData,
    estimates: &[EstimateData],
    tp: &TimePlot,
    strides: &[EstimateStrides],
) -> Vec<Panel> {
    let mut out = Vec::new();
    for (i, e) in estimates.iter().enumerate() {
        // (an `imm-bslip` estimate written with `--diagnostics none` keeps
        // its phase and speed panels: an audit found the whole panel gone)
        let imm = matches!(
            limbfuse_methods::MethodName::parse(&e.method),
            Ok(limbfuse_methods::MethodName::ImmBslip)
        );
        if e.diag.keys().any(|k| is_weight(k)) || (imm && (e.speed.is_some() || e.phase.is_some()))
        {
            out.push(imm_panel(trial, e, i, tp));
        }
        if e.diag.contains_key("j_thigh_x") {
            out.push(knee_axis_panel(e, i, tp));
        }
    }
    if trial.columns.keys().any(|k| k.starts_with("u_")) {
        out.push(fes_panel(trial, estimates, tp));
    }
    out.extend(crate::events_panel::events_panel(
        trial, estimates, tp, strides,
    ));
    out
}

fn imm_panel(trial: &TrialData, e: &EstimateData, i: usize, tp: &TimePlot) -> Panel {
    let n = trial.t.len();
    let mut by_gait: Vec<Column> = Vec::new();
    let mut by_phase: Vec<Column> = vec![vec![None; n]; 3];
    let mut mean = Vec::<[f64; 3]>::new();
    for (name, col) in &e.diag {
        let Some((g, p)) = parse_weight(name) else {
            continue;
        };
        if by_gait.len() <= g {
            by_gait.resize(g + 1, vec![None; n]);
            mean.resize(g + 1, [0.0; 3]);
        }
        let (mut sum, mut k) = (0.0, 0usize);
        for (s, v) in col.iter().enumerate() {
            if let Some(v) = v {
                add(&mut by_gait[g][s], *v);
                add(&mut by_phase[p][s], *v);
                sum += v;
                k += 1;
            }
        }
        mean[g][p] = if k > 0 { sum / k as f64 } else { f64::NAN };
    }
    let gait_label = |g: usize| {
        let speed = e
            .meta
            .get(&format!("gait g{g:02}"))
            .and_then(|v| v.split(',').next())
            .map_or(String::new(), |s| format!(" ({})", s.trim()));
        format!("g{g:02}{speed}")
    };
    let gait_lines = by_gait
        .iter()
        .enumerate()
        .map(|(g, c)| (format!("g{g:02}"), gait_label(g), color(g), c, false))
        .collect();
    let phase_lines = ["SS1", "DS", "SS2"]
        .iter()
        .zip(&by_phase)
        .enumerate()
        .map(|(k, (p, c))| (p.to_string(), p.to_string(), color(k), c, false))
        .collect();
    let has_weights = !by_gait.is_empty();
    let mut plots = Vec::new();
    if has_weights {
        plots.push(tp.plot(
            format!("plot-imm-gait-{i}"),
            "imm-gait",
            format!("{}: IMM weight per gait (summed over phases)", e.label),
            "weight",
            gait_lines,
        ));
        plots.push(tp.plot(
            format!("plot-imm-phase-{i}"),
            "imm-phase",
            format!("{}: IMM weight per phase (summed over gaits)", e.label),
            "weight",
            phase_lines,
        ));
    }
    let mut speed_lines = Vec::new();
    if let Some(s) = &e.speed {
        speed_lines.push(("speed".into(), "estimated speed".into(), color(0), s, false));
    }
    if let Some(s) = e.diag.get("speed_mean") {
        speed_lines.push((
            "speed_mean".into(),
            "weight-averaged library speed".into(),
            color(1),
            s,
            false,
        ));
    }
    // The reference: `speed_ref`, else the CoM velocity of a B-SLIP trial
    // (`com_vx`, which has no `speed_ref`; review 27: the plot had no
    // reference on them).
    let reference = trial
        .columns
        .get("speed_ref")
        .map(|s| ("speed_ref", s))
        .or_else(|| {
            trial
                .columns
                .get("com_vx")
                .map(|s| ("com_vx (forward CoM velocity, reference)", s))
        });
    if let Some((label, s)) = reference {
        speed_lines.push(("reference".into(), label.into(), "#000".into(), s, true));
    }
    if !speed_lines.is_empty() {
        plots.push(tp.plot(
            format!("plot-imm-speed-{i}"),
            "imm-speed",
            format!("{}: walking speed", e.label),
            "m/s",
            speed_lines,
        ));
    }
    if let (Some(p), Some(r)) = (&e.phase, &trial.phase_ref) {
        plots.push(tp.plot(
            format!("plot-imm-phase-track-{i}"),
            "imm-phase-track",
            format!("{}: gait phase (0 = SS1, 1 = DS, 2 = SS2)", e.label),
            "phase",
            vec![
                (
                    "reference".into(),
                    "phase_ref".into(),
                    "#000".into(),
                    r,
                    true,
                ),
                ("phase".into(), "estimated phase".into(), color(0), p, false),
            ],
        ));
    }
    let mut table = String::from(
        r#"<table class="numbers imm-weights"><thead><tr><th>gait</th><th>SS1</th><th>DS</th><th>SS2</th><th>sum</th></tr></thead><tbody>"#,
    );
    for (g, m) in mean.iter().enumerate() {
        let _ = write!(table, "<tr><td>{}</td>", esc(&gait_label(g)));
        for v in m {
            let _ = write!(table, "<td>{v:.4}</td>");
        }
        let _ = write!(table, "<td>{:.4}</td></tr>", m.iter().sum::<f64>());
    }
    table.push_str("</tbody></table>");
    Panel {
        id: format!("panel-imm-{i}"),
        kind: "imm".into(),
        title: format!("IMM over the gait library: {}", e.label),
        note: match has_weights {
            true => "The weight (mode probability, paper 003 eq 8) of each (gait, phase) model, \
                     summed per gait and per phase; the table gives each model's mean weight over the trial."
                .into(),
            false => "The estimate file has no IMM weights (`diag_w_*`: it was written with \
                      `--diagnostics none` or a list without them): only its phase and speed are shown."
                .into(),
        },
        plots,
        table: if has_weights { table } else { String::new() },
    }
}

fn add(slot: &mut Option<f64>, v: f64) {
    *slot = Some(slot.unwrap_or(0.0) + v);
}

fn knee_axis_panel(e: &EstimateData, i: usize, tp: &TimePlot) -> Panel {
    let mut plots = Vec::new();
    let mut change_lines: Vec<(String, String, String, Column)> = Vec::new();
    for (k, seg) in ["thigh", "shank"].iter().enumerate() {
        let cols: Vec<&Column> = ["x", "y", "z"]
            .iter()
            .filter_map(|a| e.diag.get(&format!("j_{seg}_{a}")))
            .collect();
        if cols.len() != 3 {
            continue;
        }
        plots.push(
            tp.plot(
                format!("plot-knee-axis-{seg}-{i}"),
                "knee-axis",
                format!(
                    "{}: {seg} joint axis j in the sensor frame (paper 002 eq 1)",
                    e.label
                ),
                "component",
                ["x", "y", "z"]
                    .iter()
                    .zip(&cols)
                    .enumerate()
                    .map(|(c, (a, col))| {
                        (a.to_string(), format!("j_{seg}_{a}"), color(c), *col, false)
                    })
                    .collect(),
            ),
        );
        change_lines.push((
            seg.to_string(),
            format!("{seg} axis"),
            color(k),
            angle_to_final(&cols),
        ));
    }
    if !change_lines.is_empty() {
        plots.push(
            tp.plot(
                format!("plot-knee-axis-change-{i}"),
                "knee-axis-change",
                format!(
                    "{}: angle between each axis estimate and the final one",
                    e.label
                ),
                "deg",
                change_lines
                    .iter()
                    .map(|(k, l, c, col)| (k.clone(), l.clone(), c.clone(), col, false))
                    .collect(),
            ),
        );
    }
    Panel {
        id: format!("panel-knee-{i}"),
        kind: "knee-axis".into(),
        title: format!("Knee-axis convergence: {}", e.label),
        note: "The joint axes identified window by window (paper 002 Alg. 3) and the angle between \
               each sample's axis and the last one: the axes have converged where it stays near zero."
            .into(),
        plots,
        table: String::new(),
    }
}

/// Angle (deg) between the axis at each sample and the last available one.
fn angle_to_final(cols: &[&Column]) -> Column {
    let n = cols[0].len();
    let at = |s: usize| -> Option<[f64; 3]> { Some([cols[0][s]?, cols[1][s]?, cols[2][s]?]) };
    let Some(last) = (0..n).rev().find_map(at) else {
        return vec![None; n];
    };
    let norm = |v: [f64; 3]| (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]).sqrt();
    (0..n)
        .map(|s| {
            let v = at(s)?;
            let d = (v[0] * last[0] + v[1] * last[1] + v[2] * last[2]) / (norm(v) * norm(last));
            d.is_finite()
                .then(|| d.clamp(-1.0, 1.0).acos().to_degrees())
        })
        .collect()
}

fn fes_panel(trial: &TrialData, estimates: &[EstimateData], tp: &TimePlot) -> Panel {
    let inputs: Vec<(&String, &Column)> = trial
        .columns
        .iter()
        .filter(|(k, _)| k.starts_with("u_") || k.starts_with("a_"))
        .collect();
    let has_activation = inputs.iter().any(|(k, _)| k.starts_with("a_"));
    // The activation an estimate carries as a state (`diag_activation`),
    // dashed, after the trial's columns.
    let estimated: Vec<(usize, &Column)> = estimates
        .iter()
        .enumerate()
        .filter_map(|(i, e)| Some((i, e.diag.get("activation")?)))
        .collect();
    let mut series: Vec<(String, String, String, &Column, bool)> = inputs
        .iter()
        .enumerate()
        .map(|(k, (name, col))| {
            (
                name.to_string(),
                name.to_string(),
                color(k),
                *col,
                name.starts_with("a_"),
            )
        })
        .collect();
    for (i, col) in &estimated {
        let label = &estimates[*i].label;
        series.push((
            format!("est-{i}-activation"),
            format!("{label}: estimated activation"),
            color(inputs.len() + i),
            col,
            true,
        ));
    }
    let mut plots = vec![tp.plot(
        "plot-fes-stimulation".into(),
        "fes-stimulation",
        if estimated.is_empty() {
            "Stimulation (u_*) and activation (a_*) from the trial".into()
        } else {
            "Stimulation (u_*) and activation (a_*) from the trial; activation estimated (dashed)"
                .into()
        },
        "normalised",
        series,
    )];
    let sd: Vec<(usize, Column)> = estimates
        .iter()
        .enumerate()
        .filter_map(|(i, e)| {
            let p = e.diag.get("p11")?;
            Some((
                i,
                p.iter()
                    .map(|v| v.filter(|v| *v >= 0.0).map(|v| v.sqrt().to_degrees()))
                    .collect(),
            ))
        })
        .collect();
    if !sd.is_empty() {
        plots.push(
            tp.plot(
                "plot-fes-sd".into(),
                "fes-sd",
                // (review 27: the whole sentence ran past the plot's right
                // edge; its explanation is in the panel's note)
                "Angle standard deviation sqrt(P_11) of each filter's covariance".into(),
                "deg",
                sd.iter()
                    .map(|(i, c)| {
                        (
                            estimates[*i].label.clone(),
                            estimates[*i].label.clone(),
                            color(*i),
                            c,
                            false,
                        )
                    })
                    .collect(),
            ),
        );
    }
    let mut note = if has_activation {
        "Stimulation commands and muscle activation as recorded in the trial.".to_string()
    } else {
        "Stimulation commands as recorded in the trial (no activation column a_*).".to_string()
    };
    // How each model-based estimate treats activation, from its own header
    // (an audit: the note said "activation = stimulation" for filters run
    // with activation as a state).
    let models: Vec<String> = estimates
        .iter()
        .filter_map(|e| Some(format!("{}: {}", e.label, e.meta.get("activation")?)))
        .collect();
    if !sd.is_empty() {
        note += " The angle standard deviation is sqrt(P_11) of each filter's covariance: the \
                 Riccati solution of sdre (paper 004 eq 4.16), the EKF's P for ekf and knee-kinematic.";
    }
    if !models.is_empty() {
        note += &format!(
            " Activation in each estimate's model: {}.",
            models.join("; ")
        );
    }
    Panel {
        id: "panel-fes".into(),
        kind: "fes".into(),
        title: "FES stimulation and activation".into(),
        note,
        plots,
        table: String::new(),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn weight_names_parse() {
        assert_eq!(parse_weight("w_g03_ds"), Some((3, 1)));
        assert_eq!(parse_weight("w_g12_ss2"), Some((12, 2)));
        assert_eq!(parse_weight("w_gx_ds"), None);
        assert_eq!(parse_weight("speed_mean"), None);
    }

    #[test]
    fn forty_lines_have_forty_colours() {
        let colours: std::collections::BTreeSet<String> = (0..40).map(color).collect();
        assert_eq!(colours.len(), 40);
        assert_eq!(color(0), PALETTE[0]);
    }

    #[test]
    fn angle_to_final_axis() {
        let x: Column = vec![Some(1.0), Some(0.0), Some(0.0)];
        let y: Column = vec![Some(0.0), Some(1.0), Some(0.0)];
        let z: Column = vec![Some(0.0), Some(0.0), Some(2.0)];
        let a = angle_to_final(&[&x, &y, &z]);
        assert!((a[0].unwrap() - 90.0).abs() < 1e-9);
        assert!((a[2].unwrap()).abs() < 1e-9);
    }
}
