//! Event functions of a B-SLIP step (paper 003 sec II-B). Each crosses zero
//! in the given direction at its event; the simulator locates the crossing.

use super::dynamics::{leg_compression, State};
use super::gait::{BslipParams, GaitParameters};

/// Touchdown (SS1 -> DS): `y - l0 sin(phi) cos(theta)`, crossing downwards
/// (the CoM falls to the height at which the leading leg, held at its
/// touchdown angles, reaches the ground).
pub fn touchdown_function(p: &BslipParams, gait: &GaitParameters, state: &State) -> f64 {
    state[1] - gait.touchdown_height(p.rest_length)
}

/// Lift-off (DS -> SS2): the trailing leg's compression `l0 - l`, crossing
/// downwards (the leg is back at its rest length, its force is zero).
pub fn lift_off_function(p: &BslipParams, state: &State, trailing_foot: [f64; 2]) -> f64 {
    leg_compression(p, state, trailing_foot)
}

/// Mid-stance (end of SS2): the vertical velocity `vy`, crossing downwards
/// (the CoM at the top of its arc over the leading leg).
pub fn mid_stance_function(state: &State) -> f64 {
    state[4]
}
