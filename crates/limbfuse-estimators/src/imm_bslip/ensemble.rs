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
