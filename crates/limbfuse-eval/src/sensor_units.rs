//! What `estimate` says when a trial's IMU readings do not look like SPEC
//! units (section 2: specific force in m/s^2, angular rate in rad/s).
//!
//! The two usual slips of a hand-made trial file, measured on a simulated
//! 3 s walk (`mjls`):
//! - **accelerometers in g**: the readings' norm is about 1 instead of
//!   9.81, so every reliability test `| ||a|| - g |` fails, the filter
//!   never corrects its gyro integration and the segment angles are 73-75
//!   deg off (the encoders keep the joints), with no warning at all;
//! - **gyroscopes in deg/s**: 57 times the rate; the sensor gate rejects
//!   the readings above its range and passes the others, the segment
//!   angles are 67-83 deg RMSE off, and the warnings speak of rejected
//!   readings and restarts, not of units.
//!
//! [`SensorUnitsWatch`] counts, for each IMU of both legs (each IMU on its
//! own since 2026-12-05: pooled, one trunk gyroscope in deg/s or one shank
//! accelerometer in g among SI readings passed, and `chain` came out 99 deg
//! off, `sdre` 7 deg; an IMU with fewer than [`MIN_READINGS`] readings
//! counts only in the pool of all of them):
//! - accelerometer readings whose norm lies in 0.5-2 (in the file's unit):
//!   for a body-worn accelerometer in m/s^2 that is near free fall, which
//!   walking, standing or sitting never sustains (the mean specific force
//!   over a stride is g); in g it is nearly every reading. Flagged when
//!   three quarters of the readings are there;
//! - gyroscope readings whose norm exceeds 25 rad/s (1430 deg/s): no body
//!   segment turns that fast (a sprinting foot peaks near 20 rad/s), while
//!   in deg/s any segment moving faster than 25 deg/s does. Flagged when 5
//!   % of the readings are there (a glitch now and then is not).
//!
//! Every [`SensorUnitsWatch::STRIDE`]-th sample is counted (shares need no
//! more; counting every sample cost 20 % of a `limbfuse.estimate` call of
//! `mjls`), and neither unit is decided on fewer than [`MIN_READINGS`]
//! readings. The CLI
//! prints what it finds as a warning, the Python package as a
//! `LimbfuseWarning`; the estimate is still written.

use std::fmt;

use limbfuse_core::runner::{BoxError, Observer};
use limbfuse_core::{Estimate, ImuSample, Record, Segment};
use nalgebra::Vector3;

use crate::sample_interval::SampleIntervalWatch;
use crate::strided::Strided;

/// Readings of a kind needed before anything is said about its unit.
pub const MIN_READINGS: u64 = 25;

/// Norms (in the file's unit) an accelerometer in g reads: 0.5-2 g covers
/// standing (1 g) and walking (0.5-2 g most of a stride at the trunk and
/// thigh); in m/s^2 it is near free fall.
const G_UNIT_NORMS: (f64, f64) = (0.5, 2.0);
/// Share of accelerometer readings in [`G_UNIT_NORMS`] that says g.
const G_UNIT_SHARE: f64 = 0.75;
/// A rate no body segment reaches (rad/s; 1430 deg/s).
const FASTER_THAN_ANY_SEGMENT: f64 = 25.0;
/// Share of gyroscope readings beyond [`FASTER_THAN_ANY_SEGMENT`] that
/// says deg/s.
const DEGREES_SHARE: f64 = 0.05;

/// IMU slots of [`SensorUnitsWatch`]: the trial's leg's trunk, thigh,
/// shank and foot, then the other leg's.
const IMU_SLOTS: usize = 8;

/// The IMUs a [`UnitSuspect`] is about: bit `k` is IMU slot `k` (0-3 the
/// trial's leg's trunk to foot, 4-7 the other leg's); `every` when it is
/// every IMU with readings.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct ImuSet {
    /// One bit per IMU slot.
    pub bits: u8,
    /// Every IMU with readings is in the set.
    pub every: bool,
}

impl fmt::Display for ImuSet {
    /// `""` for every IMU, else `"trunk "`, `"thigh and other leg's shank "`.
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        if self.every {
            return Ok(());
        }
        let names: Vec<String> = (0..IMU_SLOTS)
            .filter(|k| self.bits & (1 << k) != 0)
            .map(|k| {
                let name = Segment::ALL[k % 4].name();
                if k < 4 {
                    name.to_string()
                } else {
                    format!("other leg's {name}")
                }
            })
            .collect();
        write!(f, "{} ", names.join(" and "))
    }
}

/// An IMU unit that does not look like SPEC's.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum UnitSuspect {
    /// Accelerometers that look like g (`share` of their readings has a
    /// norm of 0.5-2).
    AccelerometerInG {
        /// Share of the readings (0-1).
        share: f64,
        /// Which accelerometers.
        which: ImuSet,
    },
    /// Gyroscopes that look like deg/s (`share` of their readings is
    /// faster than 25).
    GyroscopeInDegrees {
        /// Share of the readings (0-1).
        share: f64,
        /// Which gyroscopes.
        which: ImuSet,
    },
    /// Joint encoders that look like degrees (`share` of their readings
    /// beyond pi in magnitude).
    EncoderInDegrees {
        /// Share of the readings (0-1).
        share: f64,
    },
}

impl fmt::Display for UnitSuspect {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match *self {
            UnitSuspect::AccelerometerInG { share, which } => write!(
                f,
                "{:.0} % of the {which}accelerometer readings have a norm of {}-{}, where a body-worn \
                 accelerometer in m/s^2 reads about g = 9.81: accelerometers must be in m/s^2 \
                 (SPEC section 2); these look like g (multiply them by 9.81)",
                100.0 * share,
                G_UNIT_NORMS.0,
                G_UNIT_NORMS.1
            ),
            UnitSuspect::GyroscopeInDegrees { share, which } => write!(
                f,
                "{:.0} % of the {which}gyroscope readings turn faster than {FASTER_THAN_ANY_SEGMENT} \
                 (rad/s: 1430 deg/s), which no body segment does: gyroscopes must be in rad/s \
                 (SPEC section 2); these look like deg/s (multiply them by pi/180 = 0.017453)",
                100.0 * share
            ),
            UnitSuspect::EncoderInDegrees { share } => write!(
                f,
                "{:.0} % of the joint-encoder readings lie beyond pi, which no joint angle \
                 reaches in rad: encoders must be in rad (SPEC section 2); these look like \
                 degrees (multiply them by pi/180 = 0.017453)",
                100.0 * share
            ),
        }
    }
}

/// Share of angles beyond pi that says degrees: in rad no sagittal segment
/// or joint angle of the lower limb passes half a turn, in degrees every
/// angle beyond 3.14 deg does.
const DEGREES_ANGLE_SHARE: f64 = 0.25;

/// Counts angle references (`S_ref`, joint `_ref` columns) beyond pi: a
/// reference in degrees makes every error of `evaluate` 57 times too large
/// without saying why (measured on a simulated walk: 88-119 deg RMSE).
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct ReferenceUnitsWatch {
    seen: [u64; 7],
    beyond_pi: [u64; 7],
}

impl ReferenceUnitsWatch {
    /// Adds one record's angle references.
    pub fn push(&mut self, reference: &limbfuse_core::Reference) {
        for (k, c) in limbfuse_core::sample::AngleChannel::ALL
            .into_iter()
            .enumerate()
        {
            if let Some(v) = reference.angle(c) {
                self.seen[k] += 1;
                self.beyond_pi[k] += u64::from(v.abs() > core::f64::consts::PI);
            }
        }
    }

    /// The warning, naming the reference columns that look like degrees.
    pub fn warning(&self) -> Option<String> {
        let names: Vec<String> = limbfuse_core::sample::AngleChannel::ALL
            .into_iter()
            .enumerate()
            .filter(|&(k, _)| {
                self.seen[k] >= MIN_READINGS
                    && self.beyond_pi[k] as f64 >= DEGREES_ANGLE_SHARE * self.seen[k] as f64
            })
            .map(|(_, c)| format!("`{}_ref`", c.name()))
            .collect();
        (!names.is_empty()).then(|| {
            format!(
                "the reference column(s) {} lie beyond pi for a quarter or more of their values, \
                 which no sagittal angle reaches in rad: references must be in rad (SPEC section \
                 2); these look like degrees, and every error above is 57 times too large",
                names.join(", ")
            )
        })
    }
}

/// Counts a run's IMU readings by the norms above, and its joint-encoder
/// readings beyond pi.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct SensorUnitsWatch {
    /// Accelerometer readings, and those in [`G_UNIT_NORMS`], per IMU slot.
    acc: [(u64, u64); IMU_SLOTS],
    /// Gyroscope readings, and those beyond [`FASTER_THAN_ANY_SEGMENT`],
    /// per IMU slot.
    gyr: [(u64, u64); IMU_SLOTS],
    enc: u64,
    enc_beyond_pi: u64,
    /// Which records the [`Observer`] counts.
    records: Strided,
}

impl SensorUnitsWatch {
    /// Samples counted: sample 0, `STRIDE`, `2 STRIDE`, ... of a run.
    pub const STRIDE: usize = 8;

    /// Adds a reading of IMU slot `imu`'s accelerometer (0-3 the trial's
    /// leg's trunk to foot, 4-7 the other leg's; a non-finite norm is not
    /// counted).
    pub fn push_acc(&mut self, imu: usize, a: &Vector3<f64>) {
        let n2 = a.norm_squared();
        if let (true, Some(c)) = (n2.is_finite(), self.acc.get_mut(imu)) {
            let (lo, hi) = G_UNIT_NORMS;
            c.0 += 1;
            c.1 += u64::from((lo * lo..=hi * hi).contains(&n2));
        }
    }

    /// Adds a reading of IMU slot `imu`'s gyroscope (a non-finite norm is
    /// not counted).
    pub fn push_gyr(&mut self, imu: usize, w: &Vector3<f64>) {
        let n2 = w.norm_squared();
        if let (true, Some(c)) = (n2.is_finite(), self.gyr.get_mut(imu)) {
            c.0 += 1;
            c.1 += u64::from(n2 > FASTER_THAN_ANY_SEGMENT * FASTER_THAN_ANY_SEGMENT);
        }
    }

    /// Adds a joint-encoder reading (rad; a non-finite one is not counted).
    pub fn push_encoder(&mut self, angle: f64) {
        if angle.is_finite() {
            self.enc += 1;
            self.enc_beyond_pi += u64::from(angle.abs() > core::f64::consts::PI);
        }
    }

    /// Adds the complete vectors of one reading of IMU slot `slot`.
    pub fn push_imu(&mut self, slot: usize, imu: &ImuSample) {
        if let Some(a) = &imu.acc {
            self.push_acc(slot, a);
        }
        if let Some(w) = &imu.gyr {
            self.push_gyr(slot, w);
        }
    }

    /// Adds a sample's IMU readings (both legs) and encoder readings.
    pub fn push_sample(&mut self, s: &limbfuse_core::Sample) {
        for (slot, imu) in s.imu.iter().chain(&s.other_leg_imu).enumerate() {
            self.push_imu(slot, imu);
        }
        for e in s.encoder.iter().flatten() {
            self.push_encoder(*e);
        }
    }

    /// What looks wrong, accelerometers first.
    pub fn suspects(&self) -> impl Iterator<Item = UnitSuspect> {
        let share = |k: u64, n: u64| (n >= MIN_READINGS).then(|| k as f64 / n as f64);
        let acc = flagged(&self.acc, G_UNIT_SHARE)
            .map(|(share, which)| UnitSuspect::AccelerometerInG { share, which });
        let gyr = flagged(&self.gyr, DEGREES_SHARE)
            .map(|(share, which)| UnitSuspect::GyroscopeInDegrees { share, which });
        let enc = share(self.enc_beyond_pi, self.enc)
            .filter(|s| *s >= DEGREES_ANGLE_SHARE)
            .map(|share| UnitSuspect::EncoderInDegrees { share });
        acc.into_iter().chain(gyr).chain(enc)
    }
}

/// The IMU slots whose share of suspect readings (`(readings, suspect)`
/// per slot) reaches `threshold`, each judged on its own readings when it
/// has [`MIN_READINGS`], and the share pooled over them; when no slot has
/// enough readings, all of them pooled.
fn flagged(counts: &[(u64, u64); IMU_SLOTS], threshold: f64) -> Option<(f64, ImuSet)> {
    let with_readings = (0..IMU_SLOTS).filter(|&k| counts[k].0 > 0);
    let present: u8 = with_readings.fold(0, |b, k| b | (1 << k));
    let judged: Vec<usize> = (0..IMU_SLOTS)
        .filter(|&k| counts[k].0 >= MIN_READINGS)
        .collect();
    let bits: u8 = if judged.is_empty() {
        let (n, k) = counts.iter().fold((0, 0), |(n, k), c| (n + c.0, k + c.1));
        if n < MIN_READINGS || (k as f64) < threshold * n as f64 {
            return None;
        }
        present
    } else {
        judged
            .into_iter()
            .filter(|&k| counts[k].1 as f64 >= threshold * counts[k].0 as f64)
            .fold(0, |b, k| b | (1 << k))
    };
    if bits == 0 {
        return None;
    }
    let (n, k) = (0..IMU_SLOTS)
        .filter(|k| bits & (1 << k) != 0)
        .fold((0, 0), |(n, s), j| (n + counts[j].0, s + counts[j].1));
    Some((
        k as f64 / n as f64,
        ImuSet {
            bits,
            every: bits == present,
        },
    ))
}

/// The warnings of both unit checks, time column first: what `estimate`,
/// `align` and `inspect` say (CLI and Python alike).
pub fn unit_warnings(
    intervals: &SampleIntervalWatch,
    units: &SensorUnitsWatch,
) -> impl Iterator<Item = String> {
    let time = intervals.mismatch().map(|m| m.to_string());
    time.into_iter()
        .chain(units.suspects().map(|u| u.to_string()))
}

impl Observer for SensorUnitsWatch {
    /// Counts every [`SensorUnitsWatch::STRIDE`]-th record.
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

    /// A walking-like reading at phase `k`: specific force around g with
    /// +-0.5 g, rate up to `peak` rad/s.
    fn walking(k: usize, peak: f64) -> (Vector3<f64>, Vector3<f64>) {
        let p = k as f64 * 0.063;
        let a = Vector3::new(3.0 * p.sin(), 9.81 + 4.9 * (2.0 * p).cos(), 0.5);
        let w = Vector3::new(0.1, 0.2, peak * p.sin());
        (a, w)
    }

    fn watch(acc_scale: f64, gyr_scale: f64, peak: f64) -> Vec<UnitSuspect> {
        let mut u = SensorUnitsWatch::default();
        for k in 0..1000 {
            let (a, w) = walking(k, peak);
            u.push_acc(0, &(a * acc_scale));
            u.push_gyr(0, &(w * gyr_scale));
        }
        u.suspects().collect()
    }

    #[test]
    fn si_units_pass_even_for_a_fast_foot() {
        assert!(watch(1.0, 1.0, 8.0).is_empty());
        assert!(watch(1.0, 1.0, 20.0).is_empty());
    }

    #[test]
    fn accelerometers_in_g_are_named() {
        let s = watch(1.0 / 9.81, 1.0, 3.0);
        assert!(matches!(s[..], [UnitSuspect::AccelerometerInG { share, .. }] if share > 0.9));
        assert!(s[0]
            .to_string()
            .contains("look like g (multiply them by 9.81)"));
    }

    #[test]
    fn gyroscopes_in_degrees_are_named() {
        let s = watch(1.0, 180.0 / core::f64::consts::PI, 3.0);
        assert!(matches!(s[..], [UnitSuspect::GyroscopeInDegrees { share, .. }] if share > 0.5));
        assert!(s[0].to_string().contains("look like deg/s"));
        // both at once, accelerometers first
        let s = watch(1.0 / 9.81, 180.0 / core::f64::consts::PI, 3.0);
        assert!(matches!(
            s[..],
            [
                UnitSuspect::AccelerometerInG { .. },
                UnitSuspect::GyroscopeInDegrees { .. }
            ]
        ));
    }

    #[test]
    fn too_few_readings_say_nothing() {
        let mut u = SensorUnitsWatch::default();
        for _ in 0..MIN_READINGS - 1 {
            u.push_acc(0, &Vector3::new(0.0, 1.0, 0.0));
            u.push_gyr(0, &Vector3::new(0.0, 0.0, 100.0));
        }
        assert_eq!(u.suspects().count(), 0);
        u.push_acc(0, &Vector3::new(0.0, 1.0, 0.0));
        u.push_gyr(0, &Vector3::new(0.0, 0.0, 100.0));
        assert_eq!(u.suspects().count(), 2);
    }

    #[test]
    fn encoders_and_references_in_degrees_are_named() {
        let mut u = SensorUnitsWatch::default();
        let mut r = ReferenceUnitsWatch::default();
        let mut rad = ReferenceUnitsWatch::default();
        for k in 0..200 {
            let knee = 0.6 * (k as f64 * 0.063).sin().abs();
            u.push_encoder(knee.to_degrees());
            let mut reference = limbfuse_core::Reference::default();
            reference.joint[1] = Some(knee.to_degrees());
            reference.segment[0] = Some(0.02); // a trunk within 3 deg stays below pi in degrees
            r.push(&reference);
            reference.joint[1] = Some(knee);
            rad.push(&reference);
        }
        assert!(matches!(
            u.suspects().collect::<Vec<_>>()[..],
            [UnitSuspect::EncoderInDegrees { .. }]
        ));
        let w = r.warning().unwrap();
        assert!(w.contains("`knee_ref`") && !w.contains("trunk"), "{w}");
        assert_eq!(rad.warning(), None);
    }

    /// Twenty-seventh session's audit: pooled over every IMU, one trunk
    /// gyroscope in deg/s (walking trunk: up to ~30 deg/s) or one shank
    /// accelerometer in g among SI readings passed; each IMU is judged on
    /// its own now, and the message names it.
    #[test]
    fn one_imu_in_the_wrong_unit_is_named() {
        let mut u = SensorUnitsWatch::default();
        for k in 0..400 {
            let (a, w) = walking(k, 8.0);
            for slot in 0..4 {
                let gyr = if slot == 0 {
                    w * 0.1 * 180.0 / core::f64::consts::PI
                } else {
                    w
                };
                let acc = if slot == 2 { a / 9.81 } else { a };
                u.push_gyr(slot, &gyr);
                u.push_acc(slot, &acc);
            }
        }
        let s: Vec<String> = u.suspects().map(|x| x.to_string()).collect();
        assert_eq!(s.len(), 2, "{s:?}");
        assert!(
            s[0].contains("of the shank accelerometer readings"),
            "{}",
            s[0]
        );
        assert!(s[1].contains("of the trunk gyroscope readings"), "{}", s[1]);
        // Every IMU in the wrong unit: said of all of them, as before.
        let s = watch(1.0 / 9.81, 1.0, 3.0);
        assert!(
            s[0].to_string().contains("of the accelerometer readings"),
            "{}",
            s[0]
        );
    }

    #[test]
    fn rare_glitches_are_not_degrees() {
        let mut u = SensorUnitsWatch::default();
        for k in 0..1000 {
            let fast = if k % 40 == 0 { 1e3 } else { 1.0 };
            u.push_gyr(0, &Vector3::new(0.0, 0.0, fast));
        }
        assert_eq!(u.suspects().count(), 0);
    }
}
