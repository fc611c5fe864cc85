//! The trial columns each method reads, checked before any sample is read.

use limbfuse_core::{Joint, Segment};
use limbfuse_io::TrialLayout;

use crate::method_def::MethodInfo;
use crate::{MethodError, MethodName};

/// Columns a method cannot run without.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct ChannelNeeds {
    /// Accelerometer `SEG_acc_x/y/z`, per segment (trunk, thigh, shank, foot).
    pub acc: [bool; 4],
    /// Gyroscope `SEG_gyr_x/y/z`, per segment.
    pub gyr: [bool; 4],
    /// Joint encoders `hip_enc`, `knee_enc`, `ankle_enc`.
    pub encoder: [bool; 3],
    /// CoM position measurements `com_meas_x/y/z`.
    pub com_position: bool,
}

impl ChannelNeeds {
    /// Nothing.
    pub const NONE: ChannelNeeds = ChannelNeeds::imus([false; 4]);
    /// The four IMUs.
    pub const FOUR_IMUS: ChannelNeeds = ChannelNeeds::imus([true; 4]);

    /// Accelerometer and gyroscope of these segments (trunk, thigh, shank, foot).
    pub const fn imus(segments: [bool; 4]) -> Self {
        ChannelNeeds {
            acc: segments,
            gyr: segments,
            encoder: [false; 3],
            com_position: false,
        }
    }

    /// The column groups of these needs that `layout` lacks, as column
    /// patterns (`thigh_acc_x/y/z`, `knee_enc`, ...).
    pub fn missing(&self, layout: &TrialLayout) -> Vec<String> {
        let mut out = Vec::new();
        for s in Segment::ALL {
            let i = s.index();
            if self.acc[i] && !layout.acc[i] {
                out.push(format!("{}_acc_x/y/z", s.name()));
            }
            if self.gyr[i] && !layout.gyr[i] {
                out.push(format!("{}_gyr_x/y/z", s.name()));
            }
        }
        for j in Joint::ALL {
            if self.encoder[j.index()] && !layout.encoder[j.index()] {
                out.push(format!("{}_enc", j.name()));
            }
        }
        if self.com_position && !layout.com_meas[..3].iter().all(|&b| b) {
            out.push("com_meas_x, com_meas_y, com_meas_z".to_string());
        }
        out
    }
}

impl MethodName {
    /// The columns the method needs in every trial. Model inputs of the
    /// paper-004 filters (`u_*`, motor torques) depend on the trial's model
    /// and are checked when the estimator is built.
    pub const fn required_channels(self) -> ChannelNeeds {
        self.info().needs
    }
}

/// Checks a trial's columns against a method's [`MethodInfo::needs`].
pub fn check_info(info: &MethodInfo, layout: &TrialLayout) -> Result<(), MethodError> {
    let missing = info.needs.missing(layout);
    if missing.is_empty() {
        return Ok(());
    }
    // The hint (mjls: "use `local` or `global` on trials without
    // encoders") is about encoders: said only when one is missing (an audit:
    // a trial with every encoder and no thigh gyro was told to do without
    // encoders).
    // It is said only when `local` and `global` have their columns (a
    // fresh-user audit, session 28: a foot-only trial was sent to them).
    let others_run = [MethodName::Local, MethodName::Global]
        .into_iter()
        .all(|m| m.required_channels().missing(layout).is_empty());
    let hint = match missing.iter().any(|m| m.ends_with("_enc")) && others_run {
        true => info.needs_hint,
        false => "",
    };
    Err(MethodError::MissingChannels {
        method: info.name,
        why: info.needs_why,
        missing,
        hint,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn mjls_lists_missing_encoders_and_imus() {
        let l = TrialLayout {
            acc: [true; 4],
            gyr: [true, true, false, true],
            encoder: [true, false, true],
            ..Default::default()
        };
        let m = MethodName::Mjls.required_channels().missing(&l);
        assert_eq!(m, ["shank_gyr_x/y/z", "knee_enc"]);
        assert!(MethodName::Global.required_channels().missing(&l).len() == 1);
    }

    #[test]
    fn the_encoder_hint_is_given_only_when_an_encoder_is_missing() {
        let info = MethodName::Mjls.info();
        let no_thigh_gyro = TrialLayout {
            acc: [true; 4],
            gyr: [true, false, true, true],
            encoder: [true; 3],
            ..Default::default()
        };
        let e = check_info(&info, &no_thigh_gyro).unwrap_err().to_string();
        assert!(
            e.contains("thigh_gyr_x/y/z") && !e.contains("without encoders"),
            "{e}"
        );
        let no_knee = TrialLayout {
            encoder: [true, false, true],
            ..no_thigh_gyro
        };
        // `local` and `global` need the thigh gyro too: no hint to use them
        // (a fresh-user audit, session 28).
        let e = check_info(&info, &no_knee).unwrap_err().to_string();
        assert!(!e.contains("without encoders"), "{e}");
        let every_imu = TrialLayout {
            gyr: [true; 4],
            ..no_knee
        };
        let e = check_info(&info, &every_imu).unwrap_err().to_string();
        assert!(e.contains("without encoders"), "{e}");
    }
}
