//! What a trial's data (not its columns) rules out, for `limbfuse inspect`
//! and the Python `inspect`: a method whose columns are all there, and that
//! builds with its defaults, still estimates nothing when an input it needs
//! (or, for `sdre` / `ekf`, the stimulation `u_ke`) has no reading on any
//! row, when the trial is shorter than a knee
//! method's identification window, or when a method that finds walking
//! gets a thigh that does not move. An audit found `inspect` saying "runs"
//! for 164 (trial, method) pairs that `estimate` then refused, these among
//! them.

use limbfuse_core::{Joint, Segment};
use limbfuse_io::TrialMeta;
use limbfuse_methods::{Availability, MethodName, MethodSpec};

use crate::TrialSummary;

/// Marks the methods of `methods` that run on the trial's columns but not
/// on its data as [`Availability::NoData`], with the reason.
pub fn limit_by_data(
    methods: &mut [(MethodName, Availability)],
    summary: &TrialSummary,
    meta: &TrialMeta,
) {
    if summary.rows == 0 {
        return;
    }
    for (m, a) in methods.iter_mut() {
        if !matches!(a, Availability::Runs { .. }) {
            continue;
        }
        if let Some(why) = empty_input(*m, summary)
            .or_else(|| short_for_window(*m, summary, meta))
            .or_else(|| still_thigh(*m, summary))
        {
            *a = Availability::NoData(why);
        }
    }
}

/// Every input empty on every row; or, for the knee-axis methods (which
/// need a sample with both the thigh and the shank gyroscope), one of those
/// gyroscopes empty. (Not every method stops at an empty input it has the
/// column of: `mjls` estimates without the thigh gyro from its encoders and
/// accelerometers, so no other method is ruled out this way.)
fn empty_input(m: MethodName, s: &TrialSummary) -> Option<String> {
    if !s.inputs.is_empty() && s.inputs.iter().all(|g| g.missing_rows >= s.rows) {
        return Some(format!(
            "no input has a reading on any of the {} rows",
            s.rows
        ));
    }
    if matches!(m, MethodName::Sdre | MethodName::Ekf) {
        // The stimulation `u_ke` is an input of every paper-004 model (the
        // knee's only one, one of the fixed hip's six): without any value
        // the filters never start (they wait for a model input they have
        // not seen yet, docs/FES_ESTIMATION.md "Estimator").
        return s
            .inputs
            .iter()
            .find(|g| g.name == "u_ke" && g.missing_rows >= s.rows)
            .map(|_| {
                format!(
                    "`u_ke` (the model's stimulation input) has no reading on any of the {} rows",
                    s.rows
                )
            });
    }
    if !matches!(m, MethodName::KneeSelfAlign | MethodName::KneeGyroAxis) {
        return None;
    }
    let needs = m.required_channels();
    let mut names = Vec::new();
    for seg in Segment::ALL {
        let i = seg.index();
        if needs.acc[i] {
            names.push(format!("{} acc", seg.name()));
        }
        if needs.gyr[i] {
            names.push(format!("{} gyr", seg.name()));
        }
    }
    for j in Joint::ALL {
        if needs.encoder[j.index()] {
            names.push(format!("{}_enc", j.name()));
        }
    }
    if needs.com_position {
        names.push("com_meas".into());
    }
    let empty = s
        .inputs
        .iter()
        .find(|g| names.contains(&g.name) && g.missing_rows >= s.rows)?;
    Some(format!(
        "`{}` has no reading on any of the {} rows",
        empty.name, s.rows
    ))
}

/// A method that finds walking (`gait-events`, `lowback-speed`) on a trial
/// whose thigh accelerometer barely turns (a seated or fixed thigh: the FES
/// trials), where `estimate` ends with "no gait found"; and the knee-axis
/// methods there, which identify the thigh IMU's axis from the thigh's own
/// rotation (paper 002 eq 1: a still thigh's gyro says nothing about it),
/// where `estimate` ends with "the knee axis is unidentifiable" (the shared
/// independent FES trials and ours: an audit).
fn still_thigh(m: MethodName, s: &TrialSummary) -> Option<String> {
    let spread = s.thigh_spread_deg?;
    if spread > crate::fixed_thigh::SEATED_SPREAD_DEG {
        return None;
    }
    if m.info().finds_walking {
        return Some(format!(
            "the thigh accelerometer's direction spreads by only {spread:.1} deg (walking turns \
             it by tens of degrees): no walking for it to find"
        ));
    }
    matches!(m, MethodName::KneeSelfAlign | MethodName::KneeGyroAxis).then(|| {
        format!(
            "the thigh accelerometer's direction spreads by only {spread:.1} deg: the thigh IMU's \
             knee axis is identified from the thigh's own rotation, which a still thigh does not give"
        )
    })
}

/// A knee method whose identification window is longer than the trial.
fn short_for_window(m: MethodName, s: &TrialSummary, meta: &TrialMeta) -> Option<String> {
    if !matches!(m, MethodName::KneeSelfAlign | MethodName::KneeGyroAxis) {
        return None;
    }
    let spec = MethodSpec::defaults(m).ok()?;
    let window = limbfuse_methods::knee_window::identification_window(&spec, meta).ok()?;
    (window as u64 > s.rows).then(|| {
        format!(
            "the identification window ({window} samples) is longer than the trial ({} rows): \
             give a shorter `window_s` or `--window`",
            s.rows
        )
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::trial_summary::InputGroup;

    fn summary(rows: u64, inputs: &[(&str, u64)]) -> TrialSummary {
        TrialSummary {
            rows,
            span: None,
            median_step: None,
            stated_hz: None,
            gaps: 0,
            longest_step: None,
            inputs: inputs
                .iter()
                .map(|(n, m)| InputGroup {
                    name: n.to_string(),
                    missing_rows: *m,
                })
                .collect(),
            interval: None,
            units: Vec::new(),
            warnings: Vec::new(),
            thigh_spread_deg: None,
        }
    }

    #[test]
    fn an_empty_input_or_a_short_trial_is_no_data() {
        let runs = Availability::Runs { after_align: false };
        let mut methods = vec![
            (MethodName::KneeGyroAxis, runs.clone()),
            (MethodName::Mjls, runs.clone()),
            (MethodName::Local, Availability::MissingColumns("x".into())),
        ];
        let mut meta = TrialMeta::trial_v1();
        meta.set("sample_rate_hz", 100);
        let s = summary(
            3000,
            &[("trunk gyr", 0), ("thigh gyr", 3000), ("shank gyr", 0)],
        );
        limit_by_data(&mut methods, &s, &meta);
        assert!(
            matches!(&methods[0].1, Availability::NoData(w) if w.contains("`thigh gyr` has no reading on any of the 3000 rows")),
            "{:?}",
            methods[0].1
        );
        let mut knee = vec![(MethodName::KneeSelfAlign, runs.clone())];
        limit_by_data(&mut knee, &summary(300, &[("thigh gyr", 0)]), &meta);
        assert!(
            matches!(&knee[0].1, Availability::NoData(w) if w.contains("window (500 samples) is longer than the trial (300 rows)")),
            "{:?}",
            knee[0].1
        );
        // (mjls estimates without the thigh gyro)
        assert_eq!(methods[1].1, runs);
        assert_eq!(methods[2].1, Availability::MissingColumns("x".into()));
        let mut seated = summary(3000, &[("thigh acc", 0)]);
        seated.thigh_spread_deg = Some(2.0);
        let mut walking = vec![
            (MethodName::GaitEvents, runs.clone()),
            (MethodName::Rmx, runs.clone()),
        ];
        limit_by_data(&mut walking, &seated, &meta);
        assert!(
            matches!(&walking[0].1, Availability::NoData(w) if w.contains("spreads by only 2.0 deg")),
            "{:?}",
            walking[0].1
        );
        assert_eq!(walking[1].1, runs);
        let mut knee = vec![(MethodName::KneeSelfAlign, runs.clone())];
        limit_by_data(&mut knee, &seated, &meta);
        assert!(
            matches!(&knee[0].1, Availability::NoData(w) if w.contains("a still thigh does not give")),
            "{:?}",
            knee[0].1
        );
        let mut ok = vec![(MethodName::KneeGyroAxis, runs.clone())];
        limit_by_data(&mut ok, &summary(3000, &[("thigh gyr", 2999)]), &meta);
        assert_eq!(ok[0].1, runs);
        // a stimulation column without a value: sdre and ekf never start
        let fes = |u_missing| {
            let mut m = vec![
                (MethodName::Sdre, runs.clone()),
                (MethodName::Ekf, runs.clone()),
                (MethodName::Rmx, runs.clone()),
            ];
            let s = summary(3000, &[("shank gyr", 0), ("u_ke", u_missing)]);
            limit_by_data(&mut m, &s, &meta);
            m
        };
        let none = fes(3000);
        for (m, a) in &none[..2] {
            assert!(
                matches!(a, Availability::NoData(w) if w.contains("`u_ke` (the model's stimulation input) has no reading on any of the 3000 rows")),
                "{m:?}: {a:?}"
            );
        }
        assert_eq!(none[2].1, runs, "rmx reads no model input");
        assert!(fes(2999).iter().all(|(_, a)| *a == runs));
    }
}
