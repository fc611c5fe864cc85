//! The text table and JSON object of a [`GaitEventEvaluation`].

use serde_json::{json, Value};

use crate::blended_stride_speed::StrideFigures;
use crate::gait_events_evaluation::{EventTiming, GaitEventEvaluation};

impl StrideFigures {
    /// The JSON fields.
    pub fn to_json(&self) -> Value {
        json!({
            "n_strides": self.n_strides,
            "speed_mae_mps": self.speed_mae_mps,
            "speed_bias_mps": self.speed_bias_mps,
            "n_lengths": self.n_lengths,
            "stride_length_error_pct": self.stride_length_error_pct,
            "stride_length_mae_m": self.stride_length_mae_m,
        })
    }
}

impl EventTiming {
    /// The JSON object of one kind of event.
    pub fn to_json(&self) -> Value {
        json!({
            "n_reference": self.n_reference,
            "n_matched": self.n_matched,
            "missed": self.missed,
            "extra": self.extra,
            "median_abs_ms": self.median_abs_ms,
            "p95_abs_ms": self.p95_abs_ms,
            "mean_ms": self.mean_ms,
        })
    }

    /// One line of the text table; `columns`: which of `contact_left_ref`,
    /// `contact_right_ref` the trial has (what to blame when there is no
    /// reference event: the columns' absence, or no transition in them).
    pub fn to_text(&self, name: &str, columns: [bool; 2]) -> String {
        if self.n_reference == 0 {
            // (an audit: a trial without either column was told its
            // `contact_*_ref` had no transition)
            let why = match columns {
                [false, false] => {
                    "the trial has no contact_left_ref / contact_right_ref column".to_string()
                }
                [true, true] => "the trial's contact_*_ref has no transition".to_string(),
                [left, _] => format!(
                    "the trial's {} has no transition",
                    limbfuse_io::layout::contact_ref_column(if left {
                        limbfuse_core::Side::Left
                    } else {
                        limbfuse_core::Side::Right
                    })
                ),
            };
            return format!("{name:<16} no reference event to score against ({why})\n");
        }
        let f = |v: Option<f64>| v.map_or("-".to_string(), |v| format!("{v:.1}"));
        format!(
            "{name:<16} {} of {} found, {} missed, {} extra; |error| median {} ms, p95 {} ms, mean error {} ms\n",
            self.n_matched,
            self.n_reference,
            self.missed,
            self.extra,
            f(self.median_abs_ms),
            f(self.p95_abs_ms),
            f(self.mean_ms)
        )
    }
}

impl GaitEventEvaluation {
    /// SPEC section 4's JSON object (no angle channels) plus the gait-event fields.
    pub fn to_json(&self) -> Value {
        let mut v = json!({
            "method": self.method,
            "n_samples": self.n_samples,
            "rmse_deg": {},
            "mean_rmse_deg": null,
            "max_abs_err_deg": {},
            "corr": {},
            "initial_contact": self.initial_contact.to_json(),
            "final_contact": self.final_contact.as_ref().map(EventTiming::to_json),
            "events_per_foot": self.per_foot,
            "contact_sides": self.contact_sides.as_ref().map(|s| s.to_json()),
            "contact_accuracy_pct": self.contact_accuracy_pct,
            "phase_accuracy_pct": self.phase_accuracy_pct,
            "blended": self.blended.to_json(),
            "n_withheld": self.n_withheld,
            "speed_reference": if self.speed_from_com { "com_velocity" } else { "speed_ref" },
        });
        for fields in [self.per_stride.to_json(), self.stance_swing.to_json()] {
            if let (Value::Object(top), Value::Object(fields)) = (&mut v, fields) {
                top.extend(fields);
            }
        }
        if let (Value::Object(top), false) = (&mut v, self.warnings.is_empty()) {
            top.insert("warnings".into(), json!(self.warnings));
        }
        v
    }

    /// A short text table.
    pub fn to_text(&self) -> String {
        let f = |v: Option<f64>, unit: &str, d: usize| {
            v.map_or("-".to_string(), |v| format!("{v:.d$} {unit}"))
        };
        let mut s = format!("method {} ({} samples)\n", self.method, self.n_samples);
        s += &self
            .initial_contact
            .to_text("initial contact", self.contact_ref_columns);
        match &self.final_contact {
            Some(fc) => {
                s += &fc.to_text("final contact", self.contact_ref_columns);
                s += &self.stance_swing.to_text();
            }
            None => s += "final contact    not estimated by this method\n",
        }
        match (&self.contact_sides, self.per_foot) {
            (Some(sides), _) => s += &sides.to_text(),
            (None, false) => s +=
                "(initial contacts pooled over both feet: the method does not tell which foot)\n",
            (None, true) => {}
        }
        s += &format!(
            "contact accuracy {}\nphase accuracy   {}\nstride speed     MAE {} (bias {}) over {} strides\nstride length    error {} (MAE {}) over {} strides\n",
            f(self.contact_accuracy_pct, "%", 1),
            f(self.phase_accuracy_pct, "%", 1),
            f(self.per_stride.speed_mae_mps, "m/s", 3),
            f(self.per_stride.speed_bias_mps, "m/s", 3),
            self.per_stride.n_strides,
            f(self.per_stride.stride_length_error_pct, "%", 2),
            f(self.per_stride.stride_length_mae_m, "m", 3),
            self.per_stride.n_lengths,
        );
        if self.n_withheld > 0 {
            s += &format!(
                "(not scored: {} strides with a reference that the method withheld for a turn: no speed or length; `speed_withheld` in --strides)\n",
                self.n_withheld
            );
        }
        if self.speed_from_com {
            s += "(stride speed against the trial's horizontal CoM speed, row by row: it has no speed_ref column)\n";
            return s;
        }
        let b = &self.blended;
        s += &format!(
            "blended strides speed MAE {} (bias {}) over {} strides; length error {} (MAE {}) over {} (estimate blended as speed_ref is)\n",
            f(b.speed_mae_mps, "m/s", 3),
            f(b.speed_bias_mps, "m/s", 3),
            b.n_strides,
            f(b.stride_length_error_pct, "%", 2),
            f(b.stride_length_mae_m, "m", 3),
            b.n_lengths,
        );
        s
    }
}
