//! Which methods can run on a trial, and why not (`limbfuse inspect`, the
//! Python `limbfuse.inspect`): each method is built with its defaults, as
//! `estimate` builds it without `--params`, and sorted by what stops it.

use limbfuse_io::{TrialLayout, TrialMeta};

use crate::{build, check_channels, raw_frame_note, MethodError, MethodName, MethodSpec};

/// What a method needs beyond a trial's columns, or that it runs.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum Availability {
    /// It runs with its defaults.
    Runs {
        /// It reads aligned IMU frames and the trial declares raw ones: it
        /// runs, but its angles mean something only after `limbfuse align`.
        after_align: bool,
    },
    /// The trial has its columns, but a setting its defaults lack (a
    /// `# model:` for `sdre` / `ekf`, a gait library for `imm-bslip`): the
    /// first line of the error `estimate` would give.
    NeedsSetting(String),
    /// The trial lacks columns it needs: the first line of the error.
    MissingColumns(String),
    /// The columns are there but the data rule it out (an input empty on
    /// every row, a trial shorter than the method's window):
    /// `limbfuse_eval::data_limits` says why.
    NoData(String),
}

impl Availability {
    /// `runs`, `runs after align`, `needs a setting`, `missing columns` or
    /// `no usable data` (the kinds of `limbfuse inspect --json` and
    /// Python's `inspect`).
    pub fn kind(&self) -> &'static str {
        match self {
            Availability::Runs { after_align: false } => "runs",
            Availability::Runs { after_align: true } => "runs after align",
            Availability::NeedsSetting(_) => "needs a setting",
            Availability::MissingColumns(_) => "missing columns",
            Availability::NoData(_) => "no usable data",
        }
    }

    /// Why not (the first line of `estimate`'s error); empty when it runs.
    pub fn reason(&self) -> &str {
        match self {
            Availability::Runs { .. } => "",
            Availability::NeedsSetting(why)
            | Availability::MissingColumns(why)
            | Availability::NoData(why) => why,
        }
    }
}

/// Every method of the registry with its [`Availability`] on a trial with
/// this metadata and these columns.
pub fn availability(meta: &TrialMeta, layout: &TrialLayout) -> Vec<(MethodName, Availability)> {
    let first_line = |e: MethodError| e.to_string().lines().next().unwrap_or("").to_string();
    MethodName::ALL
        .into_iter()
        .map(|m| {
            // Columns first (what no setting can replace), then the method
            // built with its defaults; methods whose columns are one group
            // or another check them when they are built.
            let a = match check_channels(m, layout)
                .and_then(|()| MethodSpec::defaults(m))
                .and_then(|spec| build(&spec, meta, layout))
            {
                Ok(_) => Availability::Runs {
                    after_align: raw_frame_note(m, meta, "").is_some(),
                },
                Err(e @ MethodError::MissingChannels { .. }) => {
                    Availability::MissingColumns(first_line(e))
                }
                Err(e) => Availability::NeedsSetting(first_line(e)),
            };
            (m, a)
        })
        .collect()
}

/// When a parameter file with the trial's name and a `[model]` table lies
/// beside it (the shared independent-simulator FES trials ship `NAME.toml`
/// beside `NAME.csv`): the `--params` to add, for `sdre` / `ekf` refused
/// for want of a model (`estimate`'s error, `inspect`, Python's `inspect`).
pub fn model_file_hint(trial: &std::path::Path) -> Option<String> {
    let beside = trial.with_extension("toml");
    let text = std::fs::read_to_string(&beside).ok()?;
    text.lines().any(|l| l.trim() == "[model]").then(|| {
        format!(
            "the parameter file beside the trial has a [model] table: add `--params {}`",
            beside.display()
        )
    })
}

/// Each method's reason as `inspect` gives it ([`Availability::reason`]),
/// `sdre` and `ekf` needing a setting with the hint of the model file
/// beside `trial` ([`model_file_hint`]) after it: one text for the CLI's
/// `inspect --json` and Python's `limbfuse.inspect` (session 30: only
/// Python's had the hint).
pub fn inspect_reasons(
    methods: &[(MethodName, Availability)],
    trial: &std::path::Path,
) -> Vec<String> {
    let hint = needs_a_model(methods)
        .then(|| model_file_hint(trial))
        .flatten();
    methods
        .iter()
        .map(|(m, a)| match (&hint, a) {
            (Some(h), Availability::NeedsSetting(why))
                if matches!(m, MethodName::Sdre | MethodName::Ekf) =>
            {
                format!("{why}; {h}")
            }
            _ => a.reason().to_string(),
        })
        .collect()
}

/// Whether `methods` has `sdre` or `ekf` needing a setting (a model).
pub fn needs_a_model(methods: &[(MethodName, Availability)]) -> bool {
    methods.iter().any(|(m, a)| {
        matches!(m, MethodName::Sdre | MethodName::Ekf)
            && matches!(a, Availability::NeedsSetting(_))
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_walking_trial_runs_the_segment_filters_and_not_the_others() {
        let mut meta = TrialMeta::trial_v1();
        let layout = TrialLayout::walking();
        let get = |list: &[(MethodName, Availability)], m| {
            list.iter().find(|(n, _)| *n == m).unwrap().1.clone()
        };
        let list = availability(&meta, &layout);
        assert_eq!(list.len(), MethodName::ALL.len());
        assert_eq!(
            get(&list, MethodName::Mjls),
            Availability::Runs { after_align: false }
        );
        assert!(
            matches!(get(&list, MethodName::ImmBslip), Availability::MissingColumns(m) if m.contains("com_meas_x"))
        );
        assert!(
            matches!(get(&list, MethodName::Sdre), Availability::NeedsSetting(m) if m.contains("# model:"))
        );
        meta.set("imu_frame", "raw sensor frames (unaligned)");
        let list = availability(&meta, &layout);
        assert_eq!(
            get(&list, MethodName::Mjls),
            Availability::Runs { after_align: true }
        );
        assert_eq!(
            get(&list, MethodName::KneeSelfAlign),
            Availability::Runs { after_align: false }
        );
    }
}
