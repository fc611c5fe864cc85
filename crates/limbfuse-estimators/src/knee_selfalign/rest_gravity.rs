//! An accelerometer that does not read 1 g at rest is not a gravity sensor
//! (ours, issue knee31b; not in paper 002).
//!
//! Eq 5 reads the knee angle from the direction of each segment's specific
//! force in its joint plane, which is gravity's direction plus the joint's
//! accelerations. That holds only for an accelerometer that measures
//! specific force: at rest it reads gravity, so the norm of its reading is
//! `g` within the sensor's tolerance. Where a segment rests and its
//! accelerometer's norm is off `g` by more than the tolerance
//! ([`ACC_REST_TOLERANCE_G`]), its readings carry an error of that size in
//! every sample, which eq 5 turns into the angle of the error: the
//! accelerometer angle is not trusted from then on, for the rest of the run
//! ([`RestGravityCheck::miscalibrated`], sticky: a zero-g offset or scale
//! error of tens of percent is the calibration's, not the moment's; a
//! window holding no rest of its own is read by the same sensor).
//!
//! Measured (docs/KNEE_SELFALIGN.md, "An accelerometer that does not read
//! 1 g at rest"): the shared knee rig's sensors read 1.00-1.01 g in their
//! start pose and 1.10-1.24 g in the rests from 2-7 s on; the shared walks
//! (S02, the independent walks, limbfuse's simulator) hold no rest at all.

use limbfuse_core::ImuSample;
use nalgebra::Vector3;

use super::sign::GAP_SPLIT_S;

/// Default tolerance (fraction of g) of an accelerometer's norm at rest:
/// the worst-case sum of the data-sheet errors of consumer MEMS
/// accelerometers, 3 % sensitivity (scale-factor) tolerance (MPU-6050
/// class; BMI270 / ICM-42688-P +-0.4-0.5 %, docs/SIMULATOR.md) and a
/// 60 mg zero-g offset along the reading (three times the 20 mg 1-sigma
/// turn-on offset of the BMI270 / ICM-42688-P data sheets the simulator
/// follows; the MPU-6050's +-50 mg on x and y), plus 10 mg for the rest's
/// residual motion (centripetal `w^2 r` < 2 mg at [`REST_MAX_RATE`] and a
/// 0.5 m lever arm), local gravity (9.78-9.83 against the 9.81 used, 3 mg)
/// and the noise of the mean (< 1 mg): 0.03 + 0.06 + 0.01 = 0.10.
pub const ACC_REST_TOLERANCE_G: f64 = 0.10;

/// A segment rests while its gyro norm stays below this (rad/s): at a
/// 0.5 m lever arm the centripetal acceleration `w^2 r` is then 0.02 m/s^2
/// (2 mg), far below [`ACC_REST_TOLERANCE_G`]. Walking never gets there
/// for long: the thigh and shank turn at about 1-2.5 rad/s (median over
/// the shared walks) and pass through zero only at a reversal, in well
/// under [`REST_MIN_S`].
pub const REST_MAX_RATE: f64 = 0.2;

/// ... while its specific force stays within this (fraction of g) of the
/// rest's first reading: the segment's own acceleration (tangential and
/// translational) is then at most 0.05 g, half the tolerance, and the
/// rest's mean is its gravity reading to a small part of the tolerance.
pub const REST_MAX_FORCE_CHANGE_G: f64 = 0.05;

/// ... for at least this long (s): longer than a heel strike's transient
/// (tens of ms) and than a segment's rate reversal in gait (a rate below
/// [`REST_MAX_RATE`] for 0.2 s needs an angular acceleration under
/// 2 rad/s^2, ten times below the thigh's and shank's in walking).
pub const REST_MIN_S: f64 = 0.2;

/// One sensor's current rest: its start time, first reading, the sum and
/// count of its readings.
#[derive(Debug, Clone, Copy, PartialEq)]
struct Rest {
    since: f64,
    first: Vector3<f64>,
    sum: Vector3<f64>,
    n: usize,
}

/// The rest check of one sensor.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
struct SensorRest {
    rest: Option<Rest>,
    last_t: Option<f64>,
    /// `|norm/g - 1|` of the last rest of at least [`REST_MIN_S`].
    error: Option<f64>,
}

impl SensorRest {
    fn step(&mut self, t: f64, imu: &ImuSample, g: f64) -> Option<f64> {
        let gap = self.last_t.is_some_and(|l| t - l > GAP_SPLIT_S);
        self.last_t = Some(t);
        let (Some(w), Some(f)) = (imu.gyr, imu.acc) else {
            self.rest = None;
            return None;
        };
        if w.norm() >= REST_MAX_RATE {
            self.rest = None;
            return None;
        }
        match &mut self.rest {
            Some(r) if !gap && (f - r.first).norm() <= REST_MAX_FORCE_CHANGE_G * g => {
                r.sum += f;
                r.n += 1;
            }
            // A new rest starts at a quiet reading (after a change of the
            // specific force or a time gap, at this one).
            _ => {
                self.rest = Some(Rest {
                    since: t,
                    first: f,
                    sum: f,
                    n: 1,
                });
            }
        }
        let r = self.rest.as_ref()?;
        if t - r.since < REST_MIN_S {
            return None;
        }
        let e = libm::fabs((r.sum / r.n as f64).norm() / g - 1.0);
        self.error = Some(e);
        Some(e)
    }
}

/// Whether the thigh and shank accelerometers read `g` where their segments
/// rest (the module documentation). Fixed size: stepping allocates nothing.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct RestGravityCheck {
    sensors: [SensorRest; 2],
    tolerance: f64,
    g: f64,
    miscalibrated: bool,
}

impl RestGravityCheck {
    /// A check with the norm tolerance `tolerance` (fraction of `g`, m/s^2).
    pub fn new(tolerance: f64, g: f64) -> Self {
        RestGravityCheck {
            sensors: [SensorRest::default(); 2],
            tolerance,
            g,
            miscalibrated: false,
        }
    }

    /// One sample of the thigh and shank readings at time `t` (s).
    pub fn step(&mut self, t: f64, imu: &[ImuSample; 2]) {
        for (s, reading) in self.sensors.iter_mut().zip(imu) {
            if s.step(t, reading, self.g)
                .is_some_and(|e| e > self.tolerance)
            {
                self.miscalibrated = true;
            }
        }
    }

    /// Whether a rest of either sensor has read a norm off `g` by more than
    /// the tolerance so far (sticky until [`Self::reset`]).
    pub fn miscalibrated(&self) -> bool {
        self.miscalibrated
    }

    /// The last rest's `|norm/g - 1|`, the larger of the two sensors'
    /// (`diag_rest_norm_error`); `None` before a rest was seen.
    pub fn last_error(&self) -> Option<f64> {
        match (self.sensors[0].error, self.sensors[1].error) {
            (Some(a), Some(b)) => Some(a.max(b)),
            (a, b) => a.or(b),
        }
    }

    /// Forgets every rest and the verdict.
    pub fn reset(&mut self) {
        *self = Self::new(self.tolerance, self.g);
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use limbfuse_core::STANDARD_GRAVITY as G;

    fn imu(w: Vector3<f64>, f: Vector3<f64>) -> ImuSample {
        ImuSample {
            gyr: Some(w),
            acc: Some(f),
            ..ImuSample::default()
        }
    }

    /// Steps `seconds` at 100 Hz of readings given by `reading(t)`.
    fn run(seconds: f64, reading: impl Fn(f64) -> [ImuSample; 2]) -> RestGravityCheck {
        let mut c = RestGravityCheck::new(ACC_REST_TOLERANCE_G, G);
        for k in 0..(seconds * 100.0) as usize {
            let t = k as f64 * 0.01;
            c.step(t, &reading(t));
        }
        c
    }

    #[test]
    fn a_sensor_reading_one_g_at_rest_is_trusted() {
        let f = Vector3::new(0.3, -1.0, 9.75);
        let c = run(1.0, |_| [imu(Vector3::new(0.01, 0.0, -0.01), f); 2]);
        assert!(!c.miscalibrated());
        let e = c.last_error().expect("a 1 s rest was seen");
        assert!(e < 0.01, "{e}");
    }

    #[test]
    fn a_sensor_reading_1_2_g_at_rest_is_not_trusted() {
        let good = imu(Vector3::zeros(), Vector3::new(0.0, 0.0, G));
        let bad = imu(Vector3::zeros(), Vector3::new(0.0, 0.0, 1.2 * G));
        let c = run(1.0, |_| [good, bad]);
        assert!(c.miscalibrated());
        assert!((c.last_error().unwrap() - 0.2).abs() < 1e-9);
        // A rest shorter than REST_MIN_S says nothing.
        let c = run(0.15, |_| [good, bad]);
        assert!(!c.miscalibrated());
        assert_eq!(c.last_error(), None);
    }

    #[test]
    fn walking_like_motion_holds_no_rest() {
        // Thigh and shank swinging at a 1 Hz stride (+-20 / +-35 deg), the
        // shank's specific force off g by up to 1.4 g: the rate passes
        // through zero twice a stride, but never for REST_MIN_S.
        let c = run(20.0, |t| {
            let ph = core::f64::consts::TAU * t;
            let w = |amp: f64| {
                Vector3::new(
                    0.0,
                    0.0,
                    amp.to_radians() * core::f64::consts::TAU * libm::cos(ph),
                )
            };
            let f = |a: f64| Vector3::new(a * libm::sin(ph), G + a * libm::cos(2.0 * ph), 0.0);
            [imu(w(20.0), f(3.0)), imu(w(35.0), f(14.0))]
        });
        assert!(!c.miscalibrated());
        assert_eq!(c.last_error(), None);
    }

    #[test]
    fn a_missing_reading_or_a_time_gap_ends_a_rest() {
        let bad = imu(Vector3::zeros(), Vector3::new(0.0, 0.0, 1.2 * G));
        let mut c = RestGravityCheck::new(ACC_REST_TOLERANCE_G, G);
        for k in 0..40 {
            let t = k as f64 * 0.01;
            let r = if k % 15 == 14 {
                ImuSample::default()
            } else {
                bad
            };
            c.step(t, &[r, r]);
        }
        assert!(!c.miscalibrated());
        for k in 0..40 {
            c.step(k as f64 * 0.15, &[bad, bad]);
        }
        assert!(!c.miscalibrated());
    }
}
