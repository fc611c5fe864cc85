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

#[cfg(test)]
mod tests {
    use super::super::tests::template;
    use super::super::{ImmBslip, ImmBslipParams};
    use super::State;

    /// The one-gait bank (models SS1, DS, SS2) with kappa = 1e5 /m^2, the
    /// trailing foot at the origin and the leading foot down at x = 0.2 m.
    fn bank() -> ImmBslip {
        let params = ImmBslipParams::full_com();
        assert_eq!(params.kappa, 1e5);
        let mut imm = ImmBslip::new(&[template()], params).unwrap();
        assert_eq!(imm.templates[0].body.rest_length, 1.0);
        imm.set_feet([0.0, 0.0], [0.2, 0.0]);
        imm
    }

    /// Paper 003 eq 14, `lambda_p = -kappa min(0, dl)^2`, `dl` = rest length
    /// minus leg length, the smallest of the stance legs in DS. By hand with
    /// l0 = 1 m: CoM 1.01 m above the trailing foot, SS1's leg is stretched
    /// 1 cm, `lambda_p = -1e5 * 0.01^2 = -10`; CoM at 0.99 m, compressed,
    /// `lambda_p = 0`; there DS's leading leg is `sqrt(0.2^2 + 0.99^2)` =
    /// 1.01 m (stretched 1 cm) and wins the minimum over the compressed
    /// trailing leg: -10; SS2 stands on that leg alone: -10.
    #[test]
    fn physical_likelihood_matches_eq_14_by_hand() {
        let imm = bank();
        let high = State::new(0.0, 1.01, 0.0, 0.7, 0.0, 0.0);
        let low = State::new(0.0, 0.99, 0.0, 0.7, 0.0, 0.0);
        let [ss1, ds, ss2] = [imm.models[0], imm.models[1], imm.models[2]];
        let lp = |m, x| imm.physical_log_likelihood(m, x);
        assert!((lp(&ss1, &high) + 10.0).abs() < 1e-9, "{}", lp(&ss1, &high));
        assert_eq!(lp(&ss1, &low), 0.0);
        assert!((lp(&ds, &low) + 10.0).abs() < 1e-9, "{}", lp(&ds, &low));
        assert!((lp(&ss2, &low) + 10.0).abs() < 1e-9, "{}", lp(&ss2, &low));
    }

    /// Eqs 8 and 14 together: two models with the same measurement
    /// likelihood (log 3.7), one of them with a leg stretched 1 cm, get the
    /// weights `1 / (1 + e^-10)` and `1 / (1 + e^10)` = 4.5397868702e-5.
    #[test]
    fn a_leg_stretched_one_cm_costs_the_weight_a_factor_e_to_the_10() {
        let mut imm = bank();
        let low = State::new(0.0, 0.99, 0.0, 0.7, 0.0, 0.0);
        let (ss1, ds) = (imm.models[0], imm.models[1]);
        let lambda_r = 3.7;
        let l = [
            lambda_r + imm.physical_log_likelihood(&ss1, &low),
            lambda_r + imm.physical_log_likelihood(&ds, &low),
        ];
        imm.models.truncate(2);
        imm.models[0].log_l = l[0];
        imm.models[1].log_l = l[1];
        imm.normalise_weights();
        let want = 4.539_786_870_243_439_5e-5;
        assert!(
            (imm.models[1].w - want).abs() < 1e-15,
            "{}",
            imm.models[1].w
        );
        assert!((imm.models[0].w - (1.0 - want)).abs() < 1e-15);
    }

    /// Paper 003 eq 8, `w_j = l_j / sum_i l_i`, by hand (numpy): log
    /// likelihoods (-1, -2, -3) give `e^-1 / (e^-1 + e^-2 + e^-3)` ... =
    /// (0.665240955775, 0.244728471055, 0.090030573170). Shifted by -999 the
    /// likelihoods underflow (`e^-1000` = 0 in f64, so the printed formula
    /// gives 0/0) but the weights are the same.
    #[test]
    fn weights_match_eq_8_by_hand_also_when_likelihoods_underflow() {
        let want = [
            0.665_240_955_774_821_9,
            0.244_728_471_054_797_67,
            0.090_030_573_170_380_46,
        ];
        for shift in [0.0, -999.0] {
            let mut imm = bank();
            for (m, l) in imm.models.iter_mut().zip([-1.0, -2.0, -3.0]) {
                m.log_l = l + shift;
            }
            assert_eq!(libm::exp(-1000.0), 0.0);
            imm.normalise_weights();
            for (m, w) in imm.models.iter().zip(want) {
                assert!((m.w - w).abs() < 1e-15, "shift {shift}: {} vs {w}", m.w);
            }
        }
    }
}
