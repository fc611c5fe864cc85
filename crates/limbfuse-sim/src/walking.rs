//! The walking simulator: a streaming iterator of [`Record`]s.

use limbfuse_core::{ImuSample, Joint, Record, Reference, Sample, Segment};
use nalgebra::Vector3;
use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;

use crate::chain::{Frame, LegKin, PointKin};
use crate::config::{EncoderResample, Motion, SimError, WalkingConfig};
use crate::encoder_model::Encoders;
use crate::gait_curves::SpeedLaw;
use crate::gait_model::GaitModel;
use crate::imu_model::Imu;
use crate::turn_schedule::TurnSchedule;
use crate::variability::{Clock, Modulation};

/// ChaCha stream of the set-up draws (variability, mountings, sensor errors, offsets).
const STREAM_SETUP: u64 = 0;
/// ChaCha stream of the per-sample IMU noise.
const STREAM_IMU: u64 = 1;
/// ChaCha stream of the per-tick encoder noise.
const STREAM_ENCODER: u64 = 2;

/// Error-free state of the simulated body at one instant.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Truth {
    /// Time (s).
    pub t: f64,
    /// Unwrapped gait phase of the right leg (rad; 2 pi per stride, 0 = heel strike).
    pub phase: f64,
    /// Sagittal absolute segment angles (rad): trunk, thigh, shank, foot.
    pub segment_angle: [f64; 4],
    /// SPEC joint angles (rad): hip, knee, ankle.
    pub joint_angle: [f64; 3],
    /// Segment frames (rotation, world angular velocity and acceleration).
    pub frames: [Frame; 4],
    /// Hip joint centre, world.
    pub hip: PointKin,
    /// IMU mounting points, world (position, velocity, acceleration).
    pub imu_point: [PointKin; 4],
    /// Heel and metatarsal-head contact points of the simulated foot, world.
    pub contacts: [PointKin; 2],
    /// Error-free gyroscope reading, sensor frame (rad/s).
    pub gyro: [Vector3<f64>; 4],
    /// Error-free accelerometer reading (specific force), sensor frame (m/s^2).
    pub specific_force: [Vector3<f64>; 4],
}

/// The set-up draws in their fixed order (clock, amplitude modulation, the
/// four IMUs); `rng` is left where the encoder offsets are drawn next.
struct SetupDraws {
    rng: ChaCha8Rng,
    clock: Clock,
    modulation: Modulation,
    imus: [Imu; 4],
}

/// Every set-up draw of `cfg` up to the IMUs. The number of draws does not
/// depend on the speed, the motion or the variability, so the sensors of a
/// seed are the same whatever is simulated with them.
fn setup_draws(cfg: &WalkingConfig, f0: f64, phi0: f64) -> SetupDraws {
    let mut rng = ChaCha8Rng::seed_from_u64(cfg.seed);
    rng.set_stream(STREAM_SETUP);
    let var = cfg.variability.unwrap_or(crate::config::Variability {
        stride_time_cv: 0.0,
        amplitude_cv: 0.0,
    });
    let clock = Clock::new(&mut rng, f0, phi0, var.stride_time_cv);
    let modulation = Modulation::new(&mut rng, var.amplitude_cv);
    let mut draw_imu = || Imu::draw(&mut rng, &cfg.imu, cfg.mounting, cfg.imu_rate_hz, cfg.noise);
    let imus = [draw_imu(), draw_imu(), draw_imu(), draw_imu()];
    SetupDraws {
        rng,
        clock,
        modulation,
        imus,
    }
}

/// The four IMUs (trunk..foot: mounting, scale, cross-axis, turn-on and
/// initial Gauss-Markov biases) that [`WalkingSimulator::new`] draws for
/// `cfg`: the same sensors, draw for draw, for any speed or motion of the
/// same seed, IMU specification, rate and noise switch (used by
/// [`crate::calibration_poses`] to record a calibration of these sensors).
pub fn walking_sensors(cfg: &WalkingConfig) -> Result<[Imu; 4], SimError> {
    cfg.validate()?;
    Ok(setup_draws(cfg, 0.0, 0.0).imus)
}

/// The ChaCha stream of the per-sample IMU noise of `seed` (the walking
/// simulator's; a calibration recording of the same sensors uses it too).
pub fn imu_noise_rng(seed: u64) -> ChaCha8Rng {
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    rng.set_stream(STREAM_IMU);
    rng
}

/// Seeded walking simulator; iterate it for one [`Record`] per IMU sample.
#[derive(Debug, Clone)]
pub struct WalkingSimulator {
    cfg: WalkingConfig,
    model: GaitModel,
    clock: Clock,
    modulation: Modulation,
    imus: [Imu; 4],
    encoders: Encoders,
    imu_rng: ChaCha8Rng,
    enc_rng: ChaCha8Rng,
    n_samples: u64,
    next_sample: u64,
    next_tick: u64,
    last_encoder: [f64; 3],
    /// With turns: the turned hip path `H` every [`HIP_PATH_CHECKPOINT_S`].
    hip_path: Vec<Vector3<f64>>,
    /// With turns: the heading, changed in the simulated leg's swings.
    turning: TurnSchedule,
}

/// Spacing (s) of the stored points of the turned hip path.
const HIP_PATH_CHECKPOINT_S: f64 = 1.0;

fn joints(seg: &[f64; 4]) -> [f64; 3] {
    [
        Joint::Hip.from_segments(seg),
        Joint::Knee.from_segments(seg),
        Joint::Ankle.from_segments(seg),
    ]
}

impl WalkingSimulator {
    /// Validates `cfg`, calibrates the gait and draws every constant error.
    pub fn new(cfg: WalkingConfig) -> Result<Self, SimError> {
        cfg.validate()?;
        let law = SpeedLaw {
            speed: cfg.speed_mps,
            height: cfg.height_m,
        };
        let model = GaitModel::new(law, cfg.out_of_plane).map_err(|e| SimError::Calibration {
            reached: e.reached,
            wanted: e.wanted,
        })?;
        let (f0, phi0) = match cfg.motion {
            Motion::Walk => (law.stride_frequency(), cfg.start_phase),
            Motion::Stand => (0.0, 0.0),
            Motion::Pose { phase } => (0.0, phase),
        };
        let SetupDraws {
            mut rng,
            clock,
            modulation,
            imus,
        } = setup_draws(&cfg, f0, phi0);
        let encoders = Encoders::draw(&mut rng, &cfg.encoder, cfg.noise);
        let imu_rng = imu_noise_rng(cfg.seed);
        let mut enc_rng = ChaCha8Rng::seed_from_u64(cfg.seed);
        enc_rng.set_stream(STREAM_ENCODER);
        let n_samples = (cfg.duration_s * cfg.imu_rate_hz).round() as u64;
        Ok(WalkingSimulator {
            cfg,
            model,
            clock,
            modulation,
            imus,
            encoders,
            imu_rng,
            enc_rng,
            n_samples,
            next_sample: 0,
            next_tick: 0,
            last_encoder: [0.0; 3],
            hip_path: Vec::new(),
            turning: Default::default(),
        }
        .with_turn_schedule()
        .with_hip_path())
    }

    /// Places the turns of `cfg.turns` in the simulated leg's swings
    /// ([`crate::turn_schedule`]); nothing without turns or walking.
    fn with_turn_schedule(mut self) -> Self {
        if let (Some(turns), Motion::Walk) = (self.cfg.turns, self.cfg.motion) {
            let (end, f0) = (self.cfg.duration_s, self.clock.mean_frequency());
            self.turning = TurnSchedule::on_gait(&turns, end, |t| self.gait_phase(t), f0);
        }
        self
    }

    /// Integrates the turned hip path `H` (Gauss-Legendre, IMU step) and stores it
    /// every [`HIP_PATH_CHECKPOINT_S`]; nothing without turns.
    fn with_hip_path(mut self) -> Self {
        if self.cfg.turns.is_none() {
            return self;
        }
        let end = self.cfg.duration_s;
        let n = (end / HIP_PATH_CHECKPOINT_S).ceil() as usize + 1;
        let mut h = crate::body_path::horizontal(&self.mirrored_kinematics(0.0).joints[0].p);
        let mut out = Vec::with_capacity(n);
        out.push(h);
        for c in 1..n {
            let t0 = (c - 1) as f64 * HIP_PATH_CHECKPOINT_S;
            h += self.hip_path_step(t0, HIP_PATH_CHECKPOINT_S);
            out.push(h);
        }
        self.hip_path = out;
        self
    }

    /// `H(t0 + span) - H(t0)` by composite 5-point Gauss-Legendre
    /// quadrature on steps of at most one IMU interval (error far below
    /// what a second difference of positions resolves).
    fn hip_path_step(&self, t0: f64, span: f64) -> Vector3<f64> {
        const NODES: [(f64, f64); 5] = [
            (0.0, 0.568_888_888_888_888_9),
            (-0.538_469_310_105_683_1, 0.478_628_670_499_366_5),
            (0.538_469_310_105_683_1, 0.478_628_670_499_366_5),
            (-0.906_179_845_938_664, 0.236_926_885_056_189_1),
            (0.906_179_845_938_664, 0.236_926_885_056_189_1),
        ];
        if self.cfg.turns.is_none() || span <= 0.0 {
            return Vector3::zeros();
        }
        let m = (span * self.cfg.imu_rate_hz).ceil().max(1.0) as usize;
        let step = span / m as f64;
        let rate = |t: f64| {
            crate::body_path::hip_path_rate(&self.mirrored_kinematics(t), self.turning.heading(t).v)
        };
        let mut sum = Vector3::zeros();
        for i in 0..m {
            let mid = t0 + (i as f64 + 0.5) * step;
            for (x, w) in NODES {
                sum += rate(mid + 0.5 * step * x) * (0.5 * step * w);
            }
        }
        sum
    }

    /// The turned hip's horizontal position `H(t)` (zero-based checkpoints).
    fn hip_path_at(&self, t: f64) -> Vector3<f64> {
        let c = ((t / HIP_PATH_CHECKPOINT_S).floor().max(0.0) as usize)
            .min(self.hip_path.len().saturating_sub(1));
        let t0 = c as f64 * HIP_PATH_CHECKPOINT_S;
        self.hip_path.get(c).copied().unwrap_or_default() + self.hip_path_step(t0, t - t0)
    }

    /// The heading of a walk with turns, changed in the simulated leg's
    /// swings ([`crate::turn_schedule`]; empty without turns).
    pub fn turn_schedule(&self) -> &TurnSchedule {
        &self.turning
    }

    /// The configuration in use.
    pub fn config(&self) -> &WalkingConfig {
        &self.cfg
    }

    /// The calibrated gait model.
    pub fn model(&self) -> &GaitModel {
        &self.model
    }

    /// The drawn IMUs (mounting and error state), trunk..foot.
    pub fn imus(&self) -> &[Imu; 4] {
        &self.imus
    }

    /// The drawn encoders.
    pub fn encoders(&self) -> &Encoders {
        &self.encoders
    }

    /// Number of records already produced.
    pub fn len_done(&self) -> u64 {
        self.next_sample
    }

    /// Number of records the trial holds.
    pub fn sample_count(&self) -> u64 {
        self.n_samples
    }

    /// Mean stride frequency (Hz); 0 when not walking.
    pub fn stride_frequency(&self) -> f64 {
        self.clock.mean_frequency()
    }

    /// Unwrapped gait phase (rad, 0 = heel strike of the simulated leg) at
    /// `t`: the gait clock alone, without the kinematics ([`Self::truth`]).
    pub fn gait_phase(&self, t: f64) -> f64 {
        if self.cfg.motion == Motion::Stand {
            return 0.0;
        }
        self.clock.phase(t).v
    }

    /// Nominal walking speed the calibrated gait achieves (m/s):
    /// stride length x mean stride frequency.
    pub fn nominal_speed(&self) -> f64 {
        self.model.hip.stride_length * self.clock.mean_frequency()
    }

    /// Kinematics of the leg and trunk at `t` (the left leg mirrored, the
    /// path turned, see [`crate::body_path`]). Positions under turns are
    /// integrated (`with_positions`), else left relative to the unturned hip
    /// (the sensor readings do not depend on them).
    fn kinematics_at(&self, t: f64, with_positions: bool) -> (f64, LegKin, [f64; 4]) {
        let (phase, mut k, seg) = self.base_kinematics(t);
        crate::body_path::mirror_to(self.cfg.leg, &mut k);
        if self.cfg.turns.is_some() {
            let path = if with_positions {
                self.hip_path_at(t)
            } else {
                crate::body_path::horizontal(&k.joints[0].p)
            };
            let (psi, psi_trunk) = (self.turning.heading(t), self.turning.trunk_heading(t));
            crate::body_path::turn(&mut k, psi, psi_trunk, path);
        }
        (phase, k, seg)
    }

    fn kinematics(&self, t: f64) -> (f64, LegKin, [f64; 4]) {
        self.kinematics_at(t, true)
    }

    /// The leg's kinematics on the straight path (the left leg mirrored).
    fn mirrored_kinematics(&self, t: f64) -> LegKin {
        let mut k = self.base_kinematics(t).1;
        crate::body_path::mirror_to(self.cfg.leg, &mut k);
        k
    }

    /// Right-leg kinematics on the straight path.
    fn base_kinematics(&self, t: f64) -> (f64, LegKin, [f64; 4]) {
        if self.cfg.motion == Motion::Stand {
            return (0.0, self.model.standing(), [0.0; 4]);
        }
        let phase = self.clock.phase(t);
        let (k, seg) = self.model.kinematics(phase, &self.modulation);
        (phase.v, k, seg)
    }

    /// Error-free state at time `t` (s). Does not touch the random streams.
    pub fn truth(&self, t: f64) -> Truth {
        let (phase, k, seg) = self.kinematics(t);
        let g = Vector3::new(0.0, self.cfg.g, 0.0);
        let mut gyro = [Vector3::zeros(); 4];
        let mut specific_force = [Vector3::zeros(); 4];
        for i in 0..4 {
            let (w, f) = self.imus[i].ideal(&k.frames[i].r, &k.frames[i].w, &(k.imu[i].a + g));
            gyro[i] = w;
            specific_force[i] = f;
        }
        Truth {
            t,
            phase,
            segment_angle: seg,
            joint_angle: joints(&seg),
            frames: k.frames,
            hip: k.joints[0],
            imu_point: k.imu,
            contacts: k.contacts,
            gyro,
            specific_force,
        }
    }

    /// World position (m) of the IMU on segment `s` at time `t`: positions only,
    /// for checks that differentiate it numerically.
    pub fn sensor_position(&self, s: Segment, t: f64) -> Vector3<f64> {
        self.kinematics(t).1.imu[s.index()].p
    }

    /// Moves the IMU of segment `s` to `r` (segment frame, from the segment's
    /// proximal joint; the trunk's from the right hip joint centre). Takes
    /// effect from the next record. Used by [`crate::knee_scenario`].
    pub fn set_imu_position(&mut self, s: Segment, r: Vector3<f64>) {
        self.model.body.imu[s.index()] = r;
    }

    /// Replaces the sensor-to-segment rotation of the IMU of segment `s`
    /// (a re-mounting); takes effect from the next record.
    pub fn set_imu_mount(&mut self, s: Segment, mount: nalgebra::Matrix3<f64>) {
        self.imus[s.index()].mount = mount;
    }

    /// True SPEC joint angles at an encoder tick time.
    fn joint_truth(&self, t: f64) -> [f64; 3] {
        if self.cfg.motion == Motion::Stand {
            return [0.0; 3];
        }
        let phi = self.clock.phase(t).v;
        joints(&self.model.sagittal_angles(phi, self.modulation.amp(phi).v))
    }

    /// Simulates the encoder ticks up to time `t` and resamples them
    /// (`joints_at_t`: the true joint angles at `t`, reused for a tick at `t`).
    fn encoder_at(&mut self, t: f64, joints_at_t: &[f64; 3]) -> [f64; 3] {
        let rate = self.cfg.encoder_rate_hz;
        let last = (t * rate + 1e-9).floor().max(0.0) as u64;
        let mut sum = [0.0; 3];
        let mut count = 0u32;
        while self.next_tick <= last {
            let tj = self.next_tick as f64 / rate;
            let truth = if tj == t {
                *joints_at_t
            } else {
                self.joint_truth(tj)
            };
            let r = self.encoders.read(&truth, &mut self.enc_rng);
            for i in 0..3 {
                sum[i] += r[i];
            }
            count += 1;
            self.last_encoder = r;
            self.next_tick += 1;
        }
        match self.cfg.encoder_resample {
            EncoderResample::Mean if count > 0 => sum.map(|s| s / count as f64),
            _ => self.last_encoder,
        }
    }

    /// Run metadata as `key: value` pairs (for a trial file header).
    pub fn metadata(&self) -> Vec<(String, String)> {
        let c = &self.cfg;
        let m = &self.model;
        let mut out: Vec<(String, String)> = Vec::new();
        let mut put = |k: &str, v: String| out.push((k.to_string(), v));
        put("source", "limbfuse-sim walking".into());
        put("seed", c.seed.to_string());
        put("leg", c.leg.name().into());
        if let Some(tr) = c.turns {
            put(
                "turns",
                format!(
                    "every_s={} duration_s={} angle_deg={} (step turns: the leg's heading changes in its swings)",
                    tr.every_s,
                    tr.duration_s,
                    tr.angle_rad.to_degrees()
                ),
            );
        }
        put("g", c.g.to_string());
        put("sample_rate_hz", c.imu_rate_hz.to_string());
        put("encoder_rate_hz", c.encoder_rate_hz.to_string());
        put(
            "encoder_resample",
            format!("{:?}", c.encoder_resample).to_lowercase(),
        );
        put("duration_s", c.duration_s.to_string());
        put("motion", format!("{:?}", c.motion));
        put("speed_mps", c.speed_mps.to_string());
        put("nominal_speed_mps", format!("{:.6}", self.nominal_speed()));
        put(
            "cadence_steps_per_min",
            format!("{:.3}", 120.0 * self.stride_frequency()),
        );
        put(
            "stride_frequency_hz",
            format!("{:.6}", self.stride_frequency()),
        );
        put("stride_length_m", format!("{:.6}", m.hip.stride_length));
        put("height_m", c.height_m.to_string());
        // Geometry keys the `chain` method reads (docs/CHAIN.md "Geometry
        // metadata"; parsed by limbfuse-io's body_meta).
        let b = &m.body;
        put(
            "segment_lengths_m",
            format!("thigh {:.4}; shank {:.4}", b.thigh, b.shank),
        );
        put(
            "imu_mounts_m",
            Segment::ALL
                .iter()
                .map(|seg| {
                    let r = b.imu[seg.index()];
                    format!("{} ({:+.4}, {:+.4}, {:+.4})", seg.name(), r.x, r.y, r.z)
                })
                .collect::<Vec<_>>()
                .join("; "),
        );
        put("hip_gain", format!("{:.6}", m.hip_gain));
        put("hip_height_m", format!("{:.6}", m.placement.hip_height));
        put(
            "hip_vertical_excursion_m",
            format!("{:.6}", m.hip.excursion),
        );
        put("hip_speed_fluctuation", format!("{:.4}", m.hip.fluctuation));
        put("knee_gain", format!("{:.6}", m.law.knee_gain()));
        put("ankle_gain", format!("{:.6}", m.law.ankle_gain()));
        put("out_of_plane", c.out_of_plane.to_string());
        match c.variability {
            Some(v) => {
                put("stride_time_cv", v.stride_time_cv.to_string());
                put("amplitude_cv", v.amplitude_cv.to_string());
            }
            None => put("variability", "none".into()),
        }
        put("noise", c.noise.to_string());
        put("mounting", format!("{:?}", c.mounting).to_lowercase());
        if c.mounting == crate::Mounting::Random {
            // As the importers of real recordings declare theirs: methods
            // reading aligned frames then say so (`raw_frame_note`).
            put(
                "imu_frame",
                "raw sensor frames (mounted at random: the `<seg>_mount_quat` lines)".into(),
            );
        }
        let s = &c.imu;
        put(
            "gyro_spec",
            format!(
                "noise_density={:e} rad/s/sqrtHz turn_on_bias={:e} rad/s gm_sigma={:e} rad/s gm_tau={} s scale={} cross_axis={}",
                s.gyro.noise_density, s.gyro.turn_on_bias, s.gyro.bias_instability, s.gyro.bias_tau_s, s.gyro.scale_error, s.gyro.cross_axis
            ),
        );
        put(
            "acc_spec",
            format!(
                "noise_density={:e} m/s2/sqrtHz turn_on_bias={:e} m/s2 gm_sigma={:e} m/s2 gm_tau={} s scale={} cross_axis={}",
                s.acc.noise_density, s.acc.turn_on_bias, s.acc.bias_instability, s.acc.bias_tau_s, s.acc.scale_error, s.acc.cross_axis
            ),
        );
        put(
            "misalignment_sigma_rad",
            format!("{:e}", s.misalignment_rad),
        );
        put(
            "encoder_spec",
            format!(
                "bits={} noise={:e} rad offset_sigma={:e} rad",
                c.encoder.bits, c.encoder.noise_rad, c.encoder.offset_rad
            ),
        );
        for seg in Segment::ALL {
            let imu = &self.imus[seg.index()];
            let q = imu.mount_quaternion();
            put(
                &format!("{}_mount_quat", seg.name()),
                format!("{:.9} {:.9} {:.9} {:.9}", q[0], q[1], q[2], q[3]),
            );
            let (g, a) = (imu.gyro.turn_on, imu.acc.turn_on);
            put(
                &format!("{}_gyro_turn_on_bias", seg.name()),
                format!("{:e} {:e} {:e}", g.x, g.y, g.z),
            );
            put(
                &format!("{}_acc_turn_on_bias", seg.name()),
                format!("{:e} {:e} {:e}", a.x, a.y, a.z),
            );
        }
        for j in Joint::ALL {
            put(
                &format!("{}_enc_offset_rad", j.name()),
                format!("{:e}", self.encoders.offset[j.index()]),
            );
        }
        out
    }
}

impl Iterator for WalkingSimulator {
    type Item = Record;

    fn next(&mut self) -> Option<Record> {
        if self.next_sample >= self.n_samples {
            return None;
        }
        let t = self.next_sample as f64 / self.cfg.imu_rate_hz;
        self.next_sample += 1;
        let (_, k, seg) = self.kinematics_at(t, false);
        let g = Vector3::new(0.0, self.cfg.g, 0.0);
        let mut sample = Sample::empty(t);
        for i in 0..4 {
            let f = &k.frames[i];
            let (w, a) = self.imus[i].read(&f.r, &f.w, &(k.imu[i].a + g), &mut self.imu_rng);
            sample.imu[i] = ImuSample {
                acc: Some(a),
                gyr: Some(w),
                quat: None,
                ..Default::default()
            };
        }
        let joint = joints(&seg);
        sample.encoder = self.encoder_at(t, &joint).map(Some);
        let reference = Reference {
            segment: seg.map(Some),
            joint: joint.map(Some),
            ..Default::default()
        };
        Some(Record { sample, reference })
    }

    fn size_hint(&self) -> (usize, Option<usize>) {
        let left = usize::try_from(self.n_samples - self.next_sample).unwrap_or(usize::MAX);
        (left, Some(left))
    }
}

impl ExactSizeIterator for WalkingSimulator {}
