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

pub mod ekf;
mod feet;
mod names;
pub mod params;

extern crate alloc;

use alloc::vec::Vec;
use core::fmt;

use limbfuse_core::estimator::Outputs;
use limbfuse_core::{Estimate, Estimator, EstimatorError, GaitPhase, Sample, TimeStep};
use limbfuse_models::bslip::{leg_compression, GaitTemplate, State};
use nalgebra::{Matrix6, Vector3};

use ekf::{propagate, update, Cov};
use feet::{Feet, FootPlacement};
pub use names::{MAX_GAITS, WEIGHT_NAMES};
pub use params::{ImmBslipParams, ImmWeights, TouchdownRule};

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
            .chain(core::iter::once("speed_mean"))
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

    /// Eq 14's `lambda_p = -kappa min(0, dl)^2`, `dl` the smallest leg
    /// compression of the model's stance legs at `x`.
    fn physical_log_likelihood(&self, m: &Model, x: &State) -> f64 {
        if self.params.kappa == 0.0 {
            return 0.0;
        }
        let t = &self.templates[m.gait];
        let stance = self.feet[m.gait].stance_for(m.phase);
        let dl = stance
            .feet()
            .map(|f| leg_compression(&t.body, x, f))
            .fold(f64::INFINITY, f64::min);
        let d = dl.min(0.0);
        -self.params.kappa * d * d
    }

    /// [`ImmWeights::Recursive`]: adds `log c_j`, `c_j = sum_i p_ij w_i` (the
    /// Markov-predicted weight, eq 11's normaliser), to each model's log
    /// likelihood before [`Self::normalise_weights`], so that
    /// `w_j ~ c_j L_j`, the standard IMM mode probability.
    fn add_predicted_weights(&mut self) {
        for j in 0..self.models.len() {
            let c = self.predicted_weight(j);
            // c = 0 gives -inf (weight 0); every weight zero is handled by
            // normalise_weights (uniform).
            self.models[j].log_l += libm::log(c);
        }
    }

    /// Eq 8 in the log domain: `w_j = exp(l_j - max) / sum`.
    fn normalise_weights(&mut self) {
        let max = self
            .models
            .iter()
            .map(|m| m.log_l)
            .filter(|l| !l.is_nan())
            .fold(f64::NEG_INFINITY, f64::max);
        if !max.is_finite() {
            let w = 1.0 / self.models.len() as f64;
            self.models.iter_mut().for_each(|m| m.w = w);
            return;
        }
        let mut sum = 0.0;
        for m in &mut self.models {
            m.w = if m.log_l.is_nan() {
                0.0
            } else {
                libm::exp(m.log_l - max)
            };
            sum += m.w;
        }
        self.models.iter_mut().for_each(|m| m.w /= sum);
    }

    /// Markov prediction of the weights, `w_j = sum_i p_ij w_i` (samples
    /// without measurements).
    fn predict_weights(&mut self) {
        for j in 0..self.models.len() {
            self.models[j].log_l = self.predicted_weight(j);
        }
        let total: f64 = self.models.iter().map(|m| m.log_l).sum();
        for m in &mut self.models {
            m.w = m.log_l / total;
            m.log_l = libm::log(m.w);
        }
    }

    /// Eqs 9-10.
    fn fuse(&mut self) {
        let mut x = State::zeros();
        for m in self.models.iter().filter(|m| m.w > 0.0) {
            x += m.x * m.w;
        }
        let mut P = Cov::zeros();
        for m in self.models.iter().filter(|m| m.w > 0.0) {
            let d = m.x - x;
            P += (d * d.transpose() + m.P) * m.w;
        }
        self.ensemble = (x, P);
    }

    /// Per gait, after the ensemble update: [`Feet::advance`].
    fn advance_feet(&mut self, now: f64, previous_vy: f64) {
        let x = self.ensemble.0;
        let placement = FootPlacement {
            rule: self.params.touchdown,
            stay: 1.0 - self.params.p_next_phase - self.params.p_other_gait,
            next: self.params.p_next_phase,
        };
        let mut w = [[0.0; 3]; MAX_GAITS];
        for m in &self.models {
            w[m.gait][phase_index(m.phase)] = m.w;
        }
        for ((f, t), w) in self.feet.iter_mut().zip(&self.templates).zip(w) {
            f.advance(t, placement, &x, previous_vy, now, w);
        }
    }

    /// The Markov-predicted weight of model `j`, `c_j = sum_i p_ij w_i`
    /// (eq 11's normaliser).
    fn predicted_weight(&self, j: usize) -> f64 {
        let n = self.models.len();
        let mut c = 0.0;
        for i in 0..n {
            c += self.models[i].w * self.transition[i * n + j];
        }
        c
    }

    /// Eqs 11-13.
    fn mix(&mut self) {
        let n = self.models.len();
        for j in 0..n {
            let c = self.predicted_weight(j);
            if c.is_nan() || c <= 0.0 {
                let own = self.models[j];
                let finite = own.x.iter().all(|v| v.is_finite());
                self.models[j].x0 = if finite { own.x } else { self.ensemble.0 };
                self.models[j].P0 = if finite { own.P } else { self.ensemble.1 };
                continue;
            }
            let mut x0 = State::zeros();
            for i in 0..n {
                let wij = self.models[i].w * self.transition[i * n + j] / c;
                if wij > 0.0 {
                    x0 += self.models[i].x * wij;
                }
            }
            let mut P0 = Cov::zeros();
            for i in 0..n {
                let wij = self.models[i].w * self.transition[i * n + j] / c;
                if wij > 0.0 {
                    let e = self.models[i].x - x0;
                    P0 += (e * e.transpose() + self.models[i].P) * wij;
                }
            }
            self.models[j].x0 = x0;
            self.models[j].P0 = P0;
        }
    }

    fn estimate(&self, t: f64) -> Estimate {
        let mut e = Estimate::empty(t);
        let n_gaits = self.templates.len();
        let mut phase_w = [0.0; 3];
        let mut best_gait = (0usize, -1.0);
        let mut mean_speed = 0.0;
        for g in 0..n_gaits {
            let w: f64 = self
                .models
                .iter()
                .filter(|m| m.gait == g)
                .map(|m| m.w)
                .sum();
            mean_speed += w * self.templates[g].speed;
            if w > best_gait.1 {
                best_gait = (g, w);
            }
        }
        for m in &self.models {
            phase_w[phase_index(m.phase)] += m.w;
        }
        let mut best_phase = 0;
        for p in 1..3 {
            if phase_w[p] > phase_w[best_phase] {
                best_phase = p;
            }
        }
        e.phase = Some(PHASES[best_phase]);
        e.speed = Some(self.templates[best_gait.0].speed);
        let x = self.ensemble.0;
        e.com_pos = Some(Vector3::new(x[0], x[1], x[2]));
        e.com_vel = Some(Vector3::new(x[3], x[4], x[5]));
        for (d, m) in e.diag.iter_mut().zip(&self.models) {
            *d = Some(m.w);
        }
        if let Some(d) = e.diag.get_mut(self.models.len()) {
            *d = Some(mean_speed);
        }
        e
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
mod tests {
    use super::*;
    use limbfuse_models::bslip::{BslipParams, GaitParameters, Side};

    /// A gait whose touchdown height (`sin(1.2) cos(0.05)` = 0.931 m) lies
    /// below the level CoM path of [`level_walk`] (0.96 m).
    fn template() -> GaitTemplate {
        let gait = GaitParameters {
            phi: 1.2,
            theta: 0.05,
            stiffness: 20_000.0,
            height: 0.96,
            lateral: 0.05,
            forward_speed: 0.6,
        };
        GaitTemplate {
            speed: 0.6,
            body: BslipParams::default(),
            gait,
            step_length: 0.5,
            step_width: 0.1,
            step_time: 0.8,
            t_touchdown: 0.295,
            t_lift_off: 0.45,
        }
    }

    /// Feeds a level CoM path at 0.6 m/s (no vertical motion, so no MS event
    /// and no fall to the touchdown height) and returns, per sample, whether
    /// the gait's leading foot has landed.
    fn level_walk(rule: TouchdownRule) -> Vec<(f64, bool)> {
        let params = ImmBslipParams {
            touchdown: rule,
            ..ImmBslipParams::full_com()
        };
        let mut imm = ImmBslip::new(&[template()], params).unwrap();
        (0..40)
            .map(|k| {
                let t = k as f64 * 0.01;
                let mut s = Sample::empty(t);
                s.com.pos = [Some(0.6 * t), Some(0.96), Some(0.05)];
                s.com.vel = [Some(0.6), Some(0.0), None];
                imm.step(&s).unwrap();
                (t, imm.feet[0].landed.is_some())
            })
            .collect()
    }

    #[test]
    fn step_clock_lands_the_foot_t_touchdown_after_the_start() {
        for (t, landed) in level_walk(TouchdownRule::StepClock) {
            assert_eq!(landed, t >= 0.295, "t = {t}");
        }
    }

    /// Paper-free check of the mixed rule against a hand computation: DS's
    /// foot is `(w_DS stay ds + w_SS1 next swing) / (w_DS stay + w_SS1
    /// next)`, SS2's `(w_SS2 stay ss2 + w_DS next ds) / (..)`.
    #[test]
    fn mixed_rule_blends_feet_by_the_weights_flowing_between_phases() {
        let t = template();
        let mut f = Feet::new(Side::Left);
        f.start(&t, [0.0, 0.05], 0.0, TouchdownRule::Mixed);
        assert_eq!(f.landed, Some(f.swinging));
        assert_eq!(f.ss2, Some(f.swinging));
        let (ds, ss2) = ([0.40, 0.10], [0.30, 0.12]);
        f.landed = Some(ds);
        f.ss2 = Some(ss2);
        let placement = FootPlacement {
            rule: TouchdownRule::Mixed,
            stay: 0.94,
            next: 0.05,
        };
        // Rising CoM: no MS.
        let x = State::new(0.1, 0.96, 0.05, 0.6, 0.1, 0.0);
        f.advance(&t, placement, &x, 0.2, 0.01, [0.6, 0.3, 0.1]);
        let (dx, dz) = t.gait.touchdown_offset(1.0, Side::Left);
        let swing = [0.1 + dx, 0.05 + dz];
        let (a, b) = (0.3 * 0.94, 0.6 * 0.05);
        let (c, d) = (0.1 * 0.94, 0.3 * 0.05);
        for i in 0..2 {
            let want_ds = (a * ds[i] + b * swing[i]) / (a + b);
            let want_ss2 = (c * ss2[i] + d * ds[i]) / (c + d);
            assert!((f.landed.unwrap()[i] - want_ds).abs() < 1e-15);
            assert!((f.ss2.unwrap()[i] - want_ss2).abs() < 1e-15);
        }
        assert_eq!(f.stance[1], 0.05 - Side::Left.sign() * t.gait.lateral);
        // The apex near SS2's foot is MS: SS2's foot becomes the stance foot.
        let ms = f.ss2.unwrap();
        let x = State::new(ms[0], 0.96, 0.05, 0.6, -0.01, 0.0);
        f.advance(&t, placement, &x, 0.01, 0.02, [0.0, 0.1, 0.9]);
        assert_eq!(f.side, Side::Right);
        assert_eq!(f.ms_t, 0.02);
        assert!((f.stance[0] - ms[0]).abs() < 0.05);
        assert_eq!(f.landed, Some(f.swinging));
    }

    #[test]
    fn height_rule_waits_for_the_com_to_fall_to_the_touchdown_height() {
        assert!(template().gait.touchdown_height(1.0) < 0.96);
        assert!(level_walk(TouchdownRule::Height).iter().all(|&(_, l)| !l));
    }
}
