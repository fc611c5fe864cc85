//! Where each library gait's feet are on the measured walk. Paper 003 does
//! not say how a library gait's feet are placed against measured data; the
//! three [`TouchdownRule`]s are compared in docs/RESULTS.md ("Touchdown
//! rule"), the bookkeeping is described in docs/GAIT_IMM.md ("Feet").
//!
//! A gait's SS1 model stands on the stance (trailing) foot, DS on both, SS2
//! on the leading foot. Until it lands, the leading foot swings with the CoM
//! at the gait's touchdown offset `l0 (cos phi cos theta, -, +-sin theta)`
//! (the SLIP swing leg). At MS (the CoM's vertical velocity crossing zero
//! downwards within `0.1 l0` of the leading foot) the leading foot becomes
//! the stance foot and the sides swap.

use limbfuse_core::GaitPhase;
use limbfuse_models::bslip::{GaitTemplate, Side, Stance, State};

use super::params::{MidStanceEvent, TouchdownRule};

/// How feet are placed: the rule, and the Markov probabilities that
/// [`TouchdownRule::Mixed`] needs.
#[derive(Debug, Clone, Copy)]
pub(super) struct FootPlacement {
    /// When the leading foot lands.
    pub rule: TouchdownRule,
    /// Probability per sample of staying in the phase.
    pub stay: f64,
    /// Probability per sample of moving to the next phase of the same gait.
    pub next: f64,
    /// When the leading foot becomes the stance foot.
    pub mid_stance: MidStanceEvent,
}

/// One gait's feet.
#[derive(Debug, Clone, Copy)]
pub(super) struct Feet {
    /// The stance foot of SS1 (trailing foot), `(x, z)`.
    pub stance: [f64; 2],
    /// Trailing side.
    pub side: Side,
    /// DS's leading foot once it is down (Height, StepClock: from touchdown
    /// to MS; Mixed: always, mixed from the swinging foot).
    pub landed: Option<[f64; 2]>,
    /// Where the swinging leading foot is now: CoM `(x, z)` + touchdown offset.
    pub swinging: [f64; 2],
    /// Time of the last mid-stance (s).
    pub ms_t: f64,
    /// [`TouchdownRule::Mixed`]: SS2's leading foot, mixed from DS's.
    pub ss2: Option<[f64; 2]>,
}

/// `(w_own own + w_new new) / (w_own + w_new)`, or `new` when both weights
/// vanish: eq 11's mixing applied to a foot position.
fn blend(own: [f64; 2], w_own: f64, new: [f64; 2], w_new: f64) -> [f64; 2] {
    let s = w_own + w_new;
    if s > 0.0 && s.is_finite() {
        let a = w_own / s;
        [
            a * own[0] + (1.0 - a) * new[0],
            a * own[1] + (1.0 - a) * new[1],
        ]
    } else {
        new
    }
}

impl Feet {
    /// Feet before the first sample, trailing side `side`.
    pub fn new(side: Side) -> Self {
        Feet {
            stance: [0.0; 2],
            side,
            landed: None,
            swinging: [0.0; 2],
            ms_t: 0.0,
            ss2: None,
        }
    }

    /// At the first sample (MS of SS1 on `self.side`): the stance foot under
    /// the CoM `(x, z)` at the gait's MS lateral offset, the leading foot
    /// swinging.
    pub fn start(&mut self, t: &GaitTemplate, com: [f64; 2], now: f64, rule: TouchdownRule) {
        self.stance = [com[0], com[1] - self.side.sign() * t.gait.lateral];
        self.ms_t = now;
        self.swing(t, com);
        let (landed, ss2) = match rule {
            TouchdownRule::Mixed => (Some(self.swinging), Some(self.swinging)),
            TouchdownRule::Height | TouchdownRule::StepClock => (None, None),
        };
        self.landed = landed;
        self.ss2 = ss2;
    }

    /// The leading foot of DS.
    fn leading(&self) -> [f64; 2] {
        self.landed.unwrap_or(self.swinging)
    }

    /// The feet a model of `phase` stands on.
    pub fn stance_for(&self, phase: GaitPhase) -> Stance {
        match phase {
            GaitPhase::Ss1 => Stance {
                trailing: Some(self.stance),
                leading: None,
            },
            GaitPhase::Ds => Stance {
                trailing: Some(self.stance),
                leading: Some(self.leading()),
            },
            GaitPhase::Ss2 => Stance {
                trailing: None,
                leading: Some(self.ss2.unwrap_or(self.leading())),
            },
        }
    }

    /// Moves the swinging foot with the CoM `(x, z)`.
    fn swing(&mut self, t: &GaitTemplate, com: [f64; 2]) {
        let (dx, dz) = t.gait.touchdown_offset(t.body.rest_length, self.side);
        self.swinging = [com[0] + dx, com[1] + dz];
    }

    /// After the ensemble update at `now` (ensemble `x`, its vertical
    /// velocity one sample earlier `previous_vy`, this gait's posterior
    /// weights `w` of SS1, DS, SS2): the leading foot lands by the rule, and
    /// at MS it becomes the stance foot, which restarts the step clock.
    ///
    /// - Height: the CoM, falling past the stance foot, reaches the gait's
    ///   touchdown height.
    /// - StepClock: `t_touchdown` after the gait's last MS.
    /// - Mixed: DS's foot is the weighted mean of its own (weight staying in
    ///   DS, `w_DS stay`) and the swinging foot (weight entering from SS1, a
    ///   touchdown now, `w_SS1 next`); SS2's foot likewise from its own and
    ///   DS's.
    pub fn advance(
        &mut self,
        t: &GaitTemplate,
        placement: FootPlacement,
        x: &State,
        previous_vy: f64,
        now: f64,
        w: [f64; 3],
    ) {
        let FootPlacement {
            rule,
            stay,
            next,
            mid_stance,
        } = placement;
        self.swing(t, [x[0], x[2]]);
        let lead = match rule {
            TouchdownRule::Mixed => {
                let ds = self.leading();
                let ss2 = self.ss2.unwrap_or(ds);
                let [w_ss1, w_ds, w_ss2] = w;
                self.ss2 = Some(blend(ss2, w_ss2 * stay, ds, w_ds * next));
                self.landed = Some(blend(ds, w_ds * stay, self.swinging, w_ss1 * next));
                self.ss2
            }
            TouchdownRule::Height | TouchdownRule::StepClock => match self.landed {
                None => {
                    let lands = match rule {
                        TouchdownRule::StepClock => now - self.ms_t >= t.t_touchdown,
                        _ => {
                            x[4] < 0.0
                                && x[0] > self.stance[0]
                                && x[1] <= t.gait.touchdown_height(t.body.rest_length)
                        }
                    };
                    if lands {
                        self.landed = Some(self.swinging);
                    }
                    // Not a candidate for MS in the sample it lands.
                    None
                }
                landed => landed,
            },
        };
        let Some(lead) = lead else { return };
        let ms = match mid_stance {
            MidStanceEvent::ApexNearFoot { within } => {
                previous_vy > 0.0 && x[4] <= 0.0 && x[0] >= lead[0] - within * t.body.rest_length
            }
            MidStanceEvent::PastFootAndApex => x[4] <= 0.0 && x[0] >= lead[0],
        };
        if ms {
            self.stance = lead;
            self.ms_t = now;
            self.side = self.side.other();
            self.swing(t, [x[0], x[2]]);
            let after = match rule {
                TouchdownRule::Mixed => Some(self.swinging),
                TouchdownRule::Height | TouchdownRule::StepClock => None,
            };
            self.landed = after;
            self.ss2 = after;
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn blend_is_the_weighted_mean_and_falls_back_to_the_new_foot() {
        // (0.3 * [1, 2] + 0.1 * [5, -2]) / 0.4 = [2, 1].
        let b = blend([1.0, 2.0], 0.3, [5.0, -2.0], 0.1);
        assert!((b[0] - 2.0).abs() < 1e-15 && (b[1] - 1.0).abs() < 1e-15);
        assert_eq!(blend([1.0, 2.0], 0.0, [5.0, -2.0], 0.0), [5.0, -2.0]);
        assert_eq!(blend([1.0, 2.0], f64::NAN, [5.0, -2.0], 0.1), [5.0, -2.0]);
    }
}
