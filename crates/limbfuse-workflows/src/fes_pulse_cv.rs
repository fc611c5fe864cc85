//! Issue 16 item 3: choosing how much a knee-FES filter trusts its model by
//! cross-validation on the held-out stimulation pulses of a pre-trial with
//! a reference (encoder or goniometer), never on the test trial.
//!
//! The knob is the relative torque error `e` of
//! `limbfuse_estimators::fes::knee_extended::extended_knee_tuning` (`q_2`,
//! `q_d`, `p0_d` scale with `e^2`; the filter admits a torque error of
//! `e m g l_c`). The pre-trial is cut at the stimulation onsets into pulse
//! windows (the first from `T_SKIP` to the second onset, each later one from
//! its onset to the next); each candidate `e` runs once over the whole
//! pre-trial (the filter is causal, so a window's error does not depend on
//! later data) and its squared knee error is summed per window. Leave one
//! pulse out: for each window, the `e` with the least error on the other
//! windows is scored on it; the cross-validated RMSE pools those held-out
//! errors. The chosen `e` is the one with the least error over all windows.
//! A run that restarts (divergence) scores infinity.
//! Used by `limbfuse tune --method sdre|ekf` and the example `fes_tune_cv`.

use limbfuse_core::{Estimator, Record};

/// The first second of every trial is left out of every error (start-up).
pub const T_SKIP: f64 = 1.0;

/// Per-window sums of squared knee error (rad^2) and sample counts.
#[derive(Debug, Clone, PartialEq)]
pub struct WindowErrors {
    /// Sum of squared knee errors per pulse window (infinity on divergence).
    pub sse: Vec<f64>,
    /// Samples per window.
    pub n: Vec<usize>,
}

/// Start times of the pulse windows of `recs`: `T_SKIP`, then every
/// stimulation onset (`u_ke` from 0 to above 0) after the first one that
/// lies after `T_SKIP`. Trials without `u_ke` give one window.
pub fn pulse_windows(recs: &[Record]) -> Vec<f64> {
    let mut starts = vec![T_SKIP];
    let mut prev = 0.0;
    let mut first = true;
    for r in recs {
        let u = r.sample.inputs.stim[0].unwrap_or(0.0);
        if prev <= 0.0 && u > 0.0 && r.sample.t > T_SKIP {
            if first {
                first = false;
            } else {
                starts.push(r.sample.t);
            }
        }
        prev = u;
    }
    starts
}

/// Runs `est` over `recs` and sums its squared knee error per window
/// (`starts` from [`pulse_windows`]).
pub fn window_errors(est: &mut dyn Estimator, recs: &[Record], starts: &[f64]) -> WindowErrors {
    // (never stopped, it always finishes: the fallback is never taken)
    window_errors_until(est, recs, starts, &|| false).unwrap_or_else(|| WindowErrors {
        sse: vec![f64::INFINITY; starts.len()],
        n: vec![0; starts.len()],
    })
}

/// Samples between two looks at a stop check.
const STOP_STRIDE: usize = 4096;

/// [`window_errors`] that stops when `stop` says so (asked every 4096
/// samples): `None` then.
pub fn window_errors_until(
    est: &mut dyn Estimator,
    recs: &[Record],
    starts: &[f64],
    stop: &dyn Fn() -> bool,
) -> Option<WindowErrors> {
    let mut out = WindowErrors {
        sse: vec![0.0; starts.len()],
        n: vec![0; starts.len()],
    };
    let resets = est.diagnostic_names().iter().position(|n| *n == "resets");
    for (i, r) in recs.iter().enumerate() {
        if i % STOP_STRIDE == STOP_STRIDE - 1 && stop() {
            return None;
        }
        let diverged = match est.step(&r.sample) {
            Err(_) => true,
            Ok(e) => {
                if resets.and_then(|c| e.diag[c]).is_some_and(|v| v > 0.0) {
                    true
                } else if let Some(w) = starts.iter().rposition(|s| r.sample.t >= *s) {
                    if let (Some(a), Some(b)) = (e.joint[1], r.reference.joint[1]) {
                        out.sse[w] += (a - b) * (a - b);
                        out.n[w] += 1;
                    }
                    !(e.joint[1].is_some_and(f64::is_finite))
                } else {
                    false
                }
            }
        };
        if diverged {
            out.sse.iter_mut().for_each(|v| *v = f64::INFINITY);
            return Some(out);
        }
    }
    Some(out)
}

/// Result of [`leave_one_pulse_out`].
#[derive(Debug, Clone, PartialEq)]
pub struct CrossValidation {
    /// Index of the chosen candidate (least error over every window).
    pub chosen: usize,
    /// Cross-validated knee RMSE (deg): each window scored with the
    /// candidate chosen on the other windows.
    pub cv_rmse_deg: f64,
    /// RMSE over every window per candidate (deg).
    pub rmse_deg: Vec<f64>,
}

fn rmse_deg(sse: f64, n: usize) -> f64 {
    (sse / n.max(1) as f64).sqrt().to_degrees()
}

/// Leave-one-pulse-out cross-validation over candidates (`errors[c]` the
/// window errors of candidate `c`, all with the same windows). `None`
/// without candidates or with fewer than two windows.
pub fn leave_one_pulse_out(errors: &[WindowErrors]) -> Option<CrossValidation> {
    let windows = errors.first()?.sse.len();
    if windows < 2 {
        return None;
    }
    let total = |c: &WindowErrors, skip: Option<usize>| {
        let (mut s, mut n) = (0.0, 0);
        for w in (0..windows).filter(|w| Some(*w) != skip) {
            s += c.sse[w];
            n += c.n[w];
        }
        rmse_deg(s, n)
    };
    let best = |skip: Option<usize>| {
        (0..errors.len())
            .min_by(|a, b| total(&errors[*a], skip).total_cmp(&total(&errors[*b], skip)))
            .unwrap_or(0)
    };
    let (mut s, mut n) = (0.0, 0);
    for w in 0..windows {
        let c = &errors[best(Some(w))];
        s += c.sse[w];
        n += c.n[w];
    }
    Some(CrossValidation {
        chosen: best(None),
        cv_rmse_deg: rmse_deg(s, n),
        rmse_deg: errors.iter().map(|c| total(c, None)).collect(),
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn we(sse: &[f64]) -> WindowErrors {
        WindowErrors {
            sse: sse.to_vec(),
            n: vec![1; sse.len()],
        }
    }

    /// Candidate 0 wins on windows 0-1, candidate 1 on window 2 and
    /// overall; held out, window 2 is scored with candidate 0 (best on
    /// windows 0-1), windows 0 and 1 with candidate 1.
    #[test]
    fn leave_one_pulse_out_scores_each_window_with_the_others_choice() {
        let cv = leave_one_pulse_out(&[we(&[1.0, 1.0, 10.0]), we(&[2.0, 2.0, 1.0])]).unwrap();
        assert_eq!(cv.chosen, 1);
        let want = ((2.0 + 2.0 + 10.0) / 3.0f64).sqrt().to_degrees();
        assert!((cv.cv_rmse_deg - want).abs() < 1e-12, "{cv:?}");
        assert!(leave_one_pulse_out(&[we(&[1.0])]).is_none());
        assert!(leave_one_pulse_out(&[]).is_none());
    }
}
