//! Leg-extension FES trial simulator (paper 004 section 4.1.3): the knee
//! model of `limbfuse_models::fes_knee` driven by a stimulation profile,
//! with thigh and shank IMUs and a knee encoder.
//!
//! * Motion: the leg rests at its passive equilibrium for `rest_s`, then
//!   `cycles` extensions: per cycle 1 s rest, 1.5 s half-cosine ramp up,
//!   1 s hold, 1.5 s ramp down, then rest to the end of the period. The peak
//!   stimulation is the static level that holds the leg at `target_deg`
//!   (from the model, eq 4.1 with zero velocity), so every subject extends
//!   to about the same angle (a leg resting within 30 deg of the target
//!   extends to 30 deg above its rest instead). Truth integrates eq 4.1 by RK4 at 1 kHz with
//!   first-order muscle activation `a_dot = (u - a) / T_a` (Table 1's `T_a`;
//!   the estimators assume `a = u` as the thesis does) unless
//!   `activation_dynamics` is off.
//! * Sensors: thigh IMU on the horizontal thigh (static), shank IMU on the
//!   shank axis at `shank_imu_m` from the knee: angular rate and specific
//!   force (gravity, tangential and centripetal acceleration) from the
//!   motion, consumer-MEMS errors of [`crate::config::ImuSpec`] (the
//!   walking simulator's defaults), plus an optional constant gyro drift.
//! * Knee encoder and references: `knee_enc` (14-bit), `thigh_ref = pi/2`,
//!   `shank_ref = x1`, `knee_ref = pi/2 - x1`; stimulation `u_ke`.

use limbfuse_core::{Record, Reference, Sample, Segment};
use limbfuse_models::{KneeFesModel, KneeFesParams, KneeSubject, DEFAULT_BODY_HEIGHT_M};
use nalgebra::{Vector2, Vector3};
use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;

use crate::config::{EncoderSpec, ImuSpec, Mounting};
use crate::encoder_model::Encoders;
use crate::fes_error::{in_range, FesSimError};
use crate::imu_model::Imu;
use crate::planar_imu::PlanarSegment;

/// Configuration of a knee-FES trial.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct KneeFesConfig {
    /// Which leg of Table 1.
    pub subject: KneeSubject,
    /// Model parameters; `None` = the subject's preset.
    pub params: Option<KneeFesParams>,
    /// Trial length (s).
    pub duration_s: f64,
    /// IMU sample rate (Hz).
    pub rate_hz: f64,
    /// Seed of every random draw.
    pub seed: u64,
    /// Sensor errors on/off.
    pub noise: bool,
    /// IMU error figures.
    pub imu: ImuSpec,
    /// Encoder error figures.
    pub encoder: EncoderSpec,
    /// Quiet rest before the first extension (s).
    pub rest_s: f64,
    /// Number of extensions (each [`CYCLE_S`]; default 5, paper 004's 30 s
    /// trials); the leg rests after the last one.
    pub cycles: u32,
    /// Target extension angle x1 at peak stimulation (deg from hanging).
    pub target_deg: f64,
    /// Muscle activation dynamics in the truth.
    pub activation_dynamics: bool,
    /// Shank IMU distance from the knee along the shank (m).
    pub shank_imu_m: f64,
    /// Extra constant gyro drift added to both gyros' z axis (rad/s).
    pub gyro_drift: f64,
    /// How the IMUs sit on their segments (`Random` needs `limbfuse align`).
    pub mounting: Mounting,
}

/// Length of one extension cycle (s): 1 s rest, 1.5 s ramp up, 1 s hold,
/// 1.5 s ramp down, 1 s rest.
pub const CYCLE_S: f64 = 6.0;

impl KneeFesConfig {
    /// When the last extension cycle ends (s): the leg rests after it.
    pub fn cycles_end_s(&self) -> f64 {
        self.rest_s + f64::from(self.cycles) * CYCLE_S
    }
}

impl Default for KneeFesConfig {
    fn default() -> Self {
        KneeFesConfig {
            subject: KneeSubject::P1L,
            params: None,
            duration_s: 30.0,
            rate_hz: 100.0,
            seed: 1,
            noise: true,
            imu: ImuSpec::default(),
            encoder: EncoderSpec::default(),
            rest_s: 2.0,
            cycles: 5,
            target_deg: 60.0,
            activation_dynamics: true,
            shank_imu_m: 0.2,
            gyro_drift: 0.0,
            mounting: Mounting::Aligned,
        }
    }
}

/// A simulated trial: records and the metadata that describe it (the
/// records in memory, or a stream of them: [`knee_fes_stream`]).
#[derive(Debug, Clone)]
pub struct FesTrial<R = Vec<Record>> {
    /// One record per sample.
    pub records: R,
    /// `key: value` metadata (model, subject, parameters, settings).
    pub metadata: Vec<(String, String)>,
}

impl<I: Iterator<Item = Record>> FesTrial<I> {
    /// The trial with every record in memory.
    pub fn collect(self) -> FesTrial {
        FesTrial {
            records: self.records.collect(),
            metadata: self.metadata,
        }
    }
}

/// Stimulation profile of one trial.
#[derive(Debug, Clone, Copy)]
struct Profile {
    rest: f64,
    period: f64,
    cycles: u32,
    peak: f64,
}

impl Profile {
    fn u(&self, t: f64) -> f64 {
        let t = t - self.rest;
        if t < 0.0 || t >= self.period * self.cycles as f64 {
            return 0.0;
        }
        let tc = t % self.period;
        let ramp = |s: f64| 0.5 - 0.5 * (core::f64::consts::PI * s).cos();
        self.peak
            * match tc {
                tc if tc < 1.0 => 0.0,
                tc if tc < 2.5 => ramp((tc - 1.0) / 1.5),
                tc if tc < 3.5 => 1.0,
                tc if tc < 5.0 => ramp(1.0 - (tc - 3.5) / 1.5),
                _ => 0.0,
            }
    }
}

/// Metadata keys of the model parameters (`param.NAME`).
pub fn knee_param_metadata(p: &KneeFesParams) -> Vec<(String, String)> {
    let mut m = vec![
        ("param.inertia".into(), p.inertia.to_string()),
        ("param.mass".into(), p.mass.to_string()),
        ("param.l_c".into(), p.l_c.to_string()),
        ("param.g".into(), p.g.to_string()),
        ("param.phi0".into(), p.phi0.to_string()),
        ("param.theta_eq".into(), p.theta_eq.to_string()),
        ("param.t_a".into(), p.t_a.to_string()),
        ("param.i_threshold_ma".into(), p.i_threshold_ma.to_string()),
        (
            "param.i_saturation_ma".into(),
            p.i_saturation_ma.to_string(),
        ),
    ];
    for (i, d) in p.d.iter().enumerate() {
        m.push((format!("param.d{}", i + 1), d.to_string()));
    }
    for (i, c) in p.c.iter().enumerate() {
        m.push((format!("param.c{i}"), c.to_string()));
    }
    m
}

/// Simulates one knee-FES trial (all records in memory).
pub fn simulate_knee_fes(cfg: &KneeFesConfig) -> Result<FesTrial, FesSimError> {
    Ok(knee_fes_stream(cfg)?.collect())
}

/// [`simulate_knee_fes`] with the records one at a time: memory does not
/// grow with the trial (a record is about 2 KB; an hour at 2 kHz held in
/// memory was 14 GB).
pub fn knee_fes_stream(
    cfg: &KneeFesConfig,
) -> Result<FesTrial<impl Iterator<Item = Record>>, FesSimError> {
    let cfg = *cfg;
    in_range("duration_s", cfg.duration_s, 1.0, 3600.0, "[1, 3600]")?;
    in_range("rate_hz", cfg.rate_hz, 10.0, 2000.0, "[10, 2000]")?;
    in_range("target_deg", cfg.target_deg, 10.0, 85.0, "[10, 85]")?;
    in_range("shank_imu_m", cfg.shank_imu_m, 0.0, 0.6, "[0, 0.6]")?;
    in_range("gyro_drift", cfg.gyro_drift, -1.0, 1.0, "[-1, 1] rad/s")?;
    in_range("rest_s", cfg.rest_s, 0.0, 60.0, "[0, 60]")?;
    // (3600 s, the longest trial, holds 600 cycles of `CYCLE_S`)
    in_range("cycles", f64::from(cfg.cycles), 0.0, 600.0, "[0, 600]")?;
    let params = cfg
        .params
        .unwrap_or_else(|| KneeFesParams::subject(cfg.subject));
    let model = KneeFesModel::new(params)?;
    let g = params.g;
    // A leg resting high (P3-L rests near 58 deg) extends 30 deg above its rest.
    let rest_deg = model.passive_equilibrium().to_degrees();
    let target = cfg.target_deg.max(rest_deg + 30.0).min(85.0);
    let peak = [target, 50.0, 40.0]
        .iter()
        .find_map(|d| model.holding_activation(d.to_radians()))
        .ok_or(FesSimError::NoHoldingStimulation {
            subject: cfg.subject.label(),
        })?;
    let profile = Profile {
        rest: cfg.rest_s,
        period: CYCLE_S,
        cycles: cfg.cycles,
        peak,
    };
    let mut rng = ChaCha8Rng::seed_from_u64(cfg.seed);
    let mut imus = [
        Imu::draw(&mut rng, &cfg.imu, cfg.mounting, cfg.rate_hz, cfg.noise),
        Imu::draw(&mut rng, &cfg.imu, cfg.mounting, cfg.rate_hz, cfg.noise),
    ];
    let encoders = Encoders::draw(&mut rng, &cfg.encoder, cfg.noise);
    let thigh_angle = core::f64::consts::FRAC_PI_2;

    // State [x1, x2, a]: start at rest.
    let mut x = [model.passive_equilibrium(), 0.0, 0.0];
    let deriv = move |t: f64, s: &[f64; 3]| -> [f64; 3] {
        let u = profile.u(t);
        let a = if cfg.activation_dynamics { s[2] } else { u };
        let xv = Vector2::new(s[0], s[1]);
        let acc = -model.beta() * s[0].sin() + model.alpha() * model.joint_torque(&xv, a);
        [s[1], acc, (u - s[2]) / params.t_a]
    };
    let dt = 1.0 / cfg.rate_hz;
    let n = (cfg.duration_s * cfg.rate_hz).round() as usize;
    let sub = (dt / 1e-3).ceil().max(1.0) as usize;
    let h = dt / sub as f64;
    let mut metadata = vec![
        ("model".to_string(), "knee-fes".to_string()),
        ("subject".to_string(), cfg.subject.label().to_string()),
        ("seed".to_string(), cfg.seed.to_string()),
        ("noise".to_string(), cfg.noise.to_string()),
        (
            "activation_dynamics".to_string(),
            cfg.activation_dynamics.to_string(),
        ),
        ("peak_stimulation".to_string(), format!("{peak:.4}")),
        ("shank_imu_m".to_string(), cfg.shank_imu_m.to_string()),
        ("thigh_imu_m".to_string(), "0.2".to_string()),
        ("gyro_drift_rad_s".to_string(), cfg.gyro_drift.to_string()),
        ("thigh_angle_rad".to_string(), thigh_angle.to_string()),
    ];
    metadata.extend(knee_param_metadata(&params));
    if cfg.mounting == Mounting::Random {
        // As `simulate walking --mounting random` and the importers declare
        // raw frames (an audit: without it `inspect` said sdre / ekf run,
        // and they restarted 553 times on the raw channels, silently).
        metadata.push(("mounting".into(), "random".into()));
        metadata.push((
            "imu_frame".into(),
            "raw sensor frames (mounted at random: the `<seg>_mount_quat` lines)".into(),
        ));
        for (seg, imu) in ["thigh", "shank"].iter().zip(&imus) {
            let q = imu.mount_quaternion();
            metadata.push((
                format!("{seg}_mount_quat"),
                format!("{:.9} {:.9} {:.9} {:.9}", q[0], q[1], q[2], q[3]),
            ));
        }
    }
    let records = (0..n).map(move |k| {
        let t = k as f64 * dt;
        if k > 0 {
            for j in 0..sub {
                let tj = t - dt + j as f64 * h;
                x = rk4(&deriv, tj, &x, h);
            }
        }
        let d = deriv(t, &x);
        let u = profile.u(t);
        let shank = PlanarSegment {
            angle: x[0],
            rate: x[1],
            accel: d[1],
            pivot_accel: Vector2::zeros(),
        };
        let thigh = PlanarSegment {
            angle: thigh_angle,
            rate: 0.0,
            accel: 0.0,
            pivot_accel: Vector2::zeros(),
        };
        let mut sample = Sample::empty(t);
        for (i, (seg, r, which)) in [
            (thigh, 0.2, Segment::Thigh),
            (shank, cfg.shank_imu_m, Segment::Shank),
        ]
        .into_iter()
        .enumerate()
        {
            let (rot, w, f) = seg.imu_inputs(r, g);
            let (mut gyr, acc) = imus[i].read(&rot, &w, &f, &mut rng);
            gyr += Vector3::new(0.0, 0.0, cfg.gyro_drift);
            sample.imu[which.index()].gyr = Some(gyr);
            sample.imu[which.index()].acc = Some(acc);
        }
        let knee = thigh_angle - x[0];
        sample.encoder[1] = Some(encoders.read(&[0.0, knee, 0.0], &mut rng)[1]);
        sample.inputs.stim[0] = Some(u);
        let mut reference = Reference::default();
        reference.segment[Segment::Thigh.index()] = Some(thigh_angle);
        reference.segment[Segment::Shank.index()] = Some(x[0]);
        reference.joint[1] = Some(knee);
        Record { sample, reference }
    });
    Ok(FesTrial { records, metadata })
}

/// The calibration recording of the static-rotation alignment procedure
/// (paper 004 section 3.3, Fig. 9) with the same sensors as the trial of
/// `cfg` (same seed, so the same mounting and sensor errors): 12 s of quiet
/// standing, then 4 straight-leg hip flexion/extension rotations (1 s
/// forward to 30 deg, 0.5 s hold, 1 s back, 0.5 s hold). Thigh IMU 0.2 m
/// below the hip, shank IMU `shank_imu_m` below the knee (thigh 0.245 H,
/// H = [`DEFAULT_BODY_HEIGHT_M`], 1.75 m, Winter).
pub fn simulate_calibration(cfg: &KneeFesConfig) -> Result<FesTrial, FesSimError> {
    in_range("rate_hz", cfg.rate_hz, 10.0, 2000.0, "[10, 2000]")?;
    let g = cfg.params.map_or(9.81, |p| p.g);
    let mut rng = ChaCha8Rng::seed_from_u64(cfg.seed);
    let mut imus = [
        Imu::draw(&mut rng, &cfg.imu, cfg.mounting, cfg.rate_hz, cfg.noise),
        Imu::draw(&mut rng, &cfg.imu, cfg.mounting, cfg.rate_hz, cfg.noise),
    ];
    let thigh_len = 0.245 * DEFAULT_BODY_HEIGHT_M;
    let amp = 30f64.to_radians();
    // theta(t), rate, acceleration of the straight leg.
    let motion = |t: f64| -> (f64, f64, f64) {
        let t = t - 12.0;
        if !(0.0..12.0).contains(&t) {
            return (0.0, 0.0, 0.0);
        }
        let tc = t % 3.0;
        let pi = core::f64::consts::PI;
        // Smooth step s(u) = (1 - cos(pi u)) / 2 over 1 s.
        let step = |u: f64, sign: f64, base: f64| {
            (
                base + sign * amp * (1.0 - (pi * u).cos()) / 2.0,
                sign * amp * pi * (pi * u).sin() / 2.0,
                sign * amp * pi * pi * (pi * u).cos() / 2.0,
            )
        };
        match tc {
            tc if tc < 1.0 => step(tc, 1.0, 0.0),
            tc if tc < 1.5 => (amp, 0.0, 0.0),
            tc if tc < 2.5 => step(tc - 1.5, -1.0, amp),
            _ => (0.0, 0.0, 0.0),
        }
    };
    let dt = 1.0 / cfg.rate_hz;
    let n = (24.0 * cfg.rate_hz).round() as usize;
    let mut records = Vec::with_capacity(n);
    for k in 0..n {
        let t = k as f64 * dt;
        let (th, w, a) = motion(t);
        let thigh = PlanarSegment {
            angle: th,
            rate: w,
            accel: a,
            pivot_accel: Vector2::zeros(),
        };
        let shank = PlanarSegment {
            angle: th,
            rate: w,
            accel: a,
            pivot_accel: thigh.point_accel(thigh_len),
        };
        let mut sample = Sample::empty(t);
        for (i, (seg, r, which)) in [
            (thigh, 0.2, Segment::Thigh),
            (shank, cfg.shank_imu_m, Segment::Shank),
        ]
        .into_iter()
        .enumerate()
        {
            let (rot, wv, f) = seg.imu_inputs(r, g);
            let (gyr, acc) = imus[i].read(&rot, &wv, &f, &mut rng);
            sample.imu[which.index()].gyr = Some(gyr);
            sample.imu[which.index()].acc = Some(acc);
        }
        let mut reference = Reference::default();
        reference.segment[Segment::Thigh.index()] = Some(th);
        reference.segment[Segment::Shank.index()] = Some(th);
        reference.joint[1] = Some(0.0);
        records.push(Record { sample, reference });
    }
    let metadata = vec![
        (
            "source".to_string(),
            "limbfuse simulate knee-fes --calibration".to_string(),
        ),
        ("seed".to_string(), cfg.seed.to_string()),
        (
            "calibration".to_string(),
            "static-rotation: 12 s quiet standing, 4 hip flexion/extension rotations".to_string(),
        ),
    ];
    Ok(FesTrial { records, metadata })
}

/// One classical RK4 step of `x_dot = f(t, x)`.
pub fn rk4<const N: usize>(
    f: &impl Fn(f64, &[f64; N]) -> [f64; N],
    t: f64,
    x: &[f64; N],
    h: f64,
) -> [f64; N] {
    let add = |a: &[f64; N], k: &[f64; N], c: f64| {
        let mut o = *a;
        for i in 0..N {
            o[i] += k[i] * c;
        }
        o
    };
    let k1 = f(t, x);
    let k2 = f(t + h / 2.0, &add(x, &k1, h / 2.0));
    let k3 = f(t + h / 2.0, &add(x, &k2, h / 2.0));
    let k4 = f(t + h, &add(x, &k3, h));
    let mut o = *x;
    for i in 0..N {
        o[i] += h / 6.0 * (k1[i] + 2.0 * k2[i] + 2.0 * k3[i] + k4[i]);
    }
    o
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_subject_extends_and_the_signals_follow_the_motion() {
        for s in KneeSubject::ALL {
            let cfg = KneeFesConfig {
                subject: s,
                noise: false,
                ..KneeFesConfig::default()
            };
            let tr = simulate_knee_fes(&cfg).unwrap();
            assert_eq!(tr.records.len(), 3000);
            let x1: Vec<f64> = tr
                .records
                .iter()
                .map(|r| r.reference.segment[2].unwrap())
                .collect();
            let max = x1.iter().cloned().fold(f64::MIN, f64::max).to_degrees();
            let min = x1.iter().cloned().fold(f64::MAX, f64::min).to_degrees();
            eprintln!("{}: x1 {min:.1} .. {max:.1} deg", s.label());
            assert!(
                max > 35.0 && max < 86.0 && max - min > 25.0,
                "{}: {min} .. {max}",
                s.label()
            );
            // Noise-free gyro z equals the true rate; static acc_x = g sin x1 at rest.
            let r0 = &tr.records[10];
            let acc = r0.sample.imu[2].acc.unwrap();
            assert!((acc.x - 9.81 * x1[10].sin()).abs() < 1e-6);
            // Rate = derivative of angle (central difference).
            for k in [800, 1500, 2200] {
                let d = (x1[k + 1] - x1[k - 1]) / 0.02;
                let w = tr.records[k].sample.imu[2].gyr.unwrap().z;
                assert!((d - w).abs() < 0.02 * (1.0 + w.abs()), "{d} vs {w}");
            }
        }
    }

    #[test]
    fn same_seed_same_trial_and_bad_parameters_are_errors() {
        let cfg = KneeFesConfig {
            duration_s: 5.0,
            ..KneeFesConfig::default()
        };
        let a = simulate_knee_fes(&cfg).unwrap();
        let b = simulate_knee_fes(&cfg).unwrap();
        assert_eq!(a.records, b.records);
        let mut p = KneeFesParams::subject(KneeSubject::P1L);
        p.mass = 0.0;
        let e = simulate_knee_fes(&KneeFesConfig {
            params: Some(p),
            ..cfg
        })
        .unwrap_err();
        assert!(e.to_string().contains("mass"), "{e}");
    }
}
