//! `limbfuse tune --method sdre|ekf PRETRIAL --params model.toml -o tuned.toml`
//! (issue 16 item 3): how much the extended knee filter trusts its model,
//! chosen by leave-one-pulse-out cross-validation on a pre-trial with a
//! knee reference (`limbfuse_workflows::fes_pulse_cv`), never on the trial
//! the tuned file is then used on.

use std::path::Path;

use anyhow::{anyhow, bail, Context, Result};
use limbfuse_eval::TimeWindow;
use limbfuse_methods::{MethodFlags, MethodName, MethodSpec};
use limbfuse_workflows::fes_pulse_cv::{
    leave_one_pulse_out, pulse_windows, window_errors, WindowErrors,
};

use crate::cli::TuneArgs;

/// Candidate relative torque errors `e` (the filter admits `e m g l_c`):
/// 1 % to 10 times the gravity torque, half a decade apart.
pub const TORQUE_ERRORS: [f64; 7] = [0.01, 0.03, 0.1, 0.3, 1.0, 3.0, 10.0];

/// Tunes `[tuning] torque_error` of `sdre` / `ekf` on the pre-trial.
pub fn run(a: &TuneArgs, name: MethodName) -> Result<()> {
    let Some(params) = a.params.as_deref() else {
        bail!(
            "tune --method {name}: give the knee model's parameter file with --params, with [states] \
             (e.g. activation, gyro_bias, acc_bias) or [measurement]: the torque error tuned here \
             belongs to the extended knee model (docs/FES_ESTIMATION.md)"
        );
    };
    let ignored = a.optimiser_flags();
    if !ignored.is_empty() {
        bail!(
            "tune --method {name}: {} {} to local, mjls and global only; sdre and ekf choose the \
             torque error among fixed candidates by leave-one-pulse-out cross-validation within \
             --window (docs/FES_ESTIMATION.md)",
            ignored.join(", "),
            if ignored.len() == 1 {
                "applies"
            } else {
                "apply"
            }
        );
    }
    let spec = MethodSpec::resolve(name, Some(params), &MethodFlags::default())?;
    let file = match &spec {
        MethodSpec::Sdre(f) | MethodSpec::Ekf(f) => f.clone(),
        _ => bail!("tune --method {name}: not a knee-FES filter"),
    };
    if !file.is_extended() {
        bail!(
            "{}: tune --method {name} tunes the extended knee model's torque error; the file has \
             neither [states] nor [measurement] (the thesis model's q is tuned by hand, \
             docs/FES_ESTIMATION.md)",
            params.display()
        );
    }
    let window = TimeWindow::parse(&a.window).map_err(|m| anyhow!("--window: {m}"))?;
    let trial = super::protocol::read_trial(&a.trial, name)?;
    if !trial.layout.stim[0] {
        bail!(
            "{}: no `u_ke` column: the pre-trial needs the quadriceps stimulation (its pulses are \
             the cross-validation folds)",
            a.trial.display()
        );
    }
    let records: Vec<_> = trial
        .records
        .into_iter()
        .filter(|r| window.contains(r.sample.t))
        .collect();
    if !records.iter().any(|r| r.reference.joint[1].is_some()) {
        bail!(
            "{}: no `knee_ref` sample in --window {}: the pre-trial needs a knee reference (encoder or goniometer)",
            a.trial.display(),
            a.window
        );
    }
    let starts = pulse_windows(&records);
    if starts.len() < 2 {
        bail!(
            "{}: fewer than two stimulation pulses (`u_ke` rising from 0) in --window {}: \
             leave-one-pulse-out needs at least two",
            a.trial.display(),
            a.window
        );
    }
    let bar = crate::progress::bar(
        TORQUE_ERRORS.len() as u64,
        "tune {prefix} {bar:30} {pos}/{len} candidates [{elapsed} < {eta}]",
    );
    bar.set_prefix(name.to_string());
    let mut errors: Vec<WindowErrors> = Vec::with_capacity(TORQUE_ERRORS.len());
    for e in TORQUE_ERRORS {
        let candidate = file.clone().with_torque_error(e);
        let s = match name {
            MethodName::Sdre => MethodSpec::Sdre(candidate),
            _ => MethodSpec::Ekf(candidate),
        };
        let mut est = limbfuse_methods::build(&s, &trial.meta, &trial.layout)
            .with_context(|| a.trial.display().to_string())?;
        errors.push(window_errors(est.as_mut(), &records, &starts));
        bar.inc(1);
    }
    bar.finish_and_clear();
    let cv = leave_one_pulse_out(&errors).ok_or_else(|| anyhow!("no candidate was run"))?;
    if !cv.rmse_deg[cv.chosen].is_finite() {
        bail!(
            "{}: every candidate diverged on the pre-trial; check the model file {}",
            a.trial.display(),
            params.display()
        );
    }
    let e = TORQUE_ERRORS[cv.chosen];
    let text = std::fs::read_to_string(params)
        .with_context(|| format!("{}: cannot read the parameter file", params.display()))?;
    let header = format!(
        "# tuned by: limbfuse tune --method {name} {} --window {} --params {}\n\
         # leave-one-pulse-out over {} pulse windows: torque_error {e} chosen, cross-validated knee RMSE {:.3} deg\n",
        file_name(&a.trial),
        a.window,
        file_name(params),
        starts.len(),
        cv.cv_rmse_deg
    );
    super::write_file(&a.output, header + &with_torque_error(&text, e))?;
    println!(
        "tune {name}: {} pulse windows of {}, knee RMSE (deg) over all windows per torque error:",
        starts.len(),
        a.trial.display()
    );
    for (c, r) in TORQUE_ERRORS.iter().zip(&cv.rmse_deg) {
        let mark = if *c == e { "  <- chosen" } else { "" };
        match r.is_finite() {
            true => println!("  torque_error {c:>5}: {r:.3}{mark}"),
            // (an audit: printed `inf` without a word)
            false => println!("  torque_error {c:>5}: diverged (the filter restarted){mark}"),
        }
    }
    println!(
        "cross-validated knee RMSE {:.3} deg (each pulse scored with the choice made on the others)",
        cv.cv_rmse_deg
    );
    eprintln!("wrote {}", a.output.display());
    Ok(())
}

/// `text` (a TOML parameter file) with `[tuning] torque_error = e`: an
/// earlier `torque_error` line is dropped, the key goes right under the
/// `[tuning]` header, or into a new `[tuning]` table at the end.
fn with_torque_error(text: &str, e: f64) -> String {
    let line = format!("torque_error = {e}");
    let mut out = String::with_capacity(text.len() + 64);
    let mut placed = false;
    for l in text.lines() {
        let t = l.trim_start();
        if t.starts_with("torque_error") && t[12..].trim_start().starts_with('=') {
            continue;
        }
        out.push_str(l);
        out.push('\n');
        if !placed && t.starts_with("[tuning]") {
            out.push_str(&line);
            out.push('\n');
            placed = true;
        }
    }
    if !placed {
        out.push_str(&format!("\n[tuning]\n{line}\n"));
    }
    out
}

/// The file name of `path` (its display form if it has none).
fn file_name(path: &Path) -> String {
    path.file_name().map_or_else(
        || path.display().to_string(),
        |n| n.to_string_lossy().into_owned(),
    )
}

#[cfg(test)]
mod tests {
    use super::with_torque_error;

    #[test]
    fn the_torque_error_replaces_an_earlier_one_under_the_tuning_header() {
        let a = with_torque_error("[states]\nactivation = true\n", 0.3);
        assert_eq!(
            a,
            "[states]\nactivation = true\n\n[tuning]\ntorque_error = 0.3\n"
        );
        let b = with_torque_error(
            "[tuning]  # x\nq = [1, 2]\ntorque_error = 1\n[states]\n",
            3.0,
        );
        assert_eq!(b, "[tuning]  # x\ntorque_error = 3\nq = [1, 2]\n[states]\n");
    }
}
