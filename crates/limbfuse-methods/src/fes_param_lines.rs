//! A trial that states its whole knee-FES model in `# param_*` lines runs
//! `sdre` / `ekf` without a parameter file, as if the file of those values
//! were given.
//!
//! The independent FES simulator writes its model that way (its README,
//! `../shared/data/independent-sim/README.md`: "every model parameter is in
//! `# param_*` lines, and the `.toml` beside each file holds the same values
//! under limbfuse's `[model]` key names"). Its `# model:` line is free text,
//! which limbfuse refuses unless a parameter file gives the whole model
//! (docs/FES_ESTIMATION.md, "Trials of other simulators"). Ours, beside
//! SPEC: the names are that simulator's, mapped one to one
//! ([`PARAM_LINE_KEYS`]); a parameter file's `[model]` keys still win.

use std::borrow::Cow;
use std::collections::BTreeMap;

use limbfuse_io::TrialMeta;

use crate::fes_params::{number, FesBuildError, FesParamsFile};

/// Each `# param_*` line of the independent FES simulator and the
/// `[model]` key it is (the `.toml` files shipped beside its trials pair
/// them so, value for value).
pub const PARAM_LINE_KEYS: [(&str, &str); 19] = [
    ("param_J", "inertia"),
    ("param_m", "mass"),
    ("param_l_c", "l_c"),
    ("param_g", "g"),
    ("param_phi0", "phi0"),
    ("param_theta_eq", "theta_eq"),
    ("param_T_a", "t_a"),
    ("param_I_t", "i_threshold_ma"),
    ("param_I_s", "i_saturation_ma"),
    ("param_d1", "d1"),
    ("param_d2", "d2"),
    ("param_d3", "d3"),
    ("param_d4", "d4"),
    ("param_d5", "d5"),
    ("param_d6", "d6"),
    ("param_c0", "c0"),
    ("param_c1", "c1"),
    ("param_c2", "c2"),
    ("param_c3", "c3"),
];

/// The `[model]` table the trial's `# param_*` lines state, when its
/// `# model:` is not a limbfuse model (`knee-fes`, `fixed-hip`) and the
/// lines give every key; `None` otherwise. A line that is not a finite
/// number is an error naming it.
pub fn model_from_param_lines(
    meta: &TrialMeta,
) -> Result<Option<BTreeMap<String, f64>>, FesBuildError> {
    if matches!(
        meta.get("model").map(str::trim),
        Some("knee-fes" | "fixed-hip")
    ) {
        return Ok(None);
    }
    let mut model = BTreeMap::new();
    for (line, key) in PARAM_LINE_KEYS {
        let Some(v) = meta.get(line) else {
            return Ok(None);
        };
        model.insert(key.to_string(), number("metadata", line, v)?);
    }
    Ok(Some(model))
}

impl FesParamsFile {
    /// This file, with the `[model]` keys it lacks filled from the trial's
    /// `# param_*` lines when they state the whole model
    /// ([`model_from_param_lines`]); the file unchanged otherwise.
    pub fn for_trial(&self, meta: &TrialMeta) -> Result<Cow<'_, FesParamsFile>, FesBuildError> {
        let Some(mut model) = model_from_param_lines(meta)? else {
            return Ok(Cow::Borrowed(self));
        };
        model.extend(self.model.iter().map(|(k, v)| (k.clone(), *v)));
        Ok(Cow::Owned(FesParamsFile {
            model,
            ..self.clone()
        }))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn meta(model: &str) -> TrialMeta {
        let mut m = TrialMeta::new();
        m.set("model", model);
        for (i, (line, _)) in PARAM_LINE_KEYS.iter().enumerate() {
            m.set(*line, format!("{}", 1.0 + i as f64));
        }
        m
    }

    /// Every line maps to its key; the file's own keys win; a limbfuse
    /// model line, or a line missing, leaves the file as it is.
    #[test]
    fn param_lines_fill_the_model_the_file_lacks() {
        let m = meta("thesis 004 eqs 4.1-4.6: free text");
        let mut file = FesParamsFile::none();
        file.model.insert("d4".into(), 8.5);
        let got = file.for_trial(&m).unwrap();
        assert_eq!(got.model.len(), 19);
        assert_eq!(got.model["inertia"], 1.0);
        assert_eq!(got.model["i_saturation_ma"], 9.0);
        assert_eq!(got.model["d4"], 8.5, "the file wins");
        let ours = meta("knee-fes");
        assert!(matches!(file.for_trial(&ours).unwrap(), Cow::Borrowed(_)));
        let mut short = TrialMeta::new();
        for (k, v) in m.entries().iter().filter(|(k, _)| k != "param_c3") {
            short.set(k.clone(), v);
        }
        assert!(matches!(file.for_trial(&short).unwrap(), Cow::Borrowed(_)));
        let mut bad = meta("free text");
        bad.set("param_J", "heavy");
        let e = file.for_trial(&bad).unwrap_err().to_string();
        assert!(e.contains("param_J") && e.contains("heavy"), "{e}");
    }
}
