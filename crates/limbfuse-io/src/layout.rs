//! Which channels a trial carries, and their column names (SPEC section 2).

use limbfuse_core::{Joint, Segment, Side};

/// The set of channels present in a trial (besides `t`).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct TrialLayout {
    /// `S_acc_x, S_acc_y, S_acc_z` per segment.
    pub acc: [bool; 4],
    /// `S_gyr_x, S_gyr_y, S_gyr_z` per segment.
    pub gyr: [bool; 4],
    /// `S_quat_w, S_quat_x, S_quat_y, S_quat_z` per segment.
    pub quat: [bool; 4],
    /// `hip_enc, knee_enc, ankle_enc`.
    pub encoder: [bool; 3],
    /// `S_ref` per segment.
    pub segment_ref: [bool; 4],
    /// `hip_ref, knee_ref, ankle_ref`.
    pub joint_ref: [bool; 3],
    /// `com_x, com_y, com_z`.
    pub com_pos: bool,
    /// `com_vx, com_vy, com_vz`.
    pub com_vel: bool,
    /// `phase_ref`.
    pub phase_ref: bool,
    /// `u_ke, u_kf, u_he, u_hf`.
    pub stim: [bool; 4],
    /// `tau_hip_motor, tau_knee_motor, tau_ankle_motor`.
    pub motor_torque: [bool; 3],
    /// CoM measurements `com_meas_x`..`com_meas_vz` (paper 003), per column.
    pub com_meas: [bool; 6],
    /// The side of the single-leg column names: the trial's `# leg:`
    /// (right when absent, SPEC section 2); the other leg's IMUs are
    /// `S_<other side>_...` ([`TrialLayout::other_leg`]).
    pub leg: Side,
    /// `S_<other>_acc_x..z` per segment (two-leg recordings).
    pub other_acc: [bool; 4],
    /// `S_<other>_gyr_x..z` per segment (two-leg recordings).
    pub other_gyr: [bool; 4],
    /// `contact_left_ref`, `contact_right_ref` (indexed by [`Side::index`]).
    pub contact_ref: [bool; 2],
    /// `speed_ref`.
    pub speed_ref: bool,
}

/// Column name of a gait-contact reference (`contact_left_ref`, `contact_right_ref`).
pub fn contact_ref_column(side: Side) -> String {
    format!("contact_{}_ref", side.name())
}

/// Column name of the walking-speed reference (m/s).
pub const SPEED_REF: &str = "speed_ref";

/// Column-name prefix of the other leg's IMU of segment `s` (`foot_left_`).
pub fn other_leg_prefix(s: Segment, side: Side) -> String {
    format!("{}_{}_", s.name(), side.name())
}

/// Axis suffixes of 3-vectors.
pub const AXES: [&str; 3] = ["x", "y", "z"];
/// Component suffixes of quaternions (w first).
pub const QUAT: [&str; 4] = ["w", "x", "y", "z"];

impl TrialLayout {
    /// A layout with 4 IMUs (acc + gyr), 3 encoders and full angle references:
    /// what the walking simulator writes.
    pub fn walking() -> Self {
        TrialLayout {
            acc: [true; 4],
            gyr: [true; 4],
            encoder: [true; 3],
            segment_ref: [true; 4],
            joint_ref: [true; 3],
            ..Default::default()
        }
    }

    /// The side of the other leg's IMU columns (`foot_left_...` for a right-leg trial).
    pub fn other_leg(&self) -> Side {
        self.leg.other()
    }

    /// True when the trial has any IMU of the other leg.
    pub fn has_other_leg(&self) -> bool {
        self.other_acc
            .iter()
            .chain(self.other_gyr.iter())
            .any(|&b| b)
    }

    /// Column names in the canonical order used by writers (`t` first).
    pub fn column_names(&self) -> Vec<String> {
        let mut c = vec!["t".to_string()];
        for s in Segment::ALL {
            let i = s.index();
            if self.acc[i] {
                c.extend(AXES.iter().map(|a| format!("{}_acc_{a}", s.name())));
            }
            if self.gyr[i] {
                c.extend(AXES.iter().map(|a| format!("{}_gyr_{a}", s.name())));
            }
            if self.quat[i] {
                c.extend(QUAT.iter().map(|a| format!("{}_quat_{a}", s.name())));
            }
        }
        for s in Segment::ALL {
            let p = other_leg_prefix(s, self.other_leg());
            if self.other_acc[s.index()] {
                c.extend(AXES.iter().map(|a| format!("{p}acc_{a}")));
            }
            if self.other_gyr[s.index()] {
                c.extend(AXES.iter().map(|a| format!("{p}gyr_{a}")));
            }
        }
        for j in Joint::ALL {
            if self.encoder[j.index()] {
                c.push(format!("{}_enc", j.name()));
            }
        }
        for (k, name) in limbfuse_core::sample::ModelInputs::STIM_NAMES
            .iter()
            .enumerate()
        {
            if self.stim[k] {
                c.push(name.to_string());
            }
        }
        for j in Joint::ALL {
            if self.motor_torque[j.index()] {
                c.push(format!("tau_{}_motor", j.name()));
            }
        }
        for (k, name) in limbfuse_core::ComMeasurement::NAMES.iter().enumerate() {
            if self.com_meas[k] {
                c.push(name.to_string());
            }
        }
        for s in Segment::ALL {
            if self.segment_ref[s.index()] {
                c.push(format!("{}_ref", s.name()));
            }
        }
        for j in Joint::ALL {
            if self.joint_ref[j.index()] {
                c.push(format!("{}_ref", j.name()));
            }
        }
        if self.com_pos {
            c.extend(["com_x", "com_y", "com_z"].map(String::from));
        }
        if self.com_vel {
            c.extend(["com_vx", "com_vy", "com_vz"].map(String::from));
        }
        if self.phase_ref {
            c.push("phase_ref".into());
        }
        for side in Side::BOTH {
            if self.contact_ref[side.index()] {
                c.push(contact_ref_column(side));
            }
        }
        if self.speed_ref {
            c.push(SPEED_REF.into());
        }
        c
    }

    /// True when the trial has any reference angle.
    pub fn has_angle_reference(&self) -> bool {
        self.segment_ref
            .iter()
            .chain(self.joint_ref.iter())
            .any(|&b| b)
    }
}
