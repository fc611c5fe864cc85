//! Segment-angle Kalman filters of papers 000 (Nogueira et al., *Sensors*
//! 2014, MJLS-based position estimation) and 001 (Nogueira et al.,
//! *BioMedical Engineering OnLine* 2017, global Kalman filters).
//!
//! Three estimators of the four sagittal segment angles (trunk, thigh,
//! shank, foot) and the three joint angles (their differences):
//!
//! | type | `name()` | paper | measurement rows |
//! |---|---|---|---|
//! | [`LocalKf`] | `local` | 000 eqs 5-13, 001 eqs 1-6 | each segment's accelerometer inclination, gated by `rho_i < zeta_i` and `Psi_s` |
//! | [`MarkovJumpKf`] | `mjls` | 000 eqs 14-30, 001 eqs 7-13 | the most reliable accelerometer (`C(Xi)`) + three encoders |
//! | [`GlobalKf`] | `global` | 001 eqs 19-28 | four accelerometer rows (`Psi_s`) + three accelerometer-difference rows (`Upsilon`) |
//!
//! All three share the error-state formulation of 000 section 2.2: each
//! segment's gyro rate (`gyr.z` of the aligned sensor, SPEC section 1) is
//! integrated outside the filter together with a bias estimate, and an
//! 8-state Kalman filter estimates the errors `[dtheta_i, db_i]` of the
//! integrated angles and biases. By default the filter is closed-loop (the
//! corrections are fed back and the error state reset, SPEC section 6); the
//! papers' open-loop form is [`LoopMode::Open`].
//!
//! Inputs: accelerometer inclination `theta_a = atan2(acc_x, acc_y)`
//! ([`crate::inclination::accel_inclination`]), reliability `rho_i = |
//! ||acc_i|| - g |` ([`criteria::reliability`]), encoders
//! `sample.encoder[Joint]` (`theta_trunk - theta_thigh`, ...). Step length
//! from timestamps. Missing channels drop their rows; a missing gyro sample
//! holds the last rate. Nothing allocates per sample.
//!
//! Design notes, parameter sources and the resolution of the papers'
//! ambiguities: `docs/SEGMENT_FILTERS.md`.

mod chain;
pub mod criteria;
mod diagnostics;
mod gain_shares;
pub mod global;
pub mod local;
pub mod mjls;
pub mod model;
pub mod params;
pub mod rate_spikes;
pub mod robust;
pub mod sequential;
pub mod structured;

pub use criteria::{
    mjls_select, psi, reliability, reliable_flags, upsilon, AccelGate, AccelGateState, MjlsMode,
};
pub use diagnostics::SegmentDiag;
pub use gain_shares::{gain_shares, RowKind};
pub use global::{GlobalDiag, GlobalKf, GlobalKfParams};
pub use local::{LocalDiag, LocalKf, LocalKfParams};
pub use mjls::{MarkovJumpKf, MarkovJumpKfParams, MjlsDiag, WhenUnreliable};
pub use model::{global_output_matrix, local_output_matrix, mjls_output_matrix};
pub use params::{CommonParams, LoopMode, ParamError, SegmentNoise};

#[cfg(test)]
mod tests {
    use super::*;

    /// Every filter's columns end with the shared block, in its declared order.
    #[test]
    fn diagnostic_lists_end_with_the_shared_segment_block() {
        for names in [
            &LocalDiag::NAMES[..],
            &MjlsDiag::NAMES[..],
            &GlobalDiag::NAMES[..],
        ] {
            let n = names.len();
            assert_eq!(&names[n - SegmentDiag::COUNT..], &SegmentDiag::NAMES[..]);
        }
        for (i, k) in SegmentDiag::ALL.into_iter().enumerate() {
            assert_eq!(
                MjlsDiag::from(k).index(),
                MjlsDiag::COUNT - SegmentDiag::COUNT + i
            );
        }
    }
}
