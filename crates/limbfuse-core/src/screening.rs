//! The outcome of screening one sample ([`crate::SampleGate::check`]):
//! which readings to make missing, kept apart from the sample so that a
//! sample with nothing to remove (nearly every one) is not copied.

use crate::sample::Sample;

/// Which readings of one sample [`crate::SampleGate::check`] rejected: per kind,
/// bit `k` for IMU `k` (this leg's four, then the other leg's), bit `j` for
/// encoder `j`.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct Screening {
    pub(crate) gyr: u8,
    pub(crate) gyr_partial: u8,
    pub(crate) acc: u8,
    pub(crate) acc_partial: u8,
    pub(crate) encoder: u8,
}

impl Screening {
    /// True when no reading was rejected: the sample passes unchanged.
    pub fn is_clean(&self) -> bool {
        (self.gyr | self.gyr_partial | self.acc | self.acc_partial | self.encoder) == 0
    }

    /// Makes the rejected readings of `sample` missing (the sample given to
    /// [`crate::SampleGate::check`]).
    pub fn apply(&self, sample: &mut Sample) {
        let imus = sample.imu.iter_mut().chain(sample.other_leg_imu.iter_mut());
        for (k, imu) in imus.enumerate() {
            let bit = 1u8 << k;
            if self.gyr & bit != 0 {
                imu.gyr = None;
            }
            if self.gyr_partial & bit != 0 {
                imu.gyr_partial = [None; 3];
            }
            if self.acc & bit != 0 {
                imu.acc = None;
            }
            if self.acc_partial & bit != 0 {
                imu.acc_partial = [None; 3];
            }
        }
        for (j, e) in sample.encoder.iter_mut().enumerate() {
            if self.encoder & (1 << j) != 0 {
                *e = None;
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use crate::sample_gate::tests::walking_sample;
    use crate::{SampleGate, SensorRanges};
    use nalgebra::Vector3;

    /// `check` on a clean sample asks for no change (the gated estimator
    /// then passes the sample itself, uncopied); on a glitched one,
    /// `apply` drops exactly the readings `screen` drops, and both forms
    /// count and remember alike.
    #[test]
    fn issue_18_check_says_which_readings_screen_drops() {
        let (mut a, mut b) = (
            SampleGate::new(SensorRanges::default()),
            SampleGate::new(SensorRanges::default()),
        );
        let clean = walking_sample();
        assert!(a.check(&clean).is_clean());
        assert_eq!(b.screen(&clean), clean);
        let mut bad = walking_sample();
        bad.t = 1.01;
        bad.imu[2].gyr = Some(Vector3::new(0.1, -0.2, 3.0 + 30.0)); // a jump
        bad.imu[0].acc = Some(Vector3::new(1e300, 9.5, 0.0));
        bad.other_leg_imu[1].gyr = None;
        bad.other_leg_imu[1].gyr_partial = [Some(1e300), None, None];
        bad.encoder[2] = Some(f64::NAN);
        let screening = a.check(&bad);
        assert!(!screening.is_clean());
        let mut applied = bad;
        screening.apply(&mut applied);
        let screened = b.screen(&bad);
        assert_eq!(applied, screened);
        assert_eq!(applied.imu[2].gyr, None);
        assert_eq!(applied.imu[0].acc, None);
        assert_eq!(applied.other_leg_imu[1].gyr_partial, [None; 3]);
        assert_eq!(applied.encoder, [Some(0.3), Some(1.2), None]);
        assert_eq!(applied.imu[1], bad.imu[1]);
        assert_eq!(a.rejections(), b.rejections());
        assert_eq!(a.rejections().total(), 4);
        // the rejected jump's repeat is rejected by both (history alike)
        let mut again = bad;
        again.t = 1.02;
        again.imu[0].acc = clean.imu[0].acc;
        again.encoder = clean.encoder;
        again.other_leg_imu = clean.other_leg_imu;
        let screening = a.check(&again);
        let mut applied = again;
        screening.apply(&mut applied);
        assert_eq!(applied, b.screen(&again));
        assert_eq!(applied.imu[2].gyr, None);
    }
}
