//! Self-aligning knee angle from a thigh IMU and a shank IMU mounted
//! anyhow (paper 002, Pereira & Nogueira, after Seel et al. 2014): the
//! joint axis `j` and the sensor positions `o` are identified online, window
//! by window, by a constrained EKF (Algorithm 2), and the knee angle is the
//! complementary-KF fusion (Algorithm 1) of a gyro angle (eq 4) and an
//! accelerometer angle (eqs 5-7). Method name `knee-selfalign`.
//!
//! | module | paper 002 |
//! |---|---|
//! | [`crate::hinge_axis`] | eq 1 (spherical axes), eq 2 (`e_j`), eqs 10-11 (Jacobian), shared with `limbfuse align` |
//! | [`position`] | `Gamma`, eq 3 (`e_o`, a difference: SPEC 6), eqs 12-13, o-correction, rate derivative |
//! | [`param_ekf`] | Algorithm 2 (information form: linear in the window length) |
//! | [`angle`] | eq 4, eqs 5-7 (signed `atan2`: SPEC 6), Algorithm 1 |
//! | [`window`] | Algorithm 3's window, the sign rules of SPEC 6 |
//!
//! Inputs are the *raw* thigh and shank IMU channels (`sample.imu[thigh]`,
//! `sample.imu[shank]`, any sensor orientation and position). Output: the
//! `knee` joint angle (rad, SPEC sign: flexion positive) once the first
//! window has been identified (`None` before, and for a recording that never
//! moves enough to identify the axes), plus diagnostics. Design and
//! measured accuracy: `docs/KNEE_SELFALIGN.md`.

pub mod angle;
pub mod param_ekf;
pub mod params;
pub mod position;
pub mod window;

use core::fmt;

use limbfuse_core::estimator::Outputs;
use limbfuse_core::{Estimate, Estimator, EstimatorError, Joint, Sample, Segment, TimeStep};
use nalgebra::Vector3;

use angle::{accel_angle, gyro_angle_rate, ComplementaryKf, PlaneBasis, RateBiasKf};
pub use params::{AngleZero, Fusion, KneeParamError, KneeSelfAlignParams};
pub use window::Geometry;
use window::{identify, Ring, Slot, WindowOutcome};

/// Diagnostic names of [`KneeSelfAlign`], in `Estimate::diag` order.
pub const KNEE_DIAG: [&str; 28] = [
    "identified",
    "window_status",
    "unobservable",
    "windows",
    "window_usable",
    "saturated",
    "alpha_gyro",
    "alpha_acc",
    "kf_x",
    "kf_p",
    "j_thigh_x",
    "j_thigh_y",
    "j_thigh_z",
    "j_shank_x",
    "j_shank_y",
    "j_shank_z",
    "o_thigh_x",
    "o_thigh_y",
    "o_thigh_z",
    "o_shank_x",
    "o_shank_y",
    "o_shank_z",
    "rms_e_j",
    "rms_e_o",
    "information",
    "alpha_acc_lag",
    "kf_rate_bias",
    "acc_gyro_spread",
];

/// `window_status` values.
pub mod status {
    /// No window completed yet.
    pub const NONE: f64 = 0.0;
    /// The last window identified the geometry.
    pub const IDENTIFIED: f64 = 1.0;
    /// The last window had too few complete, unsaturated samples.
    pub const TOO_FEW_SAMPLES: f64 = 2.0;
    /// The last window did not determine the axes (e.g. no motion).
    pub const UNOBSERVABLE: f64 = 3.0;
    /// Algorithm 2 failed numerically on the last window.
    pub const FAILED: f64 = 4.0;
}

/// The angle-fusion filter in use.
#[derive(Debug, Clone, Copy, PartialEq)]
enum Fuser {
    Paper(ComplementaryKf),
    RateBias(RateBiasKf),
}

impl Fuser {
    fn new(p: &KneeSelfAlignParams) -> Self {
        match p.fusion {
            Fusion::Paper => Fuser::Paper(ComplementaryKf::new(p.kf_q, p.kf_r)),
            Fusion::RateBias { q_bias, p_bias0 } => {
                Fuser::RateBias(RateBiasKf::new(p.kf_q, q_bias, p.kf_r, p_bias0))
            }
        }
    }
    fn predict(&mut self, dt: f64) {
        match self {
            Fuser::Paper(k) => k.predict(),
            Fuser::RateBias(k) => k.predict(dt),
        }
    }
    fn update(&mut self, z: f64) {
        match self {
            Fuser::Paper(k) => k.update(z),
            Fuser::RateBias(k) => k.update(z),
        }
    }
    /// Correction added to the gyro angle, its variance, the rate bias.
    fn state(&self) -> (f64, f64, Option<f64>) {
        match self {
            Fuser::Paper(k) => (k.x, k.p, None),
            Fuser::RateBias(k) => (k.x[0], k.p[0][0], Some(k.x[1])),
        }
    }
}

/// The self-aligning knee estimator (paper 002, Algorithm 3 online).
#[derive(Debug, Clone)]
pub struct KneeSelfAlign {
    params: KneeSelfAlignParams,
    time: TimeStep,
    window: Ring,
    counter: usize,
    recent: Ring,
    recent_gyro_angle: [Option<f64>; 5],
    geometry: Option<Geometry>,
    bases: Option<[PlaneBasis; 2]>,
    alpha_gyro: f64,
    last_rate: Option<f64>,
    kf: Fuser,
    windows: usize,
    status: f64,
    usable: usize,
    rms: [f64; 2],
    information: f64,
    spread: f64,
    fixed: bool,
}

impl Default for KneeSelfAlign {
    fn default() -> Self {
        Self::build(KneeSelfAlignParams::default())
    }
}

fn finite(v: &Option<Vector3<f64>>, channel: &'static str) -> Result<(), EstimatorError> {
    match v {
        Some(x) if !x.iter().all(|c| c.is_finite()) => Err(EstimatorError::NonFinite { channel }),
        _ => Ok(()),
    }
}

impl KneeSelfAlign {
    /// A validated estimator; allocates its window once, here.
    pub fn new(params: KneeSelfAlignParams) -> Result<Self, KneeParamError> {
        params.validate()?;
        Ok(Self::build(params))
    }

    fn build(params: KneeSelfAlignParams) -> Self {
        KneeSelfAlign {
            params,
            time: TimeStep::new(),
            window: Ring::new(params.window),
            counter: 0,
            recent: Ring::new(5),
            recent_gyro_angle: [None; 5],
            geometry: None,
            bases: None,
            alpha_gyro: 0.0,
            last_rate: None,
            kf: Fuser::new(&params),
            windows: 0,
            status: status::NONE,
            usable: 0,
            rms: [0.0; 2],
            information: 0.0,
            spread: 1.0,
            fixed: false,
        }
    }

    /// The parameters in use.
    pub fn params(&self) -> &KneeSelfAlignParams {
        &self.params
    }

    /// Status of the last window (see [`status`]), its usable samples, the
    /// RMS residuals `[e_j, e_o]` and the information of the axes.
    pub fn last_window(&self) -> (f64, usize, [f64; 2], f64) {
        (self.status, self.usable, self.rms, self.information)
    }

    /// Uses `geometry` from now on and stops identifying windows, until
    /// [`Estimator::reset`] (for a
    /// geometry known from elsewhere, e.g. `limbfuse align --joint-axis`, and
    /// for checking the angle fusion alone). `None` when the geometry gives no
    /// joint-plane basis (an axis along its reference direction).
    pub fn fix_geometry(&mut self, geometry: Geometry) -> Option<()> {
        let bases = geometry.bases(self.params.zero)?;
        if self.geometry.is_none() {
            self.alpha_gyro = 0.0;
            self.last_rate = None;
            self.kf = Fuser::new(&self.params);
        }
        self.geometry = Some(geometry);
        self.bases = Some(bases);
        self.fixed = true;
        Some(())
    }

    /// The current joint geometry (`None` until a window was identified).
    pub fn geometry(&self) -> Option<&Geometry> {
        self.geometry.as_ref()
    }

    fn saturated(&self, g: &Option<Vector3<f64>>) -> bool {
        let limit = 0.999 * self.params.gyro_range;
        g.is_some_and(|g| g.iter().any(|c| c.abs() >= limit))
    }

    fn end_window(&mut self) {
        self.windows += 1;
        self.usable = (0..self.window.len())
            .filter(|&i| {
                let s = self.window.get(i);
                s.gyr_ok && s.acc_ok
            })
            .count();
        match identify(&self.window, self.geometry.as_ref(), &self.params) {
            WindowOutcome::Identified {
                geometry,
                rms_axis,
                rms_position,
                information,
                spread,
            } => {
                if let Some(bases) = geometry.bases(self.params.zero) {
                    if self.geometry.is_none() {
                        self.alpha_gyro = 0.0;
                        self.last_rate = None;
                        self.kf = Fuser::new(&self.params);
                        self.recent_gyro_angle = [None; 5];
                    }
                    self.geometry = Some(geometry);
                    self.bases = Some(bases);
                    self.status = status::IDENTIFIED;
                    self.rms = [rms_axis, rms_position];
                    self.information = information;
                    self.spread = spread;
                } else {
                    self.status = status::FAILED;
                }
            }
            WindowOutcome::TooFewSamples { .. } => self.status = status::TOO_FEW_SAMPLES,
            WindowOutcome::Unobservable { information } => {
                self.status = status::UNOBSERVABLE;
                self.information = information;
            }
            WindowOutcome::Failed => self.status = status::FAILED,
        }
    }

    /// Accelerometer angle of the sample two steps back (the rate derivative
    /// needs two samples after it).
    fn lagged_accel_angle(&self) -> Option<f64> {
        let (g, b) = (self.geometry.as_ref()?, self.bases.as_ref()?);
        let [kt, ks] = self.recent.kinematics(2)?;
        let at = kt.joint_acceleration(&g.position[0]);
        let as_ = ks.joint_acceleration(&g.position[1]);
        accel_angle(&at, &as_, &b[0], &b[1])
    }
}

impl Estimator for KneeSelfAlign {
    fn name(&self) -> &'static str {
        "knee-selfalign"
    }

    fn outputs(&self) -> Outputs {
        Outputs {
            joint: [false, true, false],
            ..Outputs::default()
        }
    }

    fn describe_parameters(&self, out: &mut dyn fmt::Write) -> fmt::Result {
        writeln!(out, "inputs: raw thigh and shank IMUs (any mounting)")?;
        self.params.describe(out)
    }

    fn diagnostic_names(&self) -> &[&'static str] {
        &KNEE_DIAG
    }

    fn reset(&mut self) {
        self.window.clear();
        self.recent.clear();
        self.time.reset();
        self.counter = 0;
        self.recent_gyro_angle = [None; 5];
        self.geometry = None;
        self.bases = None;
        self.alpha_gyro = 0.0;
        self.last_rate = None;
        self.kf = Fuser::new(&self.params);
        self.windows = 0;
        self.status = status::NONE;
        self.usable = 0;
        self.rms = [0.0; 2];
        self.information = 0.0;
        self.spread = 1.0;
        self.fixed = false;
    }

    fn step(&mut self, sample: &Sample) -> Result<Estimate, EstimatorError> {
        let thigh = sample.imu(Segment::Thigh);
        let shank = sample.imu(Segment::Shank);
        finite(&thigh.gyr, "thigh_gyr")?;
        finite(&shank.gyr, "shank_gyr")?;
        finite(&thigh.acc, "thigh_acc")?;
        finite(&shank.acc, "shank_acc")?;
        let dt = self.time.advance(sample.t)?;
        let saturated = self.saturated(&thigh.gyr) || self.saturated(&shank.gyr);
        let slot = Slot {
            t: sample.t,
            gyr: [thigh.gyr.unwrap_or_default(), shank.gyr.unwrap_or_default()],
            acc: [thigh.acc.unwrap_or_default(), shank.acc.unwrap_or_default()],
            gyr_ok: thigh.gyr.is_some() && shank.gyr.is_some() && !saturated,
            acc_ok: thigh.acc.is_some() && shank.acc.is_some(),
        };
        self.window.push(slot);
        self.counter += 1;
        if self.counter >= self.params.window && !self.fixed {
            self.counter = 0;
            self.end_window();
        }
        let mut est = Estimate::empty(sample.t);
        let mut alpha_acc = None;
        if let Some(g) = self.geometry {
            // Eq 4, trapezoidal; a missing gyro sample holds the last rate.
            let rate = match (thigh.gyr, shank.gyr) {
                (Some(gt), Some(gs)) => Some(gyro_angle_rate(&gt, &gs, &g.axis[0], &g.axis[1])),
                _ => None,
            };
            let r1 = rate.or(self.last_rate);
            let r0 = self.last_rate.or(r1);
            if let (Some(dt), Some(r0), Some(r1)) = (dt, r0, r1) {
                self.alpha_gyro += 0.5 * (r0 + r1) * dt;
            }
            if rate.is_some() {
                self.last_rate = rate;
            }
        }
        self.recent.push(slot);
        self.recent_gyro_angle.rotate_left(1);
        self.recent_gyro_angle[4] = self.geometry.map(|_| self.alpha_gyro);
        if self.geometry.is_some() {
            self.kf.predict(dt.unwrap_or(0.0));
            alpha_acc = self.lagged_accel_angle();
            if let (Some(a), Some(gyro)) = (alpha_acc, self.recent_gyro_angle[2]) {
                self.kf.update(a - gyro);
            }
            // An angle: reported in (-pi, pi] (the gyro integral itself is
            // not wrapped, so eq 4 stays continuous).
            est.joint[Joint::Knee.index()] = Some(angle::wrap(self.alpha_gyro + self.kf.state().0));
        }
        let d = &mut est.diag;
        d[0] = Some(if self.geometry.is_some() { 1.0 } else { 0.0 });
        d[1] = Some(self.status);
        d[2] = Some(if self.status == status::UNOBSERVABLE {
            1.0
        } else {
            0.0
        });
        d[3] = Some(self.windows as f64);
        d[4] = Some(self.usable as f64);
        d[5] = Some(if saturated { 1.0 } else { 0.0 });
        if let Some(g) = &self.geometry {
            d[6] = Some(self.alpha_gyro);
            d[7] = alpha_acc;
            let (x, p, bias) = self.kf.state();
            d[8] = Some(x);
            d[9] = Some(p);
            d[26] = bias;
            for k in 0..3 {
                d[10 + k] = Some(g.axis[0][k]);
                d[13 + k] = Some(g.axis[1][k]);
                d[16 + k] = Some(g.position[0][k]);
                d[19 + k] = Some(g.position[1][k]);
            }
            d[22] = Some(self.rms[0]);
            d[23] = Some(self.rms[1]);
            d[27] = Some(self.spread);
        }
        d[24] = Some(self.information);
        d[25] = Some(position::DERIVATIVE_LATENCY as f64);
        Ok(est)
    }
}
