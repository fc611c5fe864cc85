//! The model weights (mode probabilities) of the IMM, paper 003: the
//! physical likelihood (eq 14), the normalised weights (eq 8, log domain),
//! their Markov prediction and the mixing of the initial estimates
//! (eqs 11-13).

use limbfuse_models::bslip::{leg_compression, State};

use super::ekf::Cov;
use super::{ImmBslip, Model};

impl ImmBslip {
    /// Eq 14's `lambda_p = -kappa min(0, dl)^2`, `dl` the smallest leg
    /// compression of the model's stance legs at `x`.
    pub(super) fn physical_log_likelihood(&self, m: &Model, x: &State) -> f64 {
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
    pub(super) fn add_predicted_weights(&mut self) {
        for j in 0..self.models.len() {
            let c = self.predicted_weight(j);
            // c = 0 gives -inf (weight 0); every weight zero is handled by
            // normalise_weights (uniform).
            self.models[j].log_l += libm::log(c);
        }
    }

    /// Eq 8 in the log domain: `w_j = exp(l_j - max) / sum`.
    pub(super) fn normalise_weights(&mut self) {
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
    pub(super) fn predict_weights(&mut self) {
        for j in 0..self.models.len() {
            self.models[j].log_l = self.predicted_weight(j);
        }
        let total: f64 = self.models.iter().map(|m| m.log_l).sum();
        for m in &mut self.models {
            m.w = m.log_l / total;
            m.log_l = libm::log(m.w);
        }
    }

    /// The Markov-predicted weight of model `j`, `c_j = sum_i p_ij w_i`
    /// (eq 11's normaliser).
    pub(super) fn predicted_weight(&self, j: usize) -> f64 {
        let n = self.models.len();
        let mut c = 0.0;
        for i in 0..n {
            c += self.models[i].w * self.transition[i * n + j];
        }
        c
    }

    /// Eqs 11-13.
    pub(super) fn mix(&mut self) {
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
}
