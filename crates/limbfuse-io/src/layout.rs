//! Which channels a trial carries, and their column names (SPEC section 2).

use limbfuse_core::{Joint, Segment};

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
