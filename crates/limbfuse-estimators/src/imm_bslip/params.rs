//! Parameters of the B-SLIP IMM and their defaults (paper 003 eqs 14-18).
//!
//! Axes are this project's (x forward, y up, z right); the paper's are
//! (x forward, y lateral, z up), so its second and third entries swap.

use limbfuse_models::bslip::Side;

/// How the model weights are formed from the measurement likelihoods.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum ImmWeights {
    /// Eq 8 of paper 003: each weight is the normalised likelihood of the
    /// current sample alone, without the previous weights (default, the
    /// paper's estimator).
    #[default]
    Paper,
    /// The standard IMM mode probability (Blom & Bar-Shalom 1988): the
    /// likelihood times the Markov-predicted weight `c_j = sum_i p_ij w_i`,
    /// so the weights carry memory across samples. Not in the paper.
    Recursive,
}

impl ImmWeights {
    /// `paper` or `recursive`.
    pub const fn label(self) -> &'static str {
        match self {
            ImmWeights::Paper => "paper",
            ImmWeights::Recursive => "recursive",
        }
    }
}

/// When a gait's model puts its leading foot down. The paper does not say
/// how a library gait's feet are placed against measured data
/// (docs/GAIT_IMM.md, "Feet"; the trade-off between the two rules is
/// measured in docs/RESULTS.md, "Touchdown rule").
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum TouchdownRule {
    /// The B-SLIP touchdown guard applied to the ensemble CoM (default): the
    /// CoM, falling past the stance foot, reaches the gait's touchdown height
    /// `l0 sin(phi) cos(theta)`.
    #[default]
    Height,
    /// The gait's own step clock: the foot lands the template's
    /// `t_touchdown` after the gait's last mid-stance (the first sample of a
    /// run counts as one). Independent of the absolute CoM height, which can
    /// differ between the walker and a library gait by about as much as the
    /// whole fall from mid-stance to touchdown (1-2 cm of 2-4 cm): better
    /// phase with a gait outside the library, weaker gait (speed)
    /// discrimination, since every gait then touches down at nearly the same
    /// instant.
    StepClock,
    /// Foot placement estimated by the IMM: the DS model's leading foot is
    /// mixed like its state (eqs 11-13) — the weight flowing in from SS1
    /// brings the foot where it would land now, the weight staying in DS
    /// keeps its foot — and SS2's foot is mixed from DS's the same way. No
    /// touchdown threshold; the data decide when the foot is down.
    Mixed,
}

impl TouchdownRule {
    /// `height`, `step-clock` or `mixed`.
    pub const fn label(self) -> &'static str {
        match self {
            TouchdownRule::Height => "height",
            TouchdownRule::StepClock => "step-clock",
            TouchdownRule::Mixed => "mixed",
        }
    }
}

/// When a gait's mid-stance (MS) event fires, the leading foot becoming the
/// stance foot. The paper gives the B-SLIP MS guard for one walker, not for a
/// library gait's feet placed on measured data (docs/GAIT_IMM.md, "Feet");
/// the variants are compared in docs/RESULTS.md ("Slow gaits and the MS
/// event").
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum MidStanceEvent {
    /// The ensemble CoM's vertical velocity crosses zero downwards (its apex)
    /// no more than `within` x l0 behind the leading foot, or past it
    /// (default: `within` = 0.1).
    ApexNearFoot {
        /// How far behind the leading foot the apex may be, in leg rest lengths.
        within: f64,
    },
    /// The CoM is past the leading foot and past its apex (vertical velocity
    /// <= 0), whichever comes last: no distance threshold.
    PastFootAndApex,
}

impl Default for MidStanceEvent {
    fn default() -> Self {
        MidStanceEvent::ApexNearFoot { within: 0.1 }
    }
}

/// Parameters of [`super::ImmBslip`].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ImmBslipParams {
    /// Measurement variances R per state channel `[x, y, z, vx, vy, vz]`
    /// (m^2, m^2/s^2); a channel is used when the sample has it.
    pub r: [f64; 6],
    /// Continuous process-noise spectral densities Q (diagonal) per state
    /// channel (m^2/s^2 for positions, m^2/s^4 for velocities).
    pub q: [f64; 6],
    /// Physical-likelihood gain kappa of eq 14 (1/m^2); 0 disables it.
    pub kappa: f64,
    /// Markov probability per sample of moving to the next phase of the same gait.
    pub p_next_phase: f64,
    /// Markov probability per sample of moving to the same phase of another gait (shared among them).
    pub p_other_gait: f64,
    /// Largest RK4 sub-step (s).
    pub max_substep: f64,
    /// Initial state variances (position, velocity).
    pub p0: [f64; 2],
    /// Trailing foot at the first sample (the trial starts at MS of SS1).
    pub first_side: Side,
    /// A gap between samples longer than this (s) restarts the filter bank.
    pub max_gap: f64,
    /// Weight rule: eq 8 (default) or the recursive IMM mode probability.
    pub weights: ImmWeights,
    /// When a gait's leading foot lands.
    pub touchdown: TouchdownRule,
    /// When a gait's leading foot becomes its stance foot.
    pub mid_stance: MidStanceEvent,
}

impl ImmBslipParams {
    /// Full CoM measurements `[x, y, z, vx, vy]` (paper sec IV-A): R of eq 15
    /// `diag(5, 5, 5, 50, 50) x 1e-5` (the unmeasured lateral velocity gets
    /// the velocity variance should a trial have it), Q of eq 16 with the
    /// SPEC section 6 fix `diag(0, 0, 0, 1, 1, 1) x 1e-2`.
    pub fn full_com() -> Self {
        ImmBslipParams {
            r: [5e-5, 5e-5, 5e-5, 5e-4, 5e-4, 5e-4],
            q: [0.0, 0.0, 0.0, 1e-2, 1e-2, 1e-2],
            ..Self::common()
        }
    }

    /// Position-only measurements (paper sec IV-B): R of eq 17
    /// `diag(5, 5, 0.5) x 1e-6` and Q of eq 18 `diag(0, 0, 0, 1, 1, 10) x 1e-2`,
    /// the small / large entries on the vertical axis (y here).
    pub fn position_only() -> Self {
        ImmBslipParams {
            r: [5e-6, 0.5e-6, 5e-6, 5e-4, 5e-4, 5e-4],
            q: [0.0, 0.0, 0.0, 1e-2, 10e-2, 1e-2],
            ..Self::common()
        }
    }

    /// Settings the paper does not give (documented choices):
    /// kappa = 1e5 /m^2 (a leg stretched 1 cm beyond rest costs e^-10),
    /// phase switching 0.05 per sample (phases last 10-50 samples at 100 Hz),
    /// gait switching 0.01 per sample, touchdown at each gait's touchdown height,
    /// MS at the CoM's apex within 0.1 l0 of the leading foot, RK4 sub-steps <= 10 ms (one per
    /// sample at 100 Hz; `omega h` = 0.26 for the stiffest library leg, 55 kN/m), P0 =
    /// diag(1e-4 m^2, 1e-2 m^2/s^2), left foot trailing first, restart after
    /// a 0.25 s gap.
    fn common() -> Self {
        ImmBslipParams {
            r: [0.0; 6],
            q: [0.0; 6],
            kappa: 1e5,
            p_next_phase: 0.05,
            p_other_gait: 0.01,
            max_substep: 0.01,
            p0: [1e-4, 1e-2],
            first_side: Side::Left,
            max_gap: 0.25,
            weights: ImmWeights::Paper,
            touchdown: TouchdownRule::Height,
            mid_stance: MidStanceEvent::default(),
        }
    }

    /// Checks every value; names the first bad one.
    pub fn validate(&self) -> Result<(), &'static str> {
        let nonneg = |v: &f64| v.is_finite() && *v >= 0.0;
        if !self.r.iter().all(|v| v.is_finite() && *v > 0.0) {
            return Err("r: measurement variances must be positive");
        }
        if !self.q.iter().all(nonneg) {
            return Err("q: process noise must be non-negative");
        }
        if !nonneg(&self.kappa) {
            return Err("kappa must be non-negative");
        }
        let p = self.p_next_phase + self.p_other_gait;
        if !(nonneg(&self.p_next_phase) && nonneg(&self.p_other_gait) && p < 1.0) {
            return Err("p_next_phase and p_other_gait must be >= 0 with sum < 1");
        }
        if !(self.max_substep.is_finite() && self.max_substep > 0.0) {
            return Err("max_substep must be positive");
        }
        if !self.p0.iter().all(|v| v.is_finite() && *v > 0.0) {
            return Err("p0 must be positive");
        }
        if !(self.max_gap.is_finite() && self.max_gap > 0.0) {
            return Err("max_gap must be positive");
        }
        if let MidStanceEvent::ApexNearFoot { within } = self.mid_stance {
            if !nonneg(&within) {
                return Err("mid_stance: the apex distance must be >= 0");
            }
        }
        Ok(())
    }
}

impl Default for ImmBslipParams {
    fn default() -> Self {
        Self::full_com()
    }
}
