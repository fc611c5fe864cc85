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
//! docs/RESULTS.md "Soak"). An accelerometer vector is clipped when any
//! axis is at or beyond [`ACC_CLIPPED_FRACTION`] of its full scale
//! (2026-12-06): its direction is not the specific force's, and an
//! inclination or a kinematic chain corrected by it is wrong (a 2 g foot and
//! shank sensor on the independent 1.6 m/s walk: `chain`'s knee 0.11 ->
//! 1.72 deg, `knee-selfalign`'s 0.17 -> 0.82; 0.15 and 0.12 with the clipped
//! readings missing, docs/RESULTS.md "Clipped accelerometers"). Estimators
//! that integrate the specific force keep them
//! ([`crate::Estimator::keeps_clipped_acc`]: `gait-events`, whose strapdown
//! stride integration would lose the stride if a heel strike's sample went
//! missing, 41 instead of 55 strides, and which models the clipped impact;
//! `lowback-speed`).
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
    /// Accelerometer full scale (m/s^2). A reading with any axis at or
    /// beyond [`ACC_CLIPPED_FRACTION`] of it is clipped and rejected.
    /// `None`: no clipping check.
    pub acc_full_scale_m_s2: Option<f64>,
}

/// Fraction of a full scale from which a reading counts as clipped (the
/// rule `knee-selfalign` applies to its gyroscopes, docs/KNEE_SELFALIGN.md).
pub const CLIPPED_FRACTION: f64 = 0.999;

/// Fraction of an accelerometer's full scale from which an axis counts as
/// clipped. Not 1: a clipped reading is the rail of the raw axis passed
/// through the sensor's calibration, which moves it by the sensitivity and
/// cross-axis tolerances (MPU-6050 +-3 % and +-2 %, ICM-20948 +-0.5 % and
/// +-2 %, BMI160 +-1 % each: datasheets); the shared gaitmap walk's
/// (NilsPod, 16 g) heel strikes reach 152.3-158.1 m/s^2 and none lies between
/// 146 and 152. (A gyroscope's [`CLIPPED_FRACTION`] is 0.999: a rate at
/// 97 % of 2000 deg/s is a real one on a foot.)
pub const ACC_CLIPPED_FRACTION: f64 = 0.97;

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
            acc_full_scale_m_s2: Some(16.0 * 9.80665),
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
            let clip =
                !out_of_range && cells_clipped(cells, r.gyro_full_scale_rad_s, CLIPPED_FRACTION);
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
        if imu.acc.is_none() && imu.acc_partial.iter().any(Option::is_some) {
            let out_of_range = !cells_within(&imu.acc_partial, r.acc_m_s2);
            let clip = !out_of_range
                && cells_clipped(
                    &imu.acc_partial,
                    r.acc_full_scale_m_s2,
                    ACC_CLIPPED_FRACTION,
                );
            if out_of_range || clip {
                out.acc_partial |= bit;
                rej.acc += 1;
                rej.clipped += u64::from(clip);
            }
        }
        if let Some(a) = imu.acc.as_ref() {
            let acc_clip = r
                .acc_full_scale_m_s2
                .map_or(f64::INFINITY, |fs| ACC_CLIPPED_FRACTION * fs);
            if !within(a, r.acc_m_s2) {
                out.acc |= bit;
                rej.acc += 1;
            } else if (a.x.abs() >= acc_clip) | (a.y.abs() >= acc_clip) | (a.z.abs() >= acc_clip) {
                out.acc |= bit;
                rej.acc += 1;
                rej.clipped += 1;
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

/// Whether any present cell is at or beyond `fraction` of the full scale
/// `fs` (`None`: no clipping test).
fn cells_clipped(cells: &[Option<f64>; 3], fs: Option<f64>, fraction: f64) -> bool {
    fs.is_some_and(|fs| cells.iter().flatten().any(|x| x.abs() >= fraction * fs))
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
pub(crate) mod tests;
