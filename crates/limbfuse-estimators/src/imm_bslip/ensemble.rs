//! The IMM ensemble (paper 003 eqs 9-10) and the estimate built from it:
//! most likely phase and gait, CoM, weights and mean speed as diagnostics.

use limbfuse_core::Estimate;
use nalgebra::Vector3;

use super::ekf::Cov;
use super::{phase_index, ImmBslip, ImmDiag, State, PHASES};

impl ImmBslip {
    /// Eqs 9-10.
    pub(super) fn fuse(&mut self) {
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

    /// The estimate of the last sample: most likely phase (summed weights
    /// per phase) and gait (its library speed), ensemble CoM, and the
    /// diagnostics ([`ImmDiag`]).
    pub(super) fn estimate(&self, t: f64) -> Estimate {
        let mut e = Estimate::empty(t);
        let w = self.gait_weights();
        let mean_speed: f64 = self.templates.iter().zip(w).map(|(t, w)| w * t.speed).sum();
        let mut phase_w = [0.0; 3];
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
        e.speed = Some(self.templates[self.dominant()].speed);
        let x = self.ensemble.0;
        e.com_pos = Some(Vector3::new(x[0], x[1], x[2]));
        e.com_vel = Some(Vector3::new(x[3], x[4], x[5]));
        for (k, m) in self.models.iter().enumerate() {
            if let Some(c) = self.diagnostic_column(ImmDiag::Weight(k)) {
                e.diag[c] = Some(m.w);
            }
        }
        if let Some(c) = self.diagnostic_column(ImmDiag::SpeedMean) {
            e.diag[c] = Some(mean_speed);
        }
        e
    }
}

#[cfg(test)]
mod tests {
    use super::super::tests::template;
    use super::super::{ImmBslip, ImmBslipParams};
    use super::{Cov, State};

    /// Two models of the one-gait bank, with the 2x2 transition matrix
    /// `p = [[0.9, 0.1], [0.2, 0.8]]`, weights `(0.25, 0.75)`, states 0 and
    /// 1 in component 0 (zero elsewhere) and `P = I`.
    fn two_models() -> ImmBslip {
        let mut imm = ImmBslip::new(&[template()], ImmBslipParams::full_com()).unwrap();
        imm.models.truncate(2);
        imm.transition = alloc::vec![0.9, 0.1, 0.2, 0.8];
        for (m, (w, x)) in imm.models.iter_mut().zip([(0.25, 0.0), (0.75, 1.0)]) {
            m.w = w;
            m.x = State::zeros();
            m.x[0] = x;
            m.P = Cov::identity();
        }
        imm
    }

    /// Paper 003 eqs 9-10 by hand: `x = 0.25 * 0 + 0.75 * 1 = 0.75`,
    /// `P = 0.25 (0.75^2 + 1) + 0.75 (0.25^2 + 1) = 1.1875` in component 0;
    /// the other components keep `P = I` and `x = 0`.
    #[test]
    fn ensemble_of_two_models_matches_eqs_9_and_10_by_hand() {
        let mut imm = two_models();
        imm.fuse();
        let (x, P) = imm.ensemble;
        assert!((x[0] - 0.75).abs() < 1e-15);
        assert!(x.rows(1, 5).amax() == 0.0);
        let mut want = Cov::identity();
        want[(0, 0)] = 1.1875;
        assert!((P - want).amax() < 1e-15, "{P}");
    }

    /// Paper 003 eqs 11-13 by hand. Normalisers `c_j = sum_i w_i p_ij`:
    /// `c_1 = 0.25 * 0.9 + 0.75 * 0.2 = 0.375`, `c_2 = 0.25 * 0.1 +
    /// 0.75 * 0.8 = 0.625`; mixing weights (eq 12) `(0.6, 0.4)` into model 1
    /// and `(0.04, 0.96)` into model 2; so `x0 = (0.4, 0.96)` and (eq 13)
    /// `P0_1 = 0.6 (0.4^2 + 1) + 0.4 (0.6^2 + 1) = 1.24`,
    /// `P0_2 = 0.04 (0.96^2 + 1) + 0.96 (0.04^2 + 1) = 1.0384`.
    #[test]
    fn markov_mixing_of_two_models_matches_eqs_11_to_13_by_hand() {
        let mut imm = two_models();
        assert!((imm.predicted_weight(0) - 0.375).abs() < 1e-15);
        assert!((imm.predicted_weight(1) - 0.625).abs() < 1e-15);
        imm.mix();
        for (m, (x0, p0)) in imm.models.iter().zip([(0.4, 1.24), (0.96, 1.0384)]) {
            assert!((m.x0[0] - x0).abs() < 1e-15, "{}", m.x0[0]);
            assert!(m.x0.rows(1, 5).amax() == 0.0);
            let mut want = Cov::identity();
            want[(0, 0)] = p0;
            assert!((m.P0 - want).amax() < 1e-14, "{}", m.P0);
        }
    }
}
