//! What a three-dimensional attitude could reach on a real recording
//! (docs/RESULTS.md, "Real data: gaittoolbox S02, after `align`", issue 14),
//! beside the planar gyroscope floor of `gyro_shape_floor`.
//!
//! The reference of the S02 trial is the angle of a segment's long axis
//! projected on the walking plane (forward, up). A planar estimator
//! integrates one sensor axis; a 3D one would know the segment's attitude
//! and project its long axis the way the reference does. This example
//! takes the device's own orientation (the `<seg>_quat_*` columns: Xsens
//! on-board, gyro + accelerometer + magnetometer) as that attitude and, per
//! window and segment, the *best* constant long axis `u` (segment frame)
//! and the *best* constant walking direction `f` (horizontal, in the
//! device's world) for that window: a floor, like the ideal offset and drift
//! of `gyro_shape_floor`, not an estimator. "Up" is the window's mean
//! specific force turned into the world by the orientation. The angle is
//! `atan2(R u . f, R u . up)` up to sign, scored offset-free at the best lag
//! within +-`--max-lag` samples. A second row per window projects on the
//! plane normal to the segment's own medio-lateral axis (`z` after
//! `align`), which needs no heading; a third keeps the long axis normal
//! to that axis, as a planar model has it.
//! `cargo run --release -p limbfuse-studies --example attitude_floor -- TRIAL --window A:B [--window C:D] [--max-lag N]`

use std::f64::consts::PI;
use std::path::Path;

use clap::Parser;
use limbfuse_core::sample::AngleChannel;
use limbfuse_core::Segment;
use limbfuse_studies::example_args::GyroShapeFloorArgs;
use limbfuse_studies::recorded_trial::RecordedTrial;
use nalgebra::{Matrix3, UnitQuaternion, Vector3};

/// One window of one segment: the attitude at each row, the reference at
/// each row (both optional), and the horizontal basis of the window.
struct WindowData {
    rot: Vec<Option<Matrix3<f64>>>,
    reference: Vec<Option<f64>>,
    rows: std::ops::Range<usize>,
    up: Vector3<f64>,
    e1: Vector3<f64>,
    e2: Vector3<f64>,
    /// Project on the plane normal to the segment's own medio-lateral
    /// axis (its `z` turned into the world, made horizontal) instead of a
    /// constant walking direction: what a heading-free 3D attitude gives.
    own_plane: bool,
    /// Keep the long axis normal to the segment's `z` (`beta` = 0), as a
    /// planar model with `align`'s axis has it.
    in_plane_axis: bool,
}

/// Long axis from its two angles (`alpha` about the segment's z, `beta`
/// out of the x-y plane).
fn axis(alpha: f64, beta: f64) -> Vector3<f64> {
    Vector3::new(
        beta.cos() * alpha.cos(),
        beta.cos() * alpha.sin(),
        beta.sin(),
    )
}

fn wrap(a: f64) -> f64 {
    (a + PI).rem_euclid(2.0 * PI) - PI
}

impl WindowData {
    /// Offset-free RMS error (rad) of the projected angle for walking
    /// direction `psi`, long axis `(alpha, beta)`, estimate row k against
    /// reference row k - `lag`.
    fn rms(&self, psi: f64, alpha: f64, beta: f64, lag: i64) -> f64 {
        let u = axis(alpha, beta);
        let f = self.e1 * psi.cos() + self.e2 * psi.sin();
        let mut first: Option<f64> = None;
        let (mut n, mut s, mut ss) = (0.0, 0.0, 0.0);
        for k in self.rows.clone() {
            let Some(r) = usize::try_from(k as i64 - lag)
                .ok()
                .and_then(|j| self.reference.get(j).copied().flatten())
            else {
                continue;
            };
            let Some(rot) = self.rot[k] else { continue };
            let d = rot * u;
            let f = if self.own_plane {
                match self.up.cross(&(rot * Vector3::z())).try_normalize(1e-9) {
                    Some(h) => h,
                    None => continue,
                }
            } else {
                f
            };
            let theta = d.dot(&f).atan2(-d.dot(&self.up));
            let raw = theta - r;
            let c = *first.get_or_insert(raw);
            let e = wrap(raw - c);
            n += 1.0;
            s += e;
            ss += e * e;
        }
        if n < 3.0 {
            return f64::INFINITY;
        }
        (ss / n - (s / n) * (s / n)).max(0.0).sqrt()
    }

    /// Coarse grid, then a shrinking coordinate search, at one lag.
    fn best(&self, lag: i64, start: [f64; 3]) -> ([f64; 3], f64) {
        let mut x = start;
        let mut v = self.rms(x[0], x[1], x[2], lag);
        for step_deg in [4.0_f64, 1.0, 0.25, 0.05] {
            let step = step_deg.to_radians();
            loop {
                let mut improved = false;
                let last = if self.in_plane_axis { 2 } else { 3 };
                for i in usize::from(self.own_plane)..last {
                    for sgn in [-1.0, 1.0] {
                        let mut y = x;
                        y[i] += sgn * step;
                        let w = self.rms(y[0], y[1], y[2], lag);
                        if w < v {
                            (x, v, improved) = (y, w, true);
                        }
                    }
                }
                if !improved {
                    break;
                }
            }
        }
        (x, v)
    }

    fn coarse(&self) -> [f64; 3] {
        let mut best = ([0.0; 3], f64::INFINITY);
        let headings = if self.own_plane { 1 } else { 36 };
        for i in 0..headings {
            let psi = (i as f64 * 10.0).to_radians();
            for j in 0..36 {
                let alpha = (j as f64 * 10.0).to_radians();
                let betas = if self.in_plane_axis { 0..=0 } else { -6..=6 };
                for b in betas {
                    let beta = (b as f64 * 10.0).to_radians();
                    let v = self.rms(psi, alpha, beta, 0);
                    if v < best.1 {
                        best = ([psi, alpha, beta], v);
                    }
                }
            }
        }
        best.0
    }
}

fn main() {
    let args = GyroShapeFloorArgs::parse();
    let path = Path::new(&args.trial);
    let trial =
        RecordedTrial::read(path).unwrap_or_else(|e| panic!("{e} (run from the repository root)"));
    let records = &trial.records;
    let segments = [Segment::Thigh, Segment::Shank, Segment::Foot];
    let lag = args.max_lag as i64;
    println!(
        "{}: device attitude, best constant long axis and walking direction per window, offset-free, lag within +-{} samples",
        path.display(),
        args.max_lag
    );
    println!("| window (s) | plane | thigh | shank | foot | mean | lags thigh / shank / foot |");
    println!("|---|---|---|---|---|---|---|");
    for (&(start, end), own_plane, in_plane_axis) in args
        .windows
        .iter()
        .flat_map(|w| [(w, false, false), (w, true, false), (w, true, true)])
    {
        let first = records.partition_point(|r| r.sample.t < start);
        let last = records.partition_point(|r| r.sample.t <= end);
        let mut row = Vec::new();
        let mut lags = Vec::new();
        for s in segments {
            let rot: Vec<Option<Matrix3<f64>>> = records
                .iter()
                .map(|r| {
                    let q = r.sample.imu(s).quat?;
                    let q = nalgebra::Quaternion::new(q[0], q[1], q[2], q[3]);
                    Some(
                        UnitQuaternion::from_quaternion(q)
                            .to_rotation_matrix()
                            .into_inner(),
                    )
                })
                .collect();
            let mut g = Vector3::zeros();
            for k in first..last {
                if let (Some(rm), Some(a)) = (rot[k], records[k].sample.imu(s).acc) {
                    g += rm * a;
                }
            }
            let up = g.try_normalize(1e-9).unwrap_or_else(|| {
                panic!(
                    "{}: no {} orientation and acceleration in {start}-{end} s",
                    path.display(),
                    s.name()
                )
            });
            let helper = if up.x.abs() < 0.9 {
                Vector3::x()
            } else {
                Vector3::y()
            };
            let e1 = (helper - up * up.dot(&helper)).normalize();
            let e2 = up.cross(&e1);
            let c = AngleChannel::Segment(s);
            let data = WindowData {
                rot,
                reference: records.iter().map(|r| r.reference.angle(c)).collect(),
                rows: first..last,
                up,
                e1,
                e2,
                own_plane,
                in_plane_axis,
            };
            let start_point = data.coarse();
            let (v, l) = (-lag..=lag)
                .map(|l| (data.best(l, start_point).1, l))
                .min_by(|a, b| a.0.total_cmp(&b.0))
                .unwrap_or((f64::NAN, 0));
            row.push(v.to_degrees());
            lags.push(l);
        }
        let mean = row.iter().sum::<f64>() / row.len() as f64;
        let plane = match (own_plane, in_plane_axis) {
            (false, _) => "walking (best constant direction)",
            (true, false) => "segment's own (heading-free)",
            (true, true) => "segment's own, long axis normal to z",
        };
        println!(
            "| {start}-{end} | {plane} | {:.2} | {:.2} | {:.2} | **{mean:.2}** | {} / {} / {} |",
            row[0], row[1], row[2], lags[0], lags[1], lags[2]
        );
    }
}
