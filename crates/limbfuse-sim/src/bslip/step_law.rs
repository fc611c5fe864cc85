//! Desired step length and width as functions of walking speed, from
//! published human data (paper 003 sec II-B, which uses a polynomial fit to
//! \[20\]/\[21\]; the fit's coefficients are not printed, so limbfuse uses these
//! published relations instead).
//!
//! - **Step length**: the walk ratio (step length / step rate) is nearly
//!   constant over walking speeds (Sekiya & Nagasaki 1998, *Gait & Posture*
//!   7:225-227: 0.0064 m/(steps/min) in young men, 0.0059 in women; Nagasaki
//!   et al. 1996 over 0.2-2.4 m/s). With `v = L f / 60` (f in steps/min) this
//!   gives `L = sqrt(60 W v)`; limbfuse uses W = 0.0062 m min and scales with
//!   leg length `l0 / 0.9 m` (the studies' subjects' leg length ~0.9 m):
//!   0.39 m at 0.4 m/s, 0.53 m at 0.75 m/s, 0.61 m at 1.0 m/s for l0 = 0.9 m.
//! - **Step width**: nearly independent of speed in healthy adults
//!   (Helbostad & Moe-Nilssen 2003, *Gait & Posture* 17:209-217; Orendurff et
//!   al. 2004, *J Rehabil Res Dev* 41:829-834), about 0.10 m heel-to-heel;
//!   limbfuse uses 0.10 m scaled by `l0 / 0.9 m`. Lateral CoM excursion then
//!   grows as speed falls because steps last longer.

/// Walk ratio (m per step/min), Sekiya & Nagasaki 1998.
pub const WALK_RATIO: f64 = 0.0062;
/// Leg length of the subjects behind the step laws (m).
pub const REFERENCE_LEG_LENGTH: f64 = 0.9;
/// Step width at the reference leg length (m).
pub const STEP_WIDTH: f64 = 0.10;

/// Desired step length (m) at `speed` (m/s) for leg length `l0` (m).
pub fn step_length(speed: f64, l0: f64) -> f64 {
    (60.0 * WALK_RATIO * speed.max(0.0)).sqrt() * l0 / REFERENCE_LEG_LENGTH
}

/// Desired step width (m) for leg length `l0` (m).
pub fn step_width(l0: f64) -> f64 {
    STEP_WIDTH * l0 / REFERENCE_LEG_LENGTH
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn walk_ratio_law_reproduces_speed() {
        // v = L * f / 60 with f = L / W.
        for v in [0.4, 0.7, 1.0] {
            let l = step_length(v, REFERENCE_LEG_LENGTH);
            let f = l / WALK_RATIO;
            assert!((l * f / 60.0 - v).abs() < 1e-12);
        }
        assert!((step_length(1.0, 0.9) - 0.6099).abs() < 1e-3);
    }
}
