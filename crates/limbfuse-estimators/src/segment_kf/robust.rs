//! Robust-input constants and helpers of the segment filters (issue 18,
//! docs/ROBUST_INPUT.md): the encoder innovation gate, long time gaps, the
//! held gyro rate over a dropout, and rates borrowed through the encoders.
//! None of this is in papers 000/001; on data without gaps, dropouts or
//! glitches the filters' outputs are the papers' (the gate does not fire on
//! the clean trials of `scripts/refactor-check.sh`).

use super::chain::wrap;
use super::model::{angle_state, Mat8};

/// Chi-square threshold of the innovation gate on encoder rows: a row whose
/// normalised innovation squared `e^2 / (h P h^T + r)` exceeds it is not
/// applied (it counts as a missing reading). 23.93 is the `1 - 1e-6`
/// quantile of the chi-square distribution with one degree of freedom (a
/// 4.89-sigma innovation): a consistent filter refuses one good row in a
/// million.
///
/// Accelerometer-inclination rows are not gated: a walking foot or shank
/// whose specific force has the norm of `g` (so it passes `rho < zeta`) can
/// still point 55-85 deg away from the segment's angle, so a chi-square gate
/// on those rows refuses readings of clean trials (4 to 77 per 20-60 s
/// trial, measured; docs/ROBUST_INPUT.md) and changes the papers' outputs
/// both ways. An accelerometer glitch within range is in practice far from
/// `g` and fails `rho < zeta` anyway.
pub const INNOVATION_GATE_CHI2: f64 = 23.928;

/// A time step longer than this (s) is a gap in the recording: no rate held
/// over it means anything (it is longer than a stride, 1 s at a typical
/// 1 Hz stride frequency, Perry & Burnfield 2010), so the filter restarts
/// from the data after it.
pub const LONG_GAP_S: f64 = 1.0;

/// A time step longer than this multiple of the previous step is a time
/// gap (rows missing from the recording, shorter than [`LONG_GAP_S`]): one
/// missing row doubles the step, while clock jitter of real recordings
/// moves it by a few percent (+-1 ms at 100 Hz: at most 1.22 times the
/// previous step); 1.5 lies between the two.
pub const GAP_STEP_RATIO: f64 = 1.5;

/// Typical sagittal angular-acceleration amplitude of a walking segment
/// (rad/s^2): a shank swinging +-35 deg (0.61 rad) at a 1 Hz stride
/// frequency, `(2 pi f)^2 A` (amplitudes: D. A. Winter, *Biomechanics and
/// Motor Control of Human Movement*, 2009, normal-cadence gait data).
pub const HELD_RATE_ACCEL: f64 = 24.0;

/// Typical sagittal angular-rate amplitude of a walking segment (rad/s):
/// the same swing, `2 pi f A`.
pub const HELD_RATE_SD: f64 = 3.8;

/// Correlation time (s) of a walking segment's angular rate, `1 / (2 pi f)`
/// at a 1 Hz stride frequency: over a gyro dropout the held rate decays
/// towards the rate's mean over a stride, zero, with this time constant
/// (the best prediction of an oscillating rate long after its last reading
/// is its mean; holding the last value for seconds integrates it into
/// tens of degrees).
pub const HELD_RATE_CORRELATION_S: f64 = 0.16;

/// A segment filter that refuses an encoder row every time it is offered
/// for this long (s) restarts from the next data: either the filter has
/// diverged (its chain disagrees with a good encoder; the gate alone would
/// lock the correction out for good), or the encoder has changed for good
/// (re-zeroed, slipped), and then the restart adopts it; either way it is
/// counted in `resets` and reported. Longer than any impact transient
/// (tens of ms); half a stride at 1 Hz.
pub const GATE_LOCKOUT_S: f64 = 0.5;

/// Variance (rad^2) of the angle error built up by holding the last gyro
/// rate over a dropout of `tau` seconds: the held rate departs from the true
/// one by about `HELD_RATE_ACCEL * tau`, at most `HELD_RATE_SD`, and the
/// angle error is that rate error times `tau`. Not in the papers (which hold
/// the rate without saying how uncertain it becomes); it lets the encoder
/// and accelerometer rows take over a segment whose gyro is gone.
pub fn held_rate_variance(tau: f64) -> f64 {
    let sd = (HELD_RATE_ACCEL * tau).min(HELD_RATE_SD) * tau;
    sd * sd
}

/// Largest rate derivative (rad/s^2) the predicted rate over a dropout
/// extrapolates with: twice [`HELD_RATE_ACCEL`] (the sagittal angular
/// acceleration amplitude of walking). A derivative taken from two
/// readings across a heel-strike impact (hundreds of rad/s^2 for a few
/// milliseconds) says nothing about the next tenth of a second.
pub const PREDICTED_RATE_DERIVATIVE_MAX: f64 = 2.0 * HELD_RATE_ACCEL;

/// The transition of a segment's rate and its derivative over `tau`
/// seconds without a reading, `(phi_11, phi_12)`: the rate modelled as a
/// critically damped second-order Gauss-Markov process, `r'' + 2 s r' +
/// s^2 r = w` with `s = 1 / HELD_RATE_CORRELATION_S` (the stride's angular
/// frequency at 1 Hz), whose mean-square prediction is `r(tau) = phi_11
/// r + phi_12 r'`, `phi_11 = e^(-s tau) (1 + s tau)`, `phi_12 = tau e^(-s
/// tau)` (the matrix exponential of `[[0, 1], [-s^2, -2 s]]`; e.g. A.
/// Gelb, *Applied Optimal Estimation*, MIT Press 1974, Table 3.8-1, second-
/// order Gauss-Markov). Unlike the first-order decay `e^(-tau / T)` it has
/// no first-order loss: one missing sample at 100 Hz keeps 99.8 % of the
/// rate (the first-order decay kept 94 %, a bias towards zero at every
/// dropout), and after a stride it has decayed the same way. Ours, issue 18
/// item 2 (the papers hold the last rate).
pub fn predicted_rate_transition(tau: f64) -> (f64, f64) {
    let s = 1.0 / HELD_RATE_CORRELATION_S;
    let e = libm::exp(-s * tau);
    (e * (1.0 + s * tau), tau * e)
}

/// Longest dropout (s) over which the rate is extrapolated with the
/// second-order model ([`predicted_rate_transition`]): a quarter of
/// [`HELD_RATE_CORRELATION_S`], a quarter radian of the stride's phase at
/// 1 Hz, over which a sinusoidal rate departs from its linear extrapolation
/// by about 3 % of its amplitude (`1 - cos 0.25`). Beyond it the rate
/// decays from the value reached with the first-order time constant
/// [`HELD_RATE_CORRELATION_S`] as before: the slope of a trunk rate
/// oscillating at twice the stride frequency, integrated over a 1 s gap of
/// every IMU, turned the chain that `mjls` anchors on the trunk by 5 deg
/// (thigh RMSE over the gap 5.0 deg, 3.0 with this horizon;
/// tests/integration/issue_18_missing_data.rs).
pub const SLOPE_HORIZON_S: f64 = 0.25 * HELD_RATE_CORRELATION_S;

/// The rate predicted `tau` seconds after the last reading `r` whose
/// derivative was `r_dot`: [`predicted_rate_transition`] up to
/// [`SLOPE_HORIZON_S`], then a first-order decay (`r_dot` clipped to
/// [`PREDICTED_RATE_DERIVATIVE_MAX`]).
pub fn predicted_rate(r: f64, r_dot: f64, tau: f64) -> f64 {
    if tau > SLOPE_HORIZON_S {
        let at = predicted_rate(r, r_dot, SLOPE_HORIZON_S);
        return at * libm::exp(-(tau - SLOPE_HORIZON_S) / HELD_RATE_CORRELATION_S);
    }
    let (p11, p12) = predicted_rate_transition(tau);
    let d = r_dot.clamp(
        -PREDICTED_RATE_DERIVATIVE_MAX,
        PREDICTED_RATE_DERIVATIVE_MAX,
    );
    p11 * r + p12 * d
}

/// Derivative of a rate between its last two readings (rad/s^2), for
/// [`predicted_rate`]: the last reading `last` at `last_t` and the one
/// before, `prev` (reading, time); 0 without an earlier reading or time
/// between them. Formed when a dropout needs it, from the readings kept.
#[inline]
pub(crate) fn rate_slope(last: Option<f64>, last_t: f64, prev: (Option<f64>, f64)) -> f64 {
    match (last, prev) {
        (Some(r), (Some(l), t_prev)) if last_t > t_prev => (r - l) / (last_t - t_prev),
        _ => 0.0,
    }
}

/// Variance (rad^2) of the angle error built up over a dropout of `tau`
/// seconds by integrating [`predicted_rate`]: the rate's prediction error
/// of the second-order model, `sd(tau) = HELD_RATE_SD sqrt(1 - phi_11^2 -
/// (s phi_12)^2)` (the stationary rate and derivative have variances
/// `A^2` and `s^2 A^2`, `A` = [`HELD_RATE_SD`]), times `tau`. It grows as
/// `tau^2.5` for short dropouts (`A sqrt(4 s^3 / 3) tau^2.5`; 0.7 mrad
/// after 10 ms, where [`held_rate_variance`] gave 2.4 mrad) and tends to
/// [`held_rate_variance`]'s `(A tau)^2` after a stride.
pub fn predicted_rate_variance(tau: f64) -> f64 {
    let s = 1.0 / HELD_RATE_CORRELATION_S;
    let (p11, p12) = predicted_rate_transition(tau);
    let kept = p11 * p11 + s * s * p12 * p12;
    let sd = HELD_RATE_SD * libm::sqrt((1.0 - kept).max(0.0)) * tau;
    sd * sd
}

/// Largest angle variance the held-rate growth reaches (rad^2): an angle
/// known to +-90 deg is as unknown as the filter needs it to be.
pub(crate) const HELD_RATE_VARIANCE_CAP: f64 =
    core::f64::consts::FRAC_PI_2 * core::f64::consts::FRAC_PI_2;

/// Fills each missing gyro rate from a neighbour's rate and the encoder
/// between them (SPEC section 1: joint `j` is `theta_j - theta_(j+1)`, so
/// `omega_(j+1) = omega_j - d enc_j / dt` and `omega_j = omega_(j+1) + d
/// enc_j / dt`), the encoder rate taken over the last step from two
/// consecutive readings. Distal first, then proximal, so a rate can pass
/// along the chain. Not in the papers: a segment whose gyro is gone
/// borrows its motion from the chain instead of holding a stale rate.
pub(crate) fn borrow_rates(
    rate: &mut [Option<f64>; 4],
    encoder: &[Option<f64>; 3],
    last_encoder: &[Option<f64>; 3],
    dt: f64,
) {
    let enc_rate = |j: usize| match (encoder[j], last_encoder[j]) {
        (Some(e), Some(l)) => Some(wrap(e - l) / dt),
        _ => None,
    };
    // (the encoder rate is formed only for a missing rate)
    for i in 1..4 {
        if rate[i].is_none() {
            if let (Some(w), Some(d)) = (rate[i - 1], enc_rate(i - 1)) {
                rate[i] = Some(w - d);
            }
        }
    }
    for i in (0..3).rev() {
        if rate[i].is_none() {
            if let (Some(w), Some(d)) = (rate[i + 1], enc_rate(i)) {
                rate[i] = Some(w + d);
            }
        }
    }
}

/// Time constant (s) of the running mean square of the gyro rates: a
/// stride at 1 Hz.
const RATE_POWER_S: f64 = 1.0;

/// What [`RateDropouts::fill`] needs of the filter at one sample.
pub(crate) struct FillContext<'a> {
    /// Each initialised segment's last rate held (decaying) to this sample,
    /// for the segments whose rate this sample misses (the only ones
    /// [`RateDropouts::fill`] reads; `None` for the others).
    pub held: &'a [Option<f64>; 4],
    /// How long each own gyro rate had been missing before this sample (s).
    pub own_gap_before: &'a [f64; 4],
    /// This sample's encoders.
    pub encoder: &'a [Option<f64>; 3],
    /// The previous sample's encoders.
    pub last_encoder: &'a [Option<f64>; 3],
    /// The filter's encoder noise (rad).
    pub sigma_e: f64,
    /// Time step (s).
    pub dt: f64,
}

/// Gyro dropouts of the filters with encoder rows (`mjls`; ours, issue 18
/// item 2, docs/ROBUST_INPUT.md): how long each segment's own rate has been
/// missing and each rate's running mean square.
#[derive(Debug, Clone, Copy, Default)]
pub(crate) struct RateDropouts {
    /// How long each segment's own gyro rate has been missing (s; rates
    /// borrowed meanwhile do not end it).
    own_gap: [f64; 4],
    /// Running mean square of each segment's gyro rate (time constant
    /// [`RATE_POWER_S`]): the stillest segment anchors the chain when
    /// every gyro is gone.
    rate_power: [Option<f64>; 4],
    /// The previous time step (s), against which a time gap is told.
    last_step: Option<f64>,
    /// The smoothing weights of the rate power.
    weights: ExpWeights,
}

/// The smoothing weights `1 - exp(-dt / T)` of an exponential running mean
/// with one time constant `T` for the last few distinct steps `dt`, reused
/// when a step repeats bit for bit: timestamps such as `k * 0.01` give steps
/// that differ in their last bits, a few distinct values in turn (the
/// default, a zero step with weight zero, is exact too). One cache serves
/// one time constant.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub(crate) struct ExpWeights {
    entries: [(f64, f64); 4],
    /// The entry replaced next.
    next: usize,
}

impl ExpWeights {
    /// `1 - exp(-dt / time_constant)`, from the cache when `dt` repeats.
    pub fn weight(&mut self, dt: f64, time_constant: f64) -> f64 {
        if let Some(&(_, k)) = self.entries.iter().find(|w| w.0.to_bits() == dt.to_bits()) {
            return k;
        }
        let k = 1.0 - libm::exp(-dt / time_constant);
        self.entries[self.next] = (dt, k);
        self.next = (self.next + 1) % self.entries.len();
        k
    }
}

impl RateDropouts {
    /// A step `dt` longer than [`GAP_STEP_RATIO`] times the previous one is
    /// a time gap (missing rows): the rates between its two readings are as
    /// unknown as over a dropout of every gyro for the extra time, so the angle
    /// variance of every started segment (`init`) grows by
    /// [`predicted_rate_variance`] of it (capped as over a dropout) and the
    /// accelerometer and encoder rows after the gap re-anchor the angles; the
    /// angles themselves are integrated as before. Regular and jittered steps
    /// keep the papers' prediction, untouched (docs/ROBUST_INPUT.md, "Time
    /// gaps").
    pub fn grow_over_time_gap(&mut self, p: &mut Mat8, init: &[bool; 4], dt: f64) {
        let Some(extra) = self
            .last_step
            .replace(dt)
            .filter(|&s| dt > GAP_STEP_RATIO * s)
            .map(|s| dt - s)
        else {
            return;
        };
        let variance = predicted_rate_variance(extra);
        for (i, _) in init.iter().enumerate().filter(|(_, &started)| started) {
            let a = angle_state(i);
            let grown = p[(a, a)] + variance;
            p[(a, a)] = grown.min(HELD_RATE_VARIANCE_CAP.max(p[(a, a)]));
        }
    }

    /// Records which own rates this sample has; returns how long each had
    /// been missing before it.
    pub fn observe(&mut self, rate: &[Option<f64>; 4], dt: Option<f64>) -> [f64; 4] {
        let before = self.own_gap;
        let step = dt.unwrap_or(0.0);
        for (g, r) in self.own_gap.iter_mut().zip(rate.iter()) {
            *g = if r.is_some() { 0.0 } else { *g + step };
        }
        if let Some(dt) = dt {
            let k = self.weights.weight(dt, RATE_POWER_S);
            for (p, r) in self.rate_power.iter_mut().zip(rate.iter()) {
                if let Some(r) = r {
                    *p = Some(p.map_or(r * r, |p| p + k * (r * r - p)));
                }
            }
        }
        before
    }

    /// Fills missing rates for the integration:
    /// * a rate missing only briefly is held (decaying) rather than
    ///   borrowed while the held rate's angle variance stays below that of
    ///   a borrowed one, two encoder readings `2 sigma_e^2` (an encoder
    ///   difference puts its noise into the integrated angle at every
    ///   switch between own and borrowed rate); a held rate also lends
    ///   itself to its neighbours;
    /// * with every gyro gone for longer (a gap of the whole IMU bus) the
    ///   stillest segment (smallest mean square rate) anchors the chain
    ///   with its held rate;
    /// * the others borrow through the encoders ([`borrow_rates`]).
    ///
    /// Held rates are left missing in `rate`: the filter's prediction holds
    /// them the same way and grows their variance.
    pub fn fill(&self, rate: &mut [Option<f64>; 4], c: &FillContext) {
        let mut held_now = [false; 4];
        for i in 0..4 {
            if rate[i].is_some() {
                continue;
            }
            let brief =
                predicted_rate_variance(c.own_gap_before[i] + c.dt) < 2.0 * c.sigma_e * c.sigma_e;
            if brief {
                rate[i] = c.held[i];
                held_now[i] = rate[i].is_some();
            }
        }
        if rate.iter().all(|r| r.is_none()) {
            let anchor = (0..4)
                .filter_map(|i| Some((i, c.held[i]?, self.rate_power[i]?)))
                .min_by(|a, b| a.2.total_cmp(&b.2));
            if let Some((i, r, _)) = anchor {
                rate[i] = Some(r);
                held_now[i] = true;
            }
        }
        borrow_rates(rate, c.encoder, c.last_encoder, c.dt);
        for (r, h) in rate.iter_mut().zip(held_now) {
            if h {
                *r = None;
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use core::f64::consts::{PI, TAU};

    /// The fast path of `wrap` returns `remainder(a, 2 pi)` bit for bit:
    /// at and next to +-pi, at zero of both signs, beyond a turn, NaN.
    #[test]
    fn wrap_equals_the_remainder_bit_for_bit() {
        let below = f64::from_bits(PI.to_bits() - 1);
        let above = f64::from_bits(PI.to_bits() + 1);
        let mut values = vec![
            0.0, -0.0, PI, -PI, below, -below, above, -above, TAU, 7.0, -40.0,
        ];
        values.extend((0..2000).map(|k| (k as f64 - 1000.0) * 0.00731));
        for a in values {
            let want = libm::remainder(a, TAU);
            assert_eq!(wrap(a).to_bits(), want.to_bits(), "{a}");
        }
        assert!(wrap(f64::NAN).is_nan());
    }

    /// The cached smoothing weight is the one computed afresh, bit for bit,
    /// for steps that jitter in their last bits and for more distinct steps
    /// than the cache holds (entries replaced in turn).
    #[test]
    fn rate_power_weight_from_the_cache_equals_the_computed_one() {
        let mut d = ExpWeights::default();
        let steps = [
            0.01,
            0.010000000000000009,
            0.009999999999999787,
            0.0,
            0.02,
            0.005,
            1e-9,
        ];
        for k in 0..200 {
            let dt = steps[(k * 7 + k / 3) % steps.len()];
            let want = 1.0 - libm::exp(-dt / RATE_POWER_S);
            assert_eq!(
                d.weight(dt, RATE_POWER_S).to_bits(),
                want.to_bits(),
                "dt {dt}"
            );
        }
    }

    /// Independent value: `(min(a tau, s) tau)^2` by hand.
    #[test]
    fn held_rate_variance_grows_with_the_dropout_then_with_its_square() {
        assert_eq!(held_rate_variance(0.0), 0.0);
        // 0.1 s: rate error 2.4 rad/s, angle error 0.24 rad
        assert!((held_rate_variance(0.1) - 0.24f64.powi(2)).abs() < 1e-15);
        // 1 s: the rate error is capped at 3.8 rad/s
        assert!((held_rate_variance(1.0) - 3.8f64.powi(2)).abs() < 1e-12);
    }

    /// A four-segment chain moving as sines: the rate borrowed for a
    /// missing segment from its neighbour and the encoder between them
    /// matches the segment's true rate to the encoder's finite-difference
    /// error, `O(dt)`.
    #[test]
    fn borrowed_rates_match_the_true_rates_of_a_moving_chain() {
        let theta = |i: usize, t: f64| 0.3 * (6.0 * t + i as f64).sin() + 0.1 * i as f64;
        let omega = |i: usize, t: f64| 1.8 * (6.0 * t + i as f64).cos();
        let enc = |j: usize, t: f64| Some(theta(j, t) - theta(j + 1, t));
        let dt = 0.01;
        let t = 0.37;
        let now = [enc(0, t), enc(1, t), enc(2, t)];
        let before = [enc(0, t - dt), enc(1, t - dt), enc(2, t - dt)];
        for missing in 0..4 {
            let mut rate: [Option<f64>; 4] = core::array::from_fn(|i| Some(omega(i, t)));
            rate[missing] = None;
            borrow_rates(&mut rate, &now, &before, dt);
            let got = rate[missing].expect("borrowed");
            // backward difference: error about |theta''| dt / 2 <= 0.1 rad/s
            let want = omega(missing, t);
            assert!(
                (got - want).abs() < 0.1,
                "segment {missing}: {got} vs {want}"
            );
            assert!((got - want).abs() > 0.0);
        }
        // two missing in a row: the rate passes along the chain
        let mut rate = [Some(omega(0, t)), None, None, Some(omega(3, t))];
        borrow_rates(&mut rate, &now, &before, dt);
        for (i, r) in rate.iter().enumerate() {
            assert!((r.unwrap() - omega(i, t)).abs() < 0.2);
        }
        // no encoder history: nothing to borrow
        let mut rate = [Some(1.0), None, Some(1.0), Some(1.0)];
        borrow_rates(&mut rate, &now, &[None; 3], dt);
        assert_eq!(rate[1], None);
    }
}
