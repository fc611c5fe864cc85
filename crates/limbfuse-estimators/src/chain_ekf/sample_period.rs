//! The chain EKF's measurement variances at the recording's sample period
//! (issue 14, "generality"; docs/CHAIN.md, "Sample rate").
//!
//! The sigmas of [`super::ChainParams`] (`gyro_noise`, `acc_noise`,
//! `encoder_noise` and the anchors) are stated per sample at
//! [`REFERENCE_PERIOD_S`], where the defaults were set. Their errors are
//! mostly model error (mount positions, segment lengths, soft tissue, the
//! planar model, the anchors' priors), which is correlated over
//! [`MODEL_ERROR_CORRELATION_S`] and longer: at twice the rate the samples
//! repeat the same error, and applied as independent they would carry twice
//! the information per second. The variance per sample is therefore scaled
//! by `REFERENCE_PERIOD_S / min(T, MODEL_ERROR_CORRELATION_S)`, so that the
//! information per second is the same at any rate (the continuous-discrete
//! relation `R_k = R_c / T`: A. Gelb (ed.), *Applied Optimal Estimation*, MIT
//! Press 1974, sec. 4.4; D. Simon, *Optimal State Estimation*, Wiley 2006,
//! sec. 8.1). The sensors' white noise scales the same way when their
//! anti-alias bandwidth follows the output rate (`sigma^2 = nd^2 fs / 2`).

/// Sample period (s) at which the chain's per-sample sigmas are stated:
/// 100 Hz, the rate the defaults were set at.
pub const REFERENCE_PERIOD_S: f64 = 0.01;

/// Correlation time (s) of the accelerometer model error: the error follows
/// the movement (soft-tissue artefact has the frequency content of the bone
/// movement it disturbs, A. Leardini et al., Gait Posture 21:212-225, 2005;
/// walking kinematics lie below 6-10 Hz, D. A. Winter, *Biomechanics and
/// Motor Control of Human Movement*, 4th ed., Wiley 2009, sec. 3.4), i.e. a
/// band of about 10 Hz, `1 / (2 * 10 Hz)`. Samples further apart than this
/// are independent: below 20 Hz, or after a gap, a sample's variance stops
/// shrinking.
pub const MODEL_ERROR_CORRELATION_S: f64 = 0.05;

/// The factor on every per-sample measurement variance at sample period
/// `period` (s): `REFERENCE_PERIOD_S / min(period, MODEL_ERROR_CORRELATION_S)`,
/// rounded to 1e-6 so that the rounding of time stamps `k / fs` leaves it at
/// exactly 1 at 100 Hz (and the defaults' outputs bit for bit as before).
/// A period that is not positive and finite gives 1.
pub fn variance_scale(period: f64) -> f64 {
    if !(period.is_finite() && period > 0.0) {
        return 1.0;
    }
    let s = REFERENCE_PERIOD_S / period.min(MODEL_ERROR_CORRELATION_S);
    libm::round(s * 1e6) / 1e6
}

/// The nominal sample period (s) of `times` (the start-up window's time
/// stamps): their mean step, `None` with fewer than two or a span that is
/// not positive. The mean over the window, not each step, so that jitter in
/// the time stamps does not move the weights sample by sample.
pub fn nominal_period(first: f64, last: f64, count: usize) -> Option<f64> {
    let span = last - first;
    (count >= 2 && span.is_finite() && span > 0.0).then(|| span / (count - 1) as f64)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn one_at_100_hz_two_at_200_and_capped_at_the_correlation_time() {
        assert_eq!(variance_scale(0.01), 1.0);
        // Time stamps k / 100 rounded: the mean step is 0.01 to an ulp.
        let p = nominal_period(0.0, 100.0 * 0.01, 101).unwrap();
        assert_eq!(variance_scale(p), 1.0);
        assert_eq!(variance_scale(0.005), 2.0);
        assert_eq!(variance_scale(1.0 / 128.0), 1.28);
        assert!((variance_scale(1.0 / 60.0) - 0.6).abs() < 1e-12);
        assert_eq!(variance_scale(0.2), 0.2);
        assert_eq!(variance_scale(f64::NAN), 1.0);
        assert_eq!(nominal_period(1.0, 1.0, 5), None);
        assert_eq!(nominal_period(0.0, 1.0, 1), None);
    }
}
