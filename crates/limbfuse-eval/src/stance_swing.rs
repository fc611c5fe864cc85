//! Stance and swing time per stride against the reference (the temporal
//! parameters of gaitmap's and mobgap's per-stride tables, whose validation
//! papers report their errors; docs/GAIT_EVENTS.md "Evaluation").
//!
//! A stride's stance time is its final contact minus its initial contact,
//! its swing time its next initial contact minus the final contact
//! ([`crate::stride_table`]'s `stance_time_s`, `swing_time_s`). The
//! reference ones come from the reference contacts the evaluation pairs
//! with those three estimated contacts (the pairing that scores the
//! initial- and final-contact timing, not a second one). A stride is scored
//! when both its reference stance and swing times are known, so the two
//! errors are over the same strides.

use serde_json::{json, Value};

use crate::stride_table::StrideRow;

/// Stance and swing time errors (estimate - reference), in ms.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct StanceSwingFigures {
    /// Strides scored (stance and swing time known in estimate and reference).
    pub n_strides: usize,
    /// Mean |stance time error| (ms).
    pub stance_time_mae_ms: Option<f64>,
    /// Mean stance time error, estimate - reference (ms).
    pub stance_time_bias_ms: Option<f64>,
    /// Mean |swing time error| (ms).
    pub swing_time_mae_ms: Option<f64>,
    /// Mean swing time error, estimate - reference (ms).
    pub swing_time_bias_ms: Option<f64>,
}

impl StanceSwingFigures {
    /// The figures of the strides `rows` with stance and swing times known
    /// in the estimate and the reference.
    pub fn of_strides(rows: &[StrideRow]) -> Self {
        let errors: Vec<(f64, f64)> = rows
            .iter()
            .filter_map(|r| {
                let stance = r.stance_time_s? - r.stance_time_ref_s?;
                let swing = r.swing_time_s? - r.swing_time_ref_s?;
                Some((stance, swing))
            })
            .collect();
        Self::from_errors(&errors)
    }

    /// The figures of `(stance, swing)` time errors (s, estimate - reference).
    pub fn from_errors(errors: &[(f64, f64)]) -> Self {
        let n = errors.len();
        let mean_ms = |f: &dyn Fn(&(f64, f64)) -> f64| {
            (n > 0).then(|| 1e3 * errors.iter().map(f).sum::<f64>() / n as f64)
        };
        StanceSwingFigures {
            n_strides: n,
            stance_time_mae_ms: mean_ms(&|e| e.0.abs()),
            stance_time_bias_ms: mean_ms(&|e| e.0),
            swing_time_mae_ms: mean_ms(&|e| e.1.abs()),
            swing_time_bias_ms: mean_ms(&|e| e.1),
        }
    }

    /// The JSON fields (top-level fields of `evaluate --json`, as the
    /// per-stride speed's).
    pub fn to_json(&self) -> Value {
        json!({
            "n_stance_swing": self.n_strides,
            "stance_time_mae_ms": self.stance_time_mae_ms,
            "stance_time_bias_ms": self.stance_time_bias_ms,
            "swing_time_mae_ms": self.swing_time_mae_ms,
            "swing_time_bias_ms": self.swing_time_bias_ms,
        })
    }

    /// The two lines of `evaluate`'s text table.
    pub fn to_text(&self) -> String {
        let f = |v: Option<f64>| v.map_or("-".to_string(), |v| format!("{v:.1} ms"));
        [
            (
                "stance time",
                self.stance_time_mae_ms,
                self.stance_time_bias_ms,
            ),
            (
                "swing time",
                self.swing_time_mae_ms,
                self.swing_time_bias_ms,
            ),
        ]
        .iter()
        .map(|(name, mae, bias)| {
            format!(
                "{name:<16} MAE {} (bias {}) over {} strides\n",
                f(*mae),
                f(*bias),
                self.n_strides
            )
        })
        .collect()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn stance_swing_errors_are_mean_absolute_and_signed_in_ms() {
        let s = StanceSwingFigures::from_errors(&[(0.010, -0.020), (-0.030, 0.000)]);
        let near = |a: Option<f64>, b: f64| a.is_some_and(|a| (a - b).abs() < 1e-9);
        assert_eq!(s.n_strides, 2);
        assert!(near(s.stance_time_mae_ms, 20.0) && near(s.stance_time_bias_ms, -10.0));
        assert!(near(s.swing_time_mae_ms, 10.0) && near(s.swing_time_bias_ms, -10.0));
        assert_eq!(
            s.to_text(),
            "stance time      MAE 20.0 ms (bias -10.0 ms) over 2 strides\n\
             swing time       MAE 10.0 ms (bias -10.0 ms) over 2 strides\n"
        );
        let none = StanceSwingFigures::from_errors(&[]);
        assert_eq!(none.stance_time_mae_ms, None);
        assert_eq!(none.to_json()["n_stance_swing"], 0);
        assert!(none.to_json()["swing_time_bias_ms"].is_null());
    }
}
