//! `imm-bslip --imm-config continuous` on a trial that walks outside its
//! gait library's speeds (issue 19): the missing gaits are searched for the
//! trial's body and the trial is estimated again over the extended family.
//!
//! Outside its range the continuous family is its end gait, whose timing is
//! not the walker's (70 kg / 0.95 m walker at 0.35 m/s: 49-54 % phase with a
//! 0.4-1.0 m/s library, 80-96 % with a 0.3-1.0 one; docs/RESULTS.md).
//! Paper 003 sec V names the remedy: gaits re-parameterised to the user
//! instead of a fixed grid. The first run's estimated speeds say where the
//! trial walks ([`SpeedRangeWatch::outside`]: most of them more than
//! 0.03 m/s outside the range); [`extend_for_trial`] then runs the gait
//! search of `limbfuse gait-library build` (the homotopy of paper 003 sec
//! II-C, [`extend_library`]) for the trial's body, from the library's end
//! gait outwards on the library's own speed step, out to the grid point
//! that covers the mean of those speeds, and builds the estimator over the
//! extended family. The caller runs it again: estimators never re-read a
//! trial, so the two passes belong to the CLI (`estimate`) and the Python
//! `limbfuse.estimate`, which both call this; the streaming `Filter` sees
//! each sample once and cannot.
//!
//! On both sides of the range: below it the end gait fails (49-54 % phase at
//! 0.35 m/s), above it it serves (95.7-97.9 % at 1.15 and 1.30 m/s) but the
//! extended family does better still (99.0-99.6 %, for 0.3-0.8 s of search;
//! docs/RESULTS.md, "The library extended to the trial's speeds").

use std::time::Instant;

use limbfuse_core::Estimator;
use limbfuse_eval::{OutsideRange, RangeSide, SpeedRangeWatch};
use limbfuse_io::{TrialLayout, TrialMeta};
use limbfuse_methods::imm_params::{build_over, templates_for_trial, ImmConfig};
use limbfuse_methods::{MethodError, MethodSpec};
use limbfuse_models::bslip::GaitTemplate;
use limbfuse_sim::bslip::library::{extend_library, START_SPEED};
use limbfuse_sim::bslip::search::SearchSettings;

/// The speed step (m/s) of a library with one gait, which has none of its
/// own: the 0.1 m/s grid of the documented library builds.
const SINGLE_GAIT_STEP: f64 = 0.1;

/// At most this many gaits are added (the IMM's gait limit,
/// `limbfuse_estimators::imm_bslip::MAX_GAITS`): a speed estimate far from
/// the library with a fine step would otherwise search for minutes.
const MAX_ADDED: usize = limbfuse_estimators::imm_bslip::MAX_GAITS;

/// The extended family, or why there is none, for a trial outside its
/// library's speeds.
pub struct LibraryExtension {
    /// The estimator over the extended family, to run the trial again
    /// (`None`: the search found no gait to add).
    pub estimator: Option<Box<dyn Estimator + Send>>,
    /// The extended family's slowest and fastest gait (m/s; the library's
    /// when nothing was added).
    pub range: (f64, f64),
    /// The speeds added (m/s), in the order searched.
    pub added: Vec<f64>,
    /// What was done, one line (the CLI prints it after the method's name;
    /// the Python package gives it as a `LimbfuseWarning`).
    pub message: String,
}

impl std::fmt::Debug for LibraryExtension {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("LibraryExtension")
            .field("estimator", &self.estimator.as_ref().map(|e| e.name()))
            .field("range", &self.range)
            .field("added", &self.added)
            .field("message", &self.message)
            .finish()
    }
}

/// What a first run found that calls for an extension: `spec` is
/// `imm-bslip` in the continuous configuration with the extension on, and
/// most estimated speeds lie outside the library's range, on either side.
/// Above the range too: measured on the 70 kg / 0.95 m walker with the
/// 0.4-1.0 m/s library (docs/RESULTS.md, "The library extended to the
/// trial's speeds"), the end gait gives 95.7-97.9 % phase at 1.15 and
/// 1.30 m/s, the extended family 99.0-99.6 %.
pub fn wanted(spec: &MethodSpec, watch: &SpeedRangeWatch) -> Option<OutsideRange> {
    let MethodSpec::ImmBslip(s) = spec else {
        return None;
    };
    if s.config != ImmConfig::Continuous || !s.extend_library {
        return None;
    }
    watch.outside()
}

/// The speeds to search (m/s), outwards from the library's end gait `end`
/// on `step`, out to the first one at or beyond `mean`; none at or below
/// 0 m/s or beyond Froude number 1 (`v^2 = g l0`: an inverted-pendulum walk
/// cannot go faster, the stance leg would have to pull the body down;
/// Alexander 1984, Am. Zool. 24:85), at most [`MAX_ADDED`].
fn speeds_to_search(end: &GaitTemplate, side: RangeSide, step: f64, mean: f64) -> Vec<f64> {
    let sign = match side {
        RangeSide::Below => -1.0,
        RangeSide::Above => 1.0,
    };
    let n = (((mean - end.speed) * sign) / step - 1e-9).ceil().max(1.0) as usize;
    let froude_limit = (end.body.gravity * end.body.rest_length).sqrt();
    (1..=n.min(MAX_ADDED))
        .map(|k| ((end.speed + sign * k as f64 * step) * 1e6).round() / 1e6)
        .take_while(|&v| v > 0.0 && v < froude_limit)
        .collect()
}

fn list(speeds: &[f64]) -> String {
    let s: Vec<String> = speeds.iter().map(|v| format!("{v:.3}")).collect();
    s.join(", ")
}

/// For `imm-bslip --imm-config continuous` (extension on) on a trial with
/// metadata `meta` and columns `layout` whose first run's speeds `watch`
/// counted: when most lie outside the library's range ([`wanted`]), the
/// missing gaits searched for the trial's body and the estimator over the
/// extended family; `None` when the trial is inside the range (or the
/// method, configuration or setting does not extend). `settings`: the
/// gait search's (`SearchSettings::default()`, or with Python's Ctrl-C hook).
pub fn extend_for_trial(
    spec: &MethodSpec,
    meta: &TrialMeta,
    layout: &TrialLayout,
    watch: &SpeedRangeWatch,
    settings: &SearchSettings,
) -> Result<Option<LibraryExtension>, MethodError> {
    let (Some(outside), MethodSpec::ImmBslip(s)) = (wanted(spec, watch), spec) else {
        return Ok(None);
    };
    let (mut family, _) = templates_for_trial(s, meta)?;
    family.sort_by(|a, b| a.speed.total_cmp(&b.speed));
    let (Some(&first), Some(&last)) = (family.first(), family.last()) else {
        return Ok(None);
    };
    let n = family.len();
    let (end, step) = match outside.side {
        RangeSide::Below => (first, family.get(1).map(|g| g.speed - first.speed)),
        RangeSide::Above => (last, (n > 1).then(|| last.speed - family[n - 2].speed)),
    };
    let step = step.filter(|s| *s > 1e-6).unwrap_or(SINGLE_GAIT_STEP);
    let speeds = speeds_to_search(&end, outside.side, step, outside.mean);
    let body = end.body;
    let what = format!(
        "{}: gait search for this body ({} kg, l0 {} m, g {} m/s^2) from the library's {:.2} m/s \
         gait on its {:.3} m/s step",
        outside.finding(),
        body.mass,
        body.rest_length,
        body.gravity,
        end.speed,
        step
    );
    let started = Instant::now();
    let found = extend_library(&body, &end.gait, end.speed, &speeds, outside.mean, settings);
    let seconds = started.elapsed().as_secs_f64();
    // (the continuation from the end gait failed: searched from the start
    // speed as `gait-library build` does)
    let restart = match &found.restarted {
        Some(e) => format!(
            " (from it: {e}; searched again from {START_SPEED} m/s as `gait-library build` does)"
        ),
        None => String::new(),
    };
    let added: Vec<f64> = found.gaits.iter().map(|g| g.speed).collect();
    let stopped = found.stopped.as_ref().map(|e| {
        let grid = speeds
            .iter()
            .filter(|v| added.iter().all(|a| (*a - **v).abs() > 1e-9));
        let at = grid.copied().next().unwrap_or(end.speed);
        format!("no periodic gait at {at:.2} m/s ({e})")
    });
    if added.is_empty() {
        let why = stopped.unwrap_or_else(|| "no speed to search".to_string());
        return Ok(Some(LibraryExtension {
            estimator: None,
            range: (first.speed, last.speed),
            added,
            message: format!(
                "{what}{restart}: {why} in {seconds:.1} s; the library was not extended"
            ),
        }));
    }
    family.extend(found.gaits.iter().map(|g| g.template(&body)));
    family.sort_by(|a, b| a.speed.total_cmp(&b.speed));
    let range = (family[0].speed, family[family.len() - 1].speed);
    let estimator = limbfuse_methods::gate(build_over(s, &family, layout)?, meta)?;
    let stop_note = match &stopped {
        Some(why) => format!(" ({why}: the family stops there)"),
        None => String::new(),
    };
    let message = format!(
        "{what}{restart}: added {} m/s in {seconds:.1} s{stop_note}, estimated again over \
         {:.2}-{:.2} m/s (`--imm-extend-library off` keeps the library as it is)",
        list(&added),
        range.0,
        range.1
    );
    Ok(Some(LibraryExtension {
        estimator: Some(estimator),
        range,
        added,
        message,
    }))
}

#[cfg(test)]
mod tests {
    use super::*;
    use limbfuse_models::bslip::{BslipParams, GaitParameters};

    fn gait_at(speed: f64) -> GaitTemplate {
        GaitTemplate {
            speed,
            body: BslipParams {
                mass: 70.0,
                rest_length: 0.95,
                ..BslipParams::default()
            },
            gait: GaitParameters {
                phi: 1.2,
                theta: 0.05,
                stiffness: 20_000.0,
                height: 0.92,
                lateral: 0.03,
                forward_speed: speed,
            },
            step_length: 0.5,
            step_width: 0.1,
            step_time: 0.8,
            t_touchdown: 0.2,
            t_lift_off: 0.3,
        }
    }

    #[test]
    fn speeds_reach_the_grid_point_covering_the_mean() {
        let end = gait_at(0.4);
        assert_eq!(
            speeds_to_search(&end, RangeSide::Below, 0.1, 0.345),
            vec![0.3]
        );
        assert_eq!(
            speeds_to_search(&end, RangeSide::Below, 0.1, 0.29),
            vec![0.3, 0.2]
        );
        // Never at or below zero.
        assert_eq!(
            speeds_to_search(&end, RangeSide::Below, 0.1, 0.02),
            vec![0.3, 0.2, 0.1]
        );
        let end = gait_at(1.0);
        assert_eq!(
            speeds_to_search(&end, RangeSide::Above, 0.1, 1.15),
            vec![1.1, 1.2]
        );
        // Not beyond Froude number 1 (3.05 m/s for l0 0.95 m).
        assert_eq!(
            speeds_to_search(&end, RangeSide::Above, 1.0, 9.0),
            vec![2.0, 3.0]
        );
        // A fine step: at most MAX_ADDED gaits.
        assert_eq!(
            speeds_to_search(&end, RangeSide::Above, 0.001, 2.0).len(),
            MAX_ADDED
        );
    }
}
