//! What `estimate` says when `knee-kinematic` is given a trial whose thigh
//! moves. The method models the seated FES leg of paper 004: the thigh
//! fixed at `# thigh_angle_rad:` (default horizontal), the knee the thigh's
//! angle minus the shank's. On a walking trial it runs and writes a knee
//! that is not the knee (limbfuse's simulated 20 s walk: 110 deg RMSE),
//! with exit 0 and nothing said.
//!
//! [`FixedThighWatch`] follows the direction of the thigh accelerometer's
//! specific force. On a seat the thigh does not turn, so that direction is
//! gravity's, fixed in the sensor frame; a walking or swinging thigh tilts
//! it by tens of degrees. The spread is the angular deviation of
//! directional statistics, `sqrt(2 (1 - R))` with `R` the mean resultant
//! length of the unit vectors (Mardia & Jupp, Directional Statistics, 2000,
//! sec. 2.3.1; bounded memory: a sum of unit vectors). Flagged above
//! [`SEATED_SPREAD_DEG`] (5 deg) on at least [`MIN_READINGS`] readings
//! (every [`FixedThighWatch::STRIDE`]-th sample, as the unit checks).
//! Measured with `limbfuse estimate --method knee-kinematic`, which prints
//! the spread when it warns (docs/RESULTS.md, last section): a fixed-hip
//! trial 8.4 deg, limbfuse's 20 s walk 12.5, the knee rig 19.8, the real S02
//! walk 21.2; no seated knee-FES trial of either simulator warns.

use limbfuse_core::runner::{BoxError, Observer};
use limbfuse_core::{Estimate, Record, Sample};
use limbfuse_methods::{Availability, MethodName};
use nalgebra::Vector3;

use crate::sensor_units::MIN_READINGS;
use crate::strided::Strided;

/// The spread (deg) of the thigh's specific-force direction above which
/// the thigh is not on a seat.
pub const SEATED_SPREAD_DEG: f64 = 5.0;

/// Follows the thigh accelerometer's direction over a run (see the module).
#[derive(Debug, Clone, Default)]
pub struct FixedThighWatch {
    records: Strided,
    readings: u64,
    direction_sum: Vector3<f64>,
}

impl FixedThighWatch {
    /// Every how many samples one is counted.
    pub const STRIDE: usize = 8;

    /// Adds a sample's thigh accelerometer reading (the leg the trial names).
    pub fn push_sample(&mut self, s: &Sample) {
        if let Some(a) = &s.imu[1].acc {
            self.push_acc(a);
        }
    }

    /// Adds one thigh specific-force reading (a zero vector has no
    /// direction and is skipped).
    pub fn push_acc(&mut self, a: &Vector3<f64>) {
        let norm = a.norm();
        if norm > 0.0 && norm.is_finite() {
            self.readings += 1;
            self.direction_sum += a / norm;
        }
    }

    /// The angular deviation (deg) of the thigh's specific-force direction,
    /// when there are enough readings.
    pub fn spread_deg(&self) -> Option<f64> {
        if self.readings < MIN_READINGS {
            return None;
        }
        let r = (self.direction_sum.norm() / self.readings as f64).min(1.0);
        Some((2.0 * (1.0 - r)).sqrt().to_degrees())
    }

    /// The warning for `method` on `trial`, when the thigh moves.
    pub fn warning(&self, method: &str, trial: &str) -> Option<String> {
        let spread = self.spread_deg().filter(|s| *s > SEATED_SPREAD_DEG)?;
        Some(format!(
            "{method} on {trial}: the method models a fixed thigh (a seated FES leg, \
             `# thigh_angle_rad:`), but the thigh accelerometer's direction spreads by \
             {spread:.1} deg (a thigh on a seat stays within {SEATED_SPREAD_DEG} deg): the knee \
             it gives is not this trial's knee (`rmx`, `knee-selfalign` and `knee-gyro-axis` \
             follow a moving thigh)"
        ))
    }
}

/// What the thigh's motion says about the methods that run on a trial
/// (`limbfuse inspect`, Python's `inspect`), from the spread of
/// [`FixedThighWatch::spread_deg`]: a method modelling a fixed thigh
/// ([`limbfuse_methods::MethodInfo::assumes_fixed_thigh`]) on a thigh that
/// moves. (A method finding walking on a thigh that does not is ruled out
/// before, by [`crate::data_limits`].) Nothing without a thigh
/// accelerometer.
pub fn thigh_motion_notes(
    spread_deg: Option<f64>,
    methods: &[(MethodName, Availability)],
) -> Vec<String> {
    let Some(spread) = spread_deg else {
        return Vec::new();
    };
    let moves = spread > SEATED_SPREAD_DEG;
    methods
        .iter()
        .filter(|(_, a)| matches!(a, Availability::Runs { .. }))
        .filter_map(|(m, _)| {
            let info = m.info();
            if info.assumes_fixed_thigh && moves {
                Some(format!(
                    "{}: models a fixed (seated) thigh, but the thigh accelerometer's direction \
                     spreads by {spread:.1} deg (a thigh on a seat stays within \
                     {SEATED_SPREAD_DEG} deg): its knee would not be this trial's",
                    m.name()
                ))
            } else {
                None
            }
        })
        .collect()
}

impl Observer for FixedThighWatch {
    /// Counts every [`FixedThighWatch::STRIDE`]-th record.
    fn observe(&mut self, record: &Record, _estimate: &Estimate) -> Result<(), BoxError> {
        if self.records.due(Self::STRIDE) {
            self.push_sample(&record.sample);
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The angular deviation against an independent value: unit vectors
    /// at +-a about one axis, half each, have `R = cos a`, so the spread is
    /// `sqrt(2 (1 - cos a))` (= 2 sin(a / 2)).
    #[test]
    fn spread_is_the_angular_deviation() {
        let a = 10f64.to_radians();
        let mut w = FixedThighWatch::default();
        for k in 0..100 {
            let s = if k % 2 == 0 { a } else { -a };
            w.push_acc(&(9.81 * Vector3::new(s.sin(), s.cos(), 0.0)));
        }
        let want = (2.0 * (1.0 - a.cos())).sqrt().to_degrees();
        assert!((w.spread_deg().unwrap() - want).abs() < 1e-9);
        assert!(w
            .warning("knee-kinematic", "t.csv")
            .unwrap()
            .contains("t.csv"));
    }

    /// A seated thigh (gravity plus noise and a kick's jolt) says nothing;
    /// too few readings say nothing.
    #[test]
    fn a_seated_thigh_is_not_named() {
        let mut seated = FixedThighWatch::default();
        for k in 0..400 {
            let jolt = if k % 50 == 0 { 2.0 } else { 0.0 };
            let noise = 0.03 * ((k * 7919) % 13) as f64 / 13.0;
            seated.push_acc(&Vector3::new(9.81 + noise, jolt, noise));
        }
        assert!(seated.spread_deg().unwrap() < 2.0);
        assert!(seated.warning("knee-kinematic", "t.csv").is_none());
        let mut short = FixedThighWatch::default();
        for k in 0..(MIN_READINGS - 1) {
            short.push_acc(&Vector3::new(1.0, (k % 2) as f64, 0.0));
        }
        assert_eq!(short.spread_deg(), None);
    }

    /// `inspect`'s notes: the fixed-thigh method on a moving thigh, only
    /// for methods that run, nothing without a spread (the walking methods on
    /// a still thigh: `data_limits`).
    #[test]
    fn thigh_motion_notes_name_the_method_the_motion_contradicts() {
        let runs = Availability::Runs { after_align: false };
        let methods = [
            (MethodName::KneeKinematic, runs.clone()),
            (MethodName::GaitEvents, runs.clone()),
            (MethodName::Rmx, runs),
            (
                MethodName::LowbackSpeed,
                Availability::MissingColumns("no trunk".into()),
            ),
        ];
        let moving = thigh_motion_notes(Some(12.5), &methods);
        assert_eq!(moving.len(), 1);
        assert!(moving[0].starts_with("knee-kinematic:") && moving[0].contains("12.5 deg"));
        assert!(thigh_motion_notes(Some(0.3), &methods).is_empty());
        // At the threshold the thigh counts as still (as in the warning).
        assert!(thigh_motion_notes(Some(SEATED_SPREAD_DEG), &methods).is_empty());
        assert!(thigh_motion_notes(None, &methods).is_empty());
    }
}
