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
