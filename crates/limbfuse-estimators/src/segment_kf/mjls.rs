//! The Markov-jump (MJLS-based) Kalman filter (`mjls`) of paper 000,
//! validated in paper 001.
//!
//! Model: the 8-state stacked error model (000 eqs 14-16, 001 eqs 7-8) with
//! the mode-dependent output matrix `C-bar(Xi)` (000 eq 18, 001 eq 10): one
//! accelerometer row, selected at each sample as the most reliable
//! accelerometer `Xi = argmin_i rho_i` (000 eqs 28-29, 001 eqs 11-12), plus
//! the three encoder rows `dtheta_i - dtheta_{i+1}` (000 eq 17). The
//! measurement noise is `R = diag(sigma_a,Xi^2, sigma_e,h^2, sigma_e,k^2,
//! sigma_e,a^2)` (000 eq 27). Filter steps: 000 eqs 21-25.
//!
//! When `rho(k) <= zeta` (000 eq 30, 001 eq 13) all four rows are used.
//! Otherwise the paper only predicts ([`WhenUnreliable::PredictOnly`],
//! default); [`WhenUnreliable::EncodersOnly`] applies the three encoder rows
//! alone (SPEC section 6). A missing encoder drops its row.
#![allow(non_snake_case)]

use core::fmt;

use limbfuse_core::estimator::Outputs;
use limbfuse_core::{diagnostic_set, Estimate, Estimator, EstimatorError, Sample};
use nalgebra::{SMatrix, SVector};

use super::chain::{wrap, Chain};
use super::criteria::{mjls_select, AccelGateState};
use super::diagnostics::{write_segment_diagnostics, SegmentDiag};
use super::gain_shares::{after_update, RowKind};
use super::model::{mjls_rows, Mat8};
use super::params::{default_encoder_sigma, sigma, CommonParams, ParamError};
use super::structured::Gain;

/// What the MJLS filter does when no accelerometer is reliable.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum WhenUnreliable {
    /// Predict only (000 section 3, "unreliable measurement signal"; default).
    #[default]
    PredictOnly,
    /// Update with the three encoder rows alone (SPEC section 6).
    EncodersOnly,
}

impl WhenUnreliable {
    /// `predict-only` or `encoders-only`.
    pub const fn label(self) -> &'static str {
        match self {
            WhenUnreliable::PredictOnly => "predict-only",
            WhenUnreliable::EncodersOnly => "encoders-only",
        }
    }
}

/// Parameters of [`MarkovJumpKf`].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct MarkovJumpKfParams {
    /// Noise models, initial covariance and numerics.
    pub common: CommonParams,
    /// Encoder noise standard deviation (rad) for hip, knee, ankle
    /// (`sigma_e` of 000 eq 27). Default 8.735e-3 rad
    /// ([`crate::segment_kf::params::default_encoder_sigma`]): one LSB of
    /// white noise of a 14-bit encoder combined with a 0.5 deg zeroing
    /// offset between exoskeleton and anatomical joint.
    pub encoder_sigma: [f64; 3],
    /// Behaviour when `rho(k) > zeta`.
    pub when_unreliable: WhenUnreliable,
}

impl Default for MarkovJumpKfParams {
    fn default() -> Self {
        MarkovJumpKfParams {
            common: CommonParams::default(),
            encoder_sigma: [default_encoder_sigma(); 3],
            when_unreliable: WhenUnreliable::PredictOnly,
        }
    }
}

impl MarkovJumpKfParams {
    /// Paper 000 Table 2 ([`CommonParams::paper_2014`]). Table 2 gives no
    /// encoder noise, so the encoder rows keep the 14-bit default.
    pub fn paper_2014() -> Self {
        MarkovJumpKfParams {
            common: CommonParams::paper_2014(),
            ..MarkovJumpKfParams::default()
        }
    }

    /// Checks every value.
    pub fn validate(&self) -> Result<(), ParamError> {
        self.common.validate()?;
        for s in self.encoder_sigma {
            sigma("encoder_sigma", s)?;
        }
        Ok(())
    }
}

diagnostic_set! {
    /// Diagnostics of [`MarkovJumpKf`]: its own, then the [`SegmentDiag`]
    /// shared by the segment filters.
    pub enum MjlsDiag {
        /// The Markov mode `Xi(k)` (000 eq 29) as [`super::MjlsMode::code`]: the
        /// selected segment 0..3 (trunk..foot) when it passes the
        /// reliability test (000 eq 30), -1 otherwise.
        Mode = "mode",
        /// `rho(k) = min_i rho_i` (m/s^2, 000 eq 28).
        RhoMin = "rho_min",
        /// The accelerometer row of the trunk (the selected mode) updated the filter.
        UpdTrunk = "upd_trunk",
        /// The accelerometer row of the thigh (the selected mode) updated the filter.
        UpdThigh = "upd_thigh",
        /// The accelerometer row of the shank (the selected mode) updated the filter.
        UpdShank = "upd_shank",
        /// The accelerometer row of the foot (the selected mode) updated the filter.
        UpdFoot = "upd_foot",
        /// The hip encoder row updated the filter.
        UpdHip = "upd_hip",
        /// The knee encoder row updated the filter.
        UpdKnee = "upd_knee",
        /// The ankle encoder row updated the filter.
        UpdAnkle = "upd_ankle",
    }
    extends
    /// The diagnostics shared by the segment filters.
    Segment(SegmentDiag)
}

impl MjlsDiag {
    /// `upd_*` of the accelerometer row per selected segment (index
    /// [`limbfuse_core::Segment::index`]).
    pub const UPDATED_SEGMENT: [MjlsDiag; 4] = [
        MjlsDiag::UpdTrunk,
        MjlsDiag::UpdThigh,
        MjlsDiag::UpdShank,
        MjlsDiag::UpdFoot,
    ];
    /// `upd_*` of the encoder rows (index [`limbfuse_core::Joint::index`]).
    pub const UPDATED_JOINT: [MjlsDiag; 3] =
        [MjlsDiag::UpdHip, MjlsDiag::UpdKnee, MjlsDiag::UpdAnkle];
}

/// The Markov-jump Kalman filter of 000 (eqs 14-30). Method name `mjls`.
#[derive(Debug, Clone)]
pub struct MarkovJumpKf {
    params: MarkovJumpKfParams,
    chain: Chain,
    gate: AccelGateState,
    last: Gain<4>,
}

impl Default for MarkovJumpKf {
    fn default() -> Self {
        Self::build(MarkovJumpKfParams::default())
    }
}

impl MarkovJumpKf {
    /// A filter with the given parameters, after validating them.
    pub fn new(params: MarkovJumpKfParams) -> Result<Self, ParamError> {
        params.validate()?;
        Ok(Self::build(params))
    }

    fn build(params: MarkovJumpKfParams) -> Self {
        MarkovJumpKf {
            chain: Chain::with_encoder_start(params.common, params.encoder_sigma).with_spike_test(),
            params,
            gate: AccelGateState::default(),
            last: Gain::zero(),
        }
    }

    /// The parameters in use.
    pub fn params(&self) -> &MarkovJumpKfParams {
        &self.params
    }

    /// Gain `K` (8x4, columns: accelerometer row, hip, knee, ankle) of the
    /// last update; zero when the last sample made none.
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

    /// `R(Xi)` of 000 eq 27 (row 0 is 1 when no mode is selected; it is
    /// masked then).
    fn noise(&self, mode: Option<usize>) -> SMatrix<f64, 4, 4> {
        let mut R = SMatrix::<f64, 4, 4>::zeros();
        R[(0, 0)] = match mode {
            Some(i) => {
                let s = self.params.common.segments[i].accel_angle_sigma;
                s * s
            }
            None => 1.0,
        };
        for j in 0..3 {
            R[(1 + j, 1 + j)] = self.params.encoder_sigma[j] * self.params.encoder_sigma[j];
        }
        R
    }
}

impl Estimator for MarkovJumpKf {
    fn name(&self) -> &'static str {
        "mjls"
    }

    fn outputs(&self) -> Outputs {
        Outputs::ALL_ANGLES
    }

    fn describe_parameters(&self, out: &mut dyn fmt::Write) -> fmt::Result {
        writeln!(out, "model: MJLS-based KF (Nogueira et al. 2014 eqs 14-30)")?;
        writeln!(
            out,
            "when_unreliable: {}",
            self.params.when_unreliable.label()
        )?;
        writeln!(out, "hip.encoder_sigma: {}", self.params.encoder_sigma[0])?;
        writeln!(out, "knee.encoder_sigma: {}", self.params.encoder_sigma[1])?;
        writeln!(out, "ankle.encoder_sigma: {}", self.params.encoder_sigma[2])?;
        self.params.common.describe(out)
    }

    fn diagnostic_names(&self) -> &[&'static str] {
        &MjlsDiag::NAMES
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
        let mut est = Estimate::empty(sample.t);
        self.step_into(sample, &mut est)?;
        Ok(est)
    }

    fn step_into(&mut self, sample: &Sample, est: &mut Estimate) -> Result<(), EstimatorError> {
        let inp = self.chain.begin(sample)?;
        let zeta = self.params.common.zetas();
        let gate = self.params.common.accel_gate;
        let sel = if gate.is_off() {
            mjls_select(&inp.rho, &zeta)
        } else {
            // Segments failing the refined test take no part in the mode choice.
            let ok = self.gate.passes_sample(&gate, sample, &inp.rho, &zeta);
            let mut rho = inp.rho;
            for (r, o) in rho.iter_mut().zip(ok) {
                if !o {
                    *r = None;
                }
            }
            mjls_select(&rho, &zeta)
        };
        let mode = sel.mode().map(|s| s.index());
        let encoders_allowed =
            mode.is_some() || self.params.when_unreliable == WhenUnreliable::EncodersOnly;
        let mut active = [false; 4];
        let mut innov = SVector::<f64, 4>::zeros();
        if let Some(i) = mode {
            if let (true, Some(th)) = (inp.usable[i], inp.theta_a(i)) {
                active[0] = true;
                innov[0] = wrap(th - self.chain.angle(i));
            }
        }
        for j in 0..3 {
            if let (true, true, true, Some(e)) = (
                encoders_allowed,
                inp.usable[j],
                inp.usable[j + 1],
                inp.encoder[j],
            ) {
                active[1 + j] = true;
                innov[1 + j] = wrap(e - (self.chain.angle(j) - self.chain.angle(j + 1)));
            }
        }
        let rows = mjls_rows(sel.mode());
        let R = self.noise(mode);
        let r = [R[(0, 0)], R[(1, 1)], R[(2, 2)], R[(3, 3)]];
        let kinds = [
            RowKind::Imu(mode.unwrap_or(0)),
            RowKind::Joint,
            RowKind::Joint,
            RowKind::Joint,
        ];
        let made = self.chain.update(
            &innov,
            &rows,
            &r,
            &mut active,
            &[false, true, true, true],
            &mut self.last,
        );
        let (updated, shares) = after_update(made, active, &mut self.last, &kinds);
        self.chain.estimate_into(sample.t, est);
        let mut d = est.diagnostics_mut::<MjlsDiag>();
        d.value(MjlsDiag::Mode, sel.code());
        d.set(MjlsDiag::RhoMin, sel.rho_min);
        for (i, key) in MjlsDiag::UPDATED_SEGMENT.into_iter().enumerate() {
            d.flag(key, updated[0] && mode == Some(i));
        }
        for (key, u) in MjlsDiag::UPDATED_JOINT.into_iter().zip(&updated[1..]) {
            d.flag(key, *u);
        }
        write_segment_diagnostics(&mut d, &self.chain, &inp, true, &shares);
        Ok(())
    }
}
