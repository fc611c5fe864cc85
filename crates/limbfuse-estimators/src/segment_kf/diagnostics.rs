//! The diagnostics every segment filter reports ([`SegmentDiag`], declared
//! once and extended by [`super::LocalDiag`], [`super::MjlsDiag`] and
//! [`super::GlobalDiag`]) and the code that fills them.

use limbfuse_core::{diagnostic_set, DiagnosticWriter};

use super::chain::{Chain, Inputs};

diagnostic_set! {
    /// Diagnostics shared by the three segment filters, after each filter's
    /// own: input availability, the reliabilities `rho_i` (001 eq 11), the
    /// gyro-bias estimates, the angle standard deviations and the gain
    /// shares of 001 Fig. 6 ([`super::gain_shares`]).
    pub enum SegmentDiag {
        /// Number of missing inputs at this sample (gyros, accelerometers and,
        /// for `mjls`, encoders).
        MissingInputs = "missing_inputs",
        /// `rho_trunk = | ||a|| - g |` (m/s^2, 001 eq 11).
        RhoTrunk = "rho_trunk",
        /// `rho_thigh` (m/s^2, 001 eq 11).
        RhoThigh = "rho_thigh",
        /// `rho_shank` (m/s^2, 001 eq 11).
        RhoShank = "rho_shank",
        /// `rho_foot` (m/s^2, 001 eq 11).
        RhoFoot = "rho_foot",
        /// Trunk gyro-bias estimate (rad/s).
        BiasTrunk = "bias_trunk",
        /// Thigh gyro-bias estimate (rad/s).
        BiasThigh = "bias_thigh",
        /// Shank gyro-bias estimate (rad/s).
        BiasShank = "bias_shank",
        /// Foot gyro-bias estimate (rad/s).
        BiasFoot = "bias_foot",
        /// Standard deviation of the trunk angle, `sqrt(P_11)` (rad).
        SdTrunk = "sd_trunk",
        /// Standard deviation of the thigh angle (rad).
        SdThigh = "sd_thigh",
        /// Standard deviation of the shank angle (rad).
        SdShank = "sd_shank",
        /// Standard deviation of the foot angle (rad).
        SdFoot = "sd_foot",
        /// Share of the trunk correction from its own accelerometer (001 Fig. 6).
        ShareOwnTrunk = "share_own_trunk",
        /// Share of the thigh correction from its own accelerometer.
        ShareOwnThigh = "share_own_thigh",
        /// Share of the shank correction from its own accelerometer.
        ShareOwnShank = "share_own_shank",
        /// Share of the foot correction from its own accelerometer.
        ShareOwnFoot = "share_own_foot",
        /// Share of the trunk correction from the other segments' accelerometers.
        ShareOtherTrunk = "share_other_trunk",
        /// Share of the thigh correction from the other segments' accelerometers.
        ShareOtherThigh = "share_other_thigh",
        /// Share of the shank correction from the other segments' accelerometers.
        ShareOtherShank = "share_other_shank",
        /// Share of the foot correction from the other segments' accelerometers.
        ShareOtherFoot = "share_other_foot",
        /// Share of the trunk correction from the joint rows.
        ShareJointTrunk = "share_joint_trunk",
        /// Share of the thigh correction from the joint rows.
        ShareJointThigh = "share_joint_thigh",
        /// Share of the shank correction from the joint rows.
        ShareJointShank = "share_joint_shank",
        /// Share of the foot correction from the joint rows.
        ShareJointFoot = "share_joint_foot",
        /// Restarts so far (cumulative): after a time gap longer than
        /// [`super::robust::LONG_GAP_S`] or a diverged segment (issue 18).
        Resets = "resets",
    }
}

impl SegmentDiag {
    /// `rho_*` per segment (index [`limbfuse_core::Segment::index`]).
    pub const RHO: [SegmentDiag; 4] = [
        SegmentDiag::RhoTrunk,
        SegmentDiag::RhoThigh,
        SegmentDiag::RhoShank,
        SegmentDiag::RhoFoot,
    ];
    /// `bias_*` per segment.
    pub const BIAS: [SegmentDiag; 4] = [
        SegmentDiag::BiasTrunk,
        SegmentDiag::BiasThigh,
        SegmentDiag::BiasShank,
        SegmentDiag::BiasFoot,
    ];
    /// `sd_*` per segment.
    pub const SD: [SegmentDiag; 4] = [
        SegmentDiag::SdTrunk,
        SegmentDiag::SdThigh,
        SegmentDiag::SdShank,
        SegmentDiag::SdFoot,
    ];
    /// `share_own_*`, `share_other_*`, `share_joint_*` per segment, in the
    /// source order of [`super::gain_shares`].
    pub const SHARE: [[SegmentDiag; 4]; 3] = [
        [
            SegmentDiag::ShareOwnTrunk,
            SegmentDiag::ShareOwnThigh,
            SegmentDiag::ShareOwnShank,
            SegmentDiag::ShareOwnFoot,
        ],
        [
            SegmentDiag::ShareOtherTrunk,
            SegmentDiag::ShareOtherThigh,
            SegmentDiag::ShareOtherShank,
            SegmentDiag::ShareOtherFoot,
        ],
        [
            SegmentDiag::ShareJointTrunk,
            SegmentDiag::ShareJointThigh,
            SegmentDiag::ShareJointShank,
            SegmentDiag::ShareJointFoot,
        ],
    ];
}

/// Writes every [`SegmentDiag`] of a filter whose set `K` extends it:
/// `missing_inputs`, `rho_*`, `bias_*` and `sd_*` (bias and sd `None` for a
/// segment not yet initialised) and the gain `shares` of the last update.
pub(crate) fn write_segment_diagnostics<K>(
    w: &mut DiagnosticWriter<'_, K>,
    chain: &Chain,
    inp: &Inputs,
    with_encoders: bool,
    shares: &[[Option<f64>; 3]; 4],
) where
    K: limbfuse_core::DiagnosticSet + From<SegmentDiag>,
{
    let missing = inp.missing(inp.rate_missing, with_encoders);
    w.value(SegmentDiag::MissingInputs.into(), f64::from(missing));
    for i in 0..4 {
        w.set(SegmentDiag::RHO[i].into(), inp.rho[i]);
    }
    for i in 0..4 {
        let bias = chain.initialised(i).then(|| chain.gyro_bias(i));
        w.set(SegmentDiag::BIAS[i].into(), bias);
    }
    for i in 0..4 {
        let sd = chain.initialised(i).then(|| chain.angle_sd(i));
        w.set(SegmentDiag::SD[i].into(), sd);
    }
    for (kind, keys) in SegmentDiag::SHARE.iter().enumerate() {
        for (key, s) in keys.iter().zip(shares) {
            w.set((*key).into(), s[kind]);
        }
    }
    w.value(SegmentDiag::Resets.into(), chain.resets() as f64);
}
