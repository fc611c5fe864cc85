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
//! | [`ring`], [`window`] | Algorithm 3's window (its samples; its identification), the sign rules of SPEC 6 |
//! | [`upright`] | ours (issue 15): the upright-leg axis prior for knees eq 2 does not fit |
//! | [`acc_scale`] | ours (issue 15 item 3): a relative accelerometer scale in eqs 3 and 7 |
//! | [`position_fit`] | Algorithm 2 on eq 3 for one window (with the relative scale: ours) |
//! | [`position_fusion`] | ours (issue 15 item 3): the positions fused over windows by their information |
//! | [`position_outliers`] | ours (2026-12-07): eq 3's outliers (a gyroscope spike) left out of the fit and the accelerometer angle |
//! | [`rest_gravity`] | ours (issue knee31b): no trust in an accelerometer whose norm at rest is off g |
//!
//! Inputs are the *raw* thigh and shank IMU channels (`sample.imu[thigh]`,
//! `sample.imu[shank]`, any sensor orientation and position). Output: the
//! `knee` joint angle (rad, SPEC sign: flexion positive) once the first
//! window has been identified (`None` before, and for a recording that never
//! moves enough to identify the axes), plus diagnostics. Design and
//! measured accuracy: `docs/KNEE_SELFALIGN.md`.

pub mod acc_scale;
pub mod angle;
#[cfg(test)]
mod deferral_tests;
pub mod delay;
mod diag;
#[cfg(test)]
mod flexion_tests;
mod fuser;
pub mod param_ekf;
pub mod params;
pub mod position;
pub mod position_fit;
pub mod position_fusion;
pub mod position_outliers;
pub mod rest_gravity;
pub mod ring;
pub mod sign;
pub mod stamp_clock;
pub mod upright;
pub mod window;

use core::fmt;

use limbfuse_core::estimator::Outputs;
use limbfuse_core::{
    Estimate, Estimator, EstimatorError, ImuSample, Joint, Sample, Segment, TimeStep,
};
use nalgebra::Vector3;

use crate::segment_kf::robust::{
    held_rate_variance, HELD_RATE_CORRELATION_S, HELD_RATE_VARIANCE_CAP,
};
use angle::{accel_angle, gyro_angle_rate, PlaneBasis};
use delay::{saturated, slot, DelayLine};
pub use diag::KneeDiag;
use fuser::Fuser;
pub use params::{AngleZero, Fusion, KneeParamError, KneeSelfAlignParams};
use position_fusion::FusedPositions;
use rest_gravity::RestGravityCheck;
use upright::UprightAxes;
pub use window::Geometry;
use window::{identify, Ring, WindowOutcome};

/// What the last identification window (Algorithm 3) gave.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum WindowStatus {
    /// No window completed yet.
    #[default]
    NoWindowYet,
    /// The last window identified the geometry.
    Identified,
    /// The last window had too few complete, unsaturated samples.
    TooFewSamples,
    /// The last window did not determine the axes (e.g. no motion).
    Unobservable,
    /// Algorithm 2 failed numerically on the last window.
    Failed,
}

impl WindowStatus {
    /// The `window_status` column value: 0 no window yet, 1 identified,
    /// 2 too few samples, 3 unobservable, 4 failed.
    pub const fn code(self) -> f64 {
        match self {
            WindowStatus::NoWindowYet => 0.0,
            WindowStatus::Identified => 1.0,
            WindowStatus::TooFewSamples => 2.0,
            WindowStatus::Unobservable => 3.0,
            WindowStatus::Failed => 4.0,
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
    fused: Option<FusedPositions>,
    bases: Option<[PlaneBasis; 2]>,
    alpha_gyro: f64,
    last_rate: Option<f64>,
    /// How long the gyro knee rate has been missing (s).
    gyro_gap: f64,
    /// The gyro angle at the last knee rate, from which the first rate after
    /// a short gap bridges it (`None` after a reset or new axes).
    alpha_at_rate: Option<f64>,
    /// Shortest time step so far (s): the sampling period.
    period: f64,
    kf: Fuser,
    windows: usize,
    status: WindowStatus,
    usable: usize,
    /// RMS `e_j`, RMS `e_o`, axis source code of the last identified window.
    rms: [f64; 3],
    information: f64,
    spread: f64,
    sign_confidence: f64,
    sign_committed: bool,
    /// The gyro-angle skewness pooled while the sign is open (ours).
    flexion: sign::FlexionEvidence,
    acc_trusted: bool,
    fixed: bool,
    /// The last identified window's eq-3 residual level (ours).
    screen: Option<position_outliers::ResidualScreen>,
    /// Samples the windows' screens left out so far (`diag_position_outliers`).
    position_outliers: usize,
    /// A first window's geometry not taken because the window showed no
    /// flexion axis ([`Self::defers`], ours); `Some` once deferred.
    deferred: Option<Geometry>,
    /// The raw rows and the thigh-shank offset in use ([`delay`], ours).
    delay: DelayLine,
    /// This sample's thigh and shank readings as paired by that offset.
    aligned: [ImuSample; 2],
    /// Whether the accelerometers read g at rest ([`rest_gravity`], ours).
    rest: RestGravityCheck,
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
            fused: None,
            bases: None,
            alpha_gyro: 0.0,
            alpha_at_rate: None,
            last_rate: None,
            gyro_gap: 0.0,
            period: f64::INFINITY,
            kf: Fuser::new(&params),
            windows: 0,
            status: WindowStatus::NoWindowYet,
            usable: 0,
            rms: [0.0; 3],
            information: 0.0,
            spread: 1.0,
            sign_confidence: 0.0,
            sign_committed: false,
            flexion: sign::FlexionEvidence::default(),
            acc_trusted: true,
            fixed: false,
            screen: None,
            position_outliers: 0,
            deferred: None,
            delay: DelayLine::new(params.max_delay, params.window),
            aligned: [ImuSample::default(); 2],
            rest: RestGravityCheck::new(params.acc_rest_tolerance, limbfuse_core::STANDARD_GRAVITY),
        }
    }

    /// The parameters in use.
    pub fn params(&self) -> &KneeSelfAlignParams {
        &self.params
    }

    /// Status of the last window, its usable samples, the RMS residuals
    /// `[e_j, e_o]` and the information of the axes.
    pub fn last_window(&self) -> (WindowStatus, usize, [f64; 2], f64) {
        let [e_j, e_o, _] = self.rms;
        (self.status, self.usable, [e_j, e_o], self.information)
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
            self.alpha_at_rate = None;
            self.last_rate = None;
            self.kf = Fuser::new(&self.params);
        }
        self.geometry = Some(geometry);
        self.bases = Some(bases);
        self.fixed = true;
        self.sign_committed = true;
        Some(())
    }

    /// Whether the accelerometer angle is trusted now (`diag_acc_trusted`).
    pub fn acc_trusted(&self) -> bool {
        self.acc_trusted
    }

    /// The rest check of the accelerometers ([`rest_gravity`]).
    pub fn rest_check(&self) -> &RestGravityCheck {
        &self.rest
    }

    /// Windows completed so far.
    pub fn windows(&self) -> usize {
        self.windows
    }

    /// Sign confidence of the last identified window (`diag_sign_confidence`)
    /// and whether the relative sign is committed.
    pub fn sign_state(&self) -> (f64, bool) {
        (self.sign_confidence, self.sign_committed)
    }

    /// Samples the windows left out of their position fits so far
    /// ([`position_outliers`]).
    pub fn position_outliers(&self) -> usize {
        self.position_outliers
    }

    /// The current joint geometry (`None` until a window was identified).
    pub fn geometry(&self) -> Option<&Geometry> {
        self.geometry.as_ref()
    }

    /// [`Self::geometry`], or else the geometry of a first window that was
    /// not taken because it showed no flexion axis (docs/KNEE_SELFALIGN.md,
    /// "A first window without a flexion axis"):
    /// what a single window (`limbfuse align --joint-axis`) identified.
    pub fn geometry_or_deferred(&self) -> Option<&Geometry> {
        self.geometry.as_ref().or(self.deferred.as_ref())
    }

    fn saturated(&self, g: &Option<Vector3<f64>>) -> bool {
        saturated(g, self.params.gyro_range)
    }

    /// The thigh and shank readings of the last sample stepped, paired by
    /// the offset in use ([`delay`]).
    pub fn aligned(&self) -> [ImuSample; 2] {
        self.aligned
    }

    /// The thigh-shank offset in use (s; positive: the shank lags;
    /// `diag_sensor_delay_s`).
    pub fn sensor_delay_s(&self) -> f64 {
        match self.delay.delay() {
            0 => 0.0,
            d => d as f64 * self.delay.period().unwrap_or(0.0),
        }
    }

    /// Ours (2026-12-05): a *first* window whose hinge does not fit and in which
    /// a segment turns mainly about its long axis (the upright prior's "no
    /// flexion", [`UprightAxes::NoFlexion`]) while the segments turn about
    /// their long axes by more than [`upright::TURN_NET`] in all (a turn on
    /// the spot: a recording that starts turning) shows no flexion axis; its eq-2 axes were taken
    /// anyway, and every later window kept their sides by continuity and eq 4
    /// integrated the turn about them. On the shared S02 walk started 0.8-3.4 s
    /// later (a turn inside the first 3 s window) the knee came out 8-36 deg
    /// offset-free, up to 94 deg off in absolute terms, or negated. Such a
    /// window is now not taken (no angle, `diag_window_status` 3): the next
    /// window is identified as a first window. Only once per run: if that one
    /// shows no flexion either, its eq-2 axes are taken as before (a recording
    /// that never shows one still gets an angle, one window later).
    fn defers(&self, axis_source: f64) -> bool {
        self.geometry.is_none()
            && self.deferred.is_none()
            && axis_source == UprightAxes::NoFlexion.code()
            && upright::net_turn(&self.window) > upright::TURN_NET
    }

    fn end_window(&mut self) {
        self.windows += 1;
        self.usable = (0..self.window.len())
            .filter(|&i| {
                let s = self.window.get(i);
                s.gyr_ok && s.acc_ok
            })
            .count();
        match identify(
            &mut self.window,
            self.geometry.as_ref(),
            self.fused.as_ref(),
            self.sign_committed,
            self.rest.miscalibrated(),
            &self.params,
        ) {
            WindowOutcome::Identified {
                mut geometry,
                rms_axis,
                rms_position,
                information,
                spread,
                sign_confidence,
                acc_trusted,
                axis_source,
                fused,
                screen,
                outliers,
            } => {
                if self.defers(axis_source) {
                    self.deferred = Some(geometry);
                    self.status = WindowStatus::Unobservable;
                    self.information = information;
                    return;
                }
                self.flexion.pool_window(
                    &self.window,
                    self.geometry.as_ref(),
                    &mut geometry,
                    self.sign_committed,
                    acc_trusted,
                    self.params.zero,
                );
                if let Some(bases) = geometry.bases(self.params.zero) {
                    // A new pair of sides (first window, or an uncommitted
                    // sign that changed) changes what eq 4 integrates: the
                    // angle starts afresh.
                    let new_sides = self.geometry.is_none_or(|old| {
                        old.axis[0].dot(&geometry.axis[0]) < 0.0
                            || old.axis[1].dot(&geometry.axis[1]) < 0.0
                    });
                    if new_sides {
                        (self.recent_gyro_angle, self.last_rate) =
                            window::recent_gyro_angles(&self.recent, &geometry);
                        self.alpha_gyro = 0.0;
                        self.alpha_at_rate = None;
                        self.kf = Fuser::new(&self.params);
                    }
                    self.geometry = Some(geometry);
                    self.fused = Some(fused);
                    self.screen = screen;
                    self.position_outliers += outliers;
                    self.bases = Some(bases);
                    self.status = WindowStatus::Identified;
                    self.rms = [rms_axis, rms_position, axis_source];
                    self.information = information;
                    self.spread = spread;
                    self.sign_confidence = sign_confidence;
                    // A still window is no evidence: the first window then
                    // starts untrusted (the high-pass), later ones keep the
                    // previous state.
                    self.acc_trusted = match acc_trusted {
                        Some(v) => v,
                        None => !new_sides && self.acc_trusted,
                    };
                    if acc_trusted == Some(true) && sign_confidence >= self.params.sign_commit {
                        self.sign_committed = true;
                    }
                } else {
                    self.status = WindowStatus::Failed;
                }
            }
            WindowOutcome::TooFewSamples { .. } => self.status = WindowStatus::TooFewSamples,
            WindowOutcome::Unobservable { information } => {
                self.status = WindowStatus::Unobservable;
                self.information = information;
            }
            WindowOutcome::Failed => self.status = WindowStatus::Failed,
        }
    }

    /// The gyro angles (eq 4) of the last five samples stepped, newest last
    /// and 0, with the current geometry, and the newest sample's rate
    /// ([`window::recent_gyro_angles`]; all `None` before a geometry).
    pub fn recent_gyro_angles(&self) -> ([Option<f64>; 5], Option<f64>) {
        match &self.geometry {
            Some(g) => window::recent_gyro_angles(&self.recent, g),
            None => ([None; 5], None),
        }
    }

    /// Accelerometer angle (eqs 5-7) of the sample
    /// [`position::DERIVATIVE_LATENCY`] steps back (the rate derivative needs
    /// two samples after it), with the current geometry.
    pub fn lagged_accel_angle(&self) -> Option<f64> {
        let (g, b) = (self.geometry.as_ref()?, self.bases.as_ref()?);
        let [at, as_] = g.joint_accelerations(&self.recent.kinematics(2)?);
        if position_outliers::rejects(self.screen.as_ref(), &[at, as_]) {
            return None;
        }
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
        &KneeDiag::NAMES
    }

    fn reset(&mut self) {
        self.window.reset();
        self.recent.reset();
        self.time.reset();
        self.counter = 0;
        self.recent_gyro_angle = [None; 5];
        self.geometry = None;
        self.fused = None;
        self.bases = None;
        self.alpha_gyro = 0.0;
        self.alpha_at_rate = None;
        self.last_rate = None;
        self.gyro_gap = 0.0;
        self.period = f64::INFINITY;
        self.kf = Fuser::new(&self.params);
        self.windows = 0;
        self.status = WindowStatus::NoWindowYet;
        self.usable = 0;
        self.rms = [0.0; 3];
        self.information = 0.0;
        self.spread = 1.0;
        self.sign_confidence = 0.0;
        self.sign_committed = false;
        self.flexion = sign::FlexionEvidence::default();
        self.acc_trusted = true;
        self.fixed = false;
        self.screen = None;
        self.position_outliers = 0;
        self.deferred = None;
        self.delay.clear();
        self.rest.reset();
    }

    fn step(&mut self, sample: &Sample) -> Result<Estimate, EstimatorError> {
        let thigh = sample.imu(Segment::Thigh);
        let shank = sample.imu(Segment::Shank);
        finite(&thigh.gyr, "thigh_gyr")?;
        finite(&shank.gyr, "shank_gyr")?;
        finite(&thigh.acc, "thigh_acc")?;
        finite(&shank.acc, "shank_acc")?;
        let dt = self.time.advance(sample.t)?;
        self.aligned = self.align(sample);
        // A sensor that does not read g at rest is not trusted from now on.
        self.rest.step(sample.t, &self.aligned);
        self.acc_trusted &= !self.rest.miscalibrated();
        let [thigh, shank] = &self.aligned;
        let (thigh, shank) = (*thigh, *shank);
        let saturated = self.saturated(&thigh.gyr) || self.saturated(&shank.gyr);
        let slot = slot(sample.t, &self.aligned, self.params.gyro_range);
        self.window.push(slot);
        let dt = dt.map(|d| self.on_stamp_grid(d));
        self.counter += 1;
        if self.counter >= self.params.window && !self.fixed {
            self.counter = 0;
            self.end_window();
        }
        let mut est = Estimate::empty(sample.t);
        let mut alpha_acc = None;
        let mut gap_growth = 0.0;
        if let Some(g) = self.geometry {
            // Eq 4, trapezoidal. A missing gyro sample holds the last rate,
            // decaying towards zero over the dropout (ours, issue 18 item 2,
            // as the segment filters: HELD_RATE_CORRELATION_S).
            let rate = match (thigh.gyr, shank.gyr) {
                (Some(gt), Some(gs)) => Some(gyro_angle_rate(&gt, &gs, &g.axis[0], &g.axis[1])),
                _ => None,
            };
            let gap = self.gyro_gap;
            let held = |t: f64| {
                self.last_rate
                    .map(|r| r * libm::exp(-t / HELD_RATE_CORRELATION_S))
            };
            let step = dt.unwrap_or(0.0);
            let r1 = rate.or(held(gap + step));
            let r0 = held(gap).or(r1);
            if let (Some(dt), Some(r0), Some(r1)) = (dt, r0, r1) {
                self.alpha_gyro = match (rate, self.last_rate, self.alpha_at_rate) {
                    // The first rate after a short gap: one trapezoid from
                    // the last rate across the gap replaces the held rate's
                    // extrapolation (empty cells, 2026-12-06).
                    (Some(r), Some(last), Some(a))
                        if gap > 0.0 && gap + dt <= sign::GAP_SPLIT_S =>
                    {
                        a + 0.5 * (last + r) * (gap + dt)
                    }
                    _ => self.alpha_gyro + 0.5 * (r0 + r1) * dt,
                };
            }
            // A time gap (rows missing: `sign::GAP_SPLIT_S` and
            // `GAP_SPLIT_PERIODS` periods) is a dropout of its length too
            // (an audit: 0.5 s of rows removed, 30 deg for 0.7 s after it).
            let time_gap = step > sign::GAP_SPLIT_S && step > sign::GAP_SPLIT_PERIODS * self.period;
            if time_gap {
                gap_growth = held_rate_variance(step);
            } else if step > 0.0 {
                self.period = self.period.min(step);
            }
            if rate.is_some() {
                self.last_rate = rate;
                self.gyro_gap = 0.0;
                self.alpha_at_rate = Some(self.alpha_gyro);
            } else {
                self.gyro_gap += step;
                gap_growth = held_rate_variance(self.gyro_gap) - held_rate_variance(gap);
            }
        }
        self.recent.push(slot);
        self.recent_gyro_angle.rotate_left(1);
        self.recent_gyro_angle[4] = self.geometry.map(|_| self.alpha_gyro);
        if self.geometry.is_some() {
            self.kf.predict(dt.unwrap_or(0.0));
            // The held rate's angle error: the accelerometer angle takes over
            // after a gap (docs/ROBUST_INPUT.md).
            self.kf.inflate(gap_growth, HELD_RATE_VARIANCE_CAP);
            alpha_acc = self.lagged_accel_angle();
            if !self.acc_trusted {
                let dt = dt.unwrap_or(0.0);
                let k = 1.0 - libm::exp(-core::f64::consts::TAU * self.params.highpass_hz * dt);
                self.kf.leak(self.alpha_gyro, k);
            } else if let (Some(a), Some(gyro)) = (alpha_acc, self.recent_gyro_angle[2]) {
                self.kf.update(a - gyro);
            }
            // An angle: reported in (-pi, pi] (the gyro integral itself is
            // not wrapped, so eq 4 stays continuous).
            est.joint[Joint::Knee.index()] = Some(angle::wrap(self.alpha_gyro + self.kf.state().0));
        }
        self.write_diagnostics(&mut est, saturated, alpha_acc);
        Ok(est)
    }
}
