//! Evaluation of gait estimates (paper 003): phase accuracy against
//! `phase_ref`, CoM position error against `com_x..com_z`, and the speed
//! estimate against the reference mean forward CoM velocity.

use std::path::Path;

use limbfuse_io::{EstimateReader, TrialReader};
use serde_json::{json, Value};

use crate::evaluation::EvalError;

/// Gait-estimate errors over a trial.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct GaitEvaluation {
    /// Method name.
    pub method: String,
    /// Samples compared.
    pub n_samples: u64,
    /// % of samples with both phases whose estimated phase equals `phase_ref`.
    pub phase_accuracy_pct: Option<f64>,
    /// Phase confusion counts `[true][estimated]`, order SS1, DS, SS2.
    pub phase_confusion: [[u64; 3]; 3],
    /// RMS of the 3D CoM position error (m).
    pub com_pos_rmse_m: Option<f64>,
    /// Largest 3D CoM position error (m).
    pub com_pos_max_m: Option<f64>,
    /// Mean of the `speed` column (m/s).
    pub speed_mean_mps: Option<f64>,
    /// Mean reference forward CoM velocity (m/s).
    pub speed_ref_mps: Option<f64>,
    /// Whether the estimate file records this trial ([`crate::trial_check`]).
    pub trial_check: crate::trial_check::TrialCheck,
    /// Last lines left out of the two files, cut off mid-row (as
    /// [`crate::Evaluation::cut_lines`]); in the JSON under `warnings`.
    pub cut_lines: Vec<String>,
}

fn index(p: limbfuse_core::GaitPhase) -> usize {
    match p {
        limbfuse_core::GaitPhase::Ss1 => 0,
        limbfuse_core::GaitPhase::Ds => 1,
        limbfuse_core::GaitPhase::Ss2 => 2,
    }
}

/// Compares a gait estimate with its trial (same time base); an estimate
/// recording another trial is refused unless `allow_trial_mismatch`
/// ([`crate::trial_check`]).
pub fn evaluate_gait_files(
    trial: &Path,
    estimate: &Path,
    allow_trial_mismatch: bool,
) -> Result<GaitEvaluation, EvalError> {
    let hash = limbfuse_io::TrialFingerprint::of_file(trial)?.hash;
    let mut tr = TrialReader::open(trial)?;
    let mut er = EstimateReader::open(estimate)?;
    let trial_check = crate::trial_check::check_trial(trial, hash, &er, allow_trial_mismatch)?;
    let mut ev = GaitEvaluation {
        method: er.method().to_string(),
        trial_check,
        ..Default::default()
    };
    let (mut se, mut n_pos, mut max) = (0.0, 0u64, 0.0f64);
    let (mut speed, mut n_speed, mut vref, mut n_vref) = (0.0, 0u64, 0.0, 0u64);
    let mut index_row = 0u64;
    loop {
        match (tr.next_record()?, er.next_estimate()?) {
            (None, None) => break,
            (Some(r), Some((line, e))) => {
                EvalError::check_same_time(estimate, line, index_row, e.t, r.sample.t)?;
                ev.n_samples += 1;
                if let (Some(a), Some(b)) = (r.reference.phase, e.phase) {
                    ev.phase_confusion[index(a)][index(b)] += 1;
                }
                if let (Some(a), Some(b)) = (r.reference.com_pos, e.com_pos) {
                    let d = (a - b).norm();
                    se += d * d;
                    max = max.max(d);
                    n_pos += 1;
                }
                if let Some(s) = e.speed {
                    speed += s;
                    n_speed += 1;
                }
                if let Some(v) = r.reference.com_vel {
                    vref += v[0];
                    n_vref += 1;
                }
            }
            (Some(_), None) | (None, Some(_)) => {
                return Err(crate::evaluation::length_mismatch(
                    format!(
                        "{} and {} have different numbers of samples (mismatch after {index_row})",
                        trial.display(),
                        estimate.display()
                    ),
                    crate::evaluation::cut_lines(Some(&tr), &er),
                ))
            }
        }
        index_row += 1;
    }
    let n_phase: u64 = ev.phase_confusion.iter().flatten().sum();
    if n_phase > 0 {
        let ok: u64 = (0..3).map(|i| ev.phase_confusion[i][i]).sum();
        ev.phase_accuracy_pct = Some(100.0 * ok as f64 / n_phase as f64);
    }
    if n_pos > 0 {
        ev.com_pos_rmse_m = Some((se / n_pos as f64).sqrt());
        ev.com_pos_max_m = Some(max);
    }
    ev.speed_mean_mps = (n_speed > 0).then(|| speed / n_speed as f64);
    ev.speed_ref_mps = (n_vref > 0).then(|| vref / n_vref as f64);
    ev.cut_lines = crate::evaluation::cut_lines(Some(&tr), &er);
    Ok(ev)
}

impl GaitEvaluation {
    /// SPEC section 4's JSON object (no angle channels) plus the gait fields.
    pub fn to_json(&self) -> Value {
        let mut v = json!({
            "method": self.method,
            "n_samples": self.n_samples,
            "rmse_deg": {},
            "mean_rmse_deg": null,
            "max_abs_err_deg": {},
            "corr": {},
            "phase_accuracy_pct": self.phase_accuracy_pct,
            "phase_confusion": self.phase_confusion,
            "com_pos_rmse_m": self.com_pos_rmse_m,
            "com_pos_max_m": self.com_pos_max_m,
            "speed_mean_mps": self.speed_mean_mps,
            "speed_ref_mps": self.speed_ref_mps,
            "speed_error_mps": match (self.speed_mean_mps, self.speed_ref_mps) {
                (Some(a), Some(b)) => Some(a - b),
                _ => None,
            },
        });
        if let (false, Some(obj)) = (self.cut_lines.is_empty(), v.as_object_mut()) {
            obj.insert("warnings".into(), json!(self.cut_lines));
        }
        v
    }

    /// A short text table.
    pub fn to_text(&self) -> String {
        let f = |v: Option<f64>, scale: f64, unit: &str| {
            v.map_or("-".to_string(), |v| format!("{:.3} {unit}", v * scale))
        };
        format!(
            "method {} ({} samples)\nphase accuracy   {}\nCoM position RMS {}  (max {})\nspeed estimate   {}  (reference mean forward CoM velocity {})\nphase confusion [true SS1/DS/SS2][est]: {:?}\n",
            self.method,
            self.n_samples,
            self.phase_accuracy_pct.map_or("-".into(), |v| format!("{v:.1} %")),
            f(self.com_pos_rmse_m, 100.0, "cm"),
            f(self.com_pos_max_m, 100.0, "cm"),
            f(self.speed_mean_mps, 1.0, "m/s"),
            f(self.speed_ref_mps, 1.0, "m/s"),
            self.phase_confusion
        )
    }
}
