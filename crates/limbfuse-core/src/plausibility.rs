//! Readings that are within a sensor's range but cannot be a measurement
//! of a human limb (issue 18 item 1): a gyroscope jump faster than any
//! segment can accelerate, a repeat of a value just rejected (a saturated
//! burst: a clipped sensor repeats its full-scale value), and a stuck
//! sensor (one vector repeated exactly for [`PlausibilityLimits::stuck_s`]).
//! [`crate::SampleGate`] applies these checks after the range check.
//!
//! # Angular-acceleration bound (gyroscope jumps)
//!
//! A segment's angular acceleration is bounded by the largest joint torque
//! over the segment's moment of inertia, `alpha = tau / I`. The knee
//! extensors, the strongest actuators of the shank, give `tau` about 300 N m
//! (isokinetic peak torques of strong adults); the shank plus foot about the
//! knee of an 80 kg body has `I` about 0.43 kg m^2 (D. A. Winter,
//! *Biomechanics and Motor Control of Human Movement*, 4th ed., 2009, Table
//! 4.1: shank 0.0465 M, radius of gyration 0.528 L about the knee; foot
//! 0.0145 M about 0.45 m from the knee), so `alpha` is about 700 rad/s^2;
//! the thigh and trunk, heavier for similar torques, stay below that. The
//! foot about the ankle is light (Winter: 0.0145 M, radius of gyration
//! 0.690 L about the ankle, `I` about 0.037 kg m^2) while the plantar
//! flexors give about 250 N m: about 7000 rad/s^2. The bounds used,
//! [`PlausibilityLimits::default`], are 2000 rad/s^2 for trunk, thigh and
//! shank (about three times the shank's torque bound, for impacts and
//! vibration, which sensor-to-sensor differences also show: the shared real
//! 100 Hz shank recording peaks at 421 rad/s^2 sample to sample) and
//! 10 000 rad/s^2 for the foot (the shared real 204.8 Hz foot recording
//! peaks at 3170 rad/s^2). Every axis of a gyroscope may change by at most
//! `alpha * (t - t_last) + 1 rad/s` from the last accepted reading (the
//! 1 rad/s covers noise and quantisation of any MEMS gyroscope, whose white
//! noise is of order 0.01 rad/s). At 100 Hz a thigh or shank jump beyond
//! 21 rad/s in one sample is rejected: a saturating glitch (to the 35 rad/s
//! full scale of a 2000 deg/s gyroscope) is caught; a foot glitch mostly is
//! not (101 rad/s per sample is allowed), which is the price of not
//! rejecting real foot impacts.
//!
//! The bound grows with the time since the last accepted reading, so a
//! genuine change wrongly rejected is accepted again within
//! `|jump| / alpha` (under 40 ms for any in-range jump of the thigh).
//!
//! Accelerometers get no jump bound: heel-strike and running impacts change
//! the specific force by several g within a few milliseconds, so any jerk
//! bound loose enough for them catches nothing. An accelerometer glitch
//! within range is far from `g` and fails the segment filters' reliability
//! test `rho < zeta`, and their innovation gate (docs/ROBUST_INPUT.md).
//!
//! # Stuck sensor
//!
//! A real IMU's noise (tens of LSB of white noise on each of three axes for
//! the consumer and Xsens sensors of docs/SENSOR_NOISE.md) makes an exact
//! repeat of a whole 3-axis vector rare: even with the noise at one LSB, so
//! that one axis repeats with probability at most 1/2, nine repeats of the
//! vector in a row have probability `(1/8)^9`, under 1e-8. A vector (gyro or
//! accelerometer) repeated exactly, bit for bit, over at least
//! [`PlausibilityLimits::stuck_min_samples`] samples spanning at least
//! [`PlausibilityLimits::stuck_s`] is a stuck sensor (a frozen bus, a dead
//! driver); it and every further repeat are rejected. Encoders are not
//! checked: a joint at rest repeats its encoder count exactly.
//!
//! That argument fails for an accelerometer recorded coarser than its
//! noise: the shared knee rig's files hold the specific force to 0.01 g, and
//! a still segment's vector repeats bit for bit for seconds (74 % of the
//! thigh's samples repeat their predecessor; runs up to 8 s). A repeated
//! specific force is only wrong when the sensor turns, since turning it
//! across gravity changes the reading by about `g` times the angle. So an
//! accelerometer repeat is a stuck sensor only (i) when its IMU's gyroscope,
//! over the repeat, shows it turning across the repeated vector by more than
//! [`PlausibilityLimits::stuck_acc_turn_m_s2`] of predicted change (counting
//! rates above [`PlausibilityLimits::stuck_acc_rate_floor_rad_s`] only, so
//! that a gyroscope bias does not add up), (ii) when that gyroscope is
//! itself stuck (a frozen IMU), or (iii) when the IMU has given no gyroscope
//! reading during the repeat (no evidence either way: the repeat rule
//! alone). [`crate::SampleGate`] applies (i)-(iii).

use nalgebra::Vector3;

/// Bounds of the plausibility checks; see the module documentation for the
/// sources.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PlausibilityLimits {
    /// Largest angular acceleration per segment (rad/s^2): trunk, thigh,
    /// shank, foot (index [`crate::Segment::index`]).
    pub angular_accel_rad_s2: [f64; 4],
    /// Allowance added to every gyroscope step bound for noise and
    /// quantisation (rad/s).
    pub gyro_noise_rad_s: f64,
    /// Shortest time a vector must repeat exactly to be a stuck sensor (s).
    pub stuck_s: f64,
    /// Fewest identical consecutive vectors that make a stuck sensor.
    pub stuck_min_samples: u32,
    /// Change of the specific force (m/s^2) that the gyroscope-measured
    /// turn of an IMU must predict over an accelerometer repeat before the
    /// repeat counts as stuck: 0.5 m/s^2, five steps of the coarsest
    /// recording resolution known to us (0.01 g, the knee rig) and a turn of
    /// about 3 deg across gravity.
    pub stuck_acc_turn_m_s2: f64,
    /// Rates across the repeated specific force below this (rad/s) do not
    /// count towards [`PlausibilityLimits::stuck_acc_turn_m_s2`]: 0.1 rad/s
    /// (5.7 deg/s), over ten times the turn-on bias of uncalibrated
    /// consumer MEMS gyroscopes (0.5 deg/s, 1 sigma, BMI270 and
    /// ICM-42688-P data sheets; docs/SIMULATOR.md).
    pub stuck_acc_rate_floor_rad_s: f64,
}

impl Default for PlausibilityLimits {
    fn default() -> Self {
        PlausibilityLimits {
            angular_accel_rad_s2: [2000.0, 2000.0, 2000.0, 10_000.0],
            gyro_noise_rad_s: 1.0,
            stuck_s: 0.1,
            stuck_min_samples: 10,
            stuck_acc_turn_m_s2: 0.5,
            stuck_acc_rate_floor_rad_s: 0.1,
        }
    }
}

impl PlausibilityLimits {
    /// No plausibility check: a [`crate::SampleGate`] with these limits
    /// applies only its range, finiteness and clipping checks (`limbfuse
    /// resample`: a static calibration recording's exactly repeated readings
    /// are data there, not a stuck sensor).
    pub const fn off() -> Self {
        PlausibilityLimits {
            angular_accel_rad_s2: [f64::INFINITY; 4],
            gyro_noise_rad_s: 0.0,
            stuck_s: f64::INFINITY,
            stuck_min_samples: u32::MAX,
            stuck_acc_turn_m_s2: f64::INFINITY,
            stuck_acc_rate_floor_rad_s: 0.0,
        }
    }
}

/// Why a reading was rejected after the range check.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Implausible {
    /// A jump faster than the angular-acceleration bound, or a repeat of a
    /// value so rejected (a saturated burst).
    Jump,
    /// An exact repeat lasting [`PlausibilityLimits::stuck_s`] or more.
    Stuck,
}

/// What one 3-axis sensor has shown recently.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct VectorTrack {
    /// Last accepted reading and its time.
    last_ok: Option<(Vector3<f64>, f64)>,
    /// Axis values of the last reading rejected as a jump, on the axes that
    /// jumped (a repeat of one of them, on its axis, is rejected too: a
    /// saturated axis repeats its clip value while the others move).
    rejected: [Option<f64>; 3],
    /// The value now repeating, since when, and how many times in a row.
    run: Option<(Vector3<f64>, f64, u32)>,
}

impl VectorTrack {
    /// How many times in a row the last reading checked has been repeated
    /// (1: it differs from the one before).
    pub fn repeats(&self) -> u32 {
        self.run.map_or(0, |r| r.2)
    }

    /// Checks reading `v` at time `t`; `max_accel` is the jump bound
    /// (rad/s^2, `None`: no jump check). An accepted reading becomes the
    /// reference of the next check.
    #[inline(always)]
    pub fn check(
        &mut self,
        v: &Vector3<f64>,
        t: f64,
        max_accel: Option<f64>,
        limits: &PlausibilityLimits,
    ) -> Option<Implausible> {
        // (the run's value is kept as it is when `v` repeats it)
        let (since, n) = match &mut self.run {
            Some((value, since, n)) if *value == *v => {
                *n = n.saturating_add(1);
                (*since, *n)
            }
            run => {
                *run = Some((*v, t, 1));
                (t, 1)
            }
        };
        // (1 ns of slack: 0.61 - 0.51 is 0.0999... in binary floating point)
        if n >= limits.stuck_min_samples && t - since >= limits.stuck_s - 1e-9 {
            return Some(Implausible::Stuck);
        }
        if v.iter().zip(&self.rejected).any(|(x, r)| *r == Some(*x)) {
            return Some(Implausible::Jump);
        }
        if let (Some(alpha), Some((w, t0))) = (max_accel, &self.last_ok) {
            let bound = alpha * (t - *t0) + limits.gyro_noise_rad_s;
            let jumped = |k: usize| {
                let d = (v[k] - w[k]).abs();
                d.is_nan() || d > bound
            };
            // (one pass without branches; the rejected axes only on a jump)
            if jumped(0) | jumped(1) | jumped(2) {
                self.rejected = core::array::from_fn(|k| jumped(k).then_some(v[k]));
                return Some(Implausible::Jump);
            }
        }
        self.last_ok = Some((*v, t));
        self.rejected = [None; 3];
        None
    }

    /// The jump checks of [`VectorTrack::check`] on the present axes of an
    /// incomplete vector (issue 18 item 2): a present axis repeating a
    /// rejected jump's value, or beyond the jump bound from the last
    /// accepted complete vector, is implausible. An incomplete vector is not
    /// remembered (the bound of the other axes would start from a time at
    /// which they were not read) and takes no part in the stuck check (a
    /// stuck vector is a repeat of all three axes).
    pub fn check_axes(
        &self,
        cells: &[Option<f64>; 3],
        t: f64,
        max_accel: Option<f64>,
        limits: &PlausibilityLimits,
    ) -> Option<Implausible> {
        let present = || {
            cells
                .iter()
                .enumerate()
                .filter_map(|(k, c)| Some((k, (*c)?)))
        };
        if present().any(|(k, x)| self.rejected[k] == Some(x)) {
            return Some(Implausible::Jump);
        }
        if let (Some(alpha), Some((w, t0))) = (max_accel, self.last_ok) {
            let bound = alpha * (t - t0) + limits.gyro_noise_rad_s;
            let jumped = |k: usize, x: f64| {
                let d = (x - w[k]).abs();
                d.is_nan() || d > bound
            };
            if present().any(|(k, x)| jumped(k, x)) {
                return Some(Implausible::Jump);
            }
        }
        None
    }
}

/// What an IMU's gyroscope showed while its accelerometer repeated one
/// vector (rules (i)-(iii) of "Stuck sensor" above; [`crate::SampleGate`]
/// keeps one per IMU).
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub(crate) struct AccRepeatTurn {
    /// Predicted change of the specific force (m/s^2): the integral of
    /// `|w x a|` over the samples whose rate across `a` exceeds the floor.
    change: f64,
    /// A gyroscope reading was accepted during the repeat.
    gyro_seen: bool,
    /// The gyroscope reading and `dt` of the repeat's first sample, not yet
    /// in `change`: most accelerometer readings never repeat, so their
    /// share is computed only once the value repeats (the same sum, in the
    /// same order).
    first: Option<(Vector3<f64>, f64)>,
}

impl AccRepeatTurn {
    /// Adds one sample: accelerometer reading `a`, the accepted gyroscope
    /// reading `w` (if any), `dt` since the previous sample; a repeat
    /// count of 1 starts a new repeat.
    #[inline]
    pub(crate) fn add(
        &mut self,
        repeats: u32,
        a: &Vector3<f64>,
        w: Option<&Vector3<f64>>,
        dt: f64,
        lim: &PlausibilityLimits,
    ) {
        if repeats <= 1 {
            *self = AccRepeatTurn {
                change: 0.0,
                gyro_seen: w.is_some(),
                first: w.map(|w| (*w, dt)),
            };
            return;
        }
        if let Some((w0, dt0)) = self.first.take() {
            self.change += turn_change(a, &w0, dt0, lim);
        }
        let Some(w) = w else { return };
        self.gyro_seen = true;
        self.change += turn_change(a, w, dt, lim);
    }

    /// Whether an accelerometer repeat (of `a`) long enough to be stuck is
    /// one: the IMU turned, its gyroscope is frozen too, or no gyroscope says.
    pub(crate) fn confirms_stuck(
        &self,
        a: &Vector3<f64>,
        gyro_stuck: bool,
        lim: &PlausibilityLimits,
    ) -> bool {
        let change = match self.first {
            Some((w0, dt0)) => self.change + turn_change(a, &w0, dt0, lim),
            None => self.change,
        };
        gyro_stuck || !self.gyro_seen || change > lim.stuck_acc_turn_m_s2
    }
}

/// One sample's predicted change of the specific force `a` under the rate
/// `w` over `dt` (m/s^2): `|w x a| dt` when the rate across `a` exceeds the
/// floor, else 0.
fn turn_change(a: &Vector3<f64>, w: &Vector3<f64>, dt: f64, lim: &PlausibilityLimits) -> f64 {
    let norm = a.norm();
    if norm > 0.0 && dt.is_finite() && dt > 0.0 {
        // rate across the specific force's direction
        let across = w.cross(a).norm() / norm;
        if across > lim.stuck_acc_rate_floor_rad_s {
            return across * norm * dt;
        }
    }
    0.0
}

#[cfg(test)]
mod tests {
    use super::*;

    fn v(z: f64) -> Vector3<f64> {
        Vector3::new(0.01 * z.sin(), -0.02 * z.cos(), z)
    }

    /// With [`PlausibilityLimits::off`] a gate keeps a repeated (static)
    /// vector and a jump that the default limits reject, and still drops a
    /// reading out of range.
    #[test]
    fn limits_off_leave_only_the_range_checks() {
        use crate::{Sample, SampleGate, SensorRanges};
        for (limits, kept) in [
            (PlausibilityLimits::default(), false),
            (PlausibilityLimits::off(), true),
        ] {
            let mut g = SampleGate::with_limits(SensorRanges::default(), limits);
            let mut s = Sample::default();
            s.imu[1].acc = Some(Vector3::new(0.5, 9.8, 0.0));
            // a gyroscope repeating one vector for 0.3 s (stuck at 0.1 s)
            for k in 0..30 {
                s.t = k as f64 * 0.01;
                s.imu[1].gyr = Some(Vector3::new(0.0, 0.0, 0.25));
                let out = g.screen(&s);
                if k >= 20 {
                    assert_eq!(out.imu[1].gyr.is_some(), kept, "stuck, {k}");
                }
            }
            g.reset();
            // a 30 rad/s step in 10 ms (beyond 2000 rad/s^2, within range) at k = 5
            for k in 0..10 {
                s.t = k as f64 * 0.01;
                let z = 0.01 * k as f64 + if k == 5 { 30.0 } else { 0.0 };
                s.imu[1].gyr = Some(Vector3::new(0.0, 0.0, z));
                let out = g.screen(&s);
                assert_eq!(out.imu[1].gyr.is_some(), k != 5 || kept, "jump, {k}");
            }
            s.t = 0.3;
            s.imu[1].gyr = Some(Vector3::new(0.0, 1e308, 0.0));
            assert_eq!(g.screen(&s).imu[1].gyr, None);
        }
    }

    #[test]
    fn a_saturated_burst_is_rejected_from_its_onset_to_its_end() {
        let lim = PlausibilityLimits::default();
        let mut tr = VectorTrack::default();
        let alpha = Some(lim.angular_accel_rad_s2[1]);
        let mut rejected = Vec::new();
        for k in 0..200 {
            let t = k as f64 * 0.01;
            // walking-like thigh rate, with 50 samples saturated on z while
            // x and y keep moving
            let mut w = v(3.0 * (t * 6.0).sin());
            if (50..100).contains(&k) {
                w.z = 34.9;
            }
            if tr.check(&w, t, alpha, &lim).is_some() {
                rejected.push(k);
            }
        }
        assert_eq!(rejected, (50..100).collect::<Vec<_>>());
    }

    #[test]
    fn the_jump_bound_is_alpha_times_elapsed_time_plus_the_noise_allowance() {
        let lim = PlausibilityLimits::default();
        let mut tr = VectorTrack::default();
        let a = Some(2000.0);
        assert_eq!(tr.check(&v(0.0), 0.0, a, &lim), None);
        // 2000 * 0.01 + 1 = 21 rad/s allowed
        assert_eq!(tr.check(&v(20.9), 0.01, a, &lim), None);
        assert_eq!(tr.check(&v(-0.05), 0.02, a, &lim), None);
        assert_eq!(tr.check(&v(21.0), 0.03, a, &lim), Some(Implausible::Jump));
        // 20 ms after the last accepted reading: 41 rad/s allowed, a new value passes
        assert_eq!(tr.check(&v(21.5), 0.04, a, &lim), None);
        // without a bound, no jump is checked
        let mut free = VectorTrack::default();
        assert_eq!(free.check(&v(0.0), 0.0, None, &lim), None);
        assert_eq!(free.check(&v(1e3), 0.01, None, &lim), None);
    }

    #[test]
    fn a_stuck_vector_is_rejected_after_the_stated_time_and_count() {
        let lim = PlausibilityLimits::default();
        let mut tr = VectorTrack::default();
        let stuck = Vector3::new(1.5, 9.0, 0.25);
        let mut first = None;
        for k in 0..300 {
            let t = k as f64 * 0.01;
            if tr.check(&stuck, t, None, &lim).is_some() && first.is_none() {
                first = Some(k);
            }
        }
        // the 11th identical sample spans 0.1 s (and is the 10th or later)
        assert_eq!(first, Some(10));
        // one differing axis breaks the run (the run restarts after it)
        let mut tr = VectorTrack::default();
        for k in 0..300 {
            let mut s = stuck;
            s.x += if k % 50 == 0 { 1e-9 } else { 0.0 };
            let r = tr.check(&s, k as f64 * 0.01, None, &lim);
            assert_eq!(r.is_some(), k % 50 >= 11, "sample {k}");
        }
        // at 1 kHz the time, not the count, decides
        let mut tr = VectorTrack::default();
        let first = (0..1000)
            .find(|&k| tr.check(&stuck, k as f64 * 1e-3, None, &lim).is_some())
            .unwrap();
        assert_eq!(first, 100);
    }
}
