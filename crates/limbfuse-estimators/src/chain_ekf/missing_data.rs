//! Missing data and divergence in the chain EKF beyond docs/CHAIN.md's
//! model (ours, issue 18; docs/ROBUST_INPUT.md section 2b): the rate bound
//! that marks a diverged state, the trunk hold over a gap of every IMU, and
//! the longest run without any reading the chain predicts through.

use limbfuse_core::Sample;

use super::covariance::{scalar_update, Covariance, StateVector};
use super::state::{alpha, omega, SparseRow};

/// A segment rate (rad/s) beyond which the chain's state has diverged:
/// twice the widest gyroscope range the sample gate accepts by default
/// (`SensorRanges::default`: 2000 deg/s + 15 % = 40 rad/s, the Xsens MTw /
/// Bosch BMI270 full scale), far beyond any segment's rate in gait (the
/// foot peaks near 15 rad/s in walking and running; Winter 2009). Found by
/// `issue_18_chain_with_steps_up_to_half_a_second`: readings far from the
/// model over 0.5 s steps drove a rate to ~3e4 rad/s, and the accelerometer
/// rows linearised there (entries ~1e8) lost the covariance's positive
/// semi-definiteness to round-off. Ours, beyond docs/CHAIN.md's model.
pub const DIVERGED_RATE_RAD_S: f64 = 80.0;

/// Sagittal rate amplitude of the trunk in walking (rad/s): pitch +-2.5 deg
/// at twice the stride frequency (Winter 2009, normal-cadence trunk
/// kinematics), `0.044 rad * TRUNK_PITCH_OMEGA`.
pub const TRUNK_RATE_AMPLITUDE: f64 = 0.55;
/// Angular frequency of the trunk's pitch oscillation (rad/s): twice a 1 Hz
/// stride.
pub const TRUNK_PITCH_OMEGA: f64 = 4.0 * core::f64::consts::PI;

/// A sample without any IMU reading (only the encoders, which fix the
/// relative angles): the trunk's rate and angular acceleration are held
/// about zero within their walking amplitudes ([`TRUNK_RATE_AMPLITUDE`],
/// `TRUNK_RATE_AMPLITUDE * TRUNK_PITCH_OMEGA`), so the chain does not
/// extrapolate a turn of the whole body through the gap.
pub fn hold_trunk(x: &mut StateVector, p: &mut Covariance) {
    let sigma = [
        TRUNK_RATE_AMPLITUDE,
        TRUNK_RATE_AMPLITUDE * TRUNK_PITCH_OMEGA,
    ];
    for (k, state) in [omega(0), alpha(0)].into_iter().enumerate() {
        let mut row = SparseRow::new();
        row.add(state, 1.0);
        let nu = -x[state];
        scalar_update(x, p, &row, nu, sigma[k] * sigma[k], f64::INFINITY);
    }
}

/// Whether a sample gives the chain nothing at all: no IMU cell, no device
/// quaternion, no encoder reading.
pub fn is_blind(sample: &Sample) -> bool {
    sample.imu.iter().all(|imu| imu.is_empty()) && sample.encoder.iter().all(Option::is_none)
}

/// The current run of blind samples ([`is_blind`]).
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct BlindRun {
    since: Option<f64>,
}

impl BlindRun {
    /// Adds a sample: whether it is blind and the run has lasted longer
    /// than `limit` seconds.
    pub fn observe(&mut self, sample: &Sample, limit: f64) -> bool {
        if is_blind(sample) {
            let since = *self.since.get_or_insert(sample.t);
            sample.t - since > limit
        } else {
            self.since = None;
            false
        }
    }

    /// Whether the last sample was blind: it holds nothing for the start-up
    /// window, which opens at the next reading.
    pub fn active(&self) -> bool {
        self.since.is_some()
    }
}

/// The longest run of blind samples ([`is_blind`]) the chain predicts
/// through (s): the time after which the leg segments' angular-jerk noise
/// alone (`leg_jerk` = `q`, rad^2/s^5; the constant-angular-acceleration
/// model's angle variance grows as `q t^5 / 20`) makes a leg angle's 1-sigma
/// exceed `sigma0`, the start-up window's (`initial::ANGLE`). Past it a
/// restart knows the angles better than the prediction. With the defaults
/// (`q` = 1e4, 0.5 rad): 0.22 s. Ours, beyond docs/CHAIN.md's model: an audit
/// (twenty-seventh session) emptied every IMU cell of a walk without encoders
/// for 0.8-1.5 s; the chain extrapolated the leg angles quadratically
/// (shank -39 -> +603 deg in 0.8 s of a real walk) and re-locked after the
/// gap whole turns off or upside down (foot 158 deg off for the remaining 28
/// s), where rows removed instead (a time gap over `LONG_GAP_S`) restart it.
pub fn blind_limit_s(leg_jerk: f64, sigma0: f64) -> f64 {
    libm::pow(20.0 * sigma0 * sigma0 / leg_jerk, 0.2)
}
