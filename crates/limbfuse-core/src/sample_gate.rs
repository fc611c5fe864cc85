//! Physical-range screening of sensor readings before any estimator sees
//! them (issue 18 item 1).
//!
//! A reading outside the range its sensor can measure cannot be a
//! measurement: it is a bus glitch (a bit flip, a dropped byte, a parser
//! misreading a cell). Passed on, one such value ruins a filter for the rest
//! of a trial: a single thigh gyro cell of `1e300` left `mjls`, `global` and
//! `local` 91 deg off for a minute. [`SampleGate`] turns every reading outside
//! [`SensorRanges`] (or not finite) into a missing reading, which every
//! estimator already survives (it predicts without that update), and counts
//! it.
//!
//! The whole 3-axis vector of a sensor is dropped when any of its axes is out
//! of range: the other axes of a corrupted packet are not to be trusted
//! either. Likewise when any gyroscope axis is clipped, at or beyond
//! [`CLIPPED_FRACTION`] of the sensor's full scale: a saturated gyroscope
//! reports its full scale whatever the true rate, and integrating it costs
//! tens of degrees within 0.1 s (issue 18: found by the soak run,
//! docs/RESULTS.md "Soak"). Accelerometers are not clipped: foot impacts
//! saturate a 16 g accelerometer at heel strikes (the shared gaitmap foot
//! recording reaches 157.2 m/s^2 = 16 g on most strides), the clipped value
//! still bounds the specific force, the segment filters gate such samples
//! by their norm, and a foot's strapdown stride integration would lose the
//! stride if the sample went missing (measured: 41 instead of 55 strides).
//!
//! Readings within range then pass the plausibility checks of
//! [`crate::plausibility`]: a gyroscope jump faster than a human segment
//! can accelerate, the repeats of a value so rejected (a saturated burst),
//! and a stuck sensor (a vector repeated exactly for 0.1 s or more). They
//! too become missing and are counted, by kind and by reason.

use crate::plausibility::{Implausible, PlausibilityLimits, VectorTrack};
use crate::sample::Sample;

/// The largest readings a sensor can produce, per kind.
///
/// The defaults are the widest full-scale ranges of the IMUs used for gait
/// and exoskeleton work, plus 15 % for scale-factor and cross-axis errors:
/// Xsens MTw Awinda and MTi-3 (2000 deg/s, 160 m/s^2 = 16 g), Bosch BMI160 /
/// BMI270 and TDK ICM-20948 (2000 deg/s, 16 g) datasheets. A trial sets its
/// own with the metadata keys `gyro_range_rad_s` and `acc_range_m_s2`
/// (see docs/OUTPUTS.md); a sensor with a wider range needs them.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SensorRanges {
    /// Largest angular rate magnitude on any axis (rad/s).
    pub gyro_rad_s: f64,
    /// Largest specific force magnitude on any axis (m/s^2).
    pub acc_m_s2: f64,
    /// Largest joint-encoder angle magnitude (rad): no human joint turns
    /// further than half a turn from its zero.
    pub encoder_rad: f64,
    /// Gyroscope full scale (rad/s). A reading with any axis at or beyond
    /// [`CLIPPED_FRACTION`] of it is clipped: the sensor saturated and the
    /// true rate is unknown, so the vector is rejected from its first
    /// sample (a saturated foot gyroscope is otherwise caught only as a
    /// stuck sensor, after 0.1 s, during which integrating a full-scale rate
    /// costs tens of degrees). `None`: no clipping check.
    pub gyro_full_scale_rad_s: Option<f64>,
}

/// Fraction of a full scale from which a reading counts as clipped (the
/// rule `knee-selfalign` applies to its gyroscopes, docs/KNEE_SELFALIGN.md).
pub const CLIPPED_FRACTION: f64 = 0.999;

impl Default for SensorRanges {
    fn default() -> Self {
        let gyro_fs = 2000.0 * core::f64::consts::PI / 180.0;
        SensorRanges {
            // Written as before the full scales were fields (bit-identical
            // ranges in estimate headers).
            gyro_rad_s: 1.15 * 2000.0 * core::f64::consts::PI / 180.0,
            acc_m_s2: 1.15 * 16.0 * 9.80665,
            encoder_rad: core::f64::consts::PI,
            gyro_full_scale_rad_s: Some(gyro_fs),
        }
    }
}

/// Readings turned into missing ones so far, per sensor kind.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct Rejections {
    /// Gyroscope vectors (one per IMU and sample).
    pub gyro: u64,
    /// Accelerometer vectors (one per IMU and sample).
    pub acc: u64,
    /// Encoder readings.
    pub encoder: u64,
    /// Of all those, the ones rejected as non-physical jumps (or repeats of
    /// a rejected jump, a saturated burst) within range.
    pub jumps: u64,
    /// Of all those, the ones rejected as a stuck sensor.
    pub stuck: u64,
    /// Of all those, the ones rejected as clipped (at the full scale).
    pub clipped: u64,
    /// Time of the first sample with a rejected reading (s).
    pub first_t: Option<f64>,
}

impl Rejections {
    /// Readings rejected, all kinds.
    pub fn total(&self) -> u64 {
        self.gyro + self.acc + self.encoder
    }
}

/// Screens samples against [`SensorRanges`] and [`PlausibilityLimits`]; see
/// the module documentation.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SampleGate {
    ranges: SensorRanges,
    limits: PlausibilityLimits,
    rejections: Rejections,
    /// Gyroscope then accelerometer history of the eight IMUs (this leg's
    /// four, then the other leg's).
    tracks: [[VectorTrack; 2]; 8],
}

impl SampleGate {
    /// A gate with these ranges, the default [`PlausibilityLimits`] and
    /// nothing rejected yet.
    pub fn new(ranges: SensorRanges) -> Self {
        Self::with_limits(ranges, PlausibilityLimits::default())
    }

    /// A gate with these ranges and plausibility limits.
    pub fn with_limits(ranges: SensorRanges, limits: PlausibilityLimits) -> Self {
        SampleGate {
            ranges,
            limits,
            rejections: Rejections::default(),
            tracks: [[VectorTrack::default(); 2]; 8],
        }
    }

    /// The plausibility limits in use.
    pub fn limits(&self) -> &PlausibilityLimits {
        &self.limits
    }

    /// The ranges in use.
    pub fn ranges(&self) -> &SensorRanges {
        &self.ranges
    }

    /// What was rejected since construction or [`SampleGate::reset`].
    pub fn rejections(&self) -> &Rejections {
        &self.rejections
    }

    /// Forgets the counts and the sensors' history.
    pub fn reset(&mut self) {
        self.rejections = Rejections::default();
        self.tracks = [[VectorTrack::default(); 2]; 8];
    }

    /// `sample` with every out-of-range, non-finite or implausible sensor
    /// reading made missing; the count of rejections grows by what was
    /// removed.
    pub fn screen(&mut self, sample: &Sample) -> Sample {
        let mut out = *sample;
        let before = self.rejections.total();
        let r = self.ranges;
        let lim = self.limits;
        let t = sample.t;
        let within = |v: &nalgebra::Vector3<f64>, limit: f64| v.iter().all(|x| x.abs() <= limit);
        let clipped = |v: &nalgebra::Vector3<f64>, fs: Option<f64>| {
            fs.is_some_and(|fs| v.iter().any(|x| x.abs() >= CLIPPED_FRACTION * fs))
        };
        let rej = &mut self.rejections;
        let imus = out.imu.iter_mut().chain(out.other_leg_imu.iter_mut());
        for (k, (imu, track)) in imus.zip(self.tracks.iter_mut()).enumerate() {
            let alpha = lim.angular_accel_rad_s2[k % 4];
            if let Some(g) = imu.gyr {
                if !within(&g, r.gyro_rad_s) {
                    imu.gyr = None;
                    rej.gyro += 1;
                } else if clipped(&g, r.gyro_full_scale_rad_s) {
                    imu.gyr = None;
                    rej.gyro += 1;
                    rej.clipped += 1;
                } else if let Some(why) = track[0].check(&g, t, Some(alpha), &lim) {
                    imu.gyr = None;
                    rej.gyro += 1;
                    tally(rej, why);
                }
            }
            if let Some(a) = imu.acc {
                if !within(&a, r.acc_m_s2) {
                    imu.acc = None;
                    rej.acc += 1;
                } else if let Some(why) = track[1].check(&a, t, None, &lim) {
                    imu.acc = None;
                    rej.acc += 1;
                    tally(rej, why);
                }
            }
        }
        for e in out.encoder.iter_mut() {
            if e.is_some_and(|x| !x.is_finite() || x.abs() > r.encoder_rad) {
                *e = None;
                rej.encoder += 1;
            }
        }
        if self.rejections.total() > before && self.rejections.first_t.is_none() {
            self.rejections.first_t = Some(sample.t);
        }
        out
    }
}

/// Counts a plausibility rejection by its reason.
fn tally(rej: &mut Rejections, why: Implausible) {
    match why {
        Implausible::Jump => rej.jumps += 1,
        Implausible::Stuck => rej.stuck += 1,
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use nalgebra::Vector3;

    fn walking_sample() -> Sample {
        let mut s = Sample::empty(1.0);
        for imu in s.imu.iter_mut() {
            imu.gyr = Some(Vector3::new(0.1, -0.2, 3.0));
            imu.acc = Some(Vector3::new(2.0, 9.5, -0.3));
        }
        s.encoder = [Some(0.3), Some(1.2), Some(-0.2)];
        s.other_leg_imu = s.imu;
        s
    }

    #[test]
    fn readings_within_range_pass_unchanged() {
        let mut g = SampleGate::new(SensorRanges::default());
        let s = walking_sample();
        assert_eq!(g.screen(&s), s);
        assert_eq!(g.rejections().total(), 0);
        assert_eq!(g.rejections().first_t, None);
    }

    #[test]
    fn a_glitch_on_one_axis_drops_that_sensor_only_and_is_counted() {
        let mut g = SampleGate::new(SensorRanges::default());
        let mut s = walking_sample();
        s.imu[1].gyr = Some(Vector3::new(0.1, 1e300, 3.0));
        s.imu[2].acc = Some(Vector3::new(-1e308, 9.5, 0.0));
        s.encoder[1] = Some(f64::INFINITY);
        let out = g.screen(&s);
        assert_eq!(out.imu[1].gyr, None);
        assert_eq!(out.imu[1].acc, s.imu[1].acc);
        assert_eq!(out.imu[2].acc, None);
        assert_eq!(out.imu[2].gyr, s.imu[2].gyr);
        assert_eq!(out.encoder, [Some(0.3), None, Some(-0.2)]);
        let r = g.rejections();
        assert_eq!((r.gyro, r.acc, r.encoder, r.first_t), (1, 1, 1, Some(1.0)));
        // The other leg's IMUs (two-leg gait-event trials) are screened too.
        let mut two = walking_sample();
        two.other_leg_imu[3].gyr = Some(Vector3::new(0.0, 0.0, -1e300));
        let out = g.screen(&two);
        assert_eq!(out.other_leg_imu[3].gyr, None);
        assert_eq!(out.imu[3].gyr, two.imu[3].gyr);
        assert_eq!(g.rejections().gyro, 2);
        // The first time stays the first.
        let mut later = s;
        later.t = 2.0;
        g.screen(&later);
        assert_eq!(g.rejections().first_t, Some(1.0));
        assert_eq!(g.rejections().total(), 7);
    }

    #[test]
    fn nan_is_rejected_and_the_limit_itself_is_accepted() {
        let ranges = SensorRanges {
            gyro_rad_s: 10.0,
            acc_m_s2: 50.0,
            encoder_rad: 1.0,
            gyro_full_scale_rad_s: None,
        };
        let mut g = SampleGate::new(ranges);
        let mut s = walking_sample();
        s.imu[0].gyr = Some(Vector3::new(10.0, -10.0, 0.0));
        s.imu[0].acc = Some(Vector3::new(f64::NAN, 0.0, 0.0));
        s.encoder = [Some(1.0), Some(-1.0), Some(1.0000001)];
        let out = g.screen(&s);
        assert!(out.imu[0].gyr.is_some());
        assert!(out.imu[0].acc.is_none());
        assert_eq!(out.encoder, [Some(1.0), Some(-1.0), None]);
    }

    #[test]
    fn issue_18_a_clipped_reading_is_rejected_from_its_first_sample() {
        let mut g = SampleGate::new(SensorRanges::default());
        let fs = 2000f64.to_radians();
        // A foot gyroscope saturating at full scale: within the range (and
        // within the foot's jump bound), but clipped.
        let mut s = walking_sample();
        s.imu[3].gyr = Some(Vector3::new(fs, 3.0, -fs));
        let out = g.screen(&s);
        assert_eq!(out.imu[3].gyr, None);
        assert_eq!(out.imu[2].gyr, s.imu[2].gyr);
        let r = *g.rejections();
        assert_eq!((r.gyro, r.clipped), (1, 1));
        // Just below 99.9 % of full scale passes; a clipped accelerometer
        // (a heel strike beyond 16 g) is kept (module documentation).
        let mut t = walking_sample();
        t.t = 2.0;
        t.imu[0].gyr = Some(Vector3::new(0.998 * fs, 0.0, 0.0));
        t.imu[0].acc = Some(Vector3::new(0.0, 16.0 * 9.80665, 0.0));
        let out = g.screen(&t);
        assert_eq!(out.imu[0].gyr, t.imu[0].gyr);
        assert_eq!(out.imu[0].acc, t.imu[0].acc);
        assert_eq!(g.rejections().clipped, 1);
    }

    #[test]
    fn default_ranges_are_the_datasheet_full_scales_with_margin() {
        let r = SensorRanges::default();
        // 2000 deg/s = 34.9 rad/s; 16 g = 156.9 m/s^2; each + 15 %.
        assert!((r.gyro_rad_s - 40.142).abs() < 1e-3, "{}", r.gyro_rad_s);
        assert!((r.acc_m_s2 - 180.442).abs() < 1e-3, "{}", r.acc_m_s2);
    }
}
