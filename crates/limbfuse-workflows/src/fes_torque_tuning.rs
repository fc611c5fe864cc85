//! `limbfuse tune --method sdre|ekf` as one function (the CLI and the
//! Python `tune` call it; issue 16 item 3): the extended knee model's
//! relative torque error chosen among fixed candidates by leave-one-pulse-out
//! cross-validation ([`crate::fes_pulse_cv`]) on a pre-trial with a knee
//! reference, never on the trial the tuned file is then used on.

use limbfuse_core::Record;
use limbfuse_io::{TrialLayout, TrialMeta};
use limbfuse_methods::fes_params::FesParamsFile;
use limbfuse_methods::{MethodError, MethodName, MethodSpec};

use rayon::prelude::*;

use crate::fes_pulse_cv::{leave_one_pulse_out, pulse_windows, window_errors_until, WindowErrors};
use crate::parallel_cancellation::{run_with_stop_flag, StopFlag};

/// Candidate relative torque errors `e` (the filter admits `e m g l_c`):
/// 1 % to 10 times the gravity torque, half a decade apart.
pub const TORQUE_ERRORS: [f64; 7] = [0.01, 0.03, 0.1, 0.3, 1.0, 3.0, 10.0];

/// Why the torque error could not be tuned. `window` is the window as the
/// caller names it (the CLI: `--window 0:60`).
#[derive(Debug, thiserror::Error)]
pub enum TorqueTuningError {
    /// Not `sdre` or `ekf`.
    #[error("tune: `{0}` is not a knee-FES filter (sdre or ekf)")]
    NotKneeFes(MethodName),
    /// The thesis model's file.
    #[error(
        "tune --method {0} tunes the extended knee model's torque error; the file has neither \
         [states] nor [measurement] (the thesis model's q is tuned by hand, docs/FES_ESTIMATION.md)"
    )]
    NotExtended(MethodName),
    /// No stimulation column.
    #[error(
        "no `u_ke` column: the pre-trial needs the quadriceps stimulation (its pulses are the \
         cross-validation folds)"
    )]
    NoStimulation,
    /// No knee reference in the window.
    #[error(
        "no `knee_ref` sample in {window}: the pre-trial needs a knee reference (encoder or \
         goniometer)"
    )]
    NoReference {
        /// The window as named by the caller.
        window: String,
    },
    /// Fewer than two pulses in the window.
    #[error(
        "fewer than two stimulation pulses (`u_ke` rising from 0) in {window}: leave-one-pulse-out \
         needs at least two"
    )]
    FewPulses {
        /// The window as named by the caller.
        window: String,
    },
    /// Every candidate restarted.
    #[error("every candidate diverged on the pre-trial; check the model file")]
    AllDiverged,
    /// A candidate filter could not be built for the trial.
    #[error(transparent)]
    Build(#[from] MethodError),
    /// The caller's cancellation hook stopped the tuning.
    #[error("stopped before the end")]
    Cancelled,
}

/// The outcome: every candidate's knee RMSE and the choice.
#[derive(Debug, Clone, PartialEq)]
pub struct TorqueTuning {
    /// The method tuned.
    pub method: MethodName,
    /// Pulse windows (cross-validation folds).
    pub windows: usize,
    /// Knee RMSE over all windows per candidate of [`TORQUE_ERRORS`] (deg;
    /// infinite where the filter restarted).
    pub rmse_deg: Vec<f64>,
    /// The chosen torque error (least RMSE over all windows).
    pub torque_error: f64,
    /// Each window scored with the choice made on the others (deg).
    pub cv_rmse_deg: f64,
}

impl TorqueTuning {
    /// The CLI's summary: one line per candidate, the choice marked, and
    /// the cross-validated RMSE; `trial` names the pre-trial.
    pub fn table(&self, trial: &str) -> String {
        let mut out = format!(
            "tune {}: {} pulse windows of {trial}, knee RMSE (deg) over all windows per torque \
             error:\n",
            self.method, self.windows
        );
        for (c, r) in TORQUE_ERRORS.iter().zip(&self.rmse_deg) {
            let mark = if *c == self.torque_error {
                "  <- chosen"
            } else {
                ""
            };
            match r.is_finite() {
                true => out += &format!("  torque_error {c:>5}: {r:.3}{mark}\n"),
                // (an audit: printed `inf` without a word)
                false => {
                    out +=
                        &format!("  torque_error {c:>5}: diverged (the filter restarted){mark}\n")
                }
            }
        }
        out += &format!(
            "cross-validated knee RMSE {:.3} deg (each pulse scored with the choice made on the \
             others)\n",
            self.cv_rmse_deg
        );
        out
    }

    /// The `#` lines the tuned file starts with after its `# tuned by:`
    /// line.
    pub fn comment(&self) -> String {
        format!(
            "# leave-one-pulse-out over {} pulse windows: torque_error {} chosen, cross-validated \
             knee RMSE {:.3} deg\n",
            self.windows, self.torque_error, self.cv_rmse_deg
        )
    }
}

/// Tunes `[tuning] torque_error` of `method` (`sdre` or `ekf`, model
/// `file`) on `records`, the pre-trial's samples within the window (named
/// `window` in errors) of a trial with this metadata and layout.
/// The seven candidates run in parallel (rayon); `on_candidate` is called
/// after each (progress). `cancel` is asked on the calling thread every
/// 50 ms ([`crate::parallel_cancellation`]); a candidate stops within 4096
/// samples of its verdict.
pub fn tune_torque_error(
    method: MethodName,
    file: &FesParamsFile,
    (meta, layout): (&TrialMeta, &TrialLayout),
    records: &[Record],
    window: &str,
    on_candidate: &(dyn Fn() + Sync),
    cancel: Option<&dyn Fn() -> bool>,
) -> Result<TorqueTuning, TorqueTuningError> {
    if !matches!(method, MethodName::Sdre | MethodName::Ekf) {
        return Err(TorqueTuningError::NotKneeFes(method));
    }
    if !file.is_extended() {
        return Err(TorqueTuningError::NotExtended(method));
    }
    if !layout.stim[0] {
        return Err(TorqueTuningError::NoStimulation);
    }
    let window = window.to_string();
    if !records.iter().any(|r| r.reference.joint[1].is_some()) {
        return Err(TorqueTuningError::NoReference { window });
    }
    let starts = pulse_windows(records);
    if starts.len() < 2 {
        return Err(TorqueTuningError::FewPulses { window });
    }
    // The candidates are independent runs: on rayon's pool, largest torque
    // error first (the stiffer its Riccati equation, the more sub-steps: on
    // 600 s, e = 10 takes 11.6 s, e = 0.01 0.2 s, so the longest starts
    // first), then put back in candidate order (the result does not depend
    // on the thread count).
    let mut errors = run_with_stop_flag(
        |stop: &StopFlag| -> Result<Vec<WindowErrors>, TorqueTuningError> {
            TORQUE_ERRORS
                .par_iter()
                .rev()
                .map(|&e| {
                    if stop.raised() {
                        return Err(TorqueTuningError::Cancelled);
                    }
                    let candidate = file.clone().with_torque_error(e);
                    let spec = match method {
                        MethodName::Sdre => MethodSpec::Sdre(candidate),
                        _ => MethodSpec::Ekf(candidate),
                    };
                    let mut est = limbfuse_methods::build(&spec, meta, layout)?;
                    let errors =
                        window_errors_until(est.as_mut(), records, &starts, &|| stop.raised())
                            .ok_or(TorqueTuningError::Cancelled)?;
                    on_candidate();
                    Ok(errors)
                })
                .collect()
        },
        cancel,
    )?;
    errors.reverse();
    let cv = leave_one_pulse_out(&errors).ok_or(TorqueTuningError::AllDiverged)?;
    if !cv.rmse_deg[cv.chosen].is_finite() {
        return Err(TorqueTuningError::AllDiverged);
    }
    Ok(TorqueTuning {
        method,
        windows: starts.len(),
        rmse_deg: cv.rmse_deg,
        torque_error: TORQUE_ERRORS[cv.chosen],
        cv_rmse_deg: cv.cv_rmse_deg,
    })
}

/// `text` (a TOML parameter file) with `[tuning] torque_error = e`: an
/// earlier `torque_error` line is dropped, the key goes right under the
/// `[tuning]` header, or into a new `[tuning]` table at the end.
pub fn with_torque_error(text: &str, e: f64) -> String {
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
