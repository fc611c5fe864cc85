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
//! and a stuck sensor (a vector repeated exactly for 0.1 s or more; an
//! accelerometer's repeat only while its IMU turns, its gyroscope is frozen
//! too, or it has none). They too become missing and are counted, by kind
//! and by reason.
//!
//! An incomplete vector (some axes missing in the file: `acc_partial`,
//! `gyr_partial` of [`crate::sample::ImuSample`]; issue 18 item 2) gets the
//! same range and clipping checks per present cell (one bad cell drops the
//! vector's other present cells too) and, for gyroscopes, the jump check
//! per present axis against the last accepted complete vector. It takes no
//! part in the stuck check (a stuck sensor repeats all three axes) and is
//! not remembered as the last accepted vector. A rejected incomplete vector
//! counts as one rejected reading of its kind.

use crate::plausibility::{AccRepeatTurn, Implausible, PlausibilityLimits, VectorTrack};
use crate::sample::{ImuSample, Sample};
use crate::screening::Screening;

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
    /// Per IMU, the turn seen by its gyroscope over its accelerometer's
    /// current repeat ([`crate::plausibility`], "Stuck sensor").
    acc_turns: [AccRepeatTurn; 8],
    /// Time of the last sample screened.
    last_t: Option<f64>,
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
            acc_turns: [AccRepeatTurn::default(); 8],
            last_t: None,
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
        self.acc_turns = [AccRepeatTurn::default(); 8];
        self.last_t = None;
    }

    /// `sample` with every out-of-range, non-finite or implausible sensor
    /// reading made missing; the count of rejections grows by what was
    /// removed. The same as [`SampleGate::check`] then [`Screening::apply`]
    /// on a copy.
    pub fn screen(&mut self, sample: &Sample) -> Sample {
        let screening = self.check(sample);
        let mut out = *sample;
        screening.apply(&mut out);
        out
    }

    /// Checks `sample` as [`SampleGate::screen`] does (counting and
    /// remembering alike) and says which readings to make missing, without
    /// copying the sample: most samples need no change
    /// ([`Screening::is_clean`]).
    pub fn check(&mut self, sample: &Sample) -> Screening {
        let mut out = Screening::default();
        let before = self.rejections.total();
        let t = sample.t;
        let dt = self.last_t.map_or(f64::NAN, |t0| t - t0);
        self.last_t = Some(t);
        for k in 0..8 {
            let imu = if k < 4 {
                &sample.imu[k]
            } else {
                &sample.other_leg_imu[k - 4]
            };
            // (an IMU without a cell: nothing to check, no history to change)
            if imu.gyr.is_some() || imu.acc.is_some() || has_partial_cells(imu) {
                self.check_imu(k, imu, t, dt, &mut out);
            }
        }
        let r = &self.ranges;
        for (j, e) in sample.encoder.iter().enumerate() {
            if e.is_some_and(|x| !x.is_finite() || x.abs() > r.encoder_rad) {
                out.encoder |= 1 << j;
                self.rejections.encoder += 1;
            }
        }
        if self.rejections.total() > before && self.rejections.first_t.is_none() {
            self.rejections.first_t = Some(sample.t);
        }
        out
    }

    /// [`SampleGate::check`] on IMU `k` (this leg's four, then the other's).
    fn check_imu(&mut self, k: usize, imu: &ImuSample, t: f64, dt: f64, out: &mut Screening) {
        let SampleGate {
            ranges: r,
            limits: lim,
            rejections: rej,
            tracks,
            ..
        } = self;
        let track = &mut tracks[k];
        let within = |v: &nalgebra::Vector3<f64>, limit: f64| v.iter().all(|x| x.abs() <= limit);
        let clipped = |v: &nalgebra::Vector3<f64>, fs: Option<f64>| {
            fs.is_some_and(|fs| v.iter().any(|x| x.abs() >= CLIPPED_FRACTION * fs))
        };
        let bit = 1u8 << k;
        let alpha = lim.angular_accel_rad_s2[k % 4];
        let mut gyro_stuck = false;
        let mut gyr = imu.gyr.as_ref(); // the gyroscope as screened so far
        if let Some(g) = gyr {
            // (most readings pass the range and clipping tests: one pass, NaN fails)
            let clip = r
                .gyro_full_scale_rad_s
                .map_or(f64::INFINITY, |fs| CLIPPED_FRACTION * fs);
            let plain = (g.x.abs() <= r.gyro_rad_s)
                & (g.y.abs() <= r.gyro_rad_s)
                & (g.z.abs() <= r.gyro_rad_s)
                & (g.x.abs() < clip)
                & (g.y.abs() < clip)
                & (g.z.abs() < clip);
            let rejected = if !plain && !within(g, r.gyro_rad_s) {
                true
            } else if !plain && clipped(g, r.gyro_full_scale_rad_s) {
                rej.clipped += 1;
                true
            } else if let Some(why) = track[0].check(g, t, Some(alpha), lim) {
                gyro_stuck = why == Implausible::Stuck;
                tally(rej, why);
                true
            } else {
                false
            };
            if rejected {
                gyr = None;
                rej.gyro += 1;
                out.gyr |= bit;
            }
        }
        self.check_imu_rest(k, imu, gyr, gyro_stuck, (t, dt), out);
    }

    /// The checks after the complete gyroscope vector's (`gyr`: accepted,
    /// `gyro_stuck`: rejected as stuck): the incomplete gyroscope vector and
    /// the accelerometer, at `(t, dt)`.
    #[inline]
    fn check_imu_rest(
        &mut self,
        k: usize,
        imu: &ImuSample,
        gyr: Option<&nalgebra::Vector3<f64>>,
        gyro_stuck: bool,
        (t, dt): (f64, f64),
        out: &mut Screening,
    ) {
        let SampleGate {
            ranges: r,
            limits: lim,
            rejections: rej,
            tracks,
            acc_turns,
            ..
        } = self;
        let (track, turn) = (&mut tracks[k], &mut acc_turns[k]);
        let within = |v: &nalgebra::Vector3<f64>, limit: f64| v.iter().all(|x| x.abs() <= limit);
        let bit = 1u8 << k;
        let alpha = lim.angular_accel_rad_s2[k % 4];
        if gyr.is_none() && imu.gyr_partial.iter().any(Option::is_some) {
            let cells = &imu.gyr_partial;
            let out_of_range = !cells_within(cells, r.gyro_rad_s);
            let clip = !out_of_range && cells_clipped(cells, r.gyro_full_scale_rad_s);
            let why = (!out_of_range && !clip)
                .then(|| track[0].check_axes(cells, t, Some(alpha), lim))
                .flatten();
            if out_of_range || clip || why.is_some() {
                out.gyr_partial |= bit;
                rej.gyro += 1;
                rej.clipped += u64::from(clip);
                if let Some(why) = why {
                    tally(rej, why);
                }
            }
        }
        if imu.acc.is_none() && !cells_within(&imu.acc_partial, r.acc_m_s2) {
            out.acc_partial |= bit;
            rej.acc += 1;
        }
        if let Some(a) = imu.acc.as_ref() {
            if !within(a, r.acc_m_s2) {
                out.acc |= bit;
                rej.acc += 1;
            } else {
                let why = track[1].check(a, t, None, lim);
                turn.add(track[1].repeats(), a, gyr, dt, lim);
                let why = why.filter(|w| {
                    *w != Implausible::Stuck || turn.confirms_stuck(a, gyro_stuck, lim)
                });
                if let Some(why) = why {
                    out.acc |= bit;
                    rej.acc += 1;
                    tally(rej, why);
                }
            }
        }
    }
}

/// Whether any axis of an incomplete vector is there.
fn has_partial_cells(imu: &ImuSample) -> bool {
    imu.acc_partial
        .iter()
        .chain(&imu.gyr_partial)
        .any(Option::is_some)
}

/// Whether every present cell of an incomplete vector is finite and within
/// `limit` (a packet with one bad cell is dropped whole, as a complete
/// vector is).
fn cells_within(cells: &[Option<f64>; 3], limit: f64) -> bool {
    cells.iter().flatten().all(|x| x.abs() <= limit)
}

/// Whether any present cell is at or beyond [`CLIPPED_FRACTION`] of the
/// full scale `fs`.
fn cells_clipped(cells: &[Option<f64>; 3], fs: Option<f64>) -> bool {
    fs.is_some_and(|fs| {
        cells
            .iter()
            .flatten()
            .any(|x| x.abs() >= CLIPPED_FRACTION * fs)
    })
}

/// Counts a plausibility rejection by its reason.
fn tally(rej: &mut Rejections, why: Implausible) {
    match why {
        Implausible::Jump => rej.jumps += 1,
        Implausible::Stuck => rej.stuck += 1,
    }
}

#[cfg(test)]
mod reference;

#[cfg(test)]
pub(crate) mod tests {
    use super::*;
    use nalgebra::Vector3;

    /// All four IMUs and the encoders reading plausible walking values.
    pub(crate) fn walking_sample() -> Sample {
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
    fn issue_18_incomplete_vectors_are_screened_per_cell() {
        let mut g = SampleGate::new(SensorRanges::default());
        let s = walking_sample();
        assert_eq!(g.screen(&s), s);
        let mut p = walking_sample();
        p.t = 1.01;
        p.imu[0].gyr = None;
        p.imu[0].gyr_partial = [None, None, Some(3.1)];
        p.imu[1].acc = None;
        p.imu[1].acc_partial = [Some(2.0), Some(9.4), None];
        // plausible partial vectors pass unchanged
        assert_eq!(g.screen(&p), p);
        assert_eq!(g.rejections().total(), 0);
        p.t = 1.02;
        p.imu[0].gyr_partial = [Some(0.1), None, Some(1e300)];
        p.imu[1].acc_partial = [Some(f64::NAN), Some(9.4), None];
        p.imu[2].gyr = None;
        p.imu[2].gyr_partial = [None, None, Some(34.9)]; // clipped
        p.imu[3].gyr = None;
        p.imu[3].gyr_partial = [None, Some(-0.2), Some(3.0 + 15.0)]; // a jump (foot: 101 rad/s allowed)
        let out = g.screen(&p);
        assert_eq!(out.imu[0].gyr_partial, [None; 3]);
        assert_eq!(out.imu[1].acc_partial, [None; 3]);
        assert_eq!(out.imu[2].gyr_partial, [None; 3]);
        assert_eq!(out.imu[3].gyr_partial, p.imu[3].gyr_partial);
        let r = *g.rejections();
        assert_eq!((r.gyro, r.acc, r.clipped, r.jumps), (2, 1, 1, 0));
        p.t = 1.03;
        p.imu[1].gyr = None;
        p.imu[1].gyr_partial = [None, None, Some(3.0 + 25.0)]; // thigh: beyond 21 rad/s in 10 ms
        let out = g.screen(&p);
        assert_eq!(out.imu[1].gyr_partial, [None; 3]);
        assert_eq!(g.rejections().jumps, 1);
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

    /// The thigh accelerometer's vector rejected at each of `n` samples at
    /// 100 Hz: the accelerometer reads `acc(k)`, the gyroscope `gyr(k)`.
    fn acc_rejected(
        n: usize,
        acc: impl Fn(usize) -> Vector3<f64>,
        gyr: impl Fn(usize) -> Option<Vector3<f64>>,
    ) -> Vec<bool> {
        let mut gate = SampleGate::new(SensorRanges::default());
        (0..n)
            .map(|k| {
                let mut s = Sample::empty(k as f64 * 0.01);
                s.imu[1].acc = Some(acc(k));
                s.imu[1].gyr = gyr(k);
                gate.screen(&s).imu[1].acc.is_none()
            })
            .collect()
    }

    /// A gyroscope reading with white noise of about 0.01 rad/s and a
    /// 1.5 deg/s bias: a still segment.
    fn still_gyro(k: usize) -> Option<Vector3<f64>> {
        let n = |j: usize| 0.01 * (((k * 7 + j * 13) % 11) as f64 / 5.0 - 1.0);
        Some(Vector3::new(0.026 + n(0), n(1), -0.02 + n(2)))
    }

    #[test]
    fn issue_18_a_still_accelerometer_recorded_at_0_01_g_is_not_stuck() {
        // The knee rig's files: 0.01 g steps, a still segment repeats its
        // vector for seconds while its gyroscope shows noise and bias.
        let q = 0.0981;
        let rig = Vector3::new(12.0 * q, 100.0 * q, -3.0 * q);
        let r = acc_rejected(500, |_| rig, still_gyro);
        assert!(r.iter().all(|&x| !x), "{r:?}");
        // Turning about the specific force itself (about the vertical)
        // changes nothing it measures.
        let about_g = |k: usize| Some(rig.normalize() * (2.0 + (k as f64).sin()));
        assert!(acc_rejected(500, |_| rig, about_g).iter().all(|&x| !x));
    }

    #[test]
    fn issue_18_a_frozen_accelerometer_on_a_turning_segment_is_stuck() {
        // Walking: the thigh turns at ~2 rad/s about z; its accelerometer
        // freezes from sample 100 on.
        let frozen = Vector3::new(2.0, 9.5, -0.3);
        let acc = |k: usize| {
            if k >= 100 {
                frozen
            } else {
                Vector3::new(2.0 + 0.01 * k as f64, 9.5, -0.3)
            }
        };
        let gyr = |k: usize| Some(Vector3::new(0.1, 0.0, 2.0 * (k as f64 * 0.06).sin() + 2.5));
        let r = acc_rejected(300, acc, gyr);
        let first = r.iter().position(|&x| x);
        // the repeat rule's 0.1 s (sample 110), the turn long exceeded
        assert_eq!(first, Some(110));
        assert!(r[110..].iter().all(|&x| x));
    }

    #[test]
    fn issue_18_a_frozen_imu_and_an_imu_without_gyroscope_keep_the_repeat_rule() {
        let frozen = Vector3::new(2.0, 9.5, -0.3);
        // the whole IMU frozen: its gyroscope repeats too
        let w = Vector3::new(0.3, -0.1, 1.2);
        let r = acc_rejected(200, |_| frozen, |_| Some(w));
        assert_eq!(r.iter().position(|&x| x), Some(10));
        // no gyroscope: no evidence of stillness, the repeat alone decides
        let r = acc_rejected(200, |_| frozen, |_| None);
        assert_eq!(r.iter().position(|&x| x), Some(10));
        // a gyroscope that stays still, then turns: rejected once the turn
        // predicts 0.5 m/s^2 of change (0.5 rad/s across g: ~0.1 s)
        let gyr = |k: usize| {
            if k < 100 {
                still_gyro(k)
            } else {
                Some(Vector3::new(0.0, 0.0, 0.5))
            }
        };
        let r = acc_rejected(300, |_| frozen, gyr);
        let first = r.iter().position(|&x| x).expect("rejected once turning");
        assert!((105..=115).contains(&first), "{first}");
    }
}
