//! Diagnostics of [`super::KneeSelfAlign`] (the `diag_*` columns, docs/OUTPUTS.md).

use limbfuse_core::{diagnostic_set, Estimate};

use super::{position, KneeSelfAlign, WindowStatus};

diagnostic_set! {
    /// Diagnostics of [`super::KneeSelfAlign`].
    pub enum KneeDiag {
        /// 1 once a window has identified the geometry (the knee angle is output), else 0.
        Identified = "identified",
        /// Status of the last window, [`super::WindowStatus::code`].
        WindowStatus = "window_status",
        /// 1 when the last window did not determine the axes, else 0.
        Unobservable = "unobservable",
        /// Number of windows completed.
        Windows = "windows",
        /// Complete, unsaturated samples of the last window.
        WindowUsable = "window_usable",
        /// 1 when a gyro of this sample is saturated, else 0.
        Saturated = "saturated",
        /// Gyro knee angle, eq 4 integrated (rad).
        AlphaGyro = "alpha_gyro",
        /// Accelerometer knee angle, eqs 5-7, of the lagged sample (rad).
        AlphaAcc = "alpha_acc",
        /// Correction state of the fusion filter, Algorithm 1 (rad).
        KfX = "kf_x",
        /// Variance of that correction (rad^2).
        KfP = "kf_p",
        /// Thigh joint axis `j_1`, x (eq 1, sensor frame).
        JThighX = "j_thigh_x",
        /// Thigh joint axis `j_1`, y.
        JThighY = "j_thigh_y",
        /// Thigh joint axis `j_1`, z.
        JThighZ = "j_thigh_z",
        /// Shank joint axis `j_2`, x (eq 1, sensor frame).
        JShankX = "j_shank_x",
        /// Shank joint axis `j_2`, y.
        JShankY = "j_shank_y",
        /// Shank joint axis `j_2`, z.
        JShankZ = "j_shank_z",
        /// Thigh sensor position `o_1`, x (eq 3, m).
        OThighX = "o_thigh_x",
        /// Thigh sensor position `o_1`, y (m).
        OThighY = "o_thigh_y",
        /// Thigh sensor position `o_1`, z (m).
        OThighZ = "o_thigh_z",
        /// Shank sensor position `o_2`, x (eq 3, m).
        OShankX = "o_shank_x",
        /// Shank sensor position `o_2`, y (m).
        OShankY = "o_shank_y",
        /// Shank sensor position `o_2`, z (m).
        OShankZ = "o_shank_z",
        /// RMS of the axis residual `e_j` (eq 2) over the last identified window (rad/s).
        RmsEJ = "rms_e_j",
        /// RMS of the position residual `e_o` (eq 3) over the last identified window (m/s^2).
        RmsEO = "rms_e_o",
        /// Information of the axes in the last window: smallest eigenvalue of
        /// `H_j^T H_j / N` ((rad/s)^2).
        Information = "information",
        /// Lag of the accelerometer angle behind the gyro angle (samples).
        AlphaAccLag = "alpha_acc_lag",
        /// Rate-bias state of the [`super::Fusion::RateBias`] filter (rad/s).
        KfRateBias = "kf_rate_bias",
        /// Circular spread (1 - mean resultant length, 0..1) of `alpha_acc -
        /// integral(alpha_gyro')` over the last identified window.
        AccGyroSpread = "acc_gyro_spread",
        /// Confidence (-1..1) in the relative sign of the two axes from the
        /// last identified window ([`super::sign::confidence`]): near 1 when the
        /// accelerometer angle follows the gyro angle far better with the
        /// chosen pair than with the other, near 0 when the window cannot
        /// tell them apart, negative when it prefers the other pair.
        SignConfidence = "sign_confidence",
        /// 1 once the relative axis sign is committed (kept from then on), else 0.
        SignCommitted = "sign_committed",
        /// 1 when the last identified window's accelerometer angle follows the
        /// gyro angle (`acc_gyro_spread <= acc_max_spread`) and corrects it
        /// (Algorithm 1) and no rest has read a norm off g
        /// ([`super::rest_gravity`]); 0 when the angle is the high-passed gyro
        /// angle.
        AccTrusted = "acc_trusted",
        /// How long the gyro knee rate has been missing (s; 0 with both
        /// gyros present). Over such a gap the held rate decays and the
        /// fusion's variance grows (ours, issue 18 item 2), so the first
        /// accelerometer angles after it re-anchor the knee angle.
        GyroGap = "gyro_gap",
        /// Where the last identified window's axes came from (ours, issue 15):
        /// 0 eq 2, 1 the upright-leg prior, 2 kept from the window before.
        AxisSource = "axis_source",
        /// Relative scale of the accelerometers (thigh over shank) applied
        /// to the shank's specific force (ours, issue 15 item 3,
        /// [`super::acc_scale`]); exactly 1 when the last identified window could not
        /// tell it from 1 (within 3 standard deviations).
        AccScaleRatio = "acc_scale_ratio",
        /// Windows whose positions are fused in the current ones (ours,
        /// issue 15 item 3, [`super::position_fusion`]; 1 after a restart).
        PositionWindows = "position_windows",
        /// Time offset between the thigh and shank streams in use (s;
        /// positive: the shank's readings arrive late), found by the delay
        /// search ([`super::delay`]; ours). 0 with the search off
        /// (`max_delay = 0`) or while none has been found.
        SensorDelay = "sensor_delay_s",
        /// The last rest's `|norm/g - 1|` of the accelerometer, the larger
        /// of thigh and shank (ours, issue knee31b,
        /// [`super::rest_gravity`]); above `acc_rest_tolerance` the
        /// accelerometer angle is not trusted from then on. Empty until a
        /// rest was seen.
        RestNormError = "rest_norm_error",
        /// Samples left out of the windows' position fits so far as gross
        /// eq-3 outliers (ours, [`super::position_outliers`]: a gyroscope
        /// spike's rate derivative; 0 on every clean recording measured).
        PositionOutliers = "position_outliers",
    }
}

impl KneeDiag {
    /// `j_thigh_*`, `j_shank_*` (`[sensor][component]`).
    pub const AXIS: [[KneeDiag; 3]; 2] = [
        [KneeDiag::JThighX, KneeDiag::JThighY, KneeDiag::JThighZ],
        [KneeDiag::JShankX, KneeDiag::JShankY, KneeDiag::JShankZ],
    ];
    /// `o_thigh_*`, `o_shank_*` (`[sensor][component]`).
    pub const POSITION: [[KneeDiag; 3]; 2] = [
        [KneeDiag::OThighX, KneeDiag::OThighY, KneeDiag::OThighZ],
        [KneeDiag::OShankX, KneeDiag::OShankY, KneeDiag::OShankZ],
    ];
}

impl KneeSelfAlign {
    /// Writes this sample's `diag_*` values into `est`.
    pub(super) fn write_diagnostics(
        &self,
        est: &mut Estimate,
        saturated: bool,
        alpha_acc: Option<f64>,
    ) {
        let mut d = est.diagnostics_mut::<KneeDiag>();
        d.flag(KneeDiag::Identified, self.geometry.is_some());
        d.value(KneeDiag::WindowStatus, self.status.code());
        d.flag(
            KneeDiag::Unobservable,
            self.status == WindowStatus::Unobservable,
        );
        d.value(KneeDiag::Windows, self.windows as f64);
        d.value(KneeDiag::WindowUsable, self.usable as f64);
        d.flag(KneeDiag::Saturated, saturated);
        if let Some(g) = &self.geometry {
            d.value(KneeDiag::AlphaGyro, self.alpha_gyro);
            d.set(KneeDiag::AlphaAcc, alpha_acc);
            let (x, p, bias) = self.kf.state();
            d.value(KneeDiag::KfX, x);
            d.value(KneeDiag::KfP, p);
            d.set(KneeDiag::KfRateBias, bias);
            for sensor in 0..2 {
                for k in 0..3 {
                    d.value(KneeDiag::AXIS[sensor][k], g.axis[sensor][k]);
                    d.value(KneeDiag::POSITION[sensor][k], g.position[sensor][k]);
                }
            }
            d.value(KneeDiag::RmsEJ, self.rms[0]);
            d.value(KneeDiag::RmsEO, self.rms[1]);
            d.value(KneeDiag::AxisSource, self.rms[2]);
            d.value(KneeDiag::AccScaleRatio, g.acc_scale);
            d.set(
                KneeDiag::PositionWindows,
                self.fused.map(|f| f.windows as f64),
            );
            d.value(KneeDiag::AccGyroSpread, self.spread);
            d.value(KneeDiag::SignConfidence, self.sign_confidence);
        }
        d.flag(KneeDiag::SignCommitted, self.sign_committed);
        d.flag(KneeDiag::AccTrusted, self.acc_trusted);
        d.value(KneeDiag::GyroGap, self.gyro_gap);
        d.value(KneeDiag::Information, self.information);
        d.value(KneeDiag::AlphaAccLag, position::DERIVATIVE_LATENCY as f64);
        d.value(KneeDiag::SensorDelay, self.sensor_delay_s());
        d.set(KneeDiag::RestNormError, self.rest.last_error());
        d.value(KneeDiag::PositionOutliers, self.position_outliers as f64);
    }
}
