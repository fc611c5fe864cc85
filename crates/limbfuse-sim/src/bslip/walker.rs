//! Continuous B-SLIP walking on a library gait, phase by phase with located
//! events, for trial simulation and for sampling a gait's trajectories.
//!
//! Each step ends at MS on the leading foot; the next step starts from the
//! gait's exact periodic MS state mirrored to the other side (the jump is
//! the periodicity residual, <= 1e-8 m), so a long trial does not drift off
//! the periodic orbit of an open-loop-unstable gait.

use limbfuse_core::GaitPhase;
use limbfuse_models::bslip::{
    derivative, lift_off_function, mid_stance_function, touchdown_function, GaitTemplate, Side,
    Stance, State,
};

use super::integrator::{advance, Stop, Tolerances};
use super::step::initial_state;

/// A walker on one gait.
#[derive(Debug, Clone)]
pub struct Walker {
    template: GaitTemplate,
    tol: Tolerances,
    t: f64,
    x: State,
    phase: GaitPhase,
    side: Side,
    trailing: [f64; 2],
    leading: [f64; 2],
    h: f64,
    steps: usize,
}

impl Walker {
    /// Starts at MS of SS1 at time 0, trailing foot (`side`) at `(0, foot_z)`.
    pub fn new(template: GaitTemplate, side: Side, foot_z: f64) -> Self {
        let mut x = initial_state(&template.gait, side);
        x[2] += foot_z;
        Walker {
            template,
            tol: Tolerances::default(),
            t: 0.0,
            x,
            phase: GaitPhase::Ss1,
            side,
            trailing: [0.0, foot_z],
            leading: [0.0, foot_z],
            h: 0.0,
            steps: 0,
        }
    }

    /// Current time (s).
    pub fn time(&self) -> f64 {
        self.t
    }

    /// Current CoM state.
    pub fn state(&self) -> State {
        self.x
    }

    /// Current phase.
    pub fn phase(&self) -> GaitPhase {
        self.phase
    }

    /// Completed steps.
    pub fn steps(&self) -> usize {
        self.steps
    }

    /// The feet on the ground now.
    pub fn stance(&self) -> Stance {
        match self.phase {
            GaitPhase::Ss1 => Stance {
                trailing: Some(self.trailing),
                leading: None,
            },
            GaitPhase::Ds => Stance {
                trailing: Some(self.trailing),
                leading: Some(self.leading),
            },
            GaitPhase::Ss2 => Stance {
                trailing: None,
                leading: Some(self.leading),
            },
        }
    }

    /// Advances to time `t_end`, handling every event on the way. An event
    /// exactly at `t_end` is handled, so the phase reported at a sample time
    /// is the phase that starts there.
    pub fn advance_to(&mut self, t_end: f64) {
        let p = self.template.body;
        let gait = self.template.gait;
        while self.t < t_end {
            let stance = self.stance();
            let f = |s: &State| derivative(&p, s, &stance);
            let trailing = self.trailing;
            let td = |s: &State| touchdown_function(&p, &gait, s);
            let lo = |s: &State| lift_off_function(&p, s, trailing);
            let ms = |s: &State| mid_stance_function(s);
            let event: &dyn Fn(&State) -> f64 = match self.phase {
                GaitPhase::Ss1 => &td,
                GaitPhase::Ds => &lo,
                GaitPhase::Ss2 => &ms,
            };
            let stop = advance(
                &f,
                Some(event),
                &self.tol,
                &mut self.t,
                &mut self.x,
                t_end,
                &mut self.h,
            );
            if stop == Stop::Event {
                self.on_event();
            }
        }
    }

    fn on_event(&mut self) {
        match self.phase {
            GaitPhase::Ss1 => {
                let (dx, dz) = self
                    .template
                    .gait
                    .touchdown_offset(self.template.body.rest_length, self.side);
                self.leading = [self.x[0] + dx, self.x[2] + dz];
                self.phase = GaitPhase::Ds;
            }
            GaitPhase::Ds => self.phase = GaitPhase::Ss2,
            GaitPhase::Ss2 => {
                self.steps += 1;
                self.side = self.side.other();
                self.trailing = self.leading;
                let mut x = initial_state(&self.template.gait, self.side);
                x[0] += self.trailing[0];
                x[2] += self.trailing[1];
                self.x = x;
                self.phase = GaitPhase::Ss1;
            }
        }
    }
}

/// One step's trajectory sampled every `dt` (plus the event instants), as
/// rows `[t, x, y, z, vx, vy, vz]` per phase (SS1, DS, SS2).
pub fn sample_step(template: &GaitTemplate, dt: f64) -> [Vec<[f64; 7]>; 3] {
    let mut out: [Vec<[f64; 7]>; 3] = Default::default();
    let mut w = Walker::new(*template, Side::Left, 0.0);
    let row = |w: &Walker| {
        let x = w.state();
        [w.time(), x[0], x[1], x[2], x[3], x[4], x[5]]
    };
    let index = |p: GaitPhase| match p {
        GaitPhase::Ss1 => 0,
        GaitPhase::Ds => 1,
        GaitPhase::Ss2 => 2,
    };
    out[0].push(row(&w));
    let mut k = 1;
    loop {
        let t = (k as f64 * dt).min(template.step_time);
        let before = w.phase();
        w.advance_to(t);
        if w.steps() > 0 {
            // The end MS: the last row of SS2 is the leading-foot MS state.
            break;
        }
        if w.phase() != before {
            // Boundary rows belong to both phases.
            out[index(before)].push(row(&w));
        }
        out[index(w.phase())].push(row(&w));
        if t >= template.step_time {
            break;
        }
        k += 1;
    }
    out
}
