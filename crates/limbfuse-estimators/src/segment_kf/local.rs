//! The local Kalman filter (`local`): one 2-state error-state filter per
//! segment, stacked as paper 001's "matricial local" model.
//!
//! Model: 000 eqs 5-13 per segment (state `[dtheta, db]`, `A = [[0, 1],
//! [0, -1/tau]]`, `C = [1, 0]`), stacked block-diagonally as 001 eqs 4-6.
//! Because `A`, `Q`, `C` and `R` are block-diagonal, `P` and the gain `K`
//! stay block-diagonal (001 after eq 29): no segment's measurement touches
//! another segment's state.
//!
//! Update rows: segment row `i` enters when its accelerometer passes `rho_i
//! < zeta_i` (001 eq 14-18) and the count criterion `Psi_s` holds (at least
//! `s` accelerometers pass, 001 eqs 15-18). `s = 2` by default, the
//! criterion 001 used for its Table 1; `s = 1` is the textbook independent
//! local filter.
#![allow(non_snake_case)]

use core::fmt;

use limbfuse_core::estimator::Outputs;
use limbfuse_core::{diagnostic_set, Estimate, Estimator, EstimatorError, Sample};
use nalgebra::{SMatrix, SVector};

use super::chain::{wrap, Chain};
use super::criteria::{count_reliable, psi, AccelGateState};
use super::diagnostics::{write_segment_diagnostics, SegmentDiag};
use super::gain_shares::{after_update, RowKind};
use super::model::{Mat8, LOCAL_ROWS};
use super::params::{check_min_reliable, CommonParams, ParamError};
use super::structured::Gain;

/// Parameters of [`LocalKf`].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct LocalKfParams {
    /// Noise models, initial covariance and numerics.
    pub common: CommonParams,
    /// `s` of the count criterion `Psi_s` (001 eqs 15-18), 1..=4. Default 2
    /// (001 Table 1 uses criterion (17)).
    pub min_reliable: u8,
}

impl Default for LocalKfParams {
    fn default() -> Self {
        LocalKfParams {
            common: CommonParams::default(),
            min_reliable: 2,
        }
    }
}

impl LocalKfParams {
    /// Paper 000 Table 2 weights with the papers' numerics
    /// ([`CommonParams::paper_2014`]) and `Psi_2`.
    pub fn paper_2014() -> Self {
        LocalKfParams {
            common: CommonParams::paper_2014(),
            min_reliable: 2,
        }
    }

    /// Checks every value.
    pub fn validate(&self) -> Result<(), ParamError> {
        self.common.validate()?;
        check_min_reliable(self.min_reliable)
    }
}

diagnostic_set! {
    /// Diagnostics of [`LocalKf`]: its own, then the [`SegmentDiag`] shared
    /// by the segment filters.
    pub enum LocalDiag {
        /// Number of accelerometers passing `rho_i < zeta_i` (001 eqs 15-18).
        NReliable = "n_reliable",
        /// The count criterion `Psi_s` holds (001 eqs 15-18).
        Psi = "psi",
        /// The trunk accelerometer row updated the filter.
        UpdTrunk = "upd_trunk",
        /// The thigh accelerometer row updated the filter.
        UpdThigh = "upd_thigh",
        /// The shank accelerometer row updated the filter.
        UpdShank = "upd_shank",
        /// The foot accelerometer row updated the filter.
        UpdFoot = "upd_foot",
    }
    extends
    /// The diagnostics shared by the segment filters.
    Segment(SegmentDiag)
}

impl LocalDiag {
    /// `upd_*` per segment (index [`limbfuse_core::Segment::index`]).
    pub const UPDATED: [LocalDiag; 4] = [
        LocalDiag::UpdTrunk,
        LocalDiag::UpdThigh,
        LocalDiag::UpdShank,
        LocalDiag::UpdFoot,
    ];
}

const KINDS: [RowKind; 4] = [
    RowKind::Imu(0),
    RowKind::Imu(1),
    RowKind::Imu(2),
    RowKind::Imu(3),
];

/// The matricial local Kalman filter of 001 (eqs 1-6, 14-18), i.e. four
/// independent segment filters of 000 (eqs 5-13). Method name `local`.
#[derive(Debug, Clone)]
pub struct LocalKf {
    params: LocalKfParams,
    chain: Chain,
    gate: AccelGateState,
    R: SMatrix<f64, 4, 4>,
    last: Gain<4>,
}

impl Default for LocalKf {
    fn default() -> Self {
        Self::build(LocalKfParams::default())
    }
}

impl LocalKf {
    /// A filter with the given parameters, after validating them.
    pub fn new(params: LocalKfParams) -> Result<Self, ParamError> {
        params.validate()?;
        Ok(Self::build(params))
    }

    fn build(params: LocalKfParams) -> Self {
        let mut R = SMatrix::<f64, 4, 4>::zeros();
        for i in 0..4 {
            let s = params.common.segments[i].accel_angle_sigma;
            R[(i, i)] = s * s;
        }
        LocalKf {
            chain: Chain::new(params.common),
            params,
            gate: AccelGateState::default(),
            R,
            last: Gain::zero(),
        }
    }

    /// The parameters in use.
    pub fn params(&self) -> &LocalKfParams {
        &self.params
    }

    /// Gain `K` (8x4) of the last update; zero when the last sample made none.
    pub fn last_gain(&self) -> &SMatrix<f64, 8, 4> {
        &self.last.K
    }

    /// Error covariance `P` (8x8, state order of 000 eq 16).
    pub fn covariance(&self) -> &Mat8 {
        self.chain.covariance()
    }

    /// Error state (zero after every step in closed loop).
    pub fn error_state(&self) -> &SVector<f64, 8> {
        self.chain.error_state()
    }
}

impl Estimator for LocalKf {
    fn name(&self) -> &'static str {
        "local"
    }

    fn outputs(&self) -> Outputs {
        Outputs::ALL_ANGLES
    }

    fn describe_parameters(&self, out: &mut dyn fmt::Write) -> fmt::Result {
        writeln!(
            out,
            "model: matricial local KF (Nogueira et al. 2017 eqs 1-6, 14-18)"
        )?;
        writeln!(out, "min_reliable: {}", self.params.min_reliable)?;
        self.params.common.describe(out)
    }

    fn diagnostic_names(&self) -> &[&'static str] {
        &LocalDiag::NAMES
    }

    fn rejected_readings(&self) -> [u64; 3] {
        [0, 0, self.chain.gated_encoders()]
    }

    fn reset(&mut self) {
        self.chain.reset();
        self.gate.reset();
        self.last = Gain::zero();
    }

    fn step(&mut self, sample: &Sample) -> Result<Estimate, EstimatorError> {
        let inp = self.chain.begin(sample)?;
        let zeta = self.params.common.zetas();
        let gate = self.params.common.accel_gate;
        let reliable = self.gate.reliable(&gate, sample, &inp.rho, &zeta);
        let psi_ok = psi(&reliable, self.params.min_reliable);
        let mut active = [false; 4];
        let mut innov = SVector::<f64, 4>::zeros();
        for i in 0..4 {
            if !(psi_ok && reliable[i] && inp.usable[i]) {
                continue;
            }
            if let Some(th) = inp.theta_a(i) {
                active[i] = true;
                innov[i] = wrap(th - self.chain.angle(i));
            }
        }
        let r = [
            self.R[(0, 0)],
            self.R[(1, 1)],
            self.R[(2, 2)],
            self.R[(3, 3)],
        ];
        let made = self.chain.update(
            &innov,
            &LOCAL_ROWS,
            &r,
            &mut active,
            &[false; 4],
            &mut self.last,
        );
        let (updated, shares) = after_update(made, active, &mut self.last, &KINDS);
        let mut est = Estimate::empty(sample.t);
        self.chain.estimate_into(sample.t, &mut est);
        let mut d = est.diagnostics_mut::<LocalDiag>();
        d.value(LocalDiag::NReliable, count_reliable(&reliable) as f64);
        d.flag(LocalDiag::Psi, psi_ok);
        for (key, u) in LocalDiag::UPDATED.into_iter().zip(updated) {
            d.flag(key, u);
        }
        write_segment_diagnostics(&mut d, &self.chain, &inp, false, &shares);
        Ok(est)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use nalgebra::Vector3;

    /// Paper 000 eqs 5-6 with a finite correlation time, integrated
    /// outside the filter: with every accelerometer unreliable (norm 1.5 g,
    /// `rho` = 4.9 m/s^2 > zeta) no update happens and the angle is the
    /// integral of `theta_dot = gyro + b_hat` (eq 5) with `b_hat' = -b_hat /
    /// tau` (eq 6): for a gyro reading `r = c0 + c1 t` (exact under the
    /// trapezoid rule) and `b_hat(0) = b0`,
    /// `theta = theta0 + c0 t + c1 t^2 / 2 + b0 tau (1 - e^(-t/tau))`.
    /// Here theta0 = 0.1 rad, c0 = 0.2 rad/s, c1 = -0.01 rad/s^2, tau = 30 s,
    /// and the sensor-convention bias 0.02 rad/s (gyro reads true + bias),
    /// i.e. the papers' `b0 = -0.02`; by hand (numpy) 0.88288903 rad at 5 s,
    /// 1.80805027 rad at 20 s.
    #[test]
    fn unaided_angle_integrates_a_linear_rate_and_a_decaying_bias() {
        let (theta0, c0, c1, beta, tau) = (0.1, 0.2, -0.01, 0.02, 30.0);
        // (the angle integrated from the first sample on)
        let mut common = CommonParams {
            first_sample_start: true,
            ..CommonParams::default()
        };
        common.segments[0].bias_tau = tau;
        common.initial_gyro_bias[0] = beta;
        let mut f = LocalKf::new(LocalKfParams {
            common,
            min_reliable: 1,
        })
        .unwrap();
        let g = common.gravity;
        let acc = Vector3::new(libm::sin(theta0), libm::cos(theta0), 0.0) * (1.5 * g);
        let dt = 0.01;
        for k in 0..=2000 {
            let t = k as f64 * dt;
            let mut s = Sample::empty(t);
            s.imu[0].acc = Some(acc);
            s.imu[0].gyr = Some(Vector3::new(0.0, 0.0, c0 + c1 * t));
            let est = f.step(&s).unwrap();
            let b0 = -beta;
            let want = theta0 + c0 * t + c1 * t * t / 2.0 + b0 * tau * (1.0 - libm::exp(-t / tau));
            let got = est.segment[0].unwrap();
            assert!((got - want).abs() < 1e-11, "t = {t}: {got} vs {want}");
            if k == 500 {
                assert!((want - 0.882_889_034_9).abs() < 1e-9);
            }
            if k == 2000 {
                assert!((want - 1.808_050_271_4).abs() < 1e-9);
            }
        }
    }
}
