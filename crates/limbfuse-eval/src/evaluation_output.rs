//! How an [`Evaluation`] is written: SPEC section 4's JSON object
//! (`evaluate --json`, Python's `evaluate`) and the text table `evaluate`
//! prints.

use serde_json::{json, Map, Value};

use crate::metrics::{ChannelCoverage, Evaluation};

impl Evaluation {
    /// The JSON object of SPEC section 4 (angles in degrees), with a
    /// `resets` object (`count`, `first_t_s`) only when the estimator restarted.
    pub fn to_json(&self) -> Value {
        let mut rmse = Map::new();
        let mut max_abs = Map::new();
        let mut corr = Map::new();
        let mut mean_err = Map::new();
        for (c, s) in &self.channels {
            if s.n() == 0 {
                continue;
            }
            let name = c.name().to_string();
            rmse.insert(name.clone(), json!(self.rmse(*c).map(f64::to_degrees)));
            max_abs.insert(name.clone(), json!(s.max_abs_error().map(f64::to_degrees)));
            corr.insert(name.clone(), json!(s.correlation()));
            mean_err.insert(name, json!(s.mean_error().map(f64::to_degrees)));
        }
        let mut v = json!({
            "method": self.method,
            "n_samples": self.n_samples,
            "rmse_deg": rmse,
            "mean_rmse_deg": self.mean_rmse().map(f64::to_degrees),
            "max_abs_err_deg": max_abs,
            "corr": corr,
            "mean_err_deg": mean_err,
            "offset_free": self.offset_free,
            "sync_lag_samples": self.sync_lag,
            "window_s": [self.window.start, self.window.end.filter(|e| e.is_finite())],
            "diag_mean": self.diag_mean,
            "accel_reliability_pct": self.accel_reliability_pct,
            "accel_global_reliability_pct": self.accel_global_reliability_pct,
            "missing_input_pct": self.missing_input_pct,
        });
        let warnings: Vec<&String> = self.reference_units.iter().chain(&self.cut_lines).collect();
        if let (false, Some(obj)) = (warnings.is_empty(), v.as_object_mut()) {
            obj.insert("warnings".into(), json!(warnings));
        }
        if let Some(obj) = v.as_object_mut() {
            let rows = |f: fn(&ChannelCoverage) -> u64| -> Map<String, Value> {
                self.coverage
                    .iter()
                    .map(|c| (c.channel.name().to_string(), json!(f(c))))
                    .collect()
            };
            obj.insert("rows_scored".into(), Value::Object(rows(|c| c.scored)));
            obj.insert(
                "rows_with_reference".into(),
                Value::Object(rows(|c| c.with_reference)),
            );
        }
        if let (Some(r), Some(obj)) = (&self.resets, v.as_object_mut()) {
            obj.insert(
                "resets".into(),
                json!({"count": r.count, "first_t_s": r.first_t, "samples": r.samples}),
            );
        }
        v
    }

    /// A human-readable table (degrees), with [`Evaluation::notes`] where
    /// `evaluate` prints them.
    pub fn to_text(&self) -> String {
        let mut s = format!("method: {}   samples: {}", self.method, self.n_samples);
        if self.window.start.is_some() || self.window.end.is_some() {
            s += &format!("   window: {}", self.window);
        }
        s += "\n";
        for note in [self.offset_free_note(), self.sync_lag_note()]
            .into_iter()
            .flatten()
        {
            s += &note;
            s += "\n";
        }
        s += &format!(
            "{:<8}{:>10}{:>12}{:>12}{:>9}{:>9}\n",
            "channel", "RMSE deg", "max|e| deg", "mean e deg", "corr", "n"
        );
        for (c, st) in &self.channels {
            if st.n() == 0 {
                continue;
            }
            let f =
                |v: Option<f64>| v.map_or("-".to_string(), |v| format!("{:.3}", v.to_degrees()));
            s += &format!(
                "{:<8}{:>10}{:>12}{:>12}{:>9}{:>9}\n",
                c.name(),
                f(self.rmse(*c)),
                f(st.max_abs_error()),
                f(st.mean_error()),
                st.correlation()
                    .map_or("-".to_string(), |r| format!("{r:.4}")),
                st.n()
            );
        }
        if let Some(m) = self.mean_rmse() {
            s += &format!("mean RMSE: {:.3} deg", m.to_degrees());
            if let Some(exact) = self.exact_channels_phrase() {
                s += &format!(" ({exact})");
            }
            s += "\n";
        }
        if let Some(note) = self.knee_zero_note() {
            s += &format!("note: {note}\n");
        }
        if let Some(note) = self.coverage_note() {
            s += &format!("note: {note}\n");
        }
        for line in self.rate_notes() {
            s += &line;
            s += "\n";
        }
        if !self.diag_mean.is_empty() {
            // (an audit: "over the trial" was said with --window too)
            let over = match self.window.start.is_some() || self.window.end.is_some() {
                true => "the window",
                false => "the trial",
            };
            s += &format!(
                "({} estimator diagnostics averaged over {over}: `--diagnostics` lists them)\n",
                self.diag_mean.len()
            );
        }
        s
    }

    /// The mean of each estimator diagnostic over the trial (over the
    /// window with `--window`), one line each
    /// (`evaluate --diagnostics`; what each means: docs/OUTPUTS.md and the
    /// method's page).
    pub fn diagnostics_text(&self) -> String {
        let mut s = String::new();
        for (k, v) in &self.diag_mean {
            s += &format!("diag mean {k}: {v:.4}\n");
        }
        s
    }
}
