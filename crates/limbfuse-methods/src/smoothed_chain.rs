//! `chain` smoothed offline (`limbfuse estimate --method chain --smooth`):
//! the real-time chain EKF behind the sensor-range gate, as [`crate::build`]
//! makes it, followed by the fixed-interval Rauch-Tung-Striebel smoother
//! over blocks with overlap (`limbfuse_estimators::chain_ekf::smoother`,
//! docs/CHAIN.md "Offline smoothing"). The estimates carry the smoothed
//! angles, their smoothed standard deviations (`diag_sd_*`) and the
//! smoothed hip velocity and mean speed; every other column is the
//! filter's.

use std::fmt;

use limbfuse_core::{Estimate, Estimator, EstimatorError, OfflineEstimator, Outputs, Sample};
use limbfuse_estimators::chain_ekf::smoother::{RtsSmoother, SmootherSettings};
use limbfuse_estimators::chain_ekf::state::{hip_velocity, MEAN_SPEED};
use limbfuse_estimators::chain_ekf::{ChainDiag, ChainEkf};
use limbfuse_io::{TrialLayout, TrialMeta};

use crate::chain_method::{resolve_geometry, ChainMethod};
use crate::gated::GatedEstimator;
use crate::{MethodDef, MethodError, MethodSpec};

/// The chain EKF and its offline smoother.
pub struct SmoothedChain {
    filter: GatedEstimator<ChainEkf>,
    smoother: RtsSmoother<Estimate>,
}

/// The smoothed `chain` for a trial; an error for any other method (only
/// `chain` has a smoother).
pub fn build_smoothed(
    spec: &MethodSpec,
    meta: &TrialMeta,
    layout: &TrialLayout,
    settings: SmootherSettings,
) -> Result<SmoothedChain, MethodError> {
    let MethodSpec::Chain(s) = spec else {
        return Err(MethodError::NoSmoother(spec.method().name()));
    };
    if !settings.is_valid() {
        return Err(MethodError::Chain(format!(
            "smoother block {} s / overlap {} s: expected a positive block and a finite overlap >= 0",
            settings.block_s, settings.overlap_s
        )));
    }
    let geometry =
        resolve_geometry(meta, &s.geometry).map_err(|e| MethodError::Chain(e.to_string()))?;
    let g = meta.gravity().map_err(MethodError::Metadata)?;
    let ekf =
        ChainEkf::new(s.params, geometry, g).map_err(|e| MethodError::Chain(e.to_string()))?;
    crate::channels::check_info(&ChainMethod::INFO, layout)?;
    let q = ekf.process_noise();
    let ranges = crate::gated::sensor_ranges(meta)?;
    Ok(SmoothedChain {
        filter: GatedEstimator::new(Box::new(ekf), ranges),
        smoother: RtsSmoother::new(q, settings),
    })
}

impl SmoothedChain {
    /// Steps where the backward pass kept the filtered state because the
    /// predicted covariance was not positive definite.
    pub fn fallbacks(&self) -> u64 {
        self.smoother.fallbacks()
    }
}

impl Estimator for SmoothedChain {
    fn name(&self) -> &'static str {
        self.filter.name()
    }

    fn outputs(&self) -> Outputs {
        self.filter.outputs()
    }

    fn describe_parameters(&self, out: &mut dyn fmt::Write) -> fmt::Result {
        self.filter.describe_parameters(out)?;
        let s = self.smoother.settings();
        writeln!(
            out,
            "smoother: rts (offline Rauch-Tung-Striebel; angles, sd_* and hip/mean-speed diagnostics smoothed; block {} s, overlap {} s)",
            s.block_s, s.overlap_s
        )
    }

    fn diagnostic_names(&self) -> &[&'static str] {
        self.filter.diagnostic_names()
    }

    fn rejected_readings(&self) -> [u64; 3] {
        self.filter.rejected_readings()
    }

    fn reset(&mut self) {
        self.filter.reset();
        self.smoother = RtsSmoother::new(
            self.filter.inner().process_noise(),
            self.smoother.settings(),
        );
    }

    /// The filter's (real-time) estimate; [`OfflineEstimator::push`] runs it.
    fn step(&mut self, sample: &Sample) -> Result<Estimate, EstimatorError> {
        self.filter.step(sample)
    }
}

impl OfflineEstimator for SmoothedChain {
    fn header(&self) -> &dyn Estimator {
        self
    }

    fn push(&mut self, sample: &Sample) -> Result<(), EstimatorError> {
        let e = self.filter.step(sample)?;
        let ekf = self.filter.inner();
        self.smoother
            .push(sample.t, ekf.link(), ekf.state(), ekf.covariance(), e);
        Ok(())
    }

    fn pop(&mut self) -> Option<Estimate> {
        let (mut e, smoothed) = self.smoother.pop()?;
        if let (Some(s), true) = (smoothed, e.segment[0].is_some()) {
            for i in 0..4 {
                e.segment[i] = Some(s.angle(i));
            }
            e.joint = [None; 3];
            e.fill_joints_from_segments();
            let mut d = e.diagnostics_mut::<ChainDiag>();
            d.value(ChainDiag::HipVx, s.x[hip_velocity(0)]);
            d.value(ChainDiag::HipVy, s.x[hip_velocity(1)]);
            d.value(ChainDiag::MeanSpeed, s.x[MEAN_SPEED]);
            d.value(ChainDiag::SdTrunk, s.sd[0]);
            d.value(ChainDiag::SdThigh, s.sd[1]);
            d.value(ChainDiag::SdShank, s.sd[2]);
            d.value(ChainDiag::SdFoot, s.sd[3]);
        }
        Some(e)
    }

    fn finish(&mut self) {
        self.smoother.finish();
    }
}
