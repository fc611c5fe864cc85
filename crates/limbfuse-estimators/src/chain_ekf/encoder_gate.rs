//! The chain's encoder rows and their innovation gate (docs/CHAIN.md,
//! "Encoder gate"; not in the papers).
//!
//! An encoder row whose innovation lies beyond [`ChainParams::encoder_gate`]
//! sigmas is not applied (it counts as a refused reading,
//! `diag_rejected_encoder`): a stuck encoder (a joint at rest repeats its
//! count, so the sensor gate has no stuck test) would otherwise pull the
//! chain's joint angle with it. A joint whose row is refused every time for
//! [`GATE_LOCKOUT_S`] is taken as changed for good (re-zeroed, slipped) and
//! re-adopted: its encoder-offset state is set to the value the reading
//! implies, with the start-up offset variance and no correlation, and its
//! rows are applied again. Not a full restart, as the segment filters do:
//! chain's start-up window costs [`ChainParams::startup_s`] (1 s) of
//! estimates, while only one joint's offset is in question.
//!
//! Gyroscope rows beside an encoder (session 41, ours; docs/CHAIN.md): a
//! single-sample gyroscope glitch within the sensor gate's range and jump
//! bound (a 3 rad/s spike) moved the segment's angle by its integral (1.7
//! deg at 100 Hz) while the covariance said it could not have; the joint's
//! encoder, which was right, then lay beyond `encoder_gate`, was refused,
//! and after [`GATE_LOCKOUT_S`] re-adopted with the glitch's error as its
//! offset. While an encoder of one of the segment's joints reads, that
//! encoder observes the segment's motion relative to its neighbour, so the
//! gyroscope row is tested like the encoder rows and refused
//! ([`ChainParams::gyro_gate`]) at the cost of one sample's rate. Never
//! two in a row for a segment: a glitch is one sample, while a run of
//! outlying rows is a model that does not fit the data (sensors not aligned
//! with the segments, where refusing every other row took the filter into
//! divergence), and there the gyroscope is what the filter needs most.
//! Without an encoder beside it the row is always applied: the gyroscope is
//! then the segment's only rate, and real recordings' innovations exceed the
//! gate often (docs/RESULTS.md, "Single-sample gyroscope spikes").
//!
//! [`ChainParams::encoder_gate`]: super::ChainParams::encoder_gate
//! [`ChainParams::gyro_gate`]: super::ChainParams::gyro_gate
//! [`ChainParams::startup_s`]: super::ChainParams::startup_s

use limbfuse_core::Sample;

use super::startup::initial;
use super::state::{encoder_offset, theta, SparseRow, N};
use super::ChainEkf;
pub use crate::segment_kf::robust::GATE_LOCKOUT_S;

/// The gate's state: when each joint's rows began to be refused, and how
/// many were refused.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct EncoderGate {
    /// Time of the first refusal of the current run per joint (`None`: the
    /// last row was applied).
    refused_since: [Option<f64>; 3],
    /// Rows refused since the filter was made or reset.
    refused: u64,
    /// Joints re-adopted after a lockout since the filter was made or reset.
    readopted: u64,
    /// Gyroscope rows refused beside an encoder since the filter was made
    /// or reset.
    gyro_refused: u64,
    /// Whether each segment's last gyroscope row was refused.
    gyro_refused_last: [bool; 4],
}

impl EncoderGate {
    /// Rows refused so far.
    pub fn refused(&self) -> u64 {
        self.refused
    }

    /// Joints re-adopted after a lockout so far.
    pub fn readopted(&self) -> u64 {
        self.readopted
    }

    /// Gyroscope rows refused beside an encoder so far.
    pub fn gyro_refused(&self) -> u64 {
        self.gyro_refused
    }

    /// Whether segment `i`'s last gyroscope row was refused (its next one
    /// is then applied without the gate).
    pub(super) fn gyro_refused_last(&self, i: usize) -> bool {
        self.gyro_refused_last[i]
    }

    /// Records whether segment `i`'s gyroscope row was applied.
    pub(super) fn gyro_row(&mut self, i: usize, applied: bool) {
        self.gyro_refused_last[i] = !applied;
        if !applied {
            self.gyro_refused += 1;
        }
    }

    /// Forgets the current runs of refusals (a new start of the filter); the
    /// counts stay.
    pub fn restart(&mut self) {
        self.refused_since = [None; 3];
        self.gyro_refused_last = [false; 4];
    }
}

/// Whether an encoder of one of segment `i`'s joints (hip for the trunk,
/// hip or knee for the thigh, knee or ankle for the shank, ankle for the
/// foot) has a finite reading in `sample`.
pub(super) fn encoder_beside(sample: &Sample, i: usize) -> bool {
    let reads = |j: usize| sample.encoder[j].is_some_and(f64::is_finite);
    (i > 0 && reads(i - 1)) || (i < 3 && reads(i))
}

impl ChainEkf {
    /// The encoder rows of one sample (hip, knee, ankle), each through the
    /// gate.
    pub(super) fn encoder_rows(&mut self, sample: &Sample) {
        let (noise, gate) = (self.params.encoder_noise, self.params.encoder_gate);
        for j in 0..3 {
            let Some(e) = sample.encoder[j].filter(|e| e.is_finite()) else {
                continue;
            };
            let mut row = SparseRow::new();
            row.add(theta(j), 1.0);
            row.add(theta(j + 1), -1.0);
            row.add(encoder_offset(j), 1.0);
            let joint = self.x[theta(j)] - self.x[theta(j + 1)];
            let nu = e - (joint + self.x[encoder_offset(j)]);
            if self.apply(&row, nu, noise, gate) {
                self.encoder_gate.refused_since[j] = None;
                continue;
            }
            let since = *self.encoder_gate.refused_since[j].get_or_insert(sample.t);
            if sample.t - since < GATE_LOCKOUT_S {
                self.encoder_gate.refused += 1;
            } else {
                // Changed for good: the offset the reading implies, as
                // uncertain as at the start, then the row again.
                let k = encoder_offset(j);
                for m in 0..N {
                    self.p[(k, m)] = 0.0;
                    self.p[(m, k)] = 0.0;
                }
                self.p[(k, k)] = initial::ENCODER_OFFSET * initial::ENCODER_OFFSET;
                self.x[k] = e - joint;
                self.encoder_gate.refused_since[j] = None;
                self.encoder_gate.readopted += 1;
                self.apply(&row, 0.0, noise, f64::INFINITY);
            }
        }
    }
}
