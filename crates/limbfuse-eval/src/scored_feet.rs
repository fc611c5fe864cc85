//! Which feet a gait-event evaluation scores: a foot whose leg carries no
//! foot or shank IMU in the trial, and for which the estimate has no
//! contact or event, was not measured, so its reference events are neither
//! found nor missed (a one-foot recording with both feet's references,
//! found by the invariance audit: the unmeasured foot's 29 contacts
//! counted as missed on the gaitmap walk).

use limbfuse_core::{Segment, Side};
use limbfuse_io::TrialLayout;

/// Per side (`Side::index`): whether the trial has a foot or shank IMU on
/// that leg (accelerometer or gyroscope, recorded leg or other leg).
pub fn legs_with_imu(l: &TrialLayout) -> [bool; 2] {
    let lower = [Segment::Shank.index(), Segment::Foot.index()];
    let own = lower.iter().any(|&i| l.acc[i] || l.gyr[i]);
    let other = lower.iter().any(|&i| l.other_acc[i] || l.other_gyr[i]);
    let mut out = [false; 2];
    out[l.leg.index()] = own;
    out[l.leg.other().index()] = other;
    out
}

/// The sides to score: those with an IMU, or with any estimated contact or
/// event (a method may track a foot from elsewhere; then it is scored).
pub fn scored_sides(with_imu: [bool; 2], estimated: [bool; 2]) -> Vec<usize> {
    Side::BOTH
        .iter()
        .map(|s| s.index())
        .filter(|&s| with_imu[s] || estimated[s])
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_foot_without_imu_or_estimate_is_not_scored() {
        let mut l = TrialLayout::default();
        l.other_acc[Segment::Foot.index()] = true;
        l.other_gyr[Segment::Foot.index()] = true;
        // right-leg trial whose only IMU is the left foot's
        assert_eq!(legs_with_imu(&l), [true, false]);
        assert_eq!(scored_sides(legs_with_imu(&l), [true, false]), vec![0]);
        assert_eq!(scored_sides([true, false], [false, true]), vec![0, 1]);
        l.gyr[Segment::Shank.index()] = true;
        assert_eq!(legs_with_imu(&l), [true, true]);
    }
}
