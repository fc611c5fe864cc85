//! The matricial global Kalman filter (`global`) of paper 001.
//!
//! Model: the 8-state stacked error model (001 eq 19) with the coupled
//! output matrix `C-bar_c` (001 eqs 20-22): rows 0-3 are the segment
//! accelerometer rows `theta_a,i - theta_g,i`, rows 4-6 the "relative"
//! rows of hip, knee and ankle, whose measurement is the difference of two
//! accelerometer inclinations minus the difference of the integrated angles
//! (001 eqs 23-25): `(theta_a,i - theta_a,i+1) - (theta_g,i - theta_g,i+1)`.
//! `R = diag(sigma_a,B^2, .., sigma_a,F^2, sigma_BT^2, sigma_TS^2,
//! sigma_SF^2)` (001 eq 22).
//!
//! Row gating (SPEC section 6): segment row `i` enters when `rho_i <
//! zeta_i` and `Psi_s` holds (001 eqs 14-18); joint row `j` when
//! `Upsilon_j` holds, i.e. both of its segments pass (001 eqs 26-28).
#![allow(non_snake_case)]

use core::fmt;

use limbfuse_core::estimator::Outputs;
use limbfuse_core::{diagnostic_set, Estimate, Estimator, EstimatorError, Sample};
use nalgebra::{SMatrix, SVector};

use super::chain::{wrap, Chain};
use super::criteria::{count_reliable, psi, upsilon, AccelGateState};
use super::diagnostics::{write_segment_diagnostics, SegmentDiag};
use super::gain_shares::{after_update, RowKind};
use super::model::{Mat8, GLOBAL_ROWS};
use super::params::{check_min_reliable, sigma, CommonParams, ParamError};
use super::structured::Gain;

/// Parameters of [`GlobalKf`].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct GlobalKfParams {
    /// Noise models, initial covariance and numerics.
    pub common: CommonParams,
    /// `s` of the count criterion `Psi_s` (001 eqs 15-18), 1..=4. Default 2
    /// (001 Table 1 uses criterion (17)).
    pub min_reliable: u8,
    /// Standard deviation (rad) of the hip, knee and ankle relative rows
    /// (`sigma_a,BT`, `sigma_a,TS`, `sigma_a,SF` of 001 eq 22). `None`
    /// (default) derives it from the two segments' accelerometer-angle
    /// noise as for a difference of independent errors:
    /// `sqrt(sigma_a,i^2 + sigma_a,i+1^2)`.
    pub relative_sigma: [Option<f64>; 3],
}

impl Default for GlobalKfParams {
    fn default() -> Self {
        GlobalKfParams {
            common: CommonParams::default(),
            min_reliable: 2,
            relative_sigma: [None; 3],
        }
    }
}

impl GlobalKfParams {
    /// Paper 000 Table 2 weights with the papers' numerics
    /// ([`CommonParams::paper_2014`]), `Psi_2`, and relative-row noise
    /// derived from Table 2's sigma_a (001 does not publish its values).
    pub fn paper_2014() -> Self {
        GlobalKfParams {
            common: CommonParams::paper_2014(),
            ..GlobalKfParams::default()
        }
    }

    /// The relative-row standard deviations in use.
    pub fn resolved_relative_sigma(&self) -> [f64; 3] {
        let mut out = [0.0; 3];
        for (j, o) in out.iter_mut().enumerate() {
            *o = self.relative_sigma[j].unwrap_or_else(|| {
                let a = self.common.segments[j].accel_angle_sigma;
                let b = self.common.segments[j + 1].accel_angle_sigma;
                libm::sqrt(a * a + b * b)
            });
        }
        out
    }

    /// Checks every value.
    pub fn validate(&self) -> Result<(), ParamError> {
        self.common.validate()?;
        check_min_reliable(self.min_reliable)?;
        for s in self.relative_sigma.iter().flatten() {
            sigma("relative_sigma", *s)?;
        }
        Ok(())
    }
}

diagnostic_set! {
    /// Diagnostics of [`GlobalKf`]: its own, then the [`SegmentDiag`] shared
    /// by the segment filters.
    pub enum GlobalDiag {
        /// Number of accelerometers passing `rho_i < zeta_i` (001 eqs 15-18).
        NReliable = "n_reliable",
        /// The count criterion `Psi_s` holds (001 eqs 15-18).
        Psi = "psi",
        /// The trunk accelerometer row updated the filter (001 eq 20).
        UpdTrunk = "upd_trunk",
        /// The thigh accelerometer row updated the filter.
        UpdThigh = "upd_thigh",
        /// The shank accelerometer row updated the filter.
        UpdShank = "upd_shank",
        /// The foot accelerometer row updated the filter.
        UpdFoot = "upd_foot",
        /// The hip accelerometer-difference row (`Upsilon_h`, 001 eq 26) updated the filter.
        UpdHip = "upd_hip",
        /// The knee accelerometer-difference row (`Upsilon_k`, 001 eq 27) updated the filter.
        UpdKnee = "upd_knee",
        /// The ankle accelerometer-difference row (`Upsilon_a`, 001 eq 28) updated the filter.
        UpdAnkle = "upd_ankle",
    }
    extends
    /// The diagnostics shared by the segment filters.
    Segment(SegmentDiag)
}

impl GlobalDiag {
    /// `upd_*` per measurement row (001 eq 20 row order: the four
    /// accelerometer rows, then hip, knee, ankle).
    pub const UPDATED: [GlobalDiag; 7] = [
        GlobalDiag::UpdTrunk,
        GlobalDiag::UpdThigh,
        GlobalDiag::UpdShank,
        GlobalDiag::UpdFoot,
        GlobalDiag::UpdHip,
        GlobalDiag::UpdKnee,
        GlobalDiag::UpdAnkle,
    ];
}

const KINDS: [RowKind; 7] = [
    RowKind::Imu(0),
    RowKind::Imu(1),
    RowKind::Imu(2),
    RowKind::Imu(3),
    RowKind::Joint,
    RowKind::Joint,
    RowKind::Joint,
];

/// The matricial global Kalman filter of 001 (eqs 19-28). Method name `global`.
#[derive(Debug, Clone)]
pub struct GlobalKf {
    params: GlobalKfParams,
    chain: Chain,
    gate: AccelGateState,
    R: SMatrix<f64, 7, 7>,
    last: Gain<7>,
}

impl Default for GlobalKf {
    fn default() -> Self {
        Self::build(GlobalKfParams::default())
    }
}

impl GlobalKf {
    /// A filter with the given parameters, after validating them.
    pub fn new(params: GlobalKfParams) -> Result<Self, ParamError> {
        params.validate()?;
        Ok(Self::build(params))
    }

    fn build(params: GlobalKfParams) -> Self {
        let mut R = SMatrix::<f64, 7, 7>::zeros();
        for i in 0..4 {
            let s = params.common.segments[i].accel_angle_sigma;
            R[(i, i)] = s * s;
        }
        for (j, s) in params.resolved_relative_sigma().iter().enumerate() {
            R[(4 + j, 4 + j)] = s * s;
        }
        GlobalKf {
            chain: Chain::new(params.common).with_spike_test(),
            params,
            gate: AccelGateState::default(),
            R,
            last: Gain::zero(),
        }
    }

    /// The parameters in use.
    pub fn params(&self) -> &GlobalKfParams {
        &self.params
    }

    /// Measurement noise `R` (7x7) of 001 eq 22.
    pub fn measurement_noise(&self) -> &SMatrix<f64, 7, 7> {
        &self.R
    }

    /// Gain `K` (8x7) of the last update; zero when the last sample made none.
    pub fn last_gain(&self) -> &SMatrix<f64, 8, 7> {
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

impl Estimator for GlobalKf {
    fn name(&self) -> &'static str {
        "global"
    }

    fn outputs(&self) -> Outputs {
        Outputs::ALL_ANGLES
    }

    fn describe_parameters(&self, out: &mut dyn fmt::Write) -> fmt::Result {
        writeln!(
            out,
            "model: matricial global KF (Nogueira et al. 2017 eqs 19-28)"
        )?;
        writeln!(out, "min_reliable: {}", self.params.min_reliable)?;
        let rel = self.params.resolved_relative_sigma();
        writeln!(out, "hip.relative_sigma: {}", rel[0])?;
        writeln!(out, "knee.relative_sigma: {}", rel[1])?;
        writeln!(out, "ankle.relative_sigma: {}", rel[2])?;
        self.params.common.describe(out)
    }

    fn diagnostic_names(&self) -> &[&'static str] {
        &GlobalDiag::NAMES
    }

    fn rejected_readings(&self) -> [u64; 3] {
        [self.chain.refused_rates(), 0, self.chain.gated_encoders()]
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
        let ups = upsilon(&reliable);
        let mut active = [false; 7];
        let mut innov = SVector::<f64, 7>::zeros();
        // Inclinations of the segments that pass their test (the only ones
        // any row uses: Upsilon needs both segments of a joint to pass).
        let theta_a: [Option<f64>; 4] =
            core::array::from_fn(|i| if reliable[i] { inp.theta_a(i) } else { None });
        for i in 0..4 {
            if let (true, true, true, Some(th)) = (psi_ok, reliable[i], inp.usable[i], theta_a[i]) {
                active[i] = true;
                innov[i] = wrap(th - self.chain.angle(i));
            }
        }
        for j in 0..3 {
            if let (true, true, true, Some(a), Some(b)) = (
                ups[j],
                inp.usable[j],
                inp.usable[j + 1],
                theta_a[j],
                theta_a[j + 1],
            ) {
                active[4 + j] = true;
                innov[4 + j] = wrap((a - b) - (self.chain.angle(j) - self.chain.angle(j + 1)));
            }
        }
        let r: [f64; 7] = core::array::from_fn(|k| self.R[(k, k)]);
        let made = self.chain.update(
            &innov,
            &GLOBAL_ROWS,
            &r,
            &mut active,
            &[false; 7],
            &mut self.last,
        );
        let (updated, shares) = after_update(made, active, &mut self.last, &KINDS);
        let mut est = Estimate::empty(sample.t);
        self.chain.estimate_into(sample.t, &mut est);
        let mut d = est.diagnostics_mut::<GlobalDiag>();
        d.value(GlobalDiag::NReliable, count_reliable(&reliable) as f64);
        d.flag(GlobalDiag::Psi, psi_ok);
        for (key, u) in GlobalDiag::UPDATED.into_iter().zip(updated) {
            d.flag(key, u);
        }
        write_segment_diagnostics(&mut d, &self.chain, &inp, false, &shares);
        Ok(est)
    }
}
