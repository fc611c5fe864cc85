//! Zero-velocity-update strapdown integration of one foot stride (the
//! foot-mounted INS of Foxlin 2005 in its per-stride form, as in Rampp et
//! al. 2015 and Hannink et al. 2017): between two rest periods of the foot,
//!
//! 1. the initial attitude is the tilt that turns the mean specific force of
//!    the rest period into the vertical (heading arbitrary: only the
//!    horizontal length and the forward direction in the sensor frame are
//!    used), gravity `g_rest` is that mean's norm (absorbs an accelerometer
//!    scale error);
//! 2. second order in the sampling period (trapezoidal rule throughout):
//!    `R_{k+1} = R_k Exp((w_k + w_{k+1}) dt / 2)` (Rodrigues),
//!    `a_k = R_k f_k - (0, 0, g_rest)`, `v_{k+1} = v_k + (a_k + a_{k+1}) dt / 2`,
//!    the displacement `sum (v_k + v_{k+1}) dt / 2`, starting from the last rest
//!    sample (`v = 0`, attitude from step 1); the first-order rectangle rule
//!    (until 2026-12-06) gave stride lengths that moved with the sampling rate,
//!    1.1 % long at 100 Hz and 2.1 % at 50 Hz on a pitching stride;
//! 3. at the next rest the true velocity is zero, so the end velocity `v_N`
//!    is drift; removing it linearly in time,
//!    `v_c(tau) = v(tau) - v_N tau / T`, gives the displacement
//!    `d = int v dtau - v_N / T int tau dtau`: two running sums, no buffer
//!    (so the integrator neither allocates nor grows with the stride).
//!
//! 4. a clipped accelerometer (an axis at or beyond [`ACC_CLIP_FRACTION`]
//!    of its full scale, a heel strike's impact on a 16 g or 8 g foot
//!    sensor) lost part of its velocity change at that instant, along the
//!    clipped axis: a step in the velocity error, not a drift. Of the
//!    period's clipped samples, the one with the largest specific force (the
//!    impact's peak, which loses the most) gives the time `tau_c` and the
//!    direction `u` (its clipped axes' signed units in the world frame,
//!    normalised); the part of `v_N` against it, `delta = max(0, -u . v_N)`,
//!    is put back as a step at `tau_c`, and only the rest drifts:
//!    `d = int v dtau + u delta (T - tau_c) - (v_N + u delta) / T int tau dtau`
//!    (docs/GAIT_EVENTS.md, "Clipped impacts"). Without a clipped sample this
//!    is step 3, bit for bit.
//!
//! The stride length is the horizontal norm of `d`.

use nalgebra::{Matrix3, Vector3};

/// Fraction of an accelerometer's full scale from which an axis counts as
/// clipped: the sensor gate's
/// [`limbfuse_core::sample_gate::ACC_CLIPPED_FRACTION`] (0.97; see there
/// why not 1).
pub const ACC_CLIP_FRACTION: f64 = limbfuse_core::sample_gate::ACC_CLIPPED_FRACTION;

/// From this specific force on an axis (m/s^2: 1.5 g), a reading equal to
/// the one before it on that axis counts as clipped time
/// ([`Segment::clipped_time`]; not in step 4) whatever the full scale: a
/// moving foot's acceleration at 1.5 g or more changes by far more than one
/// quantisation step per sample, so an exact repeat there is a rail (a
/// sensor of smaller range than the 16 g assumed when the trial states
/// none; the smallest in gait work is 2 g, MPU-6050's default). None of the
/// shared recordings repeats a reading at 1.5 g or more (the knee rig's
/// 0.01 g steps included).
pub const RAIL_REPEAT_FLOOR: f64 = 1.5 * 9.80665;

/// Longest time (s) a stride's accelerometer may sit at its full scale and
/// still be a heel strike's impact, which step 4 models as a velocity step.
/// Beyond it the swing itself clipped (a 2-3 g sensor): the velocity lost
/// there has no one instant or direction, is not put back, and the stride
/// comes out short. Measured on the shared gaitmap walk with its
/// accelerometers clipped at 8 / 4 g (range stated): impacts clip for at
/// most 10 / 34 ms per stride and step 4 keeps the length (2.32 / 2.68 %);
/// at 3 / 2.5 / 2 g the clipped time is 68 / 156 / 293 ms per stride
/// (median) and strides clipped for 40-60 ms are 4 % short on average,
/// 100-150 ms 6 %, 200-300 ms 11 % (docs/GAIT_EVENTS.md "Clipped swings").
/// A stride past it is counted in the warning of `limbfuse estimate`
/// (`limbfuse_eval::ClippedSwingWatch`); its length is still given.
pub const IMPACT_CLIP_TIME: f64 = 0.04;

/// Skew-symmetric (cross-product) matrix of `v`.
fn skew(v: &Vector3<f64>) -> Matrix3<f64> {
    Matrix3::new(0.0, -v[2], v[1], v[2], 0.0, -v[0], -v[1], v[0], 0.0)
}

/// Rodrigues: the rotation matrix `Exp(r)` of rotation vector `r`.
pub fn exp_so3(r: &Vector3<f64>) -> Matrix3<f64> {
    let th = r.norm();
    let k = skew(r);
    if th < 1e-9 {
        return Matrix3::identity() + k + 0.5 * k * k;
    }
    let (s, c) = (libm::sin(th), libm::cos(th));
    Matrix3::identity() + (s / th) * k + ((1.0 - c) / (th * th)) * k * k
}

/// The rotation of smallest angle taking unit vector `u` to `+z`.
pub fn tilt_to_vertical(u: &Vector3<f64>) -> Matrix3<f64> {
    let z = Vector3::z();
    let axis = u.cross(&z);
    let s = axis.norm();
    let c = u.dot(&z);
    if s < 1e-12 {
        return if c > 0.0 {
            Matrix3::identity()
        } else {
            Matrix3::from_diagonal(&Vector3::new(1.0, -1.0, -1.0))
        };
    }
    exp_so3(&(axis * (libm::atan2(s, c) / s)))
}

/// One finished moving period of the foot.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Segment {
    /// Drift-corrected displacement in the (level, arbitrary-heading) world frame (m).
    pub displacement: Vector3<f64>,
    /// The horizontal displacement direction expressed in the sensor frame at the end (unit, or zero).
    pub forward_in_sensor: Vector3<f64>,
    /// Vertical (up) expressed in the sensor frame at the end (unit).
    pub up_in_sensor: Vector3<f64>,
    /// Duration of the moving period (s).
    pub duration: f64,
    /// How long (s) an accelerometer axis was at its full scale in the
    /// period: a heel strike's impact lasts a few samples (step 4 puts its
    /// lost velocity back); longer is a clipped swing, whose lost velocity is
    /// not recovered ([`IMPACT_CLIP_TIME`]).
    pub clipped_time: f64,
    /// Rotation (rad) of the sensor about the vertical from the rest before
    /// the period to the rest after it, counter-clockwise seen from above:
    /// the foot's heading change over the stride (gaitmap's per-stride
    /// `turning_angle`), `atan2(M_yx - M_xy, M_xx + M_yy)` of `M = R_N R_0^T`.
    pub heading_change: f64,
}

impl Segment {
    /// Horizontal length (m).
    pub fn horizontal_length(&self) -> f64 {
        libm::hypot(self.displacement[0], self.displacement[1])
    }
}

/// Streaming per-stride ZUPT integrator.
#[derive(Debug, Clone)]
pub struct StrideIntegrator {
    rest_acc: Vector3<f64>,
    rest_n: u32,
    moving: bool,
    r: Matrix3<f64>,
    /// The attitude at the start of the period (the rest's tilt).
    r0: Matrix3<f64>,
    g_rest: f64,
    v: Vector3<f64>,
    s1: Vector3<f64>,
    s2: f64,
    tau: f64,
    max_duration: f64,
    /// The previous sample's gyro reading (rad/s), for the trapezoidal attitude step.
    w_prev: Vector3<f64>,
    /// The previous sample's specific force in the sensor frame (m/s^2).
    f_prev: Vector3<f64>,
    /// The previous sample's acceleration in the world frame (m/s^2).
    a_prev: Vector3<f64>,
    /// From this specific force on an axis (m/s^2) a reading is clipped.
    clip_level: f64,
    /// Of this period's clipped samples, the one with the largest specific
    /// force: its norm (m/s^2; 0 before any), its time `tau` (s) and its
    /// clipped axes' signed units in the world frame.
    clip_norm: f64,
    clip_tau: f64,
    clip_dir: Vector3<f64>,
    /// This period's time (s) with a clipped axis.
    clipped_time: f64,
}

impl StrideIntegrator {
    /// An integrator that gives up on a moving period longer than
    /// `max_duration` (s), for an accelerometer of full scale
    /// `acc_full_scale` (m/s^2; infinite: never clipped).
    pub fn new(max_duration: f64, acc_full_scale: f64) -> Self {
        StrideIntegrator {
            rest_acc: Vector3::zeros(),
            rest_n: 0,
            moving: false,
            r: Matrix3::identity(),
            r0: Matrix3::identity(),
            g_rest: 0.0,
            v: Vector3::zeros(),
            s1: Vector3::zeros(),
            s2: 0.0,
            tau: 0.0,
            max_duration,
            w_prev: Vector3::zeros(),
            f_prev: Vector3::zeros(),
            a_prev: Vector3::zeros(),
            clip_level: ACC_CLIP_FRACTION * acc_full_scale,
            clip_norm: 0.0,
            clip_tau: 0.0,
            clip_dir: Vector3::zeros(),
            clipped_time: 0.0,
        }
    }

    /// Forgets everything (dropout): the next moving period starts after a new rest.
    pub fn reset(&mut self) {
        *self = StrideIntegrator {
            clip_level: self.clip_level,
            ..StrideIntegrator::new(self.max_duration, f64::INFINITY)
        };
    }

    /// True while integrating a moving period.
    pub fn is_moving(&self) -> bool {
        self.moving
    }

    /// One sample; returns the finished moving period when the foot comes to rest.
    pub fn update(
        &mut self,
        rest: bool,
        acc: &Vector3<f64>,
        gyr: &Vector3<f64>,
        dt: f64,
    ) -> Option<Segment> {
        if rest {
            let finished = if self.moving {
                self.moving = false;
                self.rest_acc = Vector3::zeros();
                self.rest_n = 0;
                Some(self.finish())
            } else {
                None
            };
            self.rest_acc += acc;
            self.rest_n += 1;
            self.w_prev = *gyr;
            self.f_prev = *acc;
            return finished;
        }
        if !self.moving {
            if self.rest_n == 0 {
                return None;
            }
            let mean = self.rest_acc / f64::from(self.rest_n);
            let g = mean.norm();
            if g <= 0.0 {
                return None;
            }
            self.r = tilt_to_vertical(&(mean / g));
            self.r0 = self.r;
            self.g_rest = g;
            self.v = Vector3::zeros();
            self.s1 = Vector3::zeros();
            self.s2 = 0.0;
            self.tau = 0.0;
            self.clip_norm = 0.0;
            self.clipped_time = 0.0;
            self.moving = true;
            self.a_prev = self.r * self.f_prev - Vector3::new(0.0, 0.0, self.g_rest);
        }
        self.r *= exp_so3(&((self.w_prev + gyr) * (0.5 * dt)));
        let a_w = self.r * acc - Vector3::new(0.0, 0.0, self.g_rest);
        let v = self.v + (self.a_prev + a_w) * (0.5 * dt);
        self.s1 += (self.v + v) * (0.5 * dt);
        self.s2 += (self.tau + 0.5 * dt) * dt;
        self.v = v;
        self.tau += dt;
        self.note_clipping(acc, dt);
        self.w_prev = *gyr;
        self.f_prev = *acc;
        self.a_prev = a_w;
        if self.tau > self.max_duration {
            self.reset();
        }
        None
    }

    /// Notes this sample if it is clipped (specific force `acc`, the
    /// attitude already stepped to it) with a larger specific force than
    /// the period's clipped samples before it; a clipped sample's `dt` (s)
    /// counts as clipped time, and so does a sample on a rail seen only as
    /// an exact repeat ([`RAIL_REPEAT_FLOOR`]), which step 4 does not use:
    /// a repeat is seen from a run's second sample, and a single-sample
    /// impact clip is not seen at all, so the largest clipped specific
    /// force can then be a swing's, not the impact's (the gaitmap walk
    /// clipped at 4 g without its range: 3.20 -> 3.34 % had step 4 used
    /// them, strides up to 0.13 m long).
    fn note_clipping(&mut self, acc: &Vector3<f64>, dt: f64) {
        let mut axes = Vector3::zeros();
        let mut repeats = false;
        for ((u, a), before) in axes.iter_mut().zip(acc.iter()).zip(self.f_prev.iter()) {
            let m = libm::fabs(*a);
            if m >= self.clip_level {
                *u = a.signum();
            }
            // (no branch: `m` crosses the floor back and forth in a stride)
            repeats |= (m >= RAIL_REPEAT_FLOOR) & (a == before);
        }
        let clipped = axes != Vector3::zeros();
        if clipped || repeats {
            self.clipped_time += dt;
        }
        // (the norm only for a clipped sample: nothing else on the hot path)
        if !clipped {
            return;
        }
        let norm = acc.norm();
        if norm > self.clip_norm {
            self.clip_norm = norm;
            self.clip_tau = self.tau;
            self.clip_dir = self.r * axes;
        }
    }

    fn finish(&self) -> Segment {
        let d = if self.tau <= 0.0 {
            Vector3::zeros()
        } else if let (true, Some(u)) = (self.clip_norm > 0.0, self.clip_dir.try_normalize(1e-12)) {
            // Step 4: the velocity change the clipped impact lost.
            let delta = (-u.dot(&self.v)).max(0.0);
            self.s1 + u * (delta * (self.tau - self.clip_tau))
                - (self.v + u * delta) * (self.s2 / self.tau)
        } else {
            self.s1 - self.v * (self.s2 / self.tau)
        };
        let h = Vector3::new(d[0], d[1], 0.0);
        let hn = h.norm();
        let rt = self.r.transpose();
        let m = self.r * self.r0.transpose();
        Segment {
            displacement: d,
            forward_in_sensor: if hn > 0.0 {
                rt * (h / hn)
            } else {
                Vector3::zeros()
            },
            up_in_sensor: rt * Vector3::z(),
            duration: self.tau,
            clipped_time: self.clipped_time,
            heading_change: libm::atan2(m[(1, 0)] - m[(0, 1)], m[(0, 0)] + m[(1, 1)]),
        }
    }
}

#[cfg(test)]
#[path = "strapdown_tests.rs"]
mod tests;
