//! The 3D bipedal spring-loaded inverted pendulum (B-SLIP) of paper 003
//! (Karulkar & Wensing, sec II-A; 3D form of Liu et al. 2015, 2D form of
//! Geyer et al. 2006).
//!
//! A point mass `m` rides on two massless linear springs (rest length `l0`,
//! stiffness `k`) whose feet are pinned on the ground. A step starts at
//! mid-stance (MS) on the trailing leg (SS1), the leading leg touches down
//! (TD) when the CoM has fallen to the height fixed by the touchdown angles
//! (double support, DS), the trailing leg lifts off (LO) when it is back at its
//! rest length (SS2), and the step ends at the next MS (vertical velocity
//! zero) on the leading leg.
//!
//! Frame (SPEC section 1): x forward, y up, z to the subject's right. The
//! state is `[x, y, z, vx, vy, vz]` of the CoM in the world frame; feet are
//! ground points `(x, 0, z)`. The paper's `y` (lateral) and `z` (vertical)
//! are this crate's `z` and `y`.
//!
//! The same functions drive the library builder and trial simulator
//! (`limbfuse-sim`, with event location) and the IMM's extended Kalman
//! filters (`limbfuse-estimators::imm_bslip`, fixed-step RK4 per phase).

mod dynamics;
mod events;
pub mod family;
mod gait;
mod template;

pub use dynamics::{
    acceleration, derivative, energy, jacobian, leg_compression, leg_force, leg_length, Stance,
    State,
};
pub use events::{lift_off_function, mid_stance_function, touchdown_function};
pub use gait::{BslipParams, GaitParameters, Side};
pub use template::GaitTemplate;
