//! The baseline study of issue 2: how gyro integration and accelerometer
//! inclination fail on simulated walking, and whether they fail the way
//! physics says (drift = gyro bias; inclination error grows with the
//! segment's dynamic acceleration).

use std::convert::Infallible;

use limbfuse_core::runner::{run, Observer, RunError};
use limbfuse_core::{Estimator, Record, Segment};
use limbfuse_estimators::baseline::{AccelInclination, GyroIntegration};
use limbfuse_sim::{SimError, WalkingConfig, WalkingSimulator};

use limbfuse_eval::evaluation::EvalOptions;
use limbfuse_eval::metrics::{AngleMetrics, Evaluation};

/// Per-segment figures of one simulated trial.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct SegmentFigures {
    /// Mean dynamic-acceleration index `| ||acc|| - g |` of the segment's accelerometer (m/s^2).
    pub mean_rho: f64,
    /// RMS of the error-free dynamic acceleration `||a||` of the sensor point (m/s^2).
    pub rms_dynamic_acc: f64,
    /// RMSE of accelerometer inclination (rad).
    pub accel_rmse: f64,
    /// RMSE of gyro integration (rad).
    pub gyro_rmse: f64,
    /// Slope of the gyro-integration error over time (rad/s), least squares.
    pub gyro_drift: f64,
    /// Mean gyro z error (measured - true rate) over the trial (rad/s): the bias seen by integration.
    pub gyro_bias: f64,
}

/// Figures of one trial.
#[derive(Debug, Clone, PartialEq)]
pub struct BaselineTrial {
    /// Per segment, trunk to foot.
    pub segments: [SegmentFigures; 4],
    /// Gyro-integration evaluation.
    pub gyro: Evaluation,
    /// Accelerometer-inclination evaluation.
    pub accel: Evaluation,
}

/// Why the study failed.
#[derive(Debug, thiserror::Error)]
pub enum StudyError {
    /// Bad simulator configuration.
    #[error(transparent)]
    Sim(#[from] SimError),
    /// An estimator failed.
    #[error(transparent)]
    Run(#[from] RunError),
}

/// Estimated segment angles of every sample (trunk to foot).
pub type SegmentTrack = Vec<[Option<f64>; 4]>;

/// Mean 4-segment RMSE (deg) of `estimator` over `records`, plain and
/// offset-free (mean error per channel removed), in one pass. `NaN` where
/// no segment was scored.
pub fn mean_rmse_deg(
    estimator: &mut dyn Estimator,
    records: &[Record],
) -> Result<[f64; 2], RunError> {
    let mut plain = AngleMetrics::new(estimator.name(), EvalOptions::default());
    let mut free = AngleMetrics::new(
        estimator.name(),
        EvalOptions {
            offset_free: true,
            ..EvalOptions::default()
        },
    );
    let observers: &mut [&mut dyn Observer] = &mut [&mut plain, &mut free];
    run(
        estimator,
        records.iter().map(|r| Ok::<_, Infallible>(*r)),
        observers,
    )?;
    let deg = |m: &AngleMetrics| m.evaluation().mean_rmse().unwrap_or(f64::NAN).to_degrees();
    Ok([deg(&plain), deg(&free)])
}

/// Evaluates `estimator` over `records`; returns the evaluation and the segment estimates.
pub fn evaluate_records(
    estimator: &mut dyn Estimator,
    records: &[Record],
) -> Result<(Evaluation, SegmentTrack), RunError> {
    struct Keep(SegmentTrack);
    impl Observer for Keep {
        fn observe(
            &mut self,
            _r: &Record,
            e: &limbfuse_core::Estimate,
        ) -> Result<(), limbfuse_core::runner::BoxError> {
            self.0.push(e.segment);
            Ok(())
        }
    }
    let mut metrics = AngleMetrics::new(estimator.name(), EvalOptions::default());
    let mut keep = Keep(Vec::with_capacity(records.len()));
    let observers: &mut [&mut dyn Observer] = &mut [&mut metrics, &mut keep];
    run(
        estimator,
        records.iter().map(|r| Ok::<_, Infallible>(*r)),
        observers,
    )?;
    Ok((metrics.evaluation(), keep.0))
}

/// Simulates one walking trial with `cfg` and runs both baselines on it.
pub fn baseline_trial(cfg: WalkingConfig) -> Result<BaselineTrial, StudyError> {
    let sim = WalkingSimulator::new(cfg)?;
    let truth_sim = sim.clone();
    let records: Vec<Record> = sim.collect();
    let (gyro, gyro_est) = evaluate_records(&mut GyroIntegration::new(), &records)?;
    let (accel, _) = evaluate_records(&mut AccelInclination::new(), &records)?;
    let mut segments = [SegmentFigures::default(); 4];
    for s in Segment::ALL {
        let i = s.index();
        let f = &mut segments[i];
        let n = records.len() as f64;
        let (mut st, mut se, mut stt, mut ste) = (0.0, 0.0, 0.0, 0.0);
        for (r, e) in records.iter().zip(&gyro_est) {
            let truth = truth_sim.truth(r.sample.t);
            if let Some(acc) = r.sample.imu[i].acc {
                f.mean_rho += (acc.norm() - cfg.g).abs() / n;
            }
            f.rms_dynamic_acc += truth.imu_point[i].a.norm_squared() / n;
            if let Some(g) = r.sample.imu[i].gyr {
                f.gyro_bias += (g.z - truth.gyro[i].z) / n;
            }
            if let (Some(est), Some(rf)) = (e[i], r.reference.segment[i]) {
                let (t, err) = (r.sample.t, est - rf);
                st += t;
                se += err;
                stt += t * t;
                ste += t * err;
            }
        }
        f.rms_dynamic_acc = f.rms_dynamic_acc.sqrt();
        f.gyro_drift = (n * ste - st * se) / (n * stt - st * st);
        f.accel_rmse = accel
            .rmse(limbfuse_core::sample::AngleChannel::Segment(s))
            .unwrap_or(f64::NAN);
        f.gyro_rmse = gyro
            .rmse(limbfuse_core::sample::AngleChannel::Segment(s))
            .unwrap_or(f64::NAN);
    }
    Ok(BaselineTrial {
        segments,
        gyro,
        accel,
    })
}
