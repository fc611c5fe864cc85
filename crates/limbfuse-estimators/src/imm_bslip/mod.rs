//! `imm-bslip`: gait phase and walking speed from CoM measurements by an
//! interacting multiple-model estimator over a B-SLIP gait library
//! (paper 003, Karulkar & Wensing, sec III). docs/GAIT_IMM.md.
//!
//! One continuous-discrete EKF ([`ekf`], Table I) per (gait, phase), M = N x 3.
//! Per sample: each filter propagates its mixed initial estimate by the
//! sample's `dt`; the measurement likelihood of eq 7 (with the SPEC section 6
//! sign fix) times the physical likelihood of eq 14 gives each model's
//! weight by eq 8 (normalised, without the previous weights) computed in the
//! log domain (log-sum-exp), so weights sum to one and stay finite when every
//! likelihood underflows; the filters update (Table I); the ensemble is
//! eqs 9-10; Markov mixing (eqs 11-13) gives the next initial estimates.
//!
//! Feet (`imm_bslip/feet.rs`). A (gait, phase) model needs its feet on the ground; SS1
//! uses the stance (trailing) foot, DS both, SS2 the leading foot. Each gait
//! places them by its own template applied to the ensemble CoM; when its
//! leading foot lands is the [`TouchdownRule`] (the gait's touchdown height,
//! default; its step clock; or mixed by the IMM from the weights). At the
//! first sample the stance foot lies under the measured CoM at the gait's MS
//! lateral offset (the trial starts at MS of SS1 on the `first_side` foot, as
//! in the paper's simulation).
//!
//! Degradation (documented, tested): samples without CoM channels only
//! predict (weights propagated by the Markov chain); a gap longer than
//! `max_gap` restarts the bank at the next measured position; a model whose
//! state turns non-finite gets weight zero and is re-seeded by mixing.
#![allow(non_snake_case)]

pub mod continuous;
pub mod ekf;
mod ensemble;
mod feet;
mod height_crossings;
mod mode_probabilities;
mod names;
pub mod params;
mod start_phase;
mod sway_extremum;
pub mod sway_restart;
mod weight_support;

extern crate alloc;

use alloc::vec::Vec;
use core::fmt;

use limbfuse_core::estimator::Outputs;
use limbfuse_core::{Estimate, Estimator, EstimatorError, GaitPhase, Sample, TimeStep};
use limbfuse_models::bslip::{GaitTemplate, State};
use nalgebra::{Matrix6, Vector3};

pub use continuous::ImmContinuous;
use ekf::{propagate, update, Cov};
use feet::{Feet, FootPlacement};
pub use names::{ImmDiag, MAX_GAITS, SPEED_MEAN, WEIGHT_NAMES};
pub use params::{ImmBslipParams, ImmWeights, MidStanceEvent, TouchdownRule};
pub use sway_restart::{RestartOnSide, SwayRestart};

/// Why an IMM could not be built.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum ImmBslipError {
    /// The library is empty.
    #[error("the gait library has no gaits")]
    EmptyLibrary,
    /// More gaits than the estimate has diagnostic columns for.
    #[error("the gait library has {0} gaits; at most {MAX_GAITS} are supported")]
    TooManyGaits(usize),
    /// A parameter is out of range.
    #[error("parameter {0}")]
    Parameter(&'static str),
}

const PHASES: [GaitPhase; 3] = [GaitPhase::Ss1, GaitPhase::Ds, GaitPhase::Ss2];

fn phase_index(p: GaitPhase) -> usize {
    match p {
        GaitPhase::Ss1 => 0,
        GaitPhase::Ds => 1,
        GaitPhase::Ss2 => 2,
    }
}

/// One (gait, phase) filter.
#[derive(Debug, Clone, Copy)]
struct Model {
    gait: usize,
    phase: GaitPhase,
    /// Mixed initial estimate (eqs 11, 13).
    x0: State,
    P0: Cov,
    /// Posterior estimate.
    x: State,
    P: Cov,
    log_l: f64,
    w: f64,
}

/// The B-SLIP IMM estimator (`imm-bslip`).
#[derive(Debug, Clone)]
pub struct ImmBslip {
    params: ImmBslipParams,
    templates: Vec<GaitTemplate>,
    models: Vec<Model>,
    feet: Vec<Feet>,
    /// Markov transition probabilities `p_ij`, row-major (i from, j to).
    transition: Vec<f64>,
    names: Vec<&'static str>,
    Q: Cov,
    time: TimeStep,
    last_t: Option<f64>,
    running: bool,
    ensemble: (State, Cov),
    /// Feet set from outside ([`ImmContinuous`]) instead of by the
    /// touchdown rule.
    external_feet: bool,
}

impl ImmBslip {
    /// An IMM over every (gait, phase) of `library`.
    pub fn new(library: &[GaitTemplate], params: ImmBslipParams) -> Result<Self, ImmBslipError> {
        if library.is_empty() {
            return Err(ImmBslipError::EmptyLibrary);
        }
        if library.len() > MAX_GAITS {
            return Err(ImmBslipError::TooManyGaits(library.len()));
        }
        let mut models = Vec::with_capacity(3 * library.len());
        for g in 0..library.len() {
            for p in PHASES {
                models.push((g, p));
            }
        }
        Self::build(library, &models, params)
    }

    /// An IMM with the single model (`template`, `phase`): it must equal that
    /// model's EKF.
    pub fn single(
        template: &GaitTemplate,
        phase: GaitPhase,
        params: ImmBslipParams,
    ) -> Result<Self, ImmBslipError> {
        Self::build(core::slice::from_ref(template), &[(0, phase)], params)
    }

    fn build(
        library: &[GaitTemplate],
        models: &[(usize, GaitPhase)],
        params: ImmBslipParams,
    ) -> Result<Self, ImmBslipError> {
        params.validate().map_err(ImmBslipError::Parameter)?;
        let m = models.len();
        let mut transition = alloc::vec![0.0; m * m];
        for (i, &(gi, pi)) in models.iter().enumerate() {
            let next = PHASES[(phase_index(pi) + 1) % 3];
            let others = library.len().saturating_sub(1).max(1) as f64;
            for (j, &(gj, pj)) in models.iter().enumerate() {
                transition[i * m + j] = if gi == gj && pi == pj {
                    1.0 - params.p_next_phase - params.p_other_gait
                } else if gi == gj && pj == next {
                    params.p_next_phase
                } else if gi != gj && pi == pj {
                    params.p_other_gait / others
                } else {
                    0.0
                };
            }
            let row = &mut transition[i * m..(i + 1) * m];
            let s: f64 = row.iter().sum();
            row.iter_mut().for_each(|p| *p /= s);
        }
        let names = models
            .iter()
            .map(|&(g, p)| WEIGHT_NAMES[3 * g + phase_index(p)])
            .chain(core::iter::once(SPEED_MEAN))
            .collect();
        let zero = Model {
            gait: 0,
            phase: GaitPhase::Ss1,
            x0: State::zeros(),
            P0: Cov::zeros(),
            x: State::zeros(),
            P: Cov::zeros(),
            log_l: 0.0,
            w: 0.0,
        };
        Ok(ImmBslip {
            params,
            templates: library.to_vec(),
            models: models
                .iter()
                .map(|&(gait, phase)| Model {
                    gait,
                    phase,
                    ..zero
                })
                .collect(),
            feet: library
                .iter()
                .map(|_| Feet::new(params.first_side))
                .collect(),
            transition,
            names,
            Q: Matrix6::from_diagonal(&params.q.into()),
            time: TimeStep::new(),
            last_t: None,
            running: false,
            ensemble: (State::zeros(), Cov::zeros()),
            external_feet: false,
        })
    }

    /// The library's templates.
    pub fn templates(&self) -> &[GaitTemplate] {
        &self.templates
    }

    /// Current weight of every model, in diagnostic-column order.
    pub fn weights(&self) -> impl Iterator<Item = f64> + '_ {
        self.models.iter().map(|m| m.w)
    }

    /// The column of diagnostic `d` in [`Estimate::diag`] (`None` for a
    /// weight of a model the IMM does not have).
    pub fn diagnostic_column(&self, d: ImmDiag) -> Option<usize> {
        match d {
            ImmDiag::Weight(k) => (k < self.models.len()).then_some(k),
            ImmDiag::SpeedMean => Some(self.models.len()),
        }
    }

    /// Each library gait's summed weight.
    fn gait_weights(&self) -> [f64; MAX_GAITS] {
        let mut w = [0.0; MAX_GAITS];
        for m in &self.models {
            w[m.gait] += m.w;
        }
        w
    }

    /// The library gait with the largest summed weight (the first of equals).
    fn dominant(&self) -> usize {
        let w = self.gait_weights();
        let mut best = 0;
        for g in 1..self.templates.len() {
            if w[g] > w[best] {
                best = g;
            }
        }
        best
    }

    /// The library's template with the largest summed weight.
    pub fn dominant_gait(&self) -> &GaitTemplate {
        &self.templates[self.dominant()]
    }

    /// Ensemble covariance (eq 10) of the last sample.
    pub fn ensemble_covariance(&self) -> &Cov {
        &self.ensemble.1
    }

    fn start(&mut self, now: f64, z: &[Option<f64>; 6]) {
        let pos = Vector3::new(
            z[0].unwrap_or(0.0),
            z[1].unwrap_or(0.0),
            z[2].unwrap_or(0.0),
        );
        let P0 = Matrix6::from_diagonal(&nalgebra::Vector6::new(
            self.params.p0[0],
            self.params.p0[0],
            self.params.p0[0],
            self.params.p0[1],
            self.params.p0[1],
            self.params.p0[1],
        ));
        for (f, t) in self.feet.iter_mut().zip(&self.templates) {
            f.start(t, [pos[0], pos[2]], now, self.params.touchdown);
        }
        let w = 1.0 / self.models.len() as f64;
        for m in &mut self.models {
            let t = &self.templates[m.gait];
            let v = [
                z[3].unwrap_or(t.gait.forward_speed),
                z[4].unwrap_or(0.0),
                z[5].unwrap_or(0.0),
            ];
            m.x0 = State::new(pos[0], pos[1], pos[2], v[0], v[1], v[2]);
            m.P0 = P0;
            m.w = w;
        }
        self.running = true;
    }

    /// Every gait's feet: trailing `stance`, leading `leading` (both down;
    /// [`ImmContinuous`]).
    fn set_feet(&mut self, stance: [f64; 2], leading: [f64; 2]) {
        for f in &mut self.feet {
            f.stance = stance;
            f.landed = Some(leading);
            f.ss2 = None;
        }
    }

    /// Per gait, after the ensemble update: [`Feet::advance`].
    fn advance_feet(&mut self, now: f64, previous_vy: f64) {
        if self.external_feet {
            return;
        }
        let x = self.ensemble.0;
        let placement = FootPlacement {
            rule: self.params.touchdown,
            stay: 1.0 - self.params.p_next_phase - self.params.p_other_gait,
            next: self.params.p_next_phase,
            mid_stance: self.params.mid_stance,
        };
        let mut w = [[0.0; 3]; MAX_GAITS];
        for m in &self.models {
            w[m.gait][phase_index(m.phase)] = m.w;
        }
        for ((f, t), w) in self.feet.iter_mut().zip(&self.templates).zip(w) {
            f.advance(t, placement, &x, previous_vy, now, w);
        }
    }
}

impl Estimator for ImmBslip {
    fn name(&self) -> &'static str {
        "imm-bslip"
    }

    fn outputs(&self) -> Outputs {
        Outputs {
            phase: true,
            speed: true,
            com: true,
            ..Outputs::default()
        }
    }

    fn describe_parameters(&self, out: &mut dyn fmt::Write) -> fmt::Result {
        let p = &self.params;
        writeln!(out, "r: {:?}", p.r)?;
        writeln!(out, "q: {:?}", p.q)?;
        writeln!(out, "kappa: {}", p.kappa)?;
        writeln!(out, "weights: {}", p.weights.label())?;
        writeln!(out, "touchdown: {}", p.touchdown.label())?;
        writeln!(out, "p_next_phase: {}", p.p_next_phase)?;
        writeln!(out, "p_other_gait: {}", p.p_other_gait)?;
        writeln!(out, "max_substep: {}", p.max_substep)?;
        writeln!(out, "max_gap: {}", p.max_gap)?;
        for (g, t) in self.templates.iter().enumerate() {
            writeln!(
                out,
                "gait g{g:02}: speed {:.3} m/s, step {:.3} x {:.3} m, l0 {:.3} m, k {:.0} N/m",
                t.speed, t.step_length, t.step_width, t.body.rest_length, t.body.stiffness
            )?;
        }
        Ok(())
    }

    fn diagnostic_names(&self) -> &[&'static str] {
        &self.names
    }

    fn reset(&mut self) {
        self.time.reset();
        self.last_t = None;
        self.running = false;
        for f in &mut self.feet {
            f.side = self.params.first_side;
        }
    }

    fn step(&mut self, sample: &Sample) -> Result<Estimate, EstimatorError> {
        let dt = self.time.advance(sample.t)?;
        let z = sample.com.values();
        for (v, name) in z.iter().zip(limbfuse_core::ComMeasurement::NAMES) {
            if v.is_some_and(|v| !v.is_finite()) {
                return Err(EstimatorError::NonFinite { channel: name });
            }
        }
        let has_position = z[..3].iter().all(Option::is_some);
        let gap = dt.is_some_and(|dt| dt > self.params.max_gap);
        let propagate_dt = if !self.running || gap {
            if !has_position {
                self.running = false;
                return Ok(Estimate::empty(sample.t));
            }
            self.start(sample.t, &z);
            0.0
        } else {
            dt.unwrap_or(0.0)
        };
        let measured = z.iter().any(Option::is_some);
        let max_substep = self.params.max_substep;
        for k in 0..self.models.len() {
            let m = self.models[k];
            let t = &self.templates[m.gait];
            let stance = self.feet[m.gait].stance_for(m.phase);
            let (mut x, mut P) = (m.x0, m.P0);
            propagate(
                &t.body,
                &stance,
                &mut x,
                &mut P,
                &self.Q,
                propagate_dt,
                max_substep,
            );
            let lambda_p = self.physical_log_likelihood(&m, &x);
            let log_l = if measured {
                update(&mut x, &mut P, &z, &self.params.r) + lambda_p
            } else {
                0.0
            };
            let finite = x.iter().all(|v| v.is_finite()) && P.iter().all(|v| v.is_finite());
            let model = &mut self.models[k];
            model.x = x;
            model.P = P;
            model.log_l = if finite { log_l } else { f64::NEG_INFINITY };
        }
        if measured && self.params.weights == ImmWeights::Recursive {
            self.add_predicted_weights();
        }
        if measured {
            self.normalise_weights();
        } else {
            self.predict_weights();
        }
        for m in &mut self.models {
            if !(m.x.iter().all(|v| v.is_finite())) {
                m.w = 0.0;
            }
        }
        let previous_vy = self.ensemble.0[4];
        self.fuse();
        self.advance_feet(sample.t, previous_vy);
        self.mix();
        self.last_t = Some(sample.t);
        Ok(self.estimate(sample.t))
    }
}

#[cfg(test)]
mod tests;
