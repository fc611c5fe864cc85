//! The self-aligning knee scenario (paper 002): walking with the thigh and
//! shank IMUs at random, unknown orientations *and* positions, and an
//! optional re-mounting of the thigh sensor mid-trial (002 section 3.6).
//!
//! Positions (segment frames, right leg, `+z` lateral): the thigh sensor at
//! a uniformly drawn 30-70 % of the thigh length above the knee and 6-10 cm
//! lateral of the femur axis, the shank sensor at 30-70 % of the shank length
//! below the knee and 4-7 cm lateral of the tibia axis (a sensor strapped
//! somewhere on the lateral side; the lateral distances span the soft-tissue
//! radius of the thigh and shank of adults, Winter 2009 Table 4.1 girths).
//! Anterior-posterior offsets from the segment's long-axis line are drawn
//! with standard deviation [`KneeScenario::ap_offset_sd_m`] (default 0: the
//! sensor's centre line passes through the long axis, as for a lateral
//! strap; see docs/KNEE_SELFALIGN.md for what an offset does to the zero).
//!
//! Re-mounting: at `t_s` the thigh sensor is turned in place by `angle`
//! about the thigh's long axis (segment `y`), as the paper rotated its
//! recorded thigh data; its position does not change.

use limbfuse_core::{Record, Segment};
use nalgebra::{Matrix3, Vector3};
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
use rand_distr::StandardNormal;

use crate::chain::rot_y;
use crate::config::{Mounting, SimError, WalkingConfig};
use crate::walking::WalkingSimulator;

/// ChaCha stream of the knee scenario's own draws (positions).
const STREAM_KNEE: u64 = 10;

/// A thigh-sensor re-mounting event.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Remount {
    /// Time of the event (s).
    pub t_s: f64,
    /// Rotation about the thigh's long axis (rad); paper 002: 50 deg.
    pub angle_rad: f64,
}

/// Configuration of the knee scenario.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct KneeScenario {
    /// The walking trial (its `mounting` is forced to `Random`).
    pub walking: WalkingConfig,
    /// Draw random sensor positions (otherwise the walking simulator's
    /// fixed mid-segment lateral points).
    pub random_positions: bool,
    /// Standard deviation of the anterior-posterior offset of each sensor
    /// from its segment's long-axis line (m), 0..=0.05.
    pub ap_offset_sd_m: f64,
    /// Optional re-mounting of the thigh sensor.
    pub remount: Option<Remount>,
}

impl Default for KneeScenario {
    fn default() -> Self {
        KneeScenario {
            walking: WalkingConfig {
                mounting: Mounting::Random,
                ..WalkingConfig::default()
            },
            random_positions: true,
            ap_offset_sd_m: 0.0,
            remount: None,
        }
    }
}

/// Streams the records of a [`KneeScenario`].
#[derive(Debug, Clone)]
pub struct KneeSimulator {
    sim: WalkingSimulator,
    remount: Option<Remount>,
    /// Thigh IMU position from the knee, shank IMU position from the knee
    /// (segment frames, m).
    positions: [Vector3<f64>; 2],
}

impl KneeSimulator {
    /// Validates, draws the positions and builds the walking simulator.
    pub fn new(cfg: KneeScenario) -> Result<Self, SimError> {
        if !(0.0..=0.05).contains(&cfg.ap_offset_sd_m) {
            return Err(SimError::OutOfRange {
                name: "ap_offset_sd_m",
                value: cfg.ap_offset_sd_m,
                range: "[0, 0.05] m",
            });
        }
        if let Some(r) = cfg.remount {
            let time_ok = r.t_s.is_finite() && r.t_s >= 0.0;
            let angle_ok = r.angle_rad.is_finite() && r.angle_rad.abs() <= core::f64::consts::PI;
            if !time_ok {
                return Err(SimError::OutOfRange {
                    name: "remount.t_s",
                    value: r.t_s,
                    range: "[0, inf) s",
                });
            }
            if !angle_ok {
                return Err(SimError::OutOfRange {
                    name: "remount.angle_rad",
                    value: r.angle_rad,
                    range: "[-pi, pi] rad",
                });
            }
        }
        let walking = WalkingConfig {
            mounting: Mounting::Random,
            ..cfg.walking
        };
        let mut sim = WalkingSimulator::new(walking)?;
        let body = sim.model().body;
        let mut positions = [
            body.imu[Segment::Thigh.index()] - Vector3::new(0.0, -body.thigh, 0.0),
            body.imu[Segment::Shank.index()],
        ];
        if cfg.random_positions {
            let mut rng = ChaCha8Rng::seed_from_u64(walking.seed);
            rng.set_stream(STREAM_KNEE);
            let s = body.height / 1.75;
            let mut ap = || rng.sample::<f64, _>(StandardNormal) * cfg.ap_offset_sd_m;
            let (ap_t, ap_s) = (ap(), ap());
            positions = [
                Vector3::new(
                    ap_t,
                    rng.random_range(0.3..0.7) * body.thigh,
                    rng.random_range(0.06..0.10) * s,
                ),
                Vector3::new(
                    ap_s,
                    -rng.random_range(0.3..0.7) * body.shank,
                    rng.random_range(0.04..0.07) * s,
                ),
            ];
            sim.set_imu_position(
                Segment::Thigh,
                positions[0] + Vector3::new(0.0, -body.thigh, 0.0),
            );
            sim.set_imu_position(Segment::Shank, positions[1]);
        }
        Ok(KneeSimulator {
            sim,
            remount: cfg.remount,
            positions,
        })
    }

    /// The walking simulator inside (mountings, model).
    pub fn walking(&self) -> &WalkingSimulator {
        &self.sim
    }

    /// Sensor positions relative to the knee centre, segment frames (m):
    /// thigh, shank.
    pub fn positions(&self) -> [Vector3<f64>; 2] {
        self.positions
    }

    /// True joint axis and sensor positions in the thigh and shank sensor
    /// frames (the segment z axis and the positions above), for the current
    /// mountings.
    pub fn sensor_frame_geometry(&self) -> ([Vector3<f64>; 2], [Vector3<f64>; 2]) {
        let m = |s: Segment| self.sim.imus()[s.index()].mount.transpose();
        let (mt, ms) = (m(Segment::Thigh), m(Segment::Shank));
        (
            [mt * Vector3::z(), ms * Vector3::z()],
            [mt * self.positions[0], ms * self.positions[1]],
        )
    }

    /// Metadata lines for the trial header (walking metadata plus the knee scenario).
    pub fn metadata(&self) -> Vec<(String, String)> {
        let mut m = self.sim.metadata();
        let p = self.positions;
        m.push((
            "knee_imu_positions_m".into(),
            format!(
                "thigh={:.4},{:.4},{:.4} shank={:.4},{:.4},{:.4} (segment frames, from the knee centre)",
                p[0].x, p[0].y, p[0].z, p[1].x, p[1].y, p[1].z
            ),
        ));
        if let Some(r) = self.remount {
            m.push((
                "remount".into(),
                format!(
                    "thigh sensor turned {:.1} deg about the thigh long axis at t = {} s",
                    r.angle_rad.to_degrees(),
                    r.t_s
                ),
            ));
        }
        m
    }
}

impl Iterator for KneeSimulator {
    type Item = Record;

    fn next(&mut self) -> Option<Record> {
        if let Some(r) = self.remount {
            let k = self.sim.len_done();
            let t = k as f64 / self.sim.config().imu_rate_hz;
            if t >= r.t_s {
                let m: Matrix3<f64> = self.sim.imus()[Segment::Thigh.index()].mount;
                self.sim
                    .set_imu_mount(Segment::Thigh, rot_y(r.angle_rad) * m);
                self.remount = None;
            }
        }
        self.sim.next()
    }

    fn size_hint(&self) -> (usize, Option<usize>) {
        self.sim.size_hint()
    }
}
