//! `chain`: a planar kinematic-chain EKF of the four segment angles (beyond
//! the papers; issue 14 item 2, docs/CHAIN.md).
//!
//! Instead of gating the accelerometers on `| |a| - g |` (papers 000/001),
//! the filter predicts what each accelerometer reads from the chain's
//! kinematics: the hip's linear acceleration, each segment's rate and
//! angular acceleration, the sensor's position on its segment and gravity
//! ([`kinematics`]). The common tilt of all segments, which the
//! accelerometers alone cannot see, is anchored by the hip's velocity
//! (vertical about 0, forward about a slowly varying mean speed) and by the
//! ankle standing still while the foot is still ([`ChainEkf`] "anchors").
//! Measurements are applied one scalar at a time with sparse rows
//! ([`covariance`]). Allocation-free, `no_std`.

pub mod covariance;
mod device_angle;
pub mod encoder_gate;
pub mod kinematics;
pub mod missing_data;
pub mod params;
pub mod sample_period;
pub mod smoother;
pub mod stance;
pub mod startup;
pub mod state;
#[cfg(test)]
mod tests;
pub mod time_base;
mod turn;

use core::fmt;

use alloc::boxed::Box;
use limbfuse_core::estimator::Outputs;
use limbfuse_core::sample::ImuSample;
use limbfuse_core::{diagnostic_set, Estimate, Estimator, EstimatorError, Sample, TimeStep};

use crate::segment_kf::robust::{HELD_RATE_SD, LONG_GAP_S};
pub use covariance::ProcessNoise;
use covariance::{predict_covariance, predict_state, scalar_update, Covariance, StateVector};
use encoder_gate::encoder_beside;
pub use kinematics::{ChainGeometry, OutOfPlane};
pub use missing_data::DIVERGED_RATE_RAD_S;
pub use params::{ChainParams, ChainParamsError, WALKING_MEAN_ANGLE_DEG};
use startup::{initial, Startup};
use state::{
    alpha, encoder_offset, gyro_bias, hip_acceleration, hip_velocity, omega, theta, SparseRow,
    MEAN_SPEED,
};
use time_base::StampTime;

diagnostic_set! {
    /// The `diag_*` columns of `chain`.
    pub enum ChainDiag {
        /// 1 once the filter runs (0 during the start-up window).
        Running = "running",
        /// 1 when the foot is detected still and the ankle anchor applied.
        Stance = "stance",
        /// Estimated forward hip velocity (m/s).
        HipVx = "hip_vx",
        /// Estimated vertical hip velocity (m/s).
        HipVy = "hip_vy",
        /// Estimated mean forward speed (m/s).
        MeanSpeed = "mean_speed",
        /// Accelerometer rows skipped by the gate at this sample.
        AccRejected = "acc_rejected",
        /// 1-sigma of the trunk angle (rad).
        SdTrunk = "sd_trunk",
        /// 1-sigma of the thigh angle (rad).
        SdThigh = "sd_thigh",
        /// 1-sigma of the shank angle (rad).
        SdShank = "sd_shank",
        /// 1-sigma of the foot angle (rad).
        SdFoot = "sd_foot",
    }
}

/// Typical angular acceleration of the foot at heel-off (rad/s^2), for the
/// stance anchor applied without a foot gyro reading.
const FOOT_ANGULAR_ACCELERATION: f64 = 50.0;
/// Distance from the ankle to the pivot of a foot rolling off (m).
const FOOT_PIVOT_M: f64 = 0.15;

/// The chain EKF.
#[derive(Debug, Clone)]
pub struct ChainEkf {
    params: ChainParams,
    geometry: ChainGeometry,
    g: f64,
    time: TimeStep,
    startup: Startup,
    running: bool,
    x: StateVector,
    p: Covariance,
    /// Previous gyro x/y per segment (for their derivative) and its time.
    last_xy_rate: [Option<([f64; 2], f64)>; 4],
    /// The time base of jittered stamps ([`time_base`]) and the last
    /// sample's time on it (for the out-of-plane rate derivative).
    time_base: StampTime,
    clock_t: f64,
    /// Time since which the foot has been still (`None`: moving).
    still_since: Option<f64>,
    /// Time of the last sample with a foot gyro reading.
    last_foot_gyro: Option<f64>,
    /// The start-up window's samples, replayed through the filter once the
    /// window closes (allocated once, in [`ChainEkf::new`]).
    window: Box<[Sample]>,
    /// Samples held in `window`.
    held: usize,
    /// Low-passed rate about the vertical (rad/s), `Omega` (turning).
    turn_rate: f64,
    /// The device orientation's walking direction and offset per sensor.
    device: [device_angle::DeviceAngle; 4],
    /// How the last step's state follows from the one before (for the
    /// offline smoother, [`smoother`]).
    link: Link,
    /// The angle variance the turn widening added in the running step.
    widening: f64,
    /// Factor on every measurement variance at the recording's nominal
    /// sample period ([`sample_period`]).
    variance_scale: f64,
    /// The current run of samples without any reading.
    blind: missing_data::BlindRun,
    /// The encoder rows' innovation gate ([`encoder_gate`]).
    encoder_gate: encoder_gate::EncoderGate,
}

/// How a step's filtered state follows from the previous step's (what an
/// offline smoother needs to go backwards over it, [`smoother`]).
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub enum Link {
    /// No state: start-up window, after a long gap or a divergence.
    #[default]
    None,
    /// The filter (re)started at this step, or re-adopted an encoder
    /// offset ([`encoder_gate`]): no link to the step before.
    Start,
    /// Predicted from the previous step's state over `dt` seconds, the turn
    /// widening adding `widening` (rad^2) to every angle's variance, then
    /// updated.
    Continue {
        /// Step (s).
        dt: f64,
        /// Added angle variance (rad^2).
        widening: f64,
    },
}

/// Most samples the start-up window holds: 2 s at up to 256 Hz (the
/// default 1 s at up to 512 Hz); at higher
/// rates the window closes when full.
pub const STARTUP_CAPACITY: usize = 512;

impl ChainEkf {
    /// A filter with these parameters and geometry, gravity `g` (m/s^2).
    pub fn new(
        params: ChainParams,
        geometry: ChainGeometry,
        g: f64,
    ) -> Result<Self, ChainParamsError> {
        params.validate()?;
        geometry.validate()?;
        if !(g.is_finite() && g > 0.0) {
            return Err(ChainParamsError::OutOfRange {
                name: "g",
                value: g,
                range: "positive finite numbers",
            });
        }
        Ok(ChainEkf {
            params,
            geometry,
            g,
            time: TimeStep::new(),
            startup: Startup::default(),
            running: false,
            x: StateVector::zeros(),
            p: Covariance::zeros(),
            last_xy_rate: [None; 4],
            time_base: StampTime::default(),
            clock_t: 0.0,
            still_since: None,
            last_foot_gyro: None,
            window: alloc::vec![Sample::default(); STARTUP_CAPACITY].into_boxed_slice(),
            held: 0,
            turn_rate: 0.0,
            device: Default::default(),
            link: Link::None,
            widening: 0.0,
            variance_scale: 1.0,
            blind: Default::default(),
            encoder_gate: Default::default(),
        })
    }

    /// The parameters.
    pub fn params(&self) -> &ChainParams {
        &self.params
    }

    /// The geometry.
    pub fn geometry(&self) -> &ChainGeometry {
        &self.geometry
    }

    /// The state covariance (tests, diagnostics); zero before the filter runs.
    pub fn covariance(&self) -> &Covariance {
        &self.p
    }

    /// The filtered state (zero before the filter runs).
    pub fn state(&self) -> &StateVector {
        &self.x
    }

    /// The encoder gate's counts (refused rows, re-adopted joints).
    pub fn encoder_gate(&self) -> &encoder_gate::EncoderGate {
        &self.encoder_gate
    }

    /// How the last step's state follows from the one before.
    pub fn link(&self) -> Link {
        self.link
    }

    /// The process noise of the prediction (from the parameters).
    pub fn process_noise(&self) -> ProcessNoise {
        let p = &self.params;
        ProcessNoise {
            angular_jerk: [p.trunk_jerk, p.leg_jerk, p.leg_jerk, p.leg_jerk],
            gyro_bias: p.gyro_bias_walk,
            // Stationary variance q tau / 2 = hip_acc_sd^2.
            hip_jerk: 2.0 * p.hip_acc_sd * p.hip_acc_sd / p.hip_acc_tau,
            hip_acc_rate: 1.0 / p.hip_acc_tau,
            mean_speed: p.mean_speed_walk,
            encoder_offset: 1e-10,
        }
    }

    /// Starts the filter at the window's first sample from the start-up
    /// estimates (`theta_i = m_i` there: the gyro integral starts at 0) and
    /// replays the window's samples through it, so that its convergence
    /// transient lies inside the window. `false`: the replay was refused.
    fn start(&mut self) -> bool {
        let first = self.window[0];
        let mut x = StateVector::zeros();
        let mut d = [0.0; state::N];
        for i in 0..4 {
            x[theta(i)] = self.startup.offset(i).unwrap_or(0.0);
            d[theta(i)] = initial::ANGLE;
            // Without a first gyro reading the rate is unknown to a walking
            // segment's rate amplitude (ours, issue 18 item 2; 0.1 rad/s
            // about 0 started a moving segment a degree off).
            (x[omega(i)], d[omega(i)]) = match first.imu[i].gyr_axis(2) {
                Some(w) if w.is_finite() => (w, initial::RATE),
                _ => (0.0, HELD_RATE_SD),
            };
            d[alpha(i)] = initial::ANGULAR_ACCELERATION;
            d[gyro_bias(i)] = self.params.gyro_bias_initial;
        }
        for k in 0..2 {
            d[hip_velocity(k)] = initial::VELOCITY;
            d[hip_acceleration(k)] = initial::ACCELERATION;
        }
        d[MEAN_SPEED] = initial::VELOCITY;
        for j in 0..3 {
            x[encoder_offset(j)] = self.startup.encoder_offset(j).unwrap_or(0.0);
            d[encoder_offset(j)] = initial::ENCODER_OFFSET;
        }
        self.x = x;
        self.p = Covariance::from_diagonal(&nalgebra::SVector::from(d.map(|s| s * s)));
        self.running = true;
        self.last_xy_rate = [None; 4];
        self.still_since = None;
        self.turn_rate = 0.0;
        self.device = Default::default();
        self.last_foot_gyro = None;
        self.out_of_plane_rates(&first);
        let last = self.window[self.held - 1].t;
        let period = sample_period::nominal_period(first.t, last, self.held);
        self.variance_scale = period.map_or(1.0, sample_period::variance_scale);
        let mut previous = first.t;
        for k in 1..self.held {
            let sample = self.window[k];
            self.filter_step(&sample, sample.t - previous, sample.t);
            previous = sample.t;
        }
        self.held = 0;
        // A replay that ends further than the start angle's prior 1-sigma
        // from the window's own angles left the window's evidence (audit
        // 2026-12-03: S02 started 1.5 s into the walk ended 34-87 deg off
        // and never recovered): refused, the window begins again.
        let off = |i: usize| {
            let d = self.x[theta(i)] - self.startup.angle(i).unwrap_or(self.x[theta(i)]);
            libm::fabs(libm::atan2(libm::sin(d), libm::cos(d))) > initial::ANGLE
        };
        !(0..4).any(off)
    }

    /// Begins the start-up window again (after a long gap or a divergence):
    /// no estimate until it closes, `diag_running` = 0 meanwhile.
    fn restart_startup(&mut self) {
        self.running = false;
        self.x = StateVector::zeros();
        self.p = Covariance::zeros();
        self.startup = Startup::default();
        self.held = 0;
        self.last_xy_rate = [None; 4];
        self.still_since = None;
        self.last_foot_gyro = None;
        self.encoder_gate.restart();
    }

    /// Whether the state is no estimate any more: a state or covariance
    /// entry that is not finite, or a segment rate beyond
    /// [`DIVERGED_RATE_RAD_S`] (issue 18 item 3, ours).
    fn diverged(&self) -> bool {
        !(self.x.iter().all(|v| v.is_finite()) && self.p.iter().all(|v| v.is_finite()))
            || (0..4).any(|i| libm::fabs(self.x[omega(i)]) > DIVERGED_RATE_RAD_S)
    }

    /// Applies one scalar row; returns whether it was applied.
    fn apply(&mut self, row: &SparseRow, nu: f64, sigma: f64, gate: f64) -> bool {
        let r = sigma * sigma * self.variance_scale;
        scalar_update(&mut self.x, &mut self.p, row, nu, r, gate).applied
    }

    /// One filter step after the start-up: predict, then every scalar row.
    /// Returns (stance applied, accelerometer rows rejected).
    fn filter_step(&mut self, sample: &Sample, dt: f64, t: f64) -> (bool, u32) {
        let q = self.process_noise();
        predict_state(&mut self.x, dt, &q);
        predict_covariance(&mut self.p, dt, &q);
        self.turning(sample, dt);
        let p = self.params;
        let inf = f64::INFINITY;
        for i in 0..4 {
            // gyro z, also of an incomplete vector (issue 18 item 2)
            if let Some(wz) = sample.imu[i].gyr_axis(2).filter(|w| w.is_finite()) {
                let mut row = SparseRow::new();
                row.add(omega(i), 1.0);
                row.add(gyro_bias(i), 1.0);
                let nu = wz - self.x[omega(i)] - self.x[gyro_bias(i)];
                let gated = p.use_encoders
                    && encoder_beside(sample, i)
                    && !self.encoder_gate.gyro_refused_last(i);
                let gate = if gated { p.gyro_gate } else { inf };
                let applied = self.apply(&row, nu, p.gyro_noise, gate);
                // (a row skipped for want of a positive innovation variance
                // is not a refusal)
                self.encoder_gate.gyro_row(i, applied || !gated);
            }
        }
        if p.use_encoders {
            self.encoder_rows(sample);
        }
        let mut rejected = 0;
        for i in 0..4 {
            let imu = &sample.imu[i];
            let oop = self.out_of_plane(i, imu, t);
            // Each in-plane axis that is there is its own row (issue 18 item
            // 2: an incomplete vector's x or y too). A complete vector with
            // a non-finite in-plane axis is not used at all.
            let complete_ok = imu.acc.is_none_or(|a| a.x.is_finite() && a.y.is_finite());
            for k in 0..2 {
                let Some(a) = imu.acc_axis(k).filter(|a| a.is_finite() && complete_ok) else {
                    continue;
                };
                let (f, rows) = self.geometry.specific_force(&self.x, i, self.g, &oop);
                if !self.apply(&rows[k], a - f[k], p.acc_noise, p.acc_gate) {
                    rejected += 1;
                }
            }
        }
        self.device_rows(sample, dt);
        // Anchors: vertical hip velocity about 0, forward about the mean speed.
        let mut row = SparseRow::new();
        row.add(hip_velocity(1), 1.0);
        let nu = -self.x[hip_velocity(1)];
        self.apply(&row, nu, p.hip_vertical_velocity, inf);
        let mut row = SparseRow::new();
        row.add(hip_velocity(0), 1.0);
        row.add(MEAN_SPEED, -1.0);
        let nu = -(self.x[hip_velocity(0)] - self.x[MEAN_SPEED]);
        self.apply(&row, nu, p.hip_forward_velocity, inf);
        if !sample.imu.iter().any(ImuSample::has_inertial_cells) {
            missing_data::hold_trunk(&mut self.x, &mut self.p);
        }
        let stance = self.foot_still(sample);
        if let Some(age) = stance {
            let grow = FOOT_ANGULAR_ACCELERATION * FOOT_PIVOT_M;
            for k in 0..2 {
                let (v, rows) = self.geometry.ankle_velocity(&self.x);
                self.apply(&rows[k], -v[k], p.stance_velocity + grow * age, inf);
            }
            // The acceleration anchor only with a still gyro reading now: at
            // heel-off the ankle's acceleration jumps at once (alpha r ~ 7.5
            // m/s^2 against a sigma of 0.5), so no growth with age bounds it.
            if age == 0.0 {
                for k in 0..2 {
                    let (a, rows) = self.geometry.ankle_acceleration(&self.x);
                    self.apply(&rows[k], -a[k], p.stance_acceleration, inf);
                }
            }
        }
        (stance.is_some(), rejected)
    }
}

impl Estimator for ChainEkf {
    fn name(&self) -> &'static str {
        "chain"
    }

    fn outputs(&self) -> Outputs {
        Outputs::ALL_ANGLES
    }

    fn diagnostic_names(&self) -> &[&'static str] {
        &ChainDiag::NAMES
    }

    fn describe_parameters(&self, out: &mut dyn fmt::Write) -> fmt::Result {
        let p = &self.params;
        let g = &self.geometry;
        writeln!(out, "model: planar chain EKF, 24 states (docs/CHAIN.md)")?;
        writeln!(out, "thigh_length: {}", g.thigh_length)?;
        writeln!(out, "shank_length: {}", g.shank_length)?;
        for (name, r) in ["trunk", "thigh", "shank", "foot"]
            .iter()
            .zip(g.imu_position.iter())
        {
            writeln!(out, "imu_position_{name}: {} {} {}", r[0], r[1], r[2])?;
        }
        let psi = g.frame_offset.map(f64::to_degrees);
        writeln!(
            out,
            "frame_offset_deg: {} {} {} {}",
            psi[0], psi[1], psi[2], psi[3]
        )?;
        writeln!(out, "g: {}", self.g)?;
        writeln!(out, "gyro_noise: {}", p.gyro_noise)?;
        writeln!(out, "acc_noise: {}", p.acc_noise)?;
        writeln!(out, "encoder_noise: {}", p.encoder_noise)?;
        writeln!(out, "trunk_jerk: {}", p.trunk_jerk)?;
        writeln!(out, "leg_jerk: {}", p.leg_jerk)?;
        writeln!(out, "hip_acc_sd: {}", p.hip_acc_sd)?;
        writeln!(out, "hip_acc_tau: {}", p.hip_acc_tau)?;
        writeln!(out, "gyro_bias_walk: {}", p.gyro_bias_walk)?;
        writeln!(out, "gyro_bias_initial: {}", p.gyro_bias_initial)?;
        writeln!(out, "hip_vertical_velocity: {}", p.hip_vertical_velocity)?;
        writeln!(out, "hip_forward_velocity: {}", p.hip_forward_velocity)?;
        writeln!(out, "mean_speed_walk: {}", p.mean_speed_walk)?;
        writeln!(out, "stance_velocity: {}", p.stance_velocity)?;
        writeln!(out, "stance_acceleration: {}", p.stance_acceleration)?;
        writeln!(out, "stance_gyro: {}", p.stance_gyro)?;
        writeln!(out, "stance_acc: {}", p.stance_acc)?;
        writeln!(out, "stance_min_s: {}", p.stance_min_s)?;
        writeln!(out, "startup_s: {}", p.startup_s)?;
        writeln!(out, "acc_gate: {}", p.acc_gate)?;
        writeln!(out, "encoder_gate: {}", p.encoder_gate)?;
        writeln!(out, "gyro_gate: {}", p.gyro_gate)?;
        writeln!(out, "device_orientation: {}", p.device_orientation)?;
        writeln!(out, "device_angle_noise: {}", p.device_angle_noise)?;
        writeln!(out, "use_encoders: {}", p.use_encoders)?;
        writeln!(out, "out_of_plane: {}", p.out_of_plane)?;
        writeln!(out, "turn_tau_s: {}", p.turn_tau_s)?;
        writeln!(out, "turn_rate_min: {}", p.turn_rate_min)?;
        writeln!(out, "turn_angle_noise: {}", p.turn_angle_noise)
    }

    fn reset(&mut self) {
        self.time = TimeStep::new();
        self.startup = Startup::default();
        self.running = false;
        self.x = StateVector::zeros();
        self.p = Covariance::zeros();
        self.last_xy_rate = [None; 4];
        self.still_since = None;
        self.last_foot_gyro = None;
        self.held = 0;
        self.turn_rate = 0.0;
        self.device = Default::default();
        self.link = Link::None;
        self.widening = 0.0;
        self.variance_scale = 1.0;
        self.blind = Default::default();
        self.encoder_gate = Default::default();
    }

    fn rejected_readings(&self) -> [u64; 3] {
        [
            self.encoder_gate.gyro_refused(),
            0,
            self.encoder_gate.refused(),
        ]
    }

    fn step(&mut self, sample: &Sample) -> Result<Estimate, EstimatorError> {
        // jittered stamps of a regular clock: whole steps of its grid (ours)
        let (mut dt, t_grid) = self.time_base.step(sample, self.time.advance(sample.t)?);
        self.clock_t = t_grid;
        if dt.is_some_and(|d| d > LONG_GAP_S) {
            // A gap in the recording longer than a stride (ours, issue 18
            // item 2, as the segment filters): no prediction over it means
            // anything (a 2 s step made the covariance indefinite, found by
            // tests/integration/issue_18_fuzz_chain_knee.rs), so the start-up window
            // begins again at this sample (`diag_running` = 0, no estimate
            // until it closes).
            self.restart_startup();
            dt = None;
        }
        let limit = missing_data::blind_limit_s(self.params.leg_jerk, initial::ANGLE);
        if self.blind.observe(sample, limit) && self.running {
            // Nothing measured for longer than the prediction is worth:
            // the start-up window begins again, as after a time gap.
            self.restart_startup();
        }
        let mut est = Estimate::empty(sample.t);
        let (mut stance, mut rejected) = (false, 0);
        self.link = Link::None;
        match (self.running, dt) {
            (true, Some(dt)) => {
                let adopted = self.encoder_gate.readopted();
                (stance, rejected) = self.filter_step(sample, dt, self.clock_t);
                self.link = if self.encoder_gate.readopted() == adopted {
                    Link::Continue {
                        dt,
                        widening: self.widening,
                    }
                } else {
                    // A re-adopted encoder offset: the smoother stops here.
                    Link::Start
                };
            }
            _ if self.blind.active() => {} // (`BlindRun::active`)
            _ => {
                self.startup.observe(sample, dt);
                if self.held < self.window.len() {
                    self.window[self.held] = *sample;
                    self.held += 1;
                }
                let ready = (0..4).all(|i| self.startup.angle(i).is_some());
                let closed = self.startup.elapsed(sample.t) >= self.params.startup_s
                    || self.held == self.window.len();
                if ready && closed {
                    if self.start() {
                        self.link = Link::Start;
                    } else {
                        self.restart_startup();
                    }
                } else if self.held == self.window.len() {
                    // Full before every segment had an accelerometer reading:
                    // start the window again.
                    self.startup = Startup::default();
                    self.held = 0;
                }
            }
        }
        if self.running && self.diverged() {
            // Diverged (readings no gate screened, e.g. 1e300 offered to the
            // estimator directly; tests/integration/issue_18_fuzz_chain_knee.rs): start
            // again from the next samples.
            self.restart_startup();
            self.link = Link::None;
        }
        // No estimate until the window closes (docs/CHAIN.md "Start-up").
        if self.running {
            for i in 0..4 {
                est.segment[i] = Some(self.x[theta(i)]);
            }
            est.fill_joints_from_segments();
        }
        let mut d = est.diagnostics_mut::<ChainDiag>();
        d.flag(ChainDiag::Running, self.running);
        if self.running {
            d.flag(ChainDiag::Stance, stance);
            d.value(ChainDiag::HipVx, self.x[hip_velocity(0)]);
            d.value(ChainDiag::HipVy, self.x[hip_velocity(1)]);
            d.value(ChainDiag::MeanSpeed, self.x[MEAN_SPEED]);
            d.value(ChainDiag::AccRejected, rejected as f64);
            let sd = |i: usize| libm::sqrt(self.p[(theta(i), theta(i))].max(0.0));
            d.value(ChainDiag::SdTrunk, sd(0));
            d.value(ChainDiag::SdThigh, sd(1));
            d.value(ChainDiag::SdShank, sd(2));
            d.value(ChainDiag::SdFoot, sd(3));
        }
        Ok(est)
    }
}
