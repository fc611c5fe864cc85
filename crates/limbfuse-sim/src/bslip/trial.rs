//! Simulated B-SLIP walking trials with CoM measurements (paper 003 sec IV-A).
//!
//! The CoM follows the library gait exactly (no process noise, as in the
//! paper); the measurements add zero-mean Gaussian noise of covariance R
//! (eq 15: `diag(5, 5, 5, 50, 50) x 1e-5` for `[x, y, z, vx, vy]`, i.e.
//! 7.1 mm and 22 mm/s standard deviations) to the measured channels.

use limbfuse_core::{Record, Sample};
use limbfuse_models::bslip::{GaitTemplate, Side};
use nalgebra::Vector3;
use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;
use rand_distr::{Distribution, Normal};

use super::walker::Walker;

/// Which CoM channels are measured.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum ComChannels {
    /// Position and the sagittal velocities `[x, y, z, vx, vy]` (eq 15).
    Full,
    /// Position only `[x, y, z]` (eq 17).
    Position,
}

/// Settings of a simulated B-SLIP trial.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct BslipTrialConfig {
    /// Duration (s): the trial holds `round(duration * sample_rate)`
    /// samples, at `k / sample_rate` for `k = 0, 1, ...`.
    pub duration: f64,
    /// Sample rate (Hz).
    pub sample_rate: f64,
    /// Measured channels.
    pub channels: ComChannels,
    /// Position noise variance (m^2); eq 15: 5e-5.
    pub position_variance: f64,
    /// Velocity noise variance (m^2/s^2); eq 15: 5e-4.
    pub velocity_variance: f64,
    /// Random seed.
    pub seed: u64,
}

impl Default for BslipTrialConfig {
    /// Two gait cycles' worth (4 s) at 100 Hz, full channels, eq 15 noise.
    fn default() -> Self {
        BslipTrialConfig {
            duration: 4.0,
            sample_rate: 100.0,
            channels: ComChannels::Full,
            position_variance: 5e-5,
            velocity_variance: 5e-4,
            seed: 1,
        }
    }
}

/// Simulates a trial on `template`, starting at MS with the left foot
/// trailing at the origin (all records in memory: [`trial_records`] yields
/// them one at a time).
pub fn simulate_trial(template: &GaitTemplate, cfg: &BslipTrialConfig) -> Vec<Record> {
    trial_records(template, cfg).collect()
}

/// The records of [`simulate_trial`], one at a time: memory does not grow
/// with the trial (a record is about 2 KB; an audit's `simulate bslip --rate
/// 1e7` asked for 82 GB at once and aborted).
pub fn trial_records(
    template: &GaitTemplate,
    cfg: &BslipTrialConfig,
) -> impl Iterator<Item = Record> {
    let cfg = *cfg;
    let mut rng = ChaCha8Rng::seed_from_u64(cfg.seed);
    let pos_noise = Normal::new(0.0, cfg.position_variance.max(0.0).sqrt()).ok();
    let vel_noise = Normal::new(0.0, cfg.velocity_variance.max(0.0).sqrt()).ok();
    let mut walker = Walker::new(*template, Side::Left, 0.0);
    // `round(duration x rate)` samples at `k / rate`, as every other
    // simulator writes (`simulate walking`, `knee`, `knee-fes`,
    // `fixed-hip`; the shared independent trials: 10 s at 100 Hz, 1000
    // rows to 9.99 s). It wrote `floor(duration x rate) + 1` (401 rows for
    // 4 s at 100 Hz, the last at t = duration).
    let n = (cfg.duration * cfg.sample_rate).round() as usize;
    (0..n).map(move |k| {
        let t = k as f64 / cfg.sample_rate;
        walker.advance_to(t);
        let x = walker.state();
        let mut sample = Sample::empty(t);
        for i in 0..3 {
            let e = pos_noise.map_or(0.0, |d| d.sample(&mut rng));
            sample.com.pos[i] = Some(x[i] + e);
        }
        if cfg.channels == ComChannels::Full {
            // Sagittal velocities only: forward (x) and vertical (y).
            for i in [0, 1] {
                let e = vel_noise.map_or(0.0, |d| d.sample(&mut rng));
                sample.com.vel[i] = Some(x[3 + i] + e);
            }
        }
        let mut rec = Record {
            sample,
            ..Default::default()
        };
        rec.reference.com_pos = Some(Vector3::new(x[0], x[1], x[2]));
        rec.reference.com_vel = Some(Vector3::new(x[3], x[4], x[5]));
        rec.reference.phase = Some(walker.phase());
        rec
    })
}
