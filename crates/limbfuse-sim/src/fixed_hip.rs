//! Fixed-hip swing simulator (paper 004 section 4.2.3): the 2-DOF model of
//! `limbfuse_models::fixed_hip` driven by FES of four muscle groups and two
//! motors, with thigh and shank IMUs and hip/knee encoders.
//!
//! * Desired swing (period `period_s`): thigh `q1d = A_h (1 - cos wt) / 2`
//!   (A_h = 30 deg), knee flexion `A_k (1 - cos(wt - pi/3)) / 2`
//!   (A_k = 55 deg), shank `q2d = q1d - knee`.
//! * FES: half-wave sinusoidal bursts, hip flexors while the thigh swings
//!   forward, hip extensors back, knee extensors/flexors phase-shifted by
//!   pi/3 (peak stimulation 0.3).
//! * Motors (1 kHz, zero-order hold): computed-torque control (the torque
//!   the desired acceleration needs minus what FES and the passive tissues
//!   give, plus PD on the errors with 8 s^-2 and 4 s^-1), so FES and motors
//!   share the torque as in a hybrid neuroprosthesis.
//! * Muscle activation (optional, `activation_t_a`; issue 16): the four
//!   activations follow `a' = (u - a) / T_a` from `a = u(0)` and drive the
//!   muscle torques in place of the stimulation
//!   (`limbfuse_models::fixed_hip_activation`); off by default (the
//!   thesis's `a = u`).
//! * Truth: RK4 at 1 kHz. Sensors as in the knee simulator: IMUs at mid
//!   thigh and mid shank with tangential, centripetal and (for the shank)
//!   knee acceleration, MEMS errors, optional constant gyro drift.
//! * Columns: `u_hf, u_he, u_kf, u_ke`, `tau_hip_motor`, `tau_knee_motor`
//!   (torque on the thigh / on the shank about +z), `hip_enc`, `knee_enc`,
//!   `trunk_ref = 0`, `thigh_ref = q1`, `shank_ref = q2`, `hip_ref = -q1`,
//!   `knee_ref = q1 - q2`.

use limbfuse_core::{Record, Reference, Sample, Segment};
use limbfuse_models::{FixedHipActivationModel, FixedHipModel, FixedHipParams, SdcModel};
use nalgebra::{SVector, Vector2, Vector3, Vector4};
use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;

use crate::config::{EncoderSpec, ImuSpec, Mounting};
use crate::encoder_model::Encoders;
use crate::fes_error::{in_range, FesSimError};
use crate::imu_model::Imu;
use crate::knee_fes::{rk4, FesTrial};
use crate::planar_imu::PlanarSegment;

/// Configuration of a fixed-hip trial.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct FixedHipConfig {
    /// Model parameters.
    pub params: FixedHipParams,
    /// Trial length (s).
    pub duration_s: f64,
    /// IMU sample rate (Hz).
    pub rate_hz: f64,
    /// Seed.
    pub seed: u64,
    /// Sensor errors on/off.
    pub noise: bool,
    /// IMU error figures.
    pub imu: ImuSpec,
    /// Encoder error figures.
    pub encoder: EncoderSpec,
    /// Swing period (s).
    pub period_s: f64,
    /// Extra constant gyro drift on both gyros' z axis (rad/s).
    pub gyro_drift: f64,
    /// Muscle activation dynamics in the truth with this `T_a` (s); `None`:
    /// activation equals stimulation (the thesis model).
    pub activation_t_a: Option<f64>,
}

impl Default for FixedHipConfig {
    fn default() -> Self {
        FixedHipConfig {
            params: FixedHipParams::default(),
            duration_s: 20.0,
            rate_hz: 100.0,
            seed: 1,
            noise: true,
            imu: ImuSpec::default(),
            encoder: EncoderSpec::default(),
            period_s: 2.0,
            gyro_drift: 0.0,
            activation_t_a: None,
        }
    }
}

/// Desired `(q, q_dot, q_ddot)` at time `t`.
fn desired(t: f64, period: f64) -> (Vector2<f64>, Vector2<f64>, Vector2<f64>) {
    let w = core::f64::consts::TAU / period;
    let (ah, ak) = (30f64.to_radians(), 55f64.to_radians());
    let ph = core::f64::consts::FRAC_PI_3;
    let q1 = ah * (1.0 - (w * t).cos()) / 2.0;
    let q1d = ah * w * (w * t).sin() / 2.0;
    let q1dd = ah * w * w * (w * t).cos() / 2.0;
    let k = ak * (1.0 - (w * t - ph).cos()) / 2.0;
    let kd = ak * w * (w * t - ph).sin() / 2.0;
    let kdd = ak * w * w * (w * t - ph).cos() / 2.0;
    (
        Vector2::new(q1, q1 - k),
        Vector2::new(q1d, q1d - kd),
        Vector2::new(q1dd, q1dd - kdd),
    )
}

/// Stimulation `[u_hf, u_he, u_kf, u_ke]` at time `t`.
fn stimulation(t: f64, period: f64) -> [f64; 4] {
    let w = core::f64::consts::TAU / period;
    let s = (w * t).sin();
    let k = (w * t - core::f64::consts::FRAC_PI_3).sin();
    let peak = 0.3;
    // Thigh forward (q1 rising) while sin > 0; knee flexing while k > 0.
    [
        peak * s.max(0.0),
        peak * (-s).max(0.0),
        peak * k.max(0.0),
        peak * (-k).max(0.0),
    ]
}

/// Motor torques `(tau_hip, tau_knee)`: the inverse-dynamics torque of the
/// desired acceleration minus what FES (muscle drive `s`: the stimulation,
/// or the activations) and the passive tissues already provide (the
/// controller knows the model), plus a PD law.
fn motor(model: &FixedHipModel, x: &Vector4<f64>, t: f64, period: f64, s: [f64; 4]) -> (f64, f64) {
    let (qd, vd, ad) = desired(t, period);
    let no_motor = SVector::<f64, 6>::from_row_slice(&[s[0], s[1], s[2], s[3], 0.0, 0.0]);
    let (kp, kd) = (80.0, 8.0);
    let e = Vector2::new(qd[0] - x[0], qd[1] - x[1]);
    let ev = Vector2::new(vd[0] - x[2], vd[1] - x[3]);
    // Wanted q_ddot = ad + PD; generalised torque Q = M (q_ddot - q_ddot(x, no motor)).
    let want = ad + e * kp / 10.0 + ev * kd / 2.0;
    let free = model.accelerations(x, &no_motor);
    let q = model.mass_matrix(x) * (want - free);
    // Q1 = th - tk, Q2 = tk.
    (q[0] + q[1], q[1])
}

/// Simulates one fixed-hip trial.
pub fn simulate_fixed_hip(cfg: &FixedHipConfig) -> Result<FesTrial, FesSimError> {
    Ok(fixed_hip_stream(cfg)?.collect())
}

/// [`simulate_fixed_hip`] with the records one at a time: memory does not
/// grow with the trial (a record is about 2 KB).
pub fn fixed_hip_stream(
    cfg: &FixedHipConfig,
) -> Result<FesTrial<impl Iterator<Item = Record>>, FesSimError> {
    let cfg = *cfg;
    in_range("duration_s", cfg.duration_s, 1.0, 3600.0, "[1, 3600]")?;
    in_range("rate_hz", cfg.rate_hz, 10.0, 2000.0, "[10, 2000]")?;
    in_range("period_s", cfg.period_s, 0.5, 20.0, "[0.5, 20]")?;
    in_range("gyro_drift", cfg.gyro_drift, -1.0, 1.0, "[-1, 1] rad/s")?;
    let model = FixedHipModel::new(cfg.params)?;
    let act = match cfg.activation_t_a {
        Some(t_a) => Some(FixedHipActivationModel::new(model, t_a)?),
        None => None,
    };
    let p = cfg.params;
    let g = p.g;
    let mut rng = ChaCha8Rng::seed_from_u64(cfg.seed);
    let mut imus = [
        Imu::draw(
            &mut rng,
            &cfg.imu,
            Mounting::Aligned,
            cfg.rate_hz,
            cfg.noise,
        ),
        Imu::draw(
            &mut rng,
            &cfg.imu,
            Mounting::Aligned,
            cfg.rate_hz,
            cfg.noise,
        ),
    ];
    let encoders = Encoders::draw(&mut rng, &cfg.encoder, cfg.noise);
    let dt = 1.0 / cfg.rate_hz;
    let n = (cfg.duration_s * cfg.rate_hz).round() as usize;
    let sub = (dt / 1e-3).ceil().max(1.0) as usize;
    let h = dt / sub as f64;
    let inputs = move |x: &Vector4<f64>, t: f64, held: (f64, f64)| {
        let s = stimulation(t, cfg.period_s);
        let _ = x;
        SVector::<f64, 6>::from_row_slice(&[s[0], s[1], s[2], s[3], held.0, held.1])
    };
    let (q0, v0, _) = desired(0.0, cfg.period_s);
    let mut x = Vector4::new(q0[0], q0[1], v0[0], v0[1]);
    // Activations (used when `act` is set), starting at the stimulation.
    let mut a = stimulation(0.0, cfg.period_s);
    let drive = move |a: &[f64; 4], t: f64| match act {
        Some(_) => *a,
        None => stimulation(t, cfg.period_s),
    };
    let mut metadata = vec![
        ("model".to_string(), "fixed-hip".to_string()),
        ("seed".to_string(), cfg.seed.to_string()),
        ("noise".to_string(), cfg.noise.to_string()),
        ("period_s".to_string(), cfg.period_s.to_string()),
        ("gyro_drift_rad_s".to_string(), cfg.gyro_drift.to_string()),
    ];
    if let Some(t_a) = cfg.activation_t_a {
        metadata.push(("activation_dynamics".to_string(), "true".to_string()));
        metadata.push(("param.t_a".to_string(), t_a.to_string()));
    }
    metadata.extend(fixed_hip_param_metadata(&p));
    let mut held = motor(&model, &x, 0.0, cfg.period_s, drive(&a, 0.0));
    let records = (0..n).map(move |k| {
        let t = k as f64 * dt;
        if k > 0 {
            for j in 0..sub {
                let tj = t - dt + j as f64 * h;
                let xv = x;
                held = motor(&model, &xv, tj, cfg.period_s, drive(&a, tj));
                if let Some(am) = &act {
                    let f = |ti: f64, s: &[f64; 8]| -> [f64; 8] {
                        let xs = SVector::<f64, 8>::from_row_slice(s);
                        let d = am.f(&xs, &inputs(&x, ti, held));
                        core::array::from_fn(|i| d[i])
                    };
                    let s0 = [x[0], x[1], x[2], x[3], a[0], a[1], a[2], a[3]];
                    let r = rk4(&f, tj, &s0, h);
                    x = Vector4::new(r[0], r[1], r[2], r[3]);
                    a = [r[4], r[5], r[6], r[7]];
                    continue;
                }
                let f = |ti: f64, s: &[f64; 4]| -> [f64; 4] {
                    let xs = Vector4::new(s[0], s[1], s[2], s[3]);
                    let d = model.f(&xs, &inputs(&xs, ti, held));
                    [d[0], d[1], d[2], d[3]]
                };
                let r = rk4(&f, tj, &[x[0], x[1], x[2], x[3]], h);
                x = Vector4::new(r[0], r[1], r[2], r[3]);
            }
        }
        let u = inputs(&x, t, held);
        let m = drive(&a, t);
        let muscles = SVector::<f64, 6>::from_row_slice(&[m[0], m[1], m[2], m[3], u[4], u[5]]);
        let acc = model.accelerations(&x, &muscles);
        let thigh = PlanarSegment {
            angle: x[0],
            rate: x[2],
            accel: acc[0],
            pivot_accel: Vector2::zeros(),
        };
        let knee_accel = thigh.point_accel(p.thigh_length);
        let shank = PlanarSegment {
            angle: x[1],
            rate: x[3],
            accel: acc[1],
            pivot_accel: knee_accel,
        };
        let mut sample = Sample::empty(t);
        let leg_len = p.leg_com / 0.606;
        for (i, (seg, r, which)) in [
            (thigh, 0.5 * p.thigh_length, Segment::Thigh),
            (shank, 0.5 * leg_len, Segment::Shank),
        ]
        .into_iter()
        .enumerate()
        {
            let (rot, w, f) = seg.imu_inputs(r, g);
            let (mut gyr, a) = imus[i].read(&rot, &w, &f, &mut rng);
            gyr += Vector3::new(0.0, 0.0, cfg.gyro_drift);
            sample.imu[which.index()].gyr = Some(gyr);
            sample.imu[which.index()].acc = Some(a);
        }
        let hip = -x[0];
        let knee = x[0] - x[1];
        let enc = encoders.read(&[hip, knee, 0.0], &mut rng);
        sample.encoder[0] = Some(enc[0]);
        sample.encoder[1] = Some(enc[1]);
        // ModelInputs::stim order: [u_ke, u_kf, u_he, u_hf].
        sample.inputs.stim = [Some(u[3]), Some(u[2]), Some(u[1]), Some(u[0])];
        sample.inputs.motor_torque = [Some(u[4]), Some(u[5]), None];
        let mut reference = Reference::default();
        reference.segment[Segment::Trunk.index()] = Some(0.0);
        reference.segment[Segment::Thigh.index()] = Some(x[0]);
        reference.segment[Segment::Shank.index()] = Some(x[1]);
        reference.joint[0] = Some(hip);
        reference.joint[1] = Some(knee);
        Record { sample, reference }
    });
    Ok(FesTrial { records, metadata })
}

/// Metadata keys of the fixed-hip parameters (`param.NAME`).
pub fn fixed_hip_param_metadata(p: &FixedHipParams) -> Vec<(String, String)> {
    let mut m: Vec<(String, String)> = [
        ("thigh_mass", p.thigh_mass),
        ("thigh_length", p.thigh_length),
        ("thigh_com", p.thigh_com),
        ("thigh_inertia", p.thigh_inertia),
        ("leg_mass", p.leg_mass),
        ("leg_com", p.leg_com),
        ("leg_inertia", p.leg_inertia),
        ("g", p.g),
        ("hip_stiffness", p.hip_stiffness),
        ("hip_damping", p.hip_damping),
        ("knee_phi0", p.knee_phi0),
        ("force_velocity", p.force_velocity),
    ]
    .iter()
    .map(|(k, v)| (format!("param.{k}"), v.to_string()))
    .collect();
    for (i, d) in p.knee_d.iter().enumerate() {
        m.push((format!("param.knee_d{}", i + 1), d.to_string()));
    }
    for (name, v) in ["t_hf", "t_he", "t_kf", "t_ke"].iter().zip(p.muscle_peak) {
        m.push((format!("param.{name}"), v.to_string()));
    }
    m
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn swing_tracks_the_desired_path_and_signals_follow_the_motion() {
        let cfg = FixedHipConfig {
            noise: false,
            ..FixedHipConfig::default()
        };
        let tr = simulate_fixed_hip(&cfg).unwrap();
        let mut worst: f64 = 0.0;
        for r in &tr.records {
            let (qd, _, _) = desired(r.sample.t, cfg.period_s);
            worst = worst.max((r.reference.segment[1].unwrap() - qd[0]).abs());
            worst = worst.max((r.reference.segment[2].unwrap() - qd[1]).abs());
        }
        eprintln!("worst tracking error {:.2} deg", worst.to_degrees());
        assert!(worst.to_degrees() < 10.0);
        let r = &tr.records[500];
        let th = r.reference.segment[1].unwrap();
        let w = r.sample.imu[1].gyr.unwrap().z;
        let th_next = tr.records[501].reference.segment[1].unwrap();
        let th_prev = tr.records[499].reference.segment[1].unwrap();
        assert!(((th_next - th_prev) / 0.02 - w).abs() < 0.02, "{th}");
    }
}
