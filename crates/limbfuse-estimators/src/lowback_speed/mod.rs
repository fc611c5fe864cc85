//! Walking speed and initial contacts from one lower-back (trunk) IMU in a
//! raw sensor frame (`--method lowback-speed`, docs/GAIT_EVENTS.md).
//!
//! 1. **Vertical acceleration.** Gravity in the sensor frame is the running
//!    mean of the specific force (exponential, time constant
//!    `gravity_time_constant` = 2 s: four steps or more, so the step
//!    oscillation averages out), carried along by the trunk gyroscope: before
//!    each update the mean is rotated by the sample's rotation `-w dt`, so it
//!    is a mean in a frame that does not turn with the trunk
//!    (`gravity_follows_gyro`, issue 19). Without the rotation the mean lags
//!    a posture change by its time constant: after standing up the HA001
//!    course's sensor tilts by 12 deg and the plain mean is 5-9 deg off for
//!    the first strides, which leaks forward acceleration into `a_v` (step
//!    mean `a_v` +0.3 to +0.6 m/s^2 where it is about 0) and shrinks the
//!    first strides' excursion. `a_v = a . g_hat - ||mean||` (the mean's
//!    norm, not 9.81: absorbs an accelerometer scale error). Without a
//!    trunk gyroscope the mean is not rotated.
//! 2. **Initial contacts** (McCamley et al. 2012, Gait & Posture 36(2)): the
//!    minima of the Gaussian-wavelet (`gaus1`) CWT of the integrated
//!    vertical acceleration. Integrating by parts, that CWT at scale `s` is
//!    `-s` times `a_v` smoothed by the Gaussian `exp(-(tau/s)^2)`, so the
//!    contacts are the positive maxima of `a_v` smoothed by a Gaussian of
//!    standard deviation `s / sqrt(2)`. `s` = 0.16 s: McCamley's 1.25 Hz
//!    pseudo-frequency for `gaus1`, whose centre frequency is 0.2 (MATLAB
//!    `centfrq('gaus1')`, PyWavelets `central_frequency('gaus1')`), so
//!    `s = 0.2 / 1.25 Hz` (scikit-digital-health's reading of McCamley
//!    too). Until issue 19's `gait2` work the default was 0.225 s, the 9
//!    samples at 40 Hz of Paraschiv-Ionescu et al. 2020's `gaus2` variant,
//!    i.e. that wavelet's scale applied to `gaus1`. The smoothing is an FIR
//!    truncated at 3 standard deviations, so contacts are decided with a
//!    fixed latency of `3 s / sqrt(2)` = 0.34 s. Maxima closer than
//!    `min_step_time` keep the larger; a maximum counts only while walking
//!    (RMS of `a_v` over the last 2 s above `walking_rms`).
//! 3. **Step length** (Zijlstra & Hof 2003, Gait & Posture 18(2), eq. 1, the
//!    inverted pendulum): `SL = K 2 sqrt(2 l h - h^2)` with `h` the vertical
//!    excursion of the trunk over the step (initial contact to initial
//!    contact): `a_v` integrated twice over the step, the velocity made
//!    zero-mean and the position detrended linearly (a periodic step ends
//!    where it starts), `h = max - min`. `l` is the leg length (parameter,
//!    default 0.9275 m: [`LEG_LENGTH_PER_HEIGHT`] x the default body height
//!    of every limbfuse method, `limbfuse_models::DEFAULT_BODY_HEIGHT_M` =
//!    1.75 m, i.e. the greater-trochanter height fraction 0.530 of Winter
//!    2009 Table 4.1; until 2026-12-05 0.90 m = 0.530 x 1.70 m, the only
//!    default of limbfuse assuming another body), `K` = 1.25 Zijlstra &
//!    Hof's correction factor for the under-estimate of the pendulum model.
//!    With the lower-back sensor's height as `l` (the Mobilise-D reading,
//!    trial metadata `# sensor_height_m:`), `K` is
//!    [`SENSOR_HEIGHT_CORRECTION`], the factor fitted with that length.
//! 4. **Speed**: a stride = two consecutive valid steps (0.25-1.5 s each);
//!    its speed = `(SL_1 + SL_2) / (IC_3 - IC_1)`; `speed` holds the last one.
//! 5. **Turns** (ours, beyond Zijlstra & Hof, whose model is for straight
//!    walking): the heading rate is the gyroscope's component along the
//!    gravity direction of step 1, `w_v = w . g_hat`; a stride whose mean
//!    heading rate `|psi(IC_3) - psi(IC_1)| / (IC_3 - IC_1)` exceeds
//!    `turn_rate` (15 deg/s: the turn-peak threshold of El-Gohary et al.
//!    2014, Sensors 14(1), as in mobgap's `TdElGohary`) is a turning stride:
//!    the pendulum step length does not hold there (pivot steps keep the
//!    trunk's vertical excursion but move the feet little), so its speed is
//!    unknown (no `speed`, no stride length; `stride_turn_rate` says why).
//!    The stride after a turning stride has no speed either
//!    (`withhold_after_turn`, issue 19): its first step is the turning
//!    stride's second, so the stride turns for part of its duration while its
//!    own mean heading rate may stay below `turn_rate` (measured on the
//!    HA001 course: +0.16 to +0.31 m/s on such strides). Decided when the
//!    stride ends, like the turn itself (causal); the stride *before* a turn
//!    would need the next step and is kept. Without a trunk gyroscope no turn
//!    is detected.
//! 6. **Sides** (ours, issue 19): each contact's foot from the sign of the
//!    trunk's band-passed rate about the vertical at it (McCamley et al.
//!    2012, Ullrich et al. 2021), decided 2 s later: [`sides`].
//!
//! Memory: rings of the last [`HISTORY`] vertical accelerations and
//! headings, allocated at construction; nothing is allocated per sample.

use core::fmt;

use alloc::vec;
use alloc::vec::Vec;
use limbfuse_core::estimator::Outputs;
use limbfuse_core::{
    diagnostic_set, Estimate, Estimator, EstimatorError, Sample, Segment, TimeStep,
};
use limbfuse_models::DEFAULT_BODY_HEIGHT_M;

use crate::stamp_grid::StampGrid;
use nalgebra::{Rotation3, Vector3};

use crate::cell_hold::CellHold;
use sampling_period::SamplingPeriod;
use sides::PendingContacts;

pub mod sampling_period;
pub mod sides;
mod steps;

/// Leg (greater-trochanter) height as a fraction of body height: 0.530
/// (Winter 2009, *Biomechanics and Motor Control of Human Movement*, 4th
/// ed., Table 4.1 / fig. 4.1), the pendulum length when only the body
/// height is known.
pub const LEG_LENGTH_PER_HEIGHT: f64 = 0.530;

/// The pendulum length (m) when a trial states no length and no height:
/// [`LEG_LENGTH_PER_HEIGHT`] x `limbfuse_models::DEFAULT_BODY_HEIGHT_M`
/// (1.75 m, the body every limbfuse default assumes), 0.9275 m. Chosen for
/// that consistency, not fitted to any recording.
pub const DEFAULT_LEG_LENGTH_M: f64 = LEG_LENGTH_PER_HEIGHT * DEFAULT_BODY_HEIGHT_M;

/// Zijlstra & Hof's model scaled for the *sensor height* as the pendulum
/// length: the Mobilise-D stride-length algorithm (Soltani et al. 2021, IEEE
/// TNSRE 29:1955-1964; mobgap `SlZijlstra`, `step_length_scaling_factor_ms_ms`
/// = 4.587 / 4, its default) takes `l` = the height of the lower-back sensor
/// above the ground (`LBh`) and this factor, fitted with that `l`. Used when
/// the trial gives `# sensor_height_m:`; with a leg (trochanter) length the
/// factor is Zijlstra & Hof's 1.25, fitted with theirs.
pub const SENSOR_HEIGHT_CORRECTION: f64 = 4.587 / 4.0;

/// Samples of vertical acceleration kept (steps + smoothing latency): 4096,
/// enough for 1.5 s steps plus the latency up to 1 kHz.
pub const HISTORY: usize = 4096;

/// Time constant (s) of the walking test's mean square of `a_v`: the
/// exponential mean compared with [`LowbackParams::walking_rms`] (also the
/// one `limbfuse_eval::gait_watch` reports when no gait was found).
pub const WALKING_RMS_TIME_CONSTANT_S: f64 = 2.0;

diagnostic_set! {
    /// Diagnostics of [`LowbackSpeed`].
    pub enum LowbackDiag {
        /// Time (s) of an initial contact (either foot) decided at this sample.
        Ic = "ic",
        /// Step length (m) of the step finished at this sample.
        StepLength = "step_length",
        /// Stride length (m): the last two steps.
        StrideLength = "stride_length",
        /// Stride time (s): initial contact to the second next.
        StrideTime = "stride_time",
        /// Vertical excursion `h` (m) of the step.
        Excursion = "excursion",
        /// Vertical acceleration `a_v` (m/s^2).
        VerticalAcc = "vertical_acc",
        /// Mean heading rate (rad/s, signed) over the stride finished at
        /// this sample, turning or not.
        StrideTurnRate = "stride_turn_rate",
        /// Why the stride finished at this sample has no speed: 1 = it
        /// turns (`turn_rate`), 2 = the stride before it turned
        /// (`withhold_after_turn`).
        StrideWithheld = "stride_withheld",
        /// Time (s) of an initial contact of the right foot, its side
        /// decided at this sample ([`sides`]: 2 s after the contact).
        IcRight = "ic_right",
        /// Time (s) of an initial contact of the left foot, its side
        /// decided at this sample.
        IcLeft = "ic_left",
    }
}

/// Parameters (sources in the module documentation).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct LowbackParams {
    /// Pendulum (leg) length `l` (m); default [`DEFAULT_LEG_LENGTH_M`].
    pub leg_length: f64,
    /// Zijlstra & Hof's correction factor `K`.
    pub correction: f64,
    /// McCamley's wavelet scale `s` (s).
    pub wavelet_scale: f64,
    /// Gravity-direction time constant (s).
    pub gravity_time_constant: f64,
    /// Shortest step (s).
    pub min_step_time: f64,
    /// Longest step (s).
    pub max_step_time: f64,
    /// RMS vertical acceleration (m/s^2) over 2 s above which the subject walks: 0.3
    /// (walking: 1-3 m/s^2, Moe-Nilssen 1998; quiet standing: below 0.1).
    pub walking_rms: f64,
    /// How long (s) a stride's speed stays the `speed` output.
    pub speed_hold: f64,
    /// Mean heading rate (rad/s) above which a stride is a turn (speed
    /// unknown): 15 deg/s (El-Gohary et al. 2014).
    pub turn_rate: f64,
    /// The stride after a turning stride has no speed either.
    pub withhold_after_turn: bool,
    /// The gravity mean is rotated with the trunk gyroscope.
    pub gravity_follows_gyro: bool,
    /// Band-passed rate about the vertical (rad/s) at or below which a
    /// contact's side is unknown: 3 deg/s ([`sides`]).
    pub side_min_rate: f64,
}

impl Default for LowbackParams {
    fn default() -> Self {
        LowbackParams {
            leg_length: DEFAULT_LEG_LENGTH_M,
            correction: 1.25,
            wavelet_scale: 0.16,
            gravity_time_constant: 2.0,
            min_step_time: 0.25,
            max_step_time: 1.5,
            walking_rms: 0.3,
            speed_hold: 3.0,
            turn_rate: 15.0_f64.to_radians(),
            withhold_after_turn: true,
            gravity_follows_gyro: true,
            side_min_rate: 3.0_f64.to_radians(),
        }
    }
}

/// Zijlstra & Hof 2003 eq. 1 (with the correction factor): step length
/// from the vertical excursion `h` and the pendulum length `l`.
pub fn pendulum_step_length(h: f64, l: f64, k: f64) -> f64 {
    k * 2.0 * libm::sqrt((2.0 * l * h - h * h).max(0.0))
}

/// The vertical excursion of one step from its vertical accelerations
/// (uniform step `dt`): acceleration zero-mean over the step (periodic
/// gait; since 2026-12-04), velocity zero-mean, position linearly
/// detrended.
pub fn step_excursion(a_v: impl Iterator<Item = f64> + Clone, dt: f64) -> f64 {
    let n = a_v.clone().count();
    if n < 3 {
        return 0.0;
    }
    // Over a step of periodic gait the vertical velocity comes back to its
    // start: the step's mean vertical acceleration is zero. What is not
    // (a gravity estimate still settling, a posture change) is removed.
    let a_mean = a_v.clone().sum::<f64>() / n as f64;
    let a_v = a_v.map(move |a| a - a_mean);
    let mut v = 0.0;
    let mut v_sum = 0.0;
    for a in a_v.clone() {
        v += a * dt;
        v_sum += v;
    }
    let v_mean = v_sum / n as f64;
    // First pass: the position's end value (for the linear detrend).
    let (mut v, mut p) = (0.0, 0.0);
    for a in a_v.clone() {
        v += a * dt;
        p += (v - v_mean) * dt;
    }
    let p_end = p;
    let (mut v, mut p) = (0.0, 0.0);
    let (mut lo, mut hi) = (f64::INFINITY, f64::NEG_INFINITY);
    for (k, a) in a_v.enumerate() {
        v += a * dt;
        p += (v - v_mean) * dt;
        let q = p - p_end * (k + 1) as f64 / n as f64;
        lo = lo.min(q);
        hi = hi.max(q);
    }
    hi - lo
}

/// The lower-back speed estimator.
#[derive(Debug, Clone)]
pub struct LowbackSpeed {
    params: LowbackParams,
    time: TimeStep,
    gravity: Option<Vector3<f64>>,
    history: Vec<f64>,
    heading: Vec<f64>,
    psi: f64,
    kernel: Vec<f64>,
    half: usize,
    /// The side filter's taps and half length ([`sides`]).
    side_taps: Vec<f64>,
    side_half: usize,
    /// Contacts waiting for their side.
    pending_sides: PendingContacts,
    dt: Option<f64>,
    /// The sampling period from the time steps so far that are not gaps
    /// (over `min_step_time`), lost rows counted.
    period: SamplingPeriod,
    /// The sensor's sampling grid from the stamps of the readings: its
    /// period replaces `period` once known when the stamps are not evenly
    /// spaced ([`crate::stamp_grid`]; 2026-12-07).
    grid: StampGrid,
    elapsed: f64,
    n: u64,
    rms_sq: f64,
    smoothed: [f64; 3],
    last_ic: Option<(u64, f64, f64)>,
    last_step: Option<(f64, f64, u64)>,
    last_stride_turned: bool,
    speed: Option<(f64, f64)>,
    last_reading: Option<f64>,
    /// The last reading's time, vertical acceleration and heading (for
    /// filling the samples a short gap left out).
    last_vertical: Option<(f64, f64, f64)>,
    cells: CellHold,
}

/// Steps after which the smoothing kernel is set again from the mean
/// period (the first step alone may be off by a time stamp's jitter).
const PERIOD_STEPS: u64 = 64;

impl LowbackSpeed {
    /// A new estimator.
    pub fn new(params: LowbackParams) -> Self {
        LowbackSpeed {
            params,
            time: TimeStep::new(),
            gravity: None,
            history: vec![0.0; HISTORY],
            heading: vec![0.0; HISTORY],
            psi: 0.0,
            kernel: Vec::with_capacity(HISTORY),
            half: 0,
            side_taps: Vec::with_capacity(HISTORY),
            side_half: 0,
            pending_sides: PendingContacts::default(),
            dt: None,
            period: SamplingPeriod::default(),
            grid: StampGrid::default(),
            elapsed: 0.0,
            n: 0,
            rms_sq: 0.0,
            smoothed: [0.0; 3],
            last_ic: None,
            last_step: None,
            last_stride_turned: false,
            speed: None,
            last_reading: None,
            last_vertical: None,
            cells: CellHold::default(),
        }
    }

    fn set_kernel(&mut self, dt: f64) {
        let sigma = self.params.wavelet_scale / core::f64::consts::SQRT_2;
        let half = (libm::ceil(3.0 * sigma / dt) as usize).clamp(1, HISTORY / 4);
        self.kernel.clear();
        let mut sum = 0.0;
        for j in 0..=2 * half {
            let x = (j as f64 - half as f64) * dt / sigma;
            let w = libm::exp(-0.5 * x * x);
            self.kernel.push(w);
            sum += w;
        }
        for w in &mut self.kernel {
            *w /= sum;
        }
        self.half = half;
        // The side window and the sample before it stay in the rings.
        self.side_half = sides::side_filter_taps(dt, HISTORY / 2 - 2, &mut self.side_taps);
    }

    /// After a gap in the readings (rows or accelerometer cells missing)
    /// longer than `min_step_time`, which may hide an initial contact, the
    /// step detection starts again from the next samples: the smoothing, the
    /// step excursion and the stride would otherwise join samples from both
    /// sides of the gap as if they were consecutive. Gravity, heading, the
    /// walking RMS and the held speed are kept; nothing is allocated.
    fn restart_steps(&mut self) {
        self.n = 0;
        self.smoothed = [0.0; 3];
        self.last_ic = None;
        self.last_step = None;
        self.last_stride_turned = false;
        self.last_vertical = None;
        self.pending_sides.clear();
    }

    fn at(&self, index: u64) -> f64 {
        self.history[(index % HISTORY as u64) as usize]
    }

    fn heading_at(&self, index: u64) -> f64 {
        self.heading[(index % HISTORY as u64) as usize]
    }
}

impl Estimator for LowbackSpeed {
    fn name(&self) -> &'static str {
        "lowback-speed"
    }

    /// Clipped trunk accelerometer readings are kept: each step's vertical
    /// velocity is integrated from them (a clipped impact loses part of its
    /// velocity change, a missing reading all of it).
    fn keeps_clipped_acc(&self) -> bool {
        true
    }

    fn outputs(&self) -> Outputs {
        Outputs {
            speed: true,
            ..Outputs::default()
        }
    }

    fn describe_parameters(&self, out: &mut dyn fmt::Write) -> fmt::Result {
        let p = &self.params;
        writeln!(out, "leg_length: {} m", p.leg_length)?;
        writeln!(out, "correction: {}", p.correction)?;
        writeln!(out, "wavelet_scale: {} s", p.wavelet_scale)?;
        writeln!(out, "gravity_time_constant: {} s", p.gravity_time_constant)?;
        writeln!(
            out,
            "step_time: {} - {} s",
            p.min_step_time, p.max_step_time
        )?;
        writeln!(out, "walking_rms: {} m/s^2", p.walking_rms)?;
        writeln!(out, "speed_hold: {} s", p.speed_hold)?;
        writeln!(out, "turn_rate: {:.6} deg/s", p.turn_rate.to_degrees())?;
        writeln!(out, "withhold_after_turn: {}", p.withhold_after_turn)?;
        writeln!(out, "gravity_follows_gyro: {}", p.gravity_follows_gyro)?;
        writeln!(
            out,
            "side_min_rate: {:.6} deg/s",
            p.side_min_rate.to_degrees()
        )
    }

    fn diagnostic_names(&self) -> &[&'static str] {
        &LowbackDiag::NAMES
    }

    fn reset(&mut self) {
        *self = LowbackSpeed::new(self.params);
    }

    fn step(&mut self, sample: &Sample) -> Result<Estimate, EstimatorError> {
        let t = sample.t;
        let step = self.time.advance(t)?;
        let mut e = Estimate::empty(t);
        // (an empty cell takes its axis's last value: `crate::cell_hold`)
        let trunk = &sample.imu[Segment::Trunk.index()];
        let (acc, gyr) = self.cells.complete(t, trunk, self.params.min_step_time);
        let Some(acc) = acc else {
            return Ok(e);
        };
        if !acc.iter().all(|v| v.is_finite()) {
            return Err(EstimatorError::NonFinite {
                channel: "trunk_acc",
            });
        }
        if self
            .last_reading
            .replace(t)
            .is_some_and(|last| t - last > self.params.min_step_time)
        {
            self.restart_steps();
        }
        // The sampling period: the mean of the steps so far, not the first
        // step alone (an audit, 2026-12-05: the first time stamp 3 ms off,
        // as a Bluetooth receiver's arrival stamps are, scaled every speed
        // of the HA001 walk by the squared ratio, -0.29 m/s). The smoothing
        // kernel is set at the first step and again at `PERIOD_STEPS`.
        // Lost rows are counted as the periods they span ([`sampling_period`], 2026-12-06).
        // With uneven stamps (jittered, or rows lost) the period is the
        // sensor's grid's once 64 readings fixed it: counted step by step
        // (`sampling_period`), a single step jittered past 1.5 periods
        // counts as two and the period comes out short (HA001 straight walk,
        // +-30 % jitter: 0.028 -> 0.034-0.045 m/s stride MAE; 2026-12-07).
        let counted = self.grid.observe(t);
        if let Some(s) = step.filter(|s| *s <= self.params.min_step_time) {
            let (dt, count) = self.period.add(s);
            let dt = match self.grid.period() {
                Some(p) if !self.grid.even() => p,
                _ => dt,
            };
            if count == 1 || count == PERIOD_STEPS {
                self.set_kernel(dt);
            }
            self.dt = Some(dt);
        }
        let Some(dt) = self.dt else {
            self.gravity = Some(acc);
            return Ok(e);
        };
        // Running mean over the samples so far, exponential once the time
        // constant has passed (a first sample carrying a step's dynamic
        // acceleration does not bias the first seconds).
        self.elapsed = (self.elapsed + dt).min(self.params.gravity_time_constant);
        let gyr = gyr.filter(|w| w.iter().all(|v| v.is_finite()));
        let g = self.gravity.get_or_insert(acc);
        if self.params.gravity_follows_gyro {
            if let Some(w) = gyr {
                // The sensor turned by `w dt`: gravity, fixed in the world,
                // turned by the opposite rotation in the sensor frame.
                *g = Rotation3::new(-w * dt) * *g;
            }
        }
        *g += (acc - *g) * (dt / self.elapsed);
        let gn = g.norm();
        let a_v = if gn > 0.0 { acc.dot(g) / gn - gn } else { 0.0 };
        // Heading (rad): the rate about the gravity direction, integrated;
        // a missing or non-finite gyro sample adds nothing.
        if let Some(w) = gyr {
            if gn > 0.0 {
                self.psi += w.dot(g) / gn * dt;
            }
        }
        let mut d = e.diagnostics_mut::<LowbackDiag>();
        d.value(LowbackDiag::VerticalAcc, a_v);
        // Samples missing since the previous reading (rows, or a vector
        // missing as a whole) in a gap too short to restart: the history
        // keeps one value per sampling period, so they are filled linearly
        // between the two readings; without them the step's excursion was
        // integrated over fewer periods than it lasted.
        // Counted on the sensor's grid once it is known: a step counted on
        // its own turns stamp jitter past half a period into a "missing"
        // sample (+-30 % jitter: one step in seventy; 2026-12-07).
        if let Some((t0, a0, psi0)) = self.last_vertical {
            let missing = match counted {
                Some(c) if c.on_grid => c.steps - 1.0,
                _ => libm::round((t - t0) / dt) - 1.0,
            };
            if missing >= 1.0 && missing < HISTORY as f64 {
                let k = missing as u64;
                for j in 1..=k {
                    let f = j as f64 / (k + 1) as f64;
                    let at = t0 + (t - t0) * f;
                    self.push_vertical(
                        a0 + (a_v - a0) * f,
                        psi0 + (self.psi - psi0) * f,
                        at,
                        dt,
                        &mut d,
                    );
                }
            }
        }
        self.push_vertical(a_v, self.psi, t, dt, &mut d);
        self.last_vertical = Some((t, a_v, self.psi));
        e.speed = self
            .speed
            .filter(|(_, at)| t - at <= self.params.speed_hold)
            .map(|(v, _)| v);
        Ok(e)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn pendulum_length_matches_the_geometry() {
        // A pendulum of length l swept by half-angle phi rises h = l (1 - cos phi);
        // the step (chord) is 2 l sin(phi).
        let (l, phi) = (0.9_f64, 0.3_f64);
        let h = l * (1.0 - phi.cos());
        assert!((pendulum_step_length(h, l, 1.0) - 2.0 * l * phi.sin()).abs() < 1e-12);
    }

    #[test]
    fn excursion_of_a_sinusoid_is_its_peak_to_peak() {
        // z = A cos(2 pi t / T) over one period: a_z = -A w^2 cos(w t), peak to peak 2A.
        let (amp, period, n) = (0.02, 0.55, 550);
        let dt = period / n as f64;
        let w = 2.0 * core::f64::consts::PI / period;
        let a: Vec<f64> = (0..n)
            .map(|k| -amp * w * w * libm::cos(w * (k as f64 + 0.5) * dt))
            .collect();
        let h = step_excursion(a.iter().copied(), dt);
        assert!((h - 2.0 * amp).abs() < 0.02 * 2.0 * amp, "h = {h}");
    }

    /// Issue 19 (2026-12-04): a constant offset in `a_v` (a gravity
    /// estimate still settling: a recording that starts mid-walk) does not
    /// change a step's excursion. Before, 0.3 m/s^2 added a parabola of
    /// `c T^2 / 8` = 1.1 cm to the 4 cm of this step.
    #[test]
    fn issue_19_an_offset_in_the_vertical_acceleration_is_not_excursion() {
        let (amp, period, n) = (0.02, 0.55, 550);
        let dt = period / n as f64;
        let w = 2.0 * core::f64::consts::PI / period;
        let a = |k: usize| -amp * w * w * libm::cos(w * (k as f64 + 0.5) * dt);
        let plain = step_excursion((0..n).map(a), dt);
        let offset = step_excursion((0..n).map(|k| a(k) + 0.3), dt);
        assert!((offset - plain).abs() < 1e-9, "{offset} vs {plain}");
    }
}
